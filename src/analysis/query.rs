//! The polars queries of `analyze`: every statistic starts as a lazy query over `scan_parquet`
//! of the part files, run on polars' streaming engine; Rust finishes on the small aggregated
//! tables (see [`super`]). polars' Rust API changes between minor versions; it is pinned in
//! Cargo.toml.
//!
//! **One scan, many aggregations.** The part files of every cell (one plain dataset, or the
//! cells of a sweep) are scanned into one frame: per realization its slot (cell × 20 + its
//! jackknife group, realization mod 20), the value of every analysed observable
//! ([`Observable::expr`], the one censoring rule), the integer parts of (x − c)^p about a pilot
//! centre c ([`super::exact`]), its histogram bin, and one flag per validation rule. From that
//! frame, in one streaming pass (the scan is shared by the sinks):
//!
//! - per slot: n, Σ(x − c)^p for p = 1..4, min, max, the censored count of every observable, and
//!   the number of rows breaking each rule;
//! - per (cell, group, bin): counts of every continuous observable on the dyadic grid of width
//!   2^e (bin ⌊x·2^−e⌋, exact: scaling by a power of two is exact), and of every count
//!   observable per value;
//! - per (cell, bin x, bin y): the joint counts of every requested pair;
//! - per (cell, convergence bucket): n, Σ(x − c), Σ(x − c)² of the convergence observables.
//! - with the tails, per key of each of their sinks: the sum of its counts over the batches
//!   (each batch's keys are counted where they are made), and per slot the sums of the
//!   extremes' columns ([`super::tail_counts`]).
//!
//! The pass is made over runs of at most [`CHUNK_ROWS`] realizations and batches of at most
//! [`SERIES_PER_QUERY`] observables, whose integer sums and counts add exactly: polars buffers a
//! shared scan for its slowest sink without a bound, and its planning grows faster than linearly
//! with the aggregations.
//!
//! **The pilot.** The centre c and the exponent e come from a first small query over the first
//! [`PILOT_ROWS`] rows of each cell: c is their mean (the power sums about a centre near the mean
//! lose no digits; the central moments follow exactly, [`Sums::moments`]), the bound of |x − c|
//! of the exact sums is three times their reach (checked on the whole sample), and e is the finest
//! exponent any of the analysis's histograms can need: the smallest, over the pilot rows without
//! each jackknife group, of the sketch exponent of their range ([`super::sketch`]). The whole
//! sample's range (and each leave-one-group-out range) holds that range, so every histogram the
//! analysis draws is on a grid of width 2^E with E ≥ e and is an exact sum of the pilot-grid
//! counts. The pilot decides only how fine the counts are, never what they are.
//!
//! **Validation** is in the same scan: the rules are flags summed per group; only when one is
//! broken does [`locate`] look for the first offending file, row and column, to name them
//! ([`super::rules`]). The power sums are exact integers ([`super::exact`]).

use polars::prelude::*;

use super::exact::{exact_parts, part_of, parts, quanta, term, Sums};
use super::input::{scan, Dataset, Stamp, ROW};
use super::jackknife::GROUPS;
use super::rules::{locate, rules};
use super::sketch;
use super::tail_counts;
use super::tails::{TailCounts, TailPlan};
use crate::observables::Observable;
use crate::progress::Control;

/// Rows of each cell the pilot reads.
pub(crate) const PILOT_ROWS: usize = 16_384;

/// What to aggregate: the observables, the pairs (positions in `series`) and the convergence
/// observables (positions).
pub(crate) struct Plan<'a> {
    pub series: &'a [Observable],
    pub pairs: &'a [(usize, usize)],
    pub convergence: &'a [usize],
    /// the checkpoints of the convergence table (realizations read)
    pub checkpoints: &'a [u64],
    /// what to count for the tails of each cell (None: no tails)
    pub tails: Option<&'a [TailPlan]>,
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
    /// [convergence observable][checkpoint]: the sums of the realizations read after the
    /// previous checkpoint, up to this one (the last entry: up to the last realization; only n
    /// and the powers 1 and 2 are filled)
    pub convergence: Vec<Vec<Sums>>,
    /// what the tails count ([`super::tail_counts`])
    pub tails: TailCounts,
}

