//! Tails: survival curves of stick and slip durations with the interval cut at t_a treated as
//! censored, an exact-in-t conditional estimator of the stick tail, and the extremes.
//!
//! Three polars queries over `scan_parquet` of the part files (streaming): the durations
//! exploded to one row per interval with its index k and whether it is the censored one, counted
//! per (jackknife group, k, time cell, censored); the stick entries (x, belt velocity) with their
//! holding times, counted per (group, k, belt state, cell); and per group the exceedances of the
//! longest stick and the severity and the stick ends by breakaway. Rust finishes on those counts.
//!
//! **Time cells.** Durations are counted on cells of width ρ = t_a 2^-16 (0.15 ms at t_a = 10 s)
//! split at the user's times τ (`--tail-times`): d is in cell φ(d) = ⌊d/ρ⌋ + #{τ ≤ d}, so every
//! cell edge and every τ is a boundary, and a curve read at a grid point or at a τ counts exactly
//! the durations below it (reading it at ⌊t/ρ⌋ρ instead biased P(D > t) up by f(t)·ρ: 0.5 % at
//! t = 0.5 s in a 100 s window). Ties within a cell follow the usual convention: events before
//! censorings.
//!
//! **Kaplan–Meier (product limit).** With n_c intervals at risk (duration ≥ the cell) and e_c of
//! them ending in cell c, `S(t) = Π_{cells before t} (1 − e_c / n_c)`; a censored interval (the
//! one running at t_a, whose length is only a lower bound) leaves the risk set without an event.
//! It estimates P(D > t) for the duration D of a stick begun in [0, t_a], however long it lasts,
//! when a stick's duration does not depend on when it began; near t = 0 the law of the entry
//! state still changes with time, so in a short window (where early sticks are the only ones
//! observed long) it can differ slightly from the conditional estimator below, which has no such
//! assumption.
//! The **naive** curve drops the censored intervals and takes the empirical survival of the rest:
//! it is biased low wherever long intervals are the ones the horizon cuts.
//!
//! **Conditional (exact in t).** While stuck, the mass moves with the belt, so a stick entered at x
//! on belt velocity v_s ends at the earlier of the belt's next change — exponential with the rate
//! λ_s of leaving state s, whatever happened before (a Poisson flip process is memoryless) — and
//! the breakaway after the holding time d_s(x) = `PerUnitMass::stick_duration(x, v_s)` (closed form;
//! ∞ without a spring; damping and μ_s ≥ μ_k only move the holding limit). Hence
//!
//! ```text
//!     P(D > t | x, s) = exp(−λ_s t) · 1{t < d_s(x)},     P̂(D > t) = (1/N) Σ_i exp(−λ_{s_i} t) 1{t < d_{s_i}(x_i)}
//! ```
//!
//! averaged over the N observed stick entries: unbiased for P(D > t) (the entries are the same
//! population the product limit estimates), with no noise from the belt's clock, so it resolves
//! probabilities far below 1/N. It needs the belt to be a Poisson flip process with known rates
//! (the symmetric and the telegraph belts) and fixed parameters; it is refused, with the reason,
//! otherwise (drawn parameters change d_s per realization), and for datasets without the entry
//! state (schema v1, v2).
//!
//! **Intervals (95 %).** Realizations are independent but the sticks of one realization are not,
//! so every interval is the delete-a-group jackknife over the 20 realization groups
//! ([`super::jackknife`]), which keeps that dependence: on the complementary log-log scale
//! ln(−ln S) for the product-limit and naive curves (bands inside (0, 1)), on the log scale for
//! the conditional estimator and the exceedances. Where the estimate is 0 or 1 no band is given.
//! The jackknife needs counts per group; on the fine cells those are a hash table of ~10^6 keys
//! at 10^6 realizations (most of the tails' cost), so the estimate is taken on the fine cells with
//! the groups pooled and the leave-one-group-out curves on cells `COARSE` times wider: the
//! spread of those curves (the jackknife's variance) does not depend on reading each up to one
//! coarse cell early, and the interval is centred on the fine estimate.

use polars::prelude::*;

use std::collections::HashMap;

use super::input::{scan, scan_all, Dataset};
use super::jackknife::{self, Interval, GROUPS};
use crate::physics::PerUnitMass;
use crate::scenario::ProcessName;
use crate::simulation::belt::Process;
use crate::simulation::dataset::columns as name;

/// Time cells per t_a (module docs).
const CELLS_PER_WINDOW: f64 = 65_536.0;
/// Time cells per cell of the leave-one-group-out curves (module docs).
const COARSE: i64 = 32;
/// The times `reproduce` asks of the paper scene's tails [s]: up to its longest sticks (≈ 2.4 s,
/// the holding time from the far end of the stick region).
pub const PAPER_TAIL_TIMES: [f64; 5] = [0.5, 1.0, 1.5, 2.0, 2.4];

