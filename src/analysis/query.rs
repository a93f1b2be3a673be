//! The polars queries of `analyze`: every statistic starts as a lazy query over `scan_parquet`
//! of the part files, run on polars' streaming engine; Rust finishes on the small aggregated
//! tables (see [`super`]). polars' Rust API changes between minor versions; it is pinned in
//! Cargo.toml.
//!
//! **One scan, many aggregations.** The part files of every cell (one plain dataset, or the
//! cells of a sweep) are scanned into one frame: per realization its cell, its jackknife group
//! (realization mod 20), the value of every analysed observable ([`Observable::expr`], the one
//! censoring rule), its deviation d = x − c from a pilot centre c, its histogram bin, and one
//! flag per validation rule. From that frame, in one streaming pass (the scan is shared by the
//! sinks):
//!
//! - per (cell, group): n, Σd, Σd², Σd³, Σd⁴, min, max, the censored count of every observable,
//!   the range of every pair, and the number of rows breaking each rule;
//! - per (cell, group, bin): counts of every continuous observable on the dyadic grid of width
//!   2^e (bin ⌊x·2^−e⌋, exact: scaling by a power of two is exact), and of every count
//!   observable per value;
//! - per (cell, bin x, bin y): the joint counts of every requested pair;
//! - per (cell, convergence bucket): n, Σd, Σd² of the convergence observables.
//!
//! **The pilot.** The centre c and the exponent e come from a first small query over the first
//! [`PILOT_ROWS`] rows of each cell: c is their mean (the power sums about a centre near the mean
//! lose no digits; the central moments follow exactly, [`Sums::moments`]), and e is the finest
//! exponent any of the analysis's histograms can need: the smallest, over the pilot rows without
//! each jackknife group, of the sketch exponent of their range ([`super::sketch`]). The whole
//! sample's range (and each leave-one-group-out range) holds that range, so every histogram the
//! analysis draws is on a grid of width 2^E with E ≥ e and is an exact sum of the pilot-grid
//! counts. The pilot decides only how fine the counts are, never what they are.
//!
//! **Validation** is in the same scan: the rules are flags summed per group; only when one is
//! broken does [`locate`] look for the first offending file, row and column, to name them.

use std::path::Path;

use polars::prelude::*;

use super::input::{Dataset, Stamp};
use super::jackknife::GROUPS;
use super::sketch;
use crate::observables::Observable;

/// Rows of each cell the pilot reads (the dataset's row-group size: one row group).
pub(crate) const PILOT_ROWS: usize = 131_072;

/// What to aggregate: the observables, the pairs (positions in `series`) and the convergence
/// observables (positions).
pub(crate) struct Plan<'a> {
    pub series: &'a [Observable],
    pub pairs: &'a [(usize, usize)],
    pub convergence: &'a [usize],
    /// the checkpoints of the convergence table (realizations read)
    pub checkpoints: &'a [u64],
}

/// A cell's pilot: per observable the centre and the exponent of the counts, per pair the
/// exponents of the joint counts.
#[derive(Debug, Clone)]
pub(crate) struct Pilot {
    pub center: Vec<f64>,
    /// a bound of |x − c| (checked on the whole sample after the scan)
    pub bound: Vec<f64>,
    pub exp: Vec<i32>,
    pub joint: Vec<(i32, i32)>,
    /// the cell's realizations (the n of the exact sums)
    pub rows: u64,
}

/// Power sums that do not depend on the order of addition.
///
/// polars adds in whatever order its threads and morsels meet the rows, and floating-point
/// addition is not associative: summed as floats, Σd^p would change in its last bits with the
/// thread count or the shard split. So each term t = d^p (|d| ≤ B, n rows) is split into two
/// integers, `hi = trunc(t/q₁)` and `lo = trunc((t − hi q₁)/q₂)` with q₁ = B^p n / 2^61 and
/// q₂ = q₁ n / 2^61, summed exactly as int64 (each sum stays below 2^61 in magnitude), and
/// Σt = q₁ Σhi + q₂ Σlo. The truncation loses less than q₂ per term, a relative
/// (n/2^61)² of B^p: below 1e-21 for n ≤ 10^8, far under double precision.
pub(crate) fn quanta(bound: f64, rows: u64) -> [(f64, f64); 4] {
    let r = (rows.max(1) as f64) / 2f64.powi(61);
    [1, 2, 3, 4].map(|p| {
        let q1 = bound.powi(p) * r;
        (q1, q1 * r)
    })
}