impl Aggregates {
    fn new(plan: &Plan) -> Aggregates {
        Aggregates {
            rows: 0,
            sums: vec![vec![Sums::default(); GROUPS]; plan.series.len()],
            bins: vec![vec![Vec::new(); GROUPS]; plan.series.len()],
            joint: vec![Vec::new(); plan.pairs.len()],
            convergence: vec![vec![Sums::default(); plan.checkpoints.len() + 1]; plan.convergence.len()],
            tails: TailCounts { sinks: vec![Default::default(); tail_counts::SINKS], extremes: Vec::new() },
        }
    }
}

/// Realizations per run of the main query. polars' streaming engine buffers, without a bound,
/// the morsels of a scan shared by several aggregations for the slowest of them, so memory
/// would grow with the dataset; runs of at most this many rows, whose integer sums and counts
/// add exactly, keep it bounded.
const CHUNK_ROWS: u64 = 1 << 19;

/// Column names inside the queries.
const CELL: &str = "__cell";
const GROUP: &str = "__group";
const BUCKET: &str = "__bucket";
/// cell × GROUPS + group: one int64 key (one-column keys hash fastest)
const SLOT: &str = "__slot";
/// Bits of a histogram bin in a (slot, bin) key: bins at the pilot exponent are below 2^42
/// (a value at most its scale, whose start exponent leaves 2^41 bins; a count is its own bin).
const KEY_BITS: u32 = 42;
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
fn tail_key(s: usize) -> String {
    format!("__t{s}")
}
fn tail_count(s: usize) -> String {
    format!("__tn{s}")
}
fn tail_keys(variable: usize) -> String {
    format!("__tv{variable}")
}
fn extreme(j: usize) -> String {
    format!("__e{j}")
}

/// The bin of `x` on the grid of width 2^`exp` (x ≥ 0: the cast truncates, which is the floor).
fn bin_expr(x: Expr, exp: i32) -> Expr {
    (x * lit((-exp as f64).exp2())).cast(DataType::Int64)
}