/// Points of each curve between 0 and its largest duration.
pub const CURVE_POINTS: usize = 200;

/// What the user asks of the tails.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TailOptions {
    /// t [s] at which every curve is also evaluated, and the thresholds T of P(longest stick > T)
    pub times: Vec<f64>,
    /// thresholds of P(severity > s)
    pub severity: Vec<f64>,
}

/// One survival curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// `D` or `H`
    pub variable: &'static str,
    /// k, or None pooled over every interval
    pub index: Option<u32>,
    /// `kaplan_meier`, `naive` or `conditional`
    pub method: &'static str,
    /// intervals (stick entries for `conditional`) the curve is estimated from, and how many of
    /// them are censored
    pub n: u64,
    /// of those, the censored ones (0 for `conditional`)
    pub censored: u64,
    /// (t, P(duration > t), 95 % interval)
    pub points: Vec<(f64, f64, Option<Interval>)>,
}

/// A probability or a fraction with its interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Exceedance {
    /// `longest_stick`, `severity` (P(value > threshold)) or `breakaway_fraction` (the share of
    /// sticks that end by breakaway, threshold None)
    pub statistic: &'static str,
    /// s or T of P(statistic > threshold); None for `breakaway_fraction`
    pub threshold: Option<f64>,
    /// the probability or the fraction
    pub value: f64,
    /// its 95 % jackknife interval (None where the estimate is 0 or 1)
    pub interval: Option<Interval>,
    /// realizations (sticks for the breakaway fraction) it is estimated from
    pub n: u64,
}

/// Everything the tails analysis computes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tails {
    /// survival curves of D and H, per index and pooled, by each method
    pub curves: Vec<Curve>,
    /// P(longest stick > T), P(severity > s) and the breakaway fraction
    pub exceedances: Vec<Exceedance>,
    /// why the conditional estimator was not computed (None: it was)
    pub conditional_refused: Option<String>,
}

impl Tails {
    /// What `analyze` prints of the tails: pooled P(D > t) at each of `times` by the product
    /// limit and the conditional estimator, then every exceedance, with their 95 % intervals.
    pub fn lines(&self, times: &[f64]) -> Vec<String> {
        let band = |i: Option<Interval>| i.map_or(String::new(), |(lo, hi)| format!(" [{lo:.3e}, {hi:.3e}]"));
        let at = |method: &str, time: f64| {
            let c = self.curves.iter().find(|c| c.method == method && c.variable == "D" && c.index.is_none())?;
            c.points.iter().find(|p| p.0 == time).map(|p| format!("{:.4e}{}", p.1, band(p.2)))
        };
        let mut out: Vec<String> = times
            .iter()
            .map(|&time| {
                let (km, cond) = (at("kaplan_meier", time).unwrap_or_else(|| "–".into()), at("conditional", time).unwrap_or_else(|| "–".into()));
                format!("P(D > {time} s): Kaplan-Meier {km}; conditional {cond}")
            })
            .collect();
        out.extend(self.exceedances.iter().map(|e| match e.threshold {
            Some(x) => format!("P({} > {x}) = {:.4e}{} ({} realizations)", e.statistic, e.value, band(e.interval), e.n),
            None => format!("{} = {:.4}{} ({} sticks)", e.statistic, e.value, band(e.interval), e.n),
        }));
        out
    }
}

/// Counts per (group, index, cell, flag) as the queries return them.
type Counts = Vec<(usize, u32, i64, bool, u64)>;

const G: &str = "__g";

/// One frame of every part file of `data` (any order: the counts do not depend on it).
fn frame(data: &Dataset) -> PolarsResult<LazyFrame> {
    scan_all(data, false)
}

/// Rows per run of the tails' pass: the sinks of one `collect_all` share its scan, and polars
/// buffers a shared scan for its slowest sink without a bound (10^7 realizations in one run:
/// 13 GB), so the pass is made over runs of at most this many realizations, whose counts add.
const RUN_ROWS: u64 = 1 << 19;

/// The runs of the pass: (file, first row, rows), at most [`RUN_ROWS`] rows each.
fn runs(data: &Dataset) -> Vec<(usize, u64, u64)> {
    let mut out = Vec::new();
    for (f, &rows) in data.file_rows.iter().enumerate() {
        let mut offset = 0;
        while offset < rows {
            let take = RUN_ROWS.min(rows - offset);
            out.push((f, offset, take));
            offset += take;
        }
    }
    out
}

fn group() -> Expr {
    (col(name::REALIZATION) % lit(GROUPS as i64)).cast(DataType::Int64).alias(G)
}