/// Σt from the two integer sums (see [`quanta`]).
fn exact(hi: i64, lo: i64, (q1, q2): (f64, f64)) -> f64 {
    hi as f64 * q1 + lo as f64 * q2
}

fn term(i: usize, p: usize, part: char) -> String {
    format!("__{part}{i}_{p}")
}

/// The integer parts of d^p, p = 1..=`powers` (see [`quanta`]).
fn terms(d: Expr, q: &[(f64, f64); 4], i: usize, powers: usize) -> Vec<Expr> {
    let mut out = Vec::new();
    let mut t = d.clone();
    for p in 1..=powers {
        if p > 1 {
            t = t * d.clone();
        }
        let (q1, q2) = q[p - 1];
        let hi = (t.clone() / lit(q1)).cast(DataType::Int64);
        let lo = ((t.clone() - hi.clone().cast(DataType::Float64) * lit(q1)) / lit(q2)).cast(DataType::Int64);
        out.push(hi.alias(term(i, p, 'h')));
        out.push(lo.alias(term(i, p, 'l')));
    }
    out
}

/// The power sums of one observable in one jackknife group: n, Σ(x−c)^p for p = 1..4, range,
/// and how many values were censored.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Sums {
    pub n: u64,
    pub s: [f64; 4],
    pub min: f64,
    pub max: f64,
    pub cut: u64,
}

impl Sums {
    /// The central moments from power sums about `c` (exact algebra: with δ = S1/n the offset of
    /// the mean from c, M2 = S2 − n δ², M3 = S3 − 3δ S2 + 2n δ³, M4 = S4 − 4δ S3 + 6δ² S2 − 3n δ⁴).
    pub fn moments(&self, c: f64) -> crate::stats::Moments {
        if self.n == 0 {
            return crate::stats::Moments::default();
        }
        let n = self.n as f64;
        let [s1, s2, s3, s4] = self.s;
        let d = s1 / n;
        let (d2, d3, d4) = (d * d, d * d * d, d * d * d * d);
        crate::stats::Moments {
            n: self.n,
            mean: c + d,
            m2: (s2 - n * d2).max(0.0),
            m3: s3 - 3.0 * d * s2 + 2.0 * n * d3,
            m4: (s4 - 4.0 * d * s3 + 6.0 * d2 * s2 - 3.0 * n * d4).max(0.0),
            min: self.min,
            max: self.max,
        }
    }
}

/// What the scan aggregated for one cell.
#[derive(Debug, Clone, Default)]
pub(crate) struct Aggregates {
    pub rows: u64,
    /// [observable][group]
    pub sums: Vec<Vec<Sums>>,
    /// [observable][group]: (bin at the pilot exponent, or the value of a count; count)
    pub bins: Vec<Vec<Vec<(i64, u64)>>>,
    /// [pair]: ((bin x, bin y) at the pilot's joint exponents, count)
    pub joint: Vec<Vec<((i64, i64), u64)>>,
    /// [pair]: (min x, max x, min y, max y) over the realizations with both values
    pub joint_range: Vec<Option<[f64; 4]>>,
    /// [convergence observable][checkpoint]: (n, Σd, Σd²) of the realizations read after the
    /// previous checkpoint, up to this one (the last entry: up to the last realization)
    pub convergence: Vec<Vec<(u64, f64, f64)>>,
}