/// The frame of one part file for the main query (see the module docs), in two stages so that
/// each observable's expression is evaluated once per row and the second stage reads its column.
#[allow(clippy::too_many_arguments)]
fn file_frame(
    data: &Dataset,
    file: usize,
    cell: usize,
    (offset, rows): (u64, u64),
    position: u64,
    plan: &Plan,
    pilot: &Pilot,
    batch: &Batch,
    n_rules: &mut usize,
) -> PolarsResult<LazyFrame> {
    let t_a = data.scenario.run.duration;
    let rules = if batch.extras { rules(data.file_starts[file], data) } else { Vec::new() };
    *n_rules = rules.len();
    // the observables whose values this batch needs: its own, and those of the pairs and the
    // convergence table in the batch that does them
    let mut members: Vec<usize> = batch.owned.clone();
    let mut summed: Vec<usize> = batch.owned.clone();
    if batch.extras {
        members.extend(plan.pairs.iter().flat_map(|&(i, j)| [i, j]).chain(plan.convergence.iter().copied()));
        summed.extend(plan.convergence.iter().copied());
    }
    for v in [&mut members, &mut summed] {
        v.sort_unstable();
        v.dedup();
    }
    // 1. per realization: its slot (cell and group), convergence bucket, observables, censoring
    // and rules
    let group = (col(crate::simulation::dataset::columns::REALIZATION) % lit(GROUPS as i64)).cast(DataType::Int64);
    let mut cols = vec![(group + lit((cell * GROUPS) as i64)).alias(SLOT)];
    // the convergence bucket: how many checkpoints lie below this realization's read count k
    let k = col(ROW).cast(DataType::Int64) + lit(position as i64 + 1);
    let bucket = plan.checkpoints.iter().fold(lit(0i64), |acc, &c| acc + k.clone().gt(lit(c as i64)).cast(DataType::Int64));
    cols.push(bucket.cast(DataType::Int64).alias(BUCKET));
    for &i in &members {
        cols.push(plan.series[i].expr(t_a).alias(value(i)));
    }
    for &i in &batch.owned {
        if let Some(censored) = plan.series[i].censored_expr() {
            cols.push(censored.alias(cut(i)));
        }
    }
    for (f, r) in rules.into_iter().enumerate() {
        cols.push(r.bad.alias(flag(f)));
    }
    // the tails' (key, count) lists of each batch and extremes (module docs of `tail_counts`)
    if let (true, Some(tails)) = (batch.extras, plan.tails) {
        let keys = tail_counts::keys(&tails[cell], cell, tails.len());
        cols.extend(keys.into_iter().enumerate().map(|(v, k)| k.alias(tail_keys(v))));
        if tails[cell].tails_state {
            cols.extend(tail_counts::extreme_columns(&tails[cell]).into_iter().enumerate().map(|(j, e)| e.alias(extreme(j))));
        }
    }
    let frame = scan(&data.files[file], None, true)?.slice(offset as i64, rows as IdxSize).select(cols);
    // 2. histogram bins and the integer parts of the power sums
    let mut next = Vec::new();
    for &i in &batch.owned {
        let x = col(value(i));
        let b = if plan.series[i].is_count() { x.cast(DataType::Int64) } else { bin_expr(x, pilot.exp[i]) };
        next.push((col(SLOT) * lit(1i64 << KEY_BITS) + b).alias(bin(i)));
    }
    for &i in &summed {
        next.push(exact_parts(col(value(i)), pilot.center[i], quanta(pilot.bound[i], pilot.rows)).alias(parts(i)));
    }
    for (p, &(i, j)) in plan.pairs.iter().enumerate().filter(|_| batch.extras) {
        let (ex, ey) = pilot.joint[p];
        next.push(bin_expr(col(value(i)), ex).alias(jbin(p, 'x')));
        next.push(bin_expr(col(value(j)), ey).alias(jbin(p, 'y')));
    }
    for s in (0..tail_counts::SINKS).filter(|_| batch.extras && plan.tails.is_some()) {
        let (v, keys, counts) = tail_counts::sink(s);
        next.push(col(tail_keys(v)).struct_().field_by_name(&keys).alias(tail_key(s)));
        next.push(col(tail_keys(v)).struct_().field_by_name(&counts).alias(tail_count(s)));
    }
    Ok(frame.with_columns(next))
}