/// The one int64 key of a counted interval or entry (a group-by on one integer column is a flat
/// hash table; on four it encodes rows as bytes): key = ((cell·(K+1) + k)·2 + flag)·GROUPS + g,
/// with K = `max_index` + 1, k clamped to K (the indices past the curves per k, kept for the
/// pooled curve) and cell ≥ 0 (< 2^40 with k ≤ 1001); decoded by [`counts`].
fn pack(max_index: u32, cell: i64, k: i64, flag: bool, g: i64) -> i64 {
    let top = i64::from(max_index) + 1;
    ((cell * (top + 1) + k.min(top)) * 2 + i64::from(flag)) * GROUPS as i64 + g
}

/// The jackknife group of a realization.
fn group_of(realization: i64) -> i64 {
    realization % GROUPS as i64
}

/// A list<int64> beside the lists `lists` (of equal lengths, as validated): for element j of a
/// row, `key(the lists' j-th values, k = j + 1, the row's values of `rows`)`. One pass per row,
/// so that polars explodes one integer list instead of several lists and the columns of an
/// arithmetic expression per step. A row with a null input gets a null list (no key); a null
/// element, no key.
fn element_keys<F>(lists: Vec<&'static str>, rows: Vec<Expr>, key: F) -> Expr
where
    F: Fn(&[f64], i64, &[i64]) -> i64 + Send + Sync + 'static,
{
    use polars_arrow::array::{Array, ListArray, PrimitiveArray};
    use polars_arrow::datatypes::ArrowDataType;
    let n_lists = lists.len();
    let mut inputs: Vec<Expr> = lists[1..].iter().map(|l| col(*l)).collect();
    inputs.extend(rows);
    col(lists[0])
        .map_many(
            move |c: &mut [Column]| {
                let height = c[0].len();
                let name = c[0].name().clone();
                let ls: Vec<ListChunked> = c[..n_lists].iter().map(|c| Ok(c.list()?.rechunk().into_owned())).collect::<PolarsResult<_>>()?;
                let rs: Vec<Int64Chunked> =
                    c[n_lists..].iter().map(|c| Ok(c.cast(&DataType::Int64)?.i64()?.rechunk().into_owned())).collect::<PolarsResult<_>>()?;
                let dtype = ListArray::<i64>::default_datatype(ArrowDataType::Int64);
                let (Some(arrs), Some(ints)) = (
                    ls.iter().map(|l| l.downcast_iter().next()).collect::<Option<Vec<&ListArray<i64>>>>(),
                    rs.iter().map(|r| r.downcast_iter().next()).collect::<Option<Vec<&PrimitiveArray<i64>>>>(),
                ) else {
                    return Ok(ListChunked::full_null_with_dtype(name, height, &DataType::Int64).into_column());
                };
                let vals: Vec<&PrimitiveArray<f64>> = arrs
                    .iter()
                    .map(|a| a.values().as_any().downcast_ref::<PrimitiveArray<f64>>())
                    .collect::<Option<_>>()
                    .ok_or_else(|| polars_err!(ComputeError: "{name}: a list of floats was expected"))?;
                let offs: Vec<&[i64]> = arrs.iter().map(|a| a.offsets().as_slice()).collect();
                let slices: Vec<&[f64]> = vals.iter().map(|v| v.values().as_slice()).collect();
                let dense = vals.iter().all(|v| v.null_count() == 0);
                let mut keys: Vec<i64> = Vec::with_capacity((offs[0][height] - offs[0][0]) as usize);
                let mut offsets: Vec<i64> = Vec::with_capacity(height + 1);
                offsets.push(0);
                let mut valid = polars_arrow::bitmap::MutableBitmap::with_capacity(height);
                let (mut elements, mut row) = (vec![0.0; n_lists], vec![0i64; ints.len()]);
                for r in 0..height {
                    let mut ok = arrs.iter().all(|a| a.is_valid(r));
                    for (x, a) in row.iter_mut().zip(&ints) {
                        match a.get(r) {
                            Some(v) => *x = v,
                            None => ok = false,
                        }
                    }
                    if ok {
                        // (the lists have equal lengths in a validated dataset)
                        let len = offs.iter().map(|o| o[r + 1] - o[r]).min().unwrap_or(0) as usize;
                        let starts: Vec<usize> = offs.iter().map(|o| o[r] as usize).collect();
                        for j in 0..len {
                            if !dense && vals.iter().zip(&starts).any(|(v, s)| !v.is_valid(s + j)) {
                                continue;
                            }
                            for ((e, x), s) in elements.iter_mut().zip(&slices).zip(&starts) {
                                *e = x[s + j];
                            }
                            keys.push(key(&elements, j as i64 + 1, &row));
                        }
                    }
                    offsets.push(keys.len() as i64);
                    valid.push(ok);
                }
                let offsets = polars_arrow::offset::Offsets::<i64>::try_from(offsets)?.into();
                let out = ListArray::<i64>::new(dtype, offsets, PrimitiveArray::from_vec(keys).boxed(), valid.into());
                Ok(ListChunked::from_chunk_iter(name, [out]).into_column())
            },
            &inputs,
            |_, f| Ok(Field::new(f[0].name().clone(), DataType::List(Box::new(DataType::Int64)))),
        )
        .alias(KEY)
}

const KEY: &str = "__key";

/// The plan counting the keys of `keys` (a list per row, [`element_keys`]), one sink of the
/// tails' pass.
fn count_plan(src: LazyFrame, keys: Expr) -> DslPlan {
    src.select([keys])
        .explode(by_name([KEY], true, false), ExplodeOptions { empty_as_null: false, keep_nulls: false })
        .group_by([col(KEY)])
        .agg([len().cast(DataType::Int64).alias("n")])
        .logical_plan
}

/// Counts per packed key ([`pack`]), decoded.
fn counts(df: &DataFrame, max_index: u32) -> PolarsResult<Counts> {
    let ks = i64::from(max_index) + 2;
    let key = df.column(KEY)?.cast(&DataType::Int64)?;
    let n = df.column("n")?.cast(&DataType::Int64)?;
    let decode = |key: i64| {
        let (g, rest) = (key % GROUPS as i64, key / GROUPS as i64);
        let (flag, rest) = (rest % 2 == 1, rest / 2);
        (g as usize, (rest % ks) as u32, rest / ks, flag)
    };
    Ok(key
        .i64()?
        .iter()
        .zip(n.i64()?.iter())
        .filter_map(|(key, n)| {
            let (g, k, c, f) = decode(key?);
            Some((g, k, c, f, n? as u64))
        })
        .collect())
}

/// The keys of the stick (`stick`) or slip durations on the time cells of width `width` split at
/// `times` ([`cell`]): flag = the interval is the censored one (the one rule of
/// `observables::last_cut`: the last interval cut at t_a), g = 0 when `pooled`.
fn duration_keys(stick: bool, max_index: u32, width: f64, times: Vec<f64>, pooled: bool) -> Expr {
    let (list, count) = if stick { (name::STICK_DURATION, name::N_STICK) } else { (name::SLIP_DURATION, name::N_SLIP) };
    let rows = vec![col(name::REALIZATION), col(count), crate::observables::last_cut(stick)];
    element_keys(vec![list], rows, move |d, k, row| {
        let g = if pooled { 0 } else { group_of(row[0]) };
        pack(max_index, cell(d[0], width, &times), k, row[2] != 0 && k == row[1], g)
    })
}

/// The time cell of a duration d ≥ 0: φ(d) = ⌊d/width⌋ + #{τ ∈ `times` : τ ≤ d}, the cells of
/// width `width` split at the user's times τ (sorted, distinct), so that a curve is exact at
/// each τ as at each cell edge (module docs).
fn cell(d: f64, width: f64, times: &[f64]) -> i64 {
    let uniform = if d > 0.0 { (d / width) as i64 } else { 0 };
    uniform + times.iter().filter(|&&t| d >= t).count() as i64
}

/// The evaluation points of a curve on the cells of `cell` (`width` = `COARSE`^`coarse` ρ): the
/// grid's (t, ⌊t/ρ⌋) mapped to (t, φ(t)).
fn on_cells(grid: &[(f64, i64)], times: &[f64], coarse: bool) -> Vec<(f64, i64)> {
    let step = if coarse { COARSE } else { 1 };
    grid.iter().map(|&(t, c)| (t, c / step + times.iter().filter(|&&x| x <= t).count() as i64)).collect()
}

/// The keys of the stick entries (position x, belt velocity v: `v_f` forward, −`v_r` reverse):
/// cell = the bin of the holding time d_s(x) on the evaluation times `ts` (increasing), how many
/// of them lie below it, so that the entry is held past `ts[j]` exactly when its bin exceeds j;
/// flag = the belt state is forward.
fn entry_keys(p: PerUnitMass, (v_f, v_r): (f64, f64), max_index: u32, ts: Vec<f64>) -> Expr {
    element_keys(vec![name::STICK_ENTRY_POSITION, name::STICK_ENTRY_VELOCITY], vec![col(name::REALIZATION)], move |e, k, row| {
        let (x, v) = (e[0], e[1]);
        let d = p.stick_duration(x, if v > 0.0 { v_f } else { -v_r });
        pack(max_index, ts.partition_point(|&t| t < d) as i64, k, v > 0.0, group_of(row[0]))
    })
}
/// Per group: realizations, sticks, breakaways, and the exceedance counts of each threshold.
fn extreme_plan(src: LazyFrame, opts: &TailOptions) -> DslPlan {
    let mut aggs = vec![
        len().cast(DataType::Int64).alias("__rows"),
        col(name::N_STICK).cast(DataType::Int64).sum().alias("__sticks"),
        col("__breakaways").sum().alias("__b"),
    ];
    for (i, t) in opts.times.iter().enumerate() {
        aggs.push(col(name::LONGEST_STICK).gt(lit(*t)).cast(DataType::Int64).sum().alias(format!("__l{i}")));
    }
    for (i, s) in opts.severity.iter().enumerate() {
        aggs.push(col(name::SEVERITY).gt(lit(*s)).cast(DataType::Int64).sum().alias(format!("__s{i}")));
    }
    src.select([group(), col(name::N_STICK), col(name::LONGEST_STICK), col(name::SEVERITY), crate::observables::breakaways().alias("__breakaways")])
        .group_by([col(G)])
        .agg(aggs)
        .logical_plan
}

/// The counts of [`extreme_plan`] as [group][column].
fn extreme_counts(df: &DataFrame) -> PolarsResult<Vec<Vec<u64>>> {
    let mut out = vec![vec![0u64; df.width() - 1]; GROUPS];
    let g = df.column(G)?.cast(&DataType::Int64)?;
    for (j, c) in df.columns().iter().skip(1).enumerate() {
        let c = c.cast(&DataType::Int64)?;
        for (gi, v) in g.i64()?.iter().zip(c.i64()?.iter()) {
            if let (Some(gi), Some(v)) = (gi, v) {
                out[gi as usize][j] = v as u64;
            }
        }
    }
    Ok(out)
}

/// The longest stick of the dataset [s] (0 without sticks).
fn longest(data: &Dataset) -> PolarsResult<f64> {
    let df = frame(data)?.select([col(name::LONGEST_STICK).max()]).collect_with_engine(Engine::Streaming)?.unwrap_single();
    Ok(df.column(name::LONGEST_STICK)?.f64()?.get(0).unwrap_or(0.0))
}

/// The scene of the conditional estimator with its belt's flip rates (λ forward, λ reverse) and
/// speeds (v_f, v_r), or why it does not hold for this dataset.
fn conditional_scene(data: &Dataset) -> Result<(crate::simulation::keys::Scene, BeltRates), String> {
    if !data.tails_state {
        return Err("the dataset has no stick entry state (schema v1 or v2): simulate it again with this version".into());
    }
    let name = data.scenario.process_name();
    if !matches!(name, ProcessName::Symmetric | ProcessName::Telegraph) {
        return Err(format!("the belt is \"{}\", not a two-state flip process (symmetric or telegraph)", name.as_str()));
    }
    let scene = data.scenario.scene().map_err(|e| format!("its scene cannot be rebuilt: {e}"))?;
    if !scene.random.is_empty() {
        return Err("parameters are drawn per realization, so the holding time d_s(x) differs between realizations".into());
    }
    let rates = match &scene.belt.process {
        Process::Symmetric(s) => ((s.switch_rate, s.switch_rate), (s.speed, s.speed)),
        Process::Telegraph(t) => ((t.forward_rate, t.reverse_rate), (t.forward_speed, t.reverse_speed)),
        other => return Err(format!("the belt is \"{}\", not a two-state flip process", other.name())),
    };
    Ok((scene, rates))
}

/// The flip rates (λ forward, λ reverse) and speeds (v_f, v_r) of a two-state belt.
type BeltRates = ((f64, f64), (f64, f64));

/// The tails of one dataset (module docs): one streaming pass over the part files feeding every
/// count, then the curves from the counts.
pub fn tails(data: &Dataset, max_index: u32, opts: &TailOptions) -> PolarsResult<Tails> {
    let t_a = data.scenario.run.duration;
    let rho = t_a / CELLS_PER_WINDOW;
    let scene = conditional_scene(data);
    let mut out = Tails { conditional_refused: scene.as_ref().err().cloned(), ..Tails::default() };
    let mut times: Vec<f64> = opts.times.iter().copied().filter(|t| t.is_finite() && *t > 0.0).collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    // the entries are binned on the D curve's times, so those are fixed before the pass
    let entry_grid = match &scene {
        Ok(_) => Some(grid((longest(data)? / rho) as i64 + 1, rho, &times)),
        Err(_) => None,
    };
    // per run, the sinks in order: for sticks then slips the fine and the coarse counts (and for
    // sticks the entries), then the extremes; their counts summed over the runs
    let mut sums: Vec<HashMap<(usize, u32, i64, bool), u64>> = Vec::new();
    let mut extremes: Vec<Vec<u64>> = Vec::new();
    for (f, offset, rows) in runs(data) {
        let src = scan(&data.files[f], None, false)?.slice(offset as i64, rows as IdxSize);
        let mut plans = Vec::new();
        for stick in [true, false] {
            let entries = stick && entry_grid.is_some();
            // the estimate on fine cells (groups pooled), the leave-one-group-out curves on coarse ones
            plans.push(count_plan(src.clone(), duration_keys(stick, max_index, rho, times.clone(), true)));
            plans.push(count_plan(src.clone(), duration_keys(stick, max_index, rho * COARSE as f64, times.clone(), false)));
            if let (true, Ok((scene, (_, speeds))), Some(grid)) = (entries, &scene, &entry_grid) {
                let keys = entry_keys(scene.params.per_unit_mass(), *speeds, max_index, grid.iter().map(|g| g.0).collect());
                plans.push(count_plan(src.clone(), keys));
            }
        }
        let counted = plans.len();
        if data.tails_state {
            plans.push(extreme_plan(src, opts));
        }
        let frames = LazyFrame::collect_all_with_engine(plans, Engine::Streaming, OptFlags::default())?;
        sums.resize_with(counted, HashMap::new);
        for (sum, df) in sums.iter_mut().zip(&frames) {
            for (g, k, c, flag, n) in counts(df, max_index)? {
                *sum.entry((g, k, c, flag)).or_insert(0) += n;
            }
        }
        if let Some(df) = frames.get(counted) {
            let e = extreme_counts(df)?;
            extremes.resize_with(e.len(), Vec::new);
            for (acc, row) in extremes.iter_mut().zip(e) {
                acc.resize(row.len(), 0);
                acc.iter_mut().zip(row).for_each(|(a, x)| *a += x);
            }
        }
    }
    // (a dataset without rows runs no query: every count is empty)
    sums.resize_with(4 + usize::from(entry_grid.is_some()), HashMap::new);
    let mut sinks = sums.into_iter().map(|m| m.into_iter().map(|((g, k, c, flag), n)| (g, k, c, flag, n)).collect::<Counts>());
    let mut next = || sinks.next().ok_or_else(|| polars_err!(ComputeError: "a tails query returned nothing"));
    for (stick, variable) in [(true, "D"), (false, "H")] {
        let (fine, coarse) = (next()?, next()?);
        let grid = match (stick, &entry_grid) {
            (true, Some(g)) => g.clone(),
            _ => grid(fine.iter().map(|r| r.2).max().unwrap_or(0) + 1, rho, &times),
        };
        let (fine_grid, coarse_grid) = (on_cells(&grid, &times, false), on_cells(&grid, &times, true));
        for index in indices(max_index) {
            let of_k =
                |rows: &Counts, censored: bool| -> Counts { rows.iter().filter(|r| index.is_none_or(|k| r.1 == k) && (censored || !r.3)).copied().collect() };
            let (fine_k, coarse_k) = (of_k(&fine, true), of_k(&coarse, true));
            if fine_k.is_empty() {
                continue;
            }
            for (method, censored) in [("kaplan_meier", true), ("naive", false)] {
                let (f, c) = if censored { (fine_k.clone(), coarse_k.clone()) } else { (of_k(&fine_k, false), of_k(&coarse_k, false)) };
                let n = f.iter().map(|r| r.4).sum();
                let n_censored = f.iter().filter(|r| r.3).map(|r| r.4).sum();
                let points = curve((&f, &fine_grid), (&c, &coarse_grid), product_limit, CLOGLOG);
                out.curves.push(Curve { variable, index, method, n, censored: n_censored, points });
            }
        }
        if let (true, Some(grid), Ok((_, (rates, _)))) = (stick, &entry_grid, &scene) {
            let e = next()?;
            // held past grid[j].t exactly when the bin exceeds j (`holding_bin`)
            let bins: Vec<(f64, i64)> = grid.iter().enumerate().map(|(j, g)| (g.0, j as i64 + 1)).collect();
            for index in indices(max_index) {
                let kept: Counts = e.iter().filter(|r| index.is_none_or(|k| r.1 == k)).copied().collect();
                if kept.is_empty() {
                    continue;
                }
                let n = kept.iter().map(|r| r.4).sum();
                let estimator = move |cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)]| conditional(cells, counts, at, *rates);
                let points = curve((&kept, &bins), (&kept, &bins), estimator, LN);
                out.curves.push(Curve { variable, index, method: "conditional", n, censored: 0, points });
            }
        }
    }
    if data.tails_state {
        let per_group = if extremes.is_empty() { vec![vec![0; 3 + opts.times.len() + opts.severity.len()]; GROUPS] } else { extremes };
        let total = |j: usize, g: Option<usize>| -> u64 { per_group.iter().enumerate().filter(|(h, _)| Some(*h) != g).map(|(_, r)| r[j]).sum() };
        let ratio = |num: usize, den: usize, g: Option<usize>| -> Option<f64> { (total(den, g) > 0).then(|| total(num, g) as f64 / total(den, g) as f64) };
        let mut push = |statistic: &'static str, threshold: Option<f64>, num: usize, den: usize| {
            let Some(value) = ratio(num, den, None) else { return };
            let loo: Vec<Option<f64>> = (0..GROUPS).map(|g| ratio(num, den, Some(g))).collect();
            out.exceedances.push(Exceedance { statistic, threshold, value, interval: transformed(value, &loo, LN), n: total(den, None) });
        };
        push("breakaway_fraction", None, 2, 1);
        for (i, t) in opts.times.iter().enumerate() {
            push("longest_stick", Some(*t), 3 + i, 0);
        }
        for (i, s) in opts.severity.iter().enumerate() {
            push("severity", Some(*s), 3 + opts.times.len() + i, 0);
        }
    }
    Ok(out)
}