/// Column names inside the queries.
const CELL: &str = "__cell";
const GROUP: &str = "__group";
const ROW: &str = "__row";
const BUCKET: &str = "__bucket";
fn value(i: usize) -> String {
    format!("__x{i}")
}
fn bin(i: usize) -> String {
    format!("__b{i}")
}
fn jbin(p: usize, axis: char) -> String {
    format!("__j{p}{axis}")
}
fn cut(i: usize) -> String {
    format!("__c{i}")
}
fn flag(f: usize) -> String {
    format!("__f{f}")
}

/// The scan of one part file, its rows numbered from 0 (hive partitioning off: a sweep's
/// `key=value/` directories are cells, not columns).
fn scan(path: &Path, n_rows: Option<usize>, row_index: bool) -> PolarsResult<LazyFrame> {
    let args = ScanArgsParquet {
        n_rows,
        row_index: row_index.then(|| RowIndex { name: ROW.into(), offset: 0 }),
        hive_options: HiveOptions { enabled: Some(false), ..Default::default() },
        ..Default::default()
    };
    LazyFrame::scan_parquet(PlRefPath::new(path.to_string_lossy().as_ref()), args)
}

/// One validation rule of a part file: the per-row flag of its breach (the message is made by
/// [`row_problem`] once a breach is found).
struct Rule {
    bad: Expr,
}

/// The validation rules (see [`locate`] for the messages): realization ids are the part's
/// declared consecutive range; counts are non-negative and equal their lists' lengths; event
/// times are finite and in [0, t_a]; start instants do not decrease; no nulls.
fn rules(first: u64, horizon: f64, switch_times: bool, nullable: bool) -> Vec<Rule> {
    let mut out = vec![Rule { bad: col("realization").neq(lit(first as i64) + col(ROW).cast(DataType::Int64)).fill_null(lit(true)) }];
    let mut counted = vec![("n_stick", ["stick_start", "stick_duration"].as_slice()), ("n_slip", ["slip_start", "slip_duration"].as_slice())];
    if switch_times {
        counted.push(("n_switches", ["switch_times"].as_slice()));
    }
    // a duration cut at t_a is t_a − start, rounded: a relative 1e-12 of slack
    let top = horizon * (1.0 + 1e-12);
    for (count, cols) in counted {
        for &c in cols {
            let n = col(count).cast(DataType::Int64);
            let len = col(c).list().len().cast(DataType::Int64);
            let fits = col(c).list().min().fill_null(lit(0.0)).gt_eq(lit(0.0)).and(col(c).list().max().fill_null(lit(0.0)).lt_eq(lit(top))).and(col(c).list().sum().is_finite());
            let mut bad = len.neq(n.clone()).or(n.lt(lit(0i64))).fill_null(lit(true)).or(fits.not().fill_null(lit(true)));
            if c.ends_with("_start") || c == "switch_times" {
                bad = bad.or(col(c).list().sort(SortOptions::default()).neq(col(c)).fill_null(lit(false)));
            }
            if nullable {
                bad = bad.or(col(c).list().eval(element().is_null().cast(DataType::Int64)).list().sum().gt(lit(0i64)).fill_null(lit(true)));
            }
            out.push(Rule { bad });
        }
    }
    out.push(Rule { bad: col("last_truncated").is_null() });
    out
}

/// The bin of `x` on the grid of width 2^`exp` (x ≥ 0: the cast truncates, which is the floor).
fn bin_expr(x: Expr, exp: i32) -> Expr {
    (x * lit((-exp as f64).exp2())).cast(DataType::Int64)
}