/// The pilot of each cell (module docs).
pub(crate) fn pilots(cells: &[&Dataset], plan: &Plan) -> PolarsResult<Vec<Pilot>> {
    let mut out = Vec::with_capacity(cells.len());
    for data in cells {
        let t_a = data.scenario.run.duration;
        let mut cols = vec![(col(crate::simulation::dataset::columns::REALIZATION) % lit(GROUPS as i64)).cast(DataType::Int64).alias(GROUP)];
        cols.extend(plan.series.iter().enumerate().map(|(i, o)| o.expr(t_a).alias(value(i))));
        // the first realizations of the cell, whatever files they are in (the pilot, and so the
        // results, must not depend on how the dataset is split)
        let all = super::input::scan_all(data, true)?;
        let df = all.slice(0, PILOT_ROWS as IdxSize).select(cols).collect_with_engine(Engine::Streaming)?.unwrap_single();
        let groups: Vec<i64> = df.column(GROUP)?.i64()?.into_no_null_iter().collect();
        let values = |i: usize| -> PolarsResult<Vec<Option<f64>>> { Ok(df.column(&value(i))?.f64()?.iter().collect()) };
        // the finest sketch exponent of the pilot's values without each group (and of all): the
        // range without group g from the groups' own ranges (min and max combine exactly)
        let finest = |xs: &[Option<f64>], o: Observable, cap: usize| -> i32 {
            let e0 = sketch::start_exponent(o.scale(t_a));
            let mut ranges = [(f64::INFINITY, f64::NEG_INFINITY); GROUPS];
            for (x, &h) in xs.iter().zip(&groups) {
                if let Some(x) = *x {
                    let r = &mut ranges[h.rem_euclid(GROUPS as i64) as usize];
                    *r = (r.0.min(x), r.1.max(x));
                }
            }
            (0..=GROUPS)
                .filter_map(|g| {
                    let kept = ranges.iter().enumerate().filter(|(h, _)| *h != g).map(|(_, r)| *r);
                    let (lo, hi) = kept.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(r.0), b.max(r.1)));
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
            // the bound of |x − c| for the exact sums: three times the pilot's reach (the
            // integer parts' step is a fixed fraction of the bound, so a bound near the data's
            // spread, not the scale t_a, keeps small values' digits); the scan checks it and runs
            // again with the reach it found should a value lie beyond (see `aggregate`)
            let reach = present.iter().fold(0f64, |r, x| r.max((x - center).abs()));
            pilot.bound.push(3.0 * reach + plan.series[i].scale(t_a) * 2f64.powi(-40));
            pilot.center.push(center);
            pilot.exp.push(finest(&xs, plan.series[i], sketch::CAP_1D));
            all.push(xs);
        }
        for &(i, j) in plan.pairs {
            let both = |a: &[Option<f64>], b: &[Option<f64>]| a.iter().zip(b).map(|(x, y)| x.and(*y).and(*x)).collect::<Vec<_>>();
            pilot
                .joint
                .push((finest(&both(&all[i], &all[j]), plan.series[i], sketch::CAP_2D), finest(&both(&all[j], &all[i]), plan.series[j], sketch::CAP_2D)));
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
/// `ctl` is told the realizations aggregated; when it is cancelled, the scan stops with an error
/// between runs (the caller asks `ctl` what it was).
pub(crate) fn aggregate(cells: &[&Dataset], plan: &Plan, pilots: &mut [Pilot], ctl: Control) -> PolarsResult<Vec<Aggregates>> {
    let rows = cells.iter().map(|d| d.rows).sum();
    loop {
        ctl.progress.start("analyze", rows);
        let out = aggregate_once(cells, plan, pilots, ctl)?;
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

fn aggregate_once(cells: &[&Dataset], plan: &Plan, pilots: &[Pilot], ctl: Control) -> PolarsResult<Vec<Aggregates>> {
    unchanged(cells)?;
    // runs of (cell, file, first row, rows, read position of the file's row 0)
    let mut runs: Vec<Vec<(usize, usize, u64, u64, u64)>> = vec![Vec::new()];
    let mut filled = 0;
    for (c, data) in cells.iter().enumerate() {
        let mut position = 0;
        for f in 0..data.files.len() {
            let rows = data.file_rows[f];
            let mut offset = 0;
            while offset < rows {
                if filled == CHUNK_ROWS {
                    runs.push(Vec::new());
                    filled = 0;
                }
                let take = (CHUNK_ROWS - filled).min(rows - offset);
                runs.last_mut().expect("a run").push((c, f, offset, take, position));
                (offset, filled) = (offset + take, filled + take);
            }
            position += rows;
        }
    }
    let mut out: Vec<Aggregates> = cells.iter().map(|_| Aggregates::new(plan)).collect();
    for run in runs.iter().filter(|r| !r.is_empty()) {
        if ctl.check().is_err() {
            polars_bail!(ComputeError: "interrupted");
        }
        aggregate_run(cells, plan, pilots, run, &mut out)?;
        ctl.progress.advance(run.iter().map(|r| r.3).sum());
    }
    unchanged(cells)?;
    Ok(out)
}

/// Observables per query: polars' planning grows faster than linearly with the number of
/// aggregations (`--max-index 200`, 804 observables in one query: 30 s and 5 GB on 3,000
/// realizations), so more observables are split over queries over the same rows.
const SERIES_PER_QUERY: usize = 64;

/// The observables one query aggregates, and whether it also does the rest: row counts,
/// validation, pairs and the convergence table.
struct Batch {
    owned: Vec<usize>,
    extras: bool,
}

/// Run the main query over one run of rows, adding what it aggregates to `out`.
fn aggregate_run(cells: &[&Dataset], plan: &Plan, pilots: &[Pilot], run: &[(usize, usize, u64, u64, u64)], out: &mut [Aggregates]) -> PolarsResult<()> {
    let n = plan.series.len();
    for (b, start) in (0..n.max(1)).step_by(SERIES_PER_QUERY).enumerate() {
        let batch = Batch { owned: (start..(start + SERIES_PER_QUERY).min(n)).collect(), extras: b == 0 };
        aggregate_batch(cells, plan, pilots, run, &batch, out)?;
    }
    Ok(())
}

/// One query of [`aggregate_run`].
fn aggregate_batch(
    cells: &[&Dataset],
    plan: &Plan,
    pilots: &[Pilot],
    run: &[(usize, usize, u64, u64, u64)],
    batch: &Batch,
    out: &mut [Aggregates],
) -> PolarsResult<()> {
    let mut frames = Vec::new();
    let mut n_rules = 0;
    for &(c, f, offset, rows, position) in run {
        frames.push(file_frame(cells[c], f, c, (offset, rows), position, plan, &pilots[c], batch, &mut n_rules)?);
    }
    let (pairs, convergence): (&[(usize, usize)], &[usize]) = if batch.extras { (plan.pairs, plan.convergence) } else { (&[], &[]) };
    let args =
        UnionArgs { parallel: true, rechunk: false, to_supertypes: false, diagonal: false, strict: true, from_partitioned_ds: false, maintain_order: false };
    let base = concat(frames, args)?;
    // per slot (cell and group): the power sums, ranges, censored counts and broken rules
    let mut aggs = vec![len().cast(DataType::Int64).alias("__rows")];
    for &i in &batch.owned {
        let o = plan.series[i];
        aggs.extend([
            col(value(i)).count().cast(DataType::Int64).alias(format!("n{i}")),
            col(value(i)).min().alias(format!("lo{i}")),
            col(value(i)).max().alias(format!("hi{i}")),
        ]);
        for p in 1..=4 {
            aggs.extend(['h', 'l'].map(|part| part_of(&parts(i), p, part).sum().alias(term(i, p, part))));
        }
        if o.censored_expr().is_some() {
            aggs.push(col(cut(i)).cast(DataType::Int64).sum().alias(format!("cut{i}")));
        }
    }
    for f in 0..n_rules {
        aggs.push(col(flag(f)).cast(DataType::Int64).sum().alias(flag(f)));
    }
    // (the cells of one scan are of one kind: all with the tails' state, or none)
    let tails = plan.tails.filter(|_| batch.extras);
    let extremes = tails.map_or(0, |t| if t[0].tails_state { tail_counts::extreme_columns(&t[0]).len() } else { 0 });
    for j in 0..extremes {
        aggs.push(col(extreme(j)).cast(DataType::Int64).sum().alias(extreme(j)));
    }
    let mut plans = vec![base.clone().group_by([col(SLOT)]).agg(aggs).logical_plan];
    // per (slot, bin): histogram counts, on one int64 key (one-column keys hash fastest); each
    // branch projects first: a group_by or filter on the wide shared frame copies every column
    let count = || [len().cast(DataType::Int64).alias("__n")];
    for &i in &batch.owned {
        plans.push(base.clone().select([col(bin(i))]).group_by([col(bin(i))]).agg(count()).logical_plan);
    }
    // per (slot, bin x, bin y): joint counts
    for p in 0..pairs.len() {
        let (x, y) = (jbin(p, 'x'), jbin(p, 'y'));
        plans.push(base.clone().select([col(SLOT), col(&x), col(&y)]).group_by([col(SLOT), col(&x), col(&y)]).agg(count()).logical_plan);
    }
    // per (cell, bucket): the convergence sums
    let mut conv = Vec::new();
    for &i in convergence {
        conv.push(col(value(i)).count().cast(DataType::Int64).alias(format!("n{i}")));
        for p in 1..=2 {
            conv.extend(['h', 'l'].map(|part| part_of(&parts(i), p, part).sum().alias(term(i, p, part))));
        }
    }
    if !conv.is_empty() {
        let cell = (col(SLOT) / lit(GROUPS as f64)).cast(DataType::Int64).alias(CELL);
        plans.push(base.clone().group_by([cell, col(BUCKET)]).agg(conv).logical_plan);
    }
    // per key of each tails' sink: the sum of its counts over the batches
    for s in (0..tail_counts::SINKS).filter(|_| tails.is_some()) {
        let (key, n) = (tail_key(s), tail_count(s));
        let exploded = base
            .clone()
            .select([col(&key), col(&n)])
            .explode(by_name([key.as_str(), n.as_str()], true, false), ExplodeOptions { empty_as_null: false, keep_nulls: false });
        plans.push(exploded.group_by([col(&key)]).agg([col(&n).sum().alias("__n")]).logical_plan);
    }
    let frames = LazyFrame::collect_all_with_engine(plans, Engine::Streaming, OptFlags::default())?;
    let mut frames = frames.into_iter();

    let df = frames.next().expect("the sums");
    let ints = |name: &str| int_column(&df, name);
    let floats = |name: &str| float_column(&df, name);
    let slot = ints(SLOT)?;
    let (cell_of, group_of): (Vec<i64>, Vec<i64>) = slot.iter().map(|s| (s / GROUPS as i64, s % GROUPS as i64)).unzip();
    let broken: Vec<i64> = (0..n_rules).map(|f| Ok(ints(&flag(f))?.iter().sum())).collect::<PolarsResult<_>>()?;
    if broken.iter().any(|&b| b > 0) {
        return Err(locate(cells));
    }
    let rows = ints("__rows")?;
    for r in (0..df.height()).filter(|_| batch.extras) {
        out[cell_of[r] as usize].rows += rows[r] as u64;
    }
    for j in 0..extremes {
        let e = ints(&extreme(j))?;
        for r in 0..df.height() {
            let per_group = &mut out[cell_of[r] as usize].tails.extremes;
            per_group.resize_with(GROUPS, || vec![0; extremes]);
            per_group[group_of[r] as usize][j] += e[r] as u64;
        }
    }
    for &i in &batch.owned {
        let o = plan.series[i];
        let (n, lo, hi) = (ints(&format!("n{i}"))?, floats(&format!("lo{i}"))?, floats(&format!("hi{i}"))?);
        let parts = |p: usize, part: char| ints(&term(i, p, part));
        let s: Vec<[Vec<i64>; 2]> = (1..=4).map(|p| Ok([parts(p, 'h')?, parts(p, 'l')?])).collect::<PolarsResult<_>>()?;
        let cut = if o.censored_expr().is_some() { ints(&format!("cut{i}"))? } else { vec![0; df.height()] };
        for r in 0..df.height() {
            let sums = Sums {
                n: n[r] as u64,
                parts: [0, 1, 2, 3].map(|p| [s[p][0][r], s[p][1][r]]),
                min: lo[r].unwrap_or(f64::INFINITY),
                max: hi[r].unwrap_or(f64::NEG_INFINITY),
                cut: cut[r] as u64,
            };
            out[cell_of[r] as usize].sums[i][group_of[r] as usize].add(&sums);
        }
    }
    for &i in &batch.owned {
        let df = frames.next().expect("a histogram");
        let (key, n) = (key_column(&df, &bin(i))?, key_column(&df, "__n")?);
        for r in 0..df.height() {
            // (realizations without a value: the null key)
            let (Some(key), Some(n)) = (key[r], n[r]) else { continue };
            let (slot, b) = ((key >> KEY_BITS) as usize, key & ((1 << KEY_BITS) - 1));
            // (the rules keep every value's bin below 2^KEY_BITS; a key outside is a bug, not data)
            let agg = out.get_mut(slot / GROUPS).ok_or_else(|| polars_err!(ComputeError: "histogram key {key} outside the cells"))?;
            agg.bins[i][slot % GROUPS].push((b, n as u64));
        }
    }
    for p in 0..pairs.len() {
        let df = frames.next().expect("a joint histogram");
        let (s, x, y, n) = (key_column(&df, SLOT)?, key_column(&df, &jbin(p, 'x'))?, key_column(&df, &jbin(p, 'y'))?, key_column(&df, "__n")?);
        for r in 0..df.height() {
            // (realizations without both values: a null bin)
            let (Some(s), Some(x), Some(y), Some(n)) = (s[r], x[r], y[r], n[r]) else { continue };
            out[s as usize / GROUPS].joint[p].push(((x, y), n as u64));
        }
    }
    // counts of the same bin from several runs are added up, so the tables stay as small as
    // the histograms, whatever the number of runs
    for agg in out.iter_mut() {
        for &i in &batch.owned {
            agg.bins[i].iter_mut().for_each(compact);
        }
        agg.joint.iter_mut().take(pairs.len()).for_each(compact);
    }
    if !convergence.is_empty() {
        let df = frames.next().expect("the convergence sums");
        let ints = |name: &str| int_column(&df, name);
        let (c, b) = (ints(CELL)?, ints(BUCKET)?);
        for (slot, &i) in convergence.iter().enumerate() {
            let n = ints(&format!("n{i}"))?;
            let (h1, l1, h2, l2) = (ints(&term(i, 1, 'h'))?, ints(&term(i, 1, 'l'))?, ints(&term(i, 2, 'h'))?, ints(&term(i, 2, 'l'))?);
            for r in 0..df.height() {
                let sums = Sums { n: n[r] as u64, parts: [[h1[r], l1[r]], [h2[r], l2[r]], [0, 0], [0, 0]], ..Default::default() };
                out[c[r] as usize].convergence[slot][b[r] as usize].add(&sums);
            }
        }
    }
    for s in (0..tail_counts::SINKS).filter(|_| tails.is_some()) {
        let df = frames.next().expect("a tails count");
        let mut per_cell: Vec<&mut tail_counts::HashCounts> = out.iter_mut().map(|a| &mut a.tails.sinks[s]).collect();
        tail_counts::add_counts(&df, &tail_key(s), "__n", plan.tails.map_or(0, |t| t[0].max_index), &mut per_cell)?;
    }
    Ok(())
}

/// A column of an aggregated table as integers (null as 0: a sum over no rows).
fn int_column(df: &DataFrame, name: &str) -> PolarsResult<Vec<i64>> {
    Ok(df.column(name)?.cast(&DataType::Int64)?.i64()?.iter().map(|v| v.unwrap_or(0)).collect())
}

/// A column of an aggregated table as floats (null: no value, as a min or max over no rows).
fn float_column(df: &DataFrame, name: &str) -> PolarsResult<Vec<Option<f64>>> {
    Ok(df.column(name)?.cast(&DataType::Float64)?.f64()?.iter().collect())
}

/// A key or count column of a group_by's output (null: the group of rows without a value).
fn key_column(df: &DataFrame, name: &str) -> PolarsResult<Vec<Option<i64>>> {
    Ok(df.column(name)?.i64()?.iter().collect())
}

/// Sort counts by key and add up those of the same key.
fn compact<K: Ord + Copy>(counts: &mut Vec<(K, u64)>) {
    counts.sort_unstable_by_key(|(k, _)| *k);
    counts.dedup_by(|next, kept| {
        let same = next.0 == kept.0;
        if same {
            kept.1 += next.1;
        }
        same
    });
}