/// None (pooled), then k = 1..=max_index.
fn indices(max_index: u32) -> impl Iterator<Item = Option<u32>> {
    std::iter::once(None).chain((1..=max_index).map(Some))
}

/// The evaluation points: `CURVE_POINTS` cells evenly up to `top` cells, and the user's times
/// (t, cell ⌊t/ρ⌋), in increasing t.
fn grid(top: i64, rho: f64, times: &[f64]) -> Vec<(f64, i64)> {
    let mut g: Vec<(f64, i64)> = (0..=CURVE_POINTS as i64).map(|j| j * top / CURVE_POINTS as i64).map(|c| (c as f64 * rho, c)).collect();
    g.extend(times.iter().map(|&t| (t, (t / rho).floor() as i64)));
    g.sort_by(|a, b| a.0.total_cmp(&b.0));
    g.dedup();
    g
}

/// Counts of (group, cell, flag) rows on one sorted axis of cells: `[count without the flag,
/// with it]` per cell, in total and per group (so that each leave-one-group-out sample is the
/// total minus one group, read in one pass).
struct Axis {
    cells: Vec<i64>,
    total: Vec<[u64; 2]>,
    groups: Vec<Vec<[u64; 2]>>,
}

impl Axis {
    fn new(rows: &[(usize, i64, bool, u64)]) -> Axis {
        let mut cells: Vec<i64> = rows.iter().map(|r| r.1).collect();
        cells.sort_unstable();
        cells.dedup();
        let mut groups = vec![vec![[0u64; 2]; cells.len()]; GROUPS];
        for &(g, c, flag, n) in rows {
            let i = cells.binary_search(&c).expect("every cell is on the axis");
            groups[g][i][flag as usize] += n;
        }
        let total = (0..cells.len()).map(|i| groups.iter().fold([0, 0], |a, g| [a[0] + g[i][0], a[1] + g[i][1]])).collect();
        Axis { cells, total, groups }
    }