/// The frame of one part file for the main query (see the module docs).
#[allow(clippy::too_many_arguments)]
fn file_frame(data: &Dataset, file: usize, cell: usize, position: u64, plan: &Plan, pilot: &Pilot, n_rules: &mut usize) -> PolarsResult<LazyFrame> {
    let t_a = data.scenario.run.duration;
    let rules = rules(data.file_starts[file], t_a, data.switch_times, data.nullable);
    *n_rules = rules.len();
    let mut cols = vec![lit(cell as i64).cast(DataType::Int64).alias(CELL), (col("realization") % lit(GROUPS as i64)).cast(DataType::Int64).alias(GROUP)];
    // the convergence bucket: how many checkpoints lie below this realization's read count k
    let k = col(ROW).cast(DataType::Int64) + lit(position as i64 + 1);
    let bucket = plan.checkpoints.iter().fold(lit(0i64), |acc, &c| acc + k.clone().gt(lit(c as i64)).cast(DataType::Int64));
    cols.push(bucket.cast(DataType::Int64).alias(BUCKET));
    for (i, o) in plan.series.iter().enumerate() {
        let x = o.expr(t_a);
        cols.push(x.clone().alias(value(i)));
        cols.extend(terms(x.clone() - lit(pilot.center[i]), &quanta(pilot.bound[i], pilot.rows), i, 4));
        let b = if o.is_count() { x.cast(DataType::Int64) } else { bin_expr(x, pilot.exp[i]) };
        cols.push(b.alias(bin(i)));
        if let Some(censored) = o.censored_expr() {
            cols.push(censored.alias(cut(i)));
        }
    }
    for (p, &(i, j)) in plan.pairs.iter().enumerate() {
        let (ex, ey) = pilot.joint[p];
        cols.push(bin_expr(plan.series[i].expr(t_a), ex).alias(jbin(p, 'x')));
        cols.push(bin_expr(plan.series[j].expr(t_a), ey).alias(jbin(p, 'y')));
    }
    for (f, r) in rules.into_iter().enumerate() {
        cols.push(r.bad.alias(flag(f)));
    }
    Ok(scan(&data.files[file], None, true)?.select(cols))
}

/// The pilot of each cell (module docs).
pub(crate) fn pilots(cells: &[&Dataset], plan: &Plan) -> PolarsResult<Vec<Pilot>> {
    let mut out = Vec::with_capacity(cells.len());
    for data in cells {
        let t_a = data.scenario.run.duration;
        let mut cols = vec![(col("realization") % lit(GROUPS as i64)).cast(DataType::Int64).alias(GROUP)];
        cols.extend(plan.series.iter().enumerate().map(|(i, o)| o.expr(t_a).alias(value(i))));
        // the first realizations of the cell, whatever files they are in (the pilot, and so the
        // results, must not depend on how the dataset is split)
        let files = data.files.iter().map(|f| scan(f, None, false)).collect::<PolarsResult<Vec<_>>>()?;
        let all = concat(files, UnionArgs { maintain_order: true, ..Default::default() })?;
        let df = all.slice(0, PILOT_ROWS as IdxSize).select(cols).collect()?;
        let groups: Vec<i64> = df.column(GROUP)?.i64()?.into_no_null_iter().collect();
        let e0 = sketch::start_exponent(t_a);
        let values = |i: usize| -> PolarsResult<Vec<Option<f64>>> { Ok(df.column(&value(i))?.f64()?.iter().collect()) };
        // the finest sketch exponent of the pilot's values without each group (and of all)
        let finest = |xs: &[Option<f64>], cap: usize| -> i32 {
            (0..=GROUPS as i64)
                .filter_map(|g| {
                    let kept = xs.iter().zip(&groups).filter(|(_, h)| **h != g).filter_map(|(x, _)| *x);
                    let (lo, hi) = kept.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
                    (lo <= hi).then(|| sketch::exponent_for(lo, hi, e0, cap))
                })
                .min()
                .unwrap_or(e0)
        };
        let mut pilot = Pilot { center: Vec::new(), bound: Vec::new(), exp: Vec::new(), joint: Vec::new(), rows: data.rows };
        let mut all = Vec::new();
        for i in 0..plan.series.len() {
            let xs = values(i)?;
            let present: Vec<f64> = xs.iter().filter_map(|x| *x).filter(|x| x.is_finite()).collect();
            let center = if present.is_empty() { 0.0 } else { present.iter().sum::<f64>() / present.len() as f64 };
            // |x − c| ≤ the observable's scale for times, durations and the fraction; for a
            // count, twice the pilot's reach (the scan checks it; see `aggregate`)
            let reach = present.iter().fold(0f64, |r, x| r.max((x - center).abs()));
            pilot.bound.push(if plan.series[i].is_count() { 2.0 * reach + 16.0 } else { 1.01 * super::scale(plan.series[i], t_a) });
            pilot.center.push(center);
            pilot.exp.push(finest(&xs, sketch::CAP_1D));
            all.push(xs);
        }
        for &(i, j) in plan.pairs {
            let both = |a: &[Option<f64>], b: &[Option<f64>]| a.iter().zip(b).map(|(x, y)| x.and(*y).and(*x)).collect::<Vec<_>>();
            pilot.joint.push((finest(&both(&all[i], &all[j]), sketch::CAP_2D), finest(&both(&all[j], &all[i]), sketch::CAP_2D)));
        }
        out.push(pilot);
    }
    Ok(out)
}