    /// The counts without group `g` (all with None).
    fn without(&self, g: Option<usize>) -> Vec<[u64; 2]> {
        match g {
            None => self.total.clone(),
            Some(g) => self.total.iter().zip(&self.groups[g]).map(|(t, x)| [t[0] - x[0], t[1] - x[1]]).collect(),
        }
    }
}

/// A curve with its jackknife band on the scale `scale` (and its inverse): the estimate from
/// `full` (rows and the grid's (t, cell) on their cells), the leave-one-group-out values from
/// `loo` (on their own, possibly coarser, cells); `estimate` maps an axis' cells, their counts
/// and the evaluation points to the curve's values.
fn curve(
    full: (&Counts, &[(f64, i64)]),
    loo: (&Counts, &[(f64, i64)]),
    estimate: impl Fn(&[i64], &[[u64; 2]], &[(f64, i64)]) -> Vec<f64>,
    scale: (fn(f64) -> Option<f64>, fn(f64) -> f64),
) -> Vec<(f64, f64, Option<Interval>)> {
    let axis = |rows: &Counts| Axis::new(&rows.iter().map(|r| (r.0, r.2, r.3, r.4)).collect::<Vec<_>>());
    let (whole, parts) = (axis(full.0), axis(loo.0));
    let value = estimate(&whole.cells, &whole.without(None), full.1);
    let loo: Vec<Vec<f64>> = (0..GROUPS).map(|g| estimate(&parts.cells, &parts.without(Some(g)), loo.1)).collect();
    full.1
        .iter()
        .enumerate()
        .map(|(j, &(t, _))| {
            let column: Vec<Option<f64>> = loo.iter().map(|l| Some(l[j])).collect();
            (t, value[j], transformed(value[j], &column, scale))
        })
        .collect()
}