/// Fail unless every part file still looks as it did when checked.
fn unchanged(cells: &[&Dataset]) -> PolarsResult<()> {
    for data in cells {
        for (path, stamp) in data.files.iter().zip(&data.file_stamps) {
            if Stamp::of(path).ok().as_ref() != Some(stamp) {
                polars_bail!(ComputeError: "{}: the file changed while it was being analysed (is a simulate still writing here?); run analyze again when it is done", path.display());
            }
        }
    }
    Ok(())
}

/// Run the main query over every cell (module docs); a broken rule is reported by [`locate`].
/// Should a value lie farther from its centre than the pilot's bound of the exact sums (a count
/// beyond twice the pilot's reach), the scan is run once more with the bound the data show.
pub(crate) fn aggregate(cells: &[&Dataset], plan: &Plan, pilots: &[Pilot]) -> PolarsResult<Vec<Aggregates>> {
    let mut pilots = pilots.to_vec();
    loop {
        let out = aggregate_once(cells, plan, &pilots)?;
        let mut again = false;
        for (agg, pilot) in out.iter().zip(pilots.iter_mut()) {
            for (i, groups) in agg.sums.iter().enumerate() {
                let reach = groups.iter().filter(|g| g.n > 0).fold(0f64, |r, g| r.max((g.min - pilot.center[i]).abs()).max((g.max - pilot.center[i]).abs()));
                if reach > pilot.bound[i] {
                    pilot.bound[i] = 1.01 * reach;
                    again = true;
                }
            }
        }
        if !again {
            return Ok(out);
        }
    }
}