/// The jackknife interval of `value` on the scale `(to, back)`.
fn transformed(value: f64, loo: &[Option<f64>], (to, back): (fn(f64) -> Option<f64>, fn(f64) -> f64)) -> Option<Interval> {
    jackknife::transformed(Some(value), loo, to, back)
}

/// ln(−ln S) and back, for S in (0, 1).
const CLOGLOG: (fn(f64) -> Option<f64>, fn(f64) -> f64) = (|s| (s > 0.0 && s < 1.0).then(|| (-s.ln()).ln()), |y| (-y.exp()).exp());
/// ln p and back, for p > 0.
const LN: (fn(f64) -> Option<f64>, fn(f64) -> f64) = (|p| (p > 0.0).then(|| p.ln()), f64::exp);

/// The product limit at the grid's cells `at` (increasing) from the sorted `cells` and their
/// counts [events, censored] (module docs): S just after the events of the cells below each.
fn product_limit(cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)]) -> Vec<f64> {
    let mut at_risk: u64 = counts.iter().map(|c| c[0] + c[1]).sum();
    let (mut s, mut i) = (1.0, 0);
    at.iter()
        .map(|&(_, t)| {
            while i < cells.len() && cells[i] < t {
                let [events, cut] = counts[i];
                if at_risk > 0 {
                    s *= 1.0 - events as f64 / at_risk as f64;
                }
                at_risk -= events + cut;
                i += 1;
            }
            s
        })
        .collect()
}