fn aggregate_once(cells: &[&Dataset], plan: &Plan, pilots: &[Pilot]) -> PolarsResult<Vec<Aggregates>> {
    unchanged(cells)?;
    let mut frames = Vec::new();
    let mut n_rules = 0;
    for (c, data) in cells.iter().enumerate() {
        let mut position = 0;
        for f in 0..data.files.len() {
            frames.push(file_frame(data, f, c, position, plan, &pilots[c], &mut n_rules)?);
            position += data.file_rows[f];
        }
    }
    let args = UnionArgs { parallel: true, rechunk: false, to_supertypes: false, diagonal: false, strict: true, from_partitioned_ds: false, maintain_order: false };
    let base = concat(frames, args)?;
    let keys = |extra: Vec<Expr>| -> Vec<Expr> { [col(CELL), col(GROUP)].into_iter().chain(extra).collect() };

    // per (cell, group): the power sums, ranges, censored counts, pair ranges and broken rules
    let mut aggs = vec![len().cast(DataType::Int64).alias("__rows")];
    for (i, o) in plan.series.iter().enumerate() {
        aggs.extend([col(value(i)).count().cast(DataType::Int64).alias(format!("n{i}")), col(value(i)).min().alias(format!("lo{i}")), col(value(i)).max().alias(format!("hi{i}"))]);
        for p in 1..=4 {
            aggs.extend(['h', 'l'].map(|part| col(term(i, p, part)).sum().alias(term(i, p, part))));
        }
        if o.censored_expr().is_some() {
            aggs.push(col(cut(i)).cast(DataType::Int64).sum().alias(format!("cut{i}")));
        }
    }
    for (p, &(i, j)) in plan.pairs.iter().enumerate() {
        let both = col(value(i)).is_not_null().and(col(value(j)).is_not_null());
        for (axis, s) in [('x', i), ('y', j)] {
            let v = when(both.clone()).then(col(value(s))).otherwise(lit(NULL).cast(DataType::Float64));
            aggs.push(v.clone().min().alias(format!("p{p}{axis}lo")));
            aggs.push(v.max().alias(format!("p{p}{axis}hi")));
        }
    }
    for f in 0..n_rules {
        aggs.push(col(flag(f)).cast(DataType::Int64).sum().alias(flag(f)));
    }
    let mut plans = vec![base.clone().group_by(keys(vec![])).agg(aggs).logical_plan];
    // per (cell, group, bin): histogram counts
    for i in 0..plan.series.len() {
        plans.push(base.clone().filter(col(bin(i)).is_not_null()).group_by(keys(vec![col(bin(i))])).agg([len().cast(DataType::Int64).alias("__n")]).logical_plan);
    }
    // per (cell, bin x, bin y): joint counts
    for p in 0..plan.pairs.len() {
        let (x, y) = (jbin(p, 'x'), jbin(p, 'y'));
        plans.push(base.clone().filter(col(&x).is_not_null().and(col(&y).is_not_null())).group_by([col(CELL), col(&x), col(&y)]).agg([len().cast(DataType::Int64).alias("__n")]).logical_plan);
    }
    // per (cell, bucket): the convergence sums
    let mut conv = Vec::new();
    for &i in plan.convergence {
        conv.push(col(value(i)).count().cast(DataType::Int64).alias(format!("n{i}")));
        for p in 1..=2 {
            conv.extend(['h', 'l'].map(|part| col(term(i, p, part)).sum().alias(term(i, p, part))));
        }
    }
    if !conv.is_empty() {
        plans.push(base.clone().group_by([col(CELL), col(BUCKET)]).agg(conv).logical_plan);
    }
    let frames = LazyFrame::collect_all_with_engine(plans, Engine::Streaming, OptFlags::default())?;
    unchanged(cells)?;

    let mut out: Vec<Aggregates> = cells
        .iter()
        .map(|_| Aggregates {
            rows: 0,
            sums: vec![vec![Sums { min: f64::INFINITY, max: f64::NEG_INFINITY, ..Default::default() }; GROUPS]; plan.series.len()],
            bins: vec![vec![Vec::new(); GROUPS]; plan.series.len()],
            joint: vec![Vec::new(); plan.pairs.len()],
            joint_range: vec![None; plan.pairs.len()],
            convergence: vec![vec![(0, 0.0, 0.0); plan.checkpoints.len() + 1]; plan.convergence.len()],
        })
        .collect();
    let mut frames = frames.into_iter();

    let df = frames.next().expect("the sums");
    let ints = |name: &str| -> PolarsResult<Vec<i64>> { Ok(df.column(name)?.cast(&DataType::Int64)?.i64()?.iter().map(|v| v.unwrap_or(0)).collect()) };
    let floats = |name: &str| -> PolarsResult<Vec<Option<f64>>> { Ok(df.column(name)?.cast(&DataType::Float64)?.f64()?.iter().collect()) };
    let (cell_of, group_of) = (ints(CELL)?, ints(GROUP)?);
    let broken: Vec<i64> = (0..n_rules).map(|f| Ok(ints(&flag(f))?.iter().sum())).collect::<PolarsResult<_>>()?;
    if broken.iter().any(|&b| b > 0) {
        return Err(locate(cells));
    }
    let rows = ints("__rows")?;
    for r in 0..df.height() {
        out[cell_of[r] as usize].rows += rows[r] as u64;
    }
    for (i, o) in plan.series.iter().enumerate() {
        let (n, lo, hi) = (ints(&format!("n{i}"))?, floats(&format!("lo{i}"))?, floats(&format!("hi{i}"))?);
        let parts = |p: usize, part: char| ints(&term(i, p, part));
        let s: Vec<(Vec<i64>, Vec<i64>)> = (1..=4).map(|p| Ok((parts(p, 'h')?, parts(p, 'l')?))).collect::<PolarsResult<_>>()?;
        let cut = if o.censored_expr().is_some() { ints(&format!("cut{i}"))? } else { vec![0; df.height()] };
        for r in 0..df.height() {
            let c = cell_of[r] as usize;
            let q = quanta(pilots[c].bound[i], pilots[c].rows);
            out[c].sums[i][group_of[r] as usize] = Sums {
                n: n[r] as u64,
                s: [0, 1, 2, 3].map(|p| exact(s[p].0[r], s[p].1[r], q[p])),
                min: lo[r].unwrap_or(f64::INFINITY),
                max: hi[r].unwrap_or(f64::NEG_INFINITY),
                cut: cut[r] as u64,
            };
        }
    }
    for p in 0..plan.pairs.len() {
        let cols: Vec<Vec<Option<f64>>> = ["xlo", "xhi", "ylo", "yhi"].iter().map(|s| floats(&format!("p{p}{s}"))).collect::<PolarsResult<_>>()?;
        for r in 0..df.height() {
            let Some(v) = [0, 1, 2, 3].map(|k| cols[k][r]).into_iter().collect::<Option<Vec<f64>>>() else { continue };
            let range = &mut out[cell_of[r] as usize].joint_range[p];
            *range = Some(match range {
                None => [v[0], v[1], v[2], v[3]],
                Some(a) => [a[0].min(v[0]), a[1].max(v[1]), a[2].min(v[2]), a[3].max(v[3])],
            });
        }
    }
    for i in 0..plan.series.len() {
        let df = frames.next().expect("a histogram");
        let col_i = |name: &str| -> PolarsResult<Vec<i64>> { Ok(df.column(name)?.i64()?.into_no_null_iter().collect()) };
        let (c, g, b, n) = (col_i(CELL)?, col_i(GROUP)?, col_i(&bin(i))?, col_i("__n")?);
        for r in 0..df.height() {
            out[c[r] as usize].bins[i][g[r] as usize].push((b[r], n[r] as u64));
        }
    }
    for p in 0..plan.pairs.len() {
        let df = frames.next().expect("a joint histogram");
        let col_i = |name: &str| -> PolarsResult<Vec<i64>> { Ok(df.column(name)?.i64()?.into_no_null_iter().collect()) };
        let (c, x, y, n) = (col_i(CELL)?, col_i(&jbin(p, 'x'))?, col_i(&jbin(p, 'y'))?, col_i("__n")?);
        for r in 0..df.height() {
            out[c[r] as usize].joint[p].push(((x[r], y[r]), n[r] as u64));
        }
    }
    if !plan.convergence.is_empty() {
        let df = frames.next().expect("the convergence sums");
        let (c, b) = (df.column(CELL)?.i64()?.clone(), df.column(BUCKET)?.cast(&DataType::Int64)?.i64()?.clone());
        let ints = |name: &str| -> PolarsResult<Vec<i64>> { Ok(df.column(name)?.cast(&DataType::Int64)?.i64()?.iter().map(|v| v.unwrap_or(0)).collect()) };
        for (slot, &i) in plan.convergence.iter().enumerate() {
            let n = ints(&format!("n{i}"))?;
            let (h1, l1, h2, l2) = (ints(&term(i, 1, 'h'))?, ints(&term(i, 1, 'l'))?, ints(&term(i, 2, 'h'))?, ints(&term(i, 2, 'l'))?);
            for r in 0..df.height() {
                let (cell, bucket) = (c.get(r).unwrap_or(0) as usize, b.get(r).unwrap_or(0) as usize);
                let q = quanta(pilots[cell].bound[i], pilots[cell].rows);
                out[cell].convergence[slot][bucket] = (n[r] as u64, exact(h1[r], l1[r], q[0]), exact(h2[r], l2[r], q[1]));
            }
        }
    }
    Ok(out)
}

/// The error naming the first file, row and column that break a rule (the main query found one):
/// each file is scanned again for its first offending row, which is checked in Rust for the
/// message ([`row_problem`]).
fn locate(cells: &[&Dataset]) -> PolarsError {
    for data in cells {
        for f in 0..data.files.len() {
            let rules = rules(data.file_starts[f], data.scenario.run.duration, data.switch_times, data.nullable);
            let any = rules.iter().map(|r| r.bad.clone()).reduce(|a, b| a.or(b)).expect("rules");
            let found = scan(&data.files[f], None, true).and_then(|lf| lf.filter(any).limit(1).collect());
            let df = match found {
                Ok(df) if df.height() == 0 => continue,
                Ok(df) => df,
                Err(e) => return polars_err!(ComputeError: "{}: {e}", data.files[f].display()),
            };
            let why = row_problem(&df, data.file_starts[f], data.scenario.run.duration, data.switch_times).unwrap_or_else(|| "a value breaks the dataset's rules".into());
            return polars_err!(ComputeError: "{}: {why}", data.files[f].display());
        }
    }
    polars_err!(ComputeError: "a value breaks the dataset's rules, but no file shows it when read again (did a file change?)")
}

/// The message for the first broken rule of a one-row frame (row `__row` of a part whose first
/// realization is `first`): row, realization, column, and what is wrong.
fn row_problem(df: &DataFrame, first: u64, horizon: f64, switch_times: bool) -> Option<String> {
    let int = |name: &str| df.column(name).ok()?.cast(&DataType::Int64).ok()?.i64().ok()?.get(0);
    let row = int(ROW)? as u64;
    let id = int("realization");
    let at = |c: &str, why: String| Some(format!("row {} (realization {}), column `{c}`: {why}", first + row, id.map_or("null".into(), |i| i.to_string())));
    if id != Some((first + row) as i64) {
        return at("realization", format!("expected realization {} (the part's declared range), found {}", first + row, id.map_or("null".into(), |i| i.to_string())));
    }
    let mut counted = vec![("n_stick", ["stick_start", "stick_duration"].as_slice()), ("n_slip", ["slip_start", "slip_duration"].as_slice())];
    if switch_times {
        counted.push(("n_switches", ["switch_times"].as_slice()));
    }
    for (count, cols) in counted {
        let n = int(count);
        for &c in cols {
            let list = df.column(c).ok()?.list().ok()?.get_as_series(0);
            let Some(list) = list else { return at(c, "a null list (lists are never null; an empty list is [])".into()) };
            let values: Vec<Option<f64>> = list.cast(&DataType::Float64).ok()?.f64().ok()?.iter().collect();
            match n {
                Some(n) if n >= 0 && values.len() as i64 == n => {}
                Some(n) => return at(c, format!("{} values, but `{count}` = {n}", values.len())),
                None => return at(count, "a null count".into()),
            }
            if values.iter().any(Option::is_none) {
                return at(c, "a null element inside a list".into());
            }
            let values: Vec<f64> = values.into_iter().flatten().collect();
            if let Some(x) = values.iter().find(|x| !(**x >= 0.0 && **x <= horizon * (1.0 + 1e-12))) {
                return at(c, format!("value {} (event times and durations lie in [0, t_a = {horizon}] s)", crate::scenario::short(*x)));
            }
            if (c.ends_with("_start") || c == "switch_times") && values.windows(2).any(|w| w[1] < w[0]) {
                return at(c, "values decrease (start instants are in increasing order)".into());
            }
        }
    }
    df.column("last_truncated").ok().filter(|c| c.null_count() > 0).and_then(|_| at("last_truncated", "a null value".into()))
}