/// The conditional estimator at the grid's (t, bin) `at` from the sorted holding-time bins
/// `cells` and their counts [reverse state, forward state]: (1/N) Σ_s exp(−λ_s t) #{entries in s
/// held past t}, an entry counting as held past t when its bin is at least the one given with t
/// (`holding_bin`: both the exponential and the indicator exact at t).
fn conditional(cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)], (rate_f, rate_r): (f64, f64)) -> Vec<f64> {
    // suffix sums: entries held at or past each cell, per state
    let mut held = vec![[0u64; 2]; cells.len() + 1];
    for i in (0..cells.len()).rev() {
        held[i] = [held[i + 1][0] + counts[i][0], held[i + 1][1] + counts[i][1]];
    }
    let n = held[0][0] + held[0][1];
    at.iter()
        .map(|&(t, c)| {
            if n == 0 {
                return 0.0;
            }
            let [r, f] = held[cells.partition_point(|&x| x < c)];
            ((-rate_f * t).exp() * f as f64 + (-rate_r * t).exp() * r as f64) / n as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_limit_matches_a_hand_computation() {
        // cells 1, 2 (censored), 3, 3, 5: S after cell 1 = 4/5, after 3 = 4/5 · (1 − 2/3)
        let (cells, counts) = ([1, 2, 3, 5], [[1, 0], [0, 1], [2, 0], [1, 0]]);
        let grid = |cells: &[i64]| cells.iter().map(|&c| (c as f64, c)).collect::<Vec<_>>();
        let s = product_limit(&cells, &counts, &grid(&[0, 1, 2, 3, 4, 6]));
        let expect = [1.0, 1.0, 0.8, 0.8, 0.8 * (1.0 - 2.0 / 3.0), 0.0];
        for (a, b) in s.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{s:?}");
        }
        // without censoring it is the empirical survival
        assert_eq!(product_limit(&[1, 4], &[[2, 0], [3, 0]], &grid(&[1, 2, 5])), [1.0, 0.6, 0.0]);
    }

    #[test]
    fn conditional_is_the_mean_of_the_per_entry_survivals() {
        // two entries held to cell 10 (forward, λ = 1), one to cell 3 (reverse, λ = 2); ρ = 0.1
        let s = conditional(&[3, 10], &[[1, 0], [0, 2]], &[(0.0, 0), (0.2, 2), (0.5, 5)], (1.0, 2.0));
        assert!((s[0] - 1.0).abs() < 1e-15);
        assert!((s[1] - (2.0 * (-0.2f64).exp() + (-0.4f64).exp()) / 3.0).abs() < 1e-15);
        assert!((s[2] - 2.0 * (-0.5f64).exp() / 3.0).abs() < 1e-15);
    }

    #[test]
    fn leave_one_group_out_counts_are_the_total_minus_the_group() {
        let rows = [(0, 5, false, 2), (1, 5, true, 1), (0, 7, false, 4)];
        let axis = Axis::new(&rows);
        assert_eq!(axis.cells, [5, 7]);
        assert_eq!(axis.without(None), [[2, 1], [4, 0]]);
        assert_eq!(axis.without(Some(0)), [[0, 1], [0, 0]]);
    }
}
