//! The fold of `analyze`'s main pass: every batch of rows polars hands over (the per-realization
//! frame of [`super::query`]: slot, read count, each observable's value, censoring and
//! rule flags, the tails' per-batch counts and extremes) is added into the aggregates in one pass
//! over its columns — each value is read once, and every aggregate it feeds is updated there:
//!
//! - per slot (cell × 20 + jackknife group) and observable: n, the exact integer parts of
//!   Σ(x − c)^p for p = 1..4 ([`super::exact`]), min, max and the censored count;
//! - per observable, slot and bin: the histogram counts on the pilot's dyadic grid (bin
//!   ⌊x·2^−e⌋, exact: scaling by a power of two is exact; a count is its own bin);
//! - per pair, cell and (bin x, bin y): the joint counts;
//! - per convergence observable, cell and bucket: n and the parts of Σ(x − c), Σ(x − c)²;
//! - per tails' sink and cell: the counts per key; per slot the sums of the extremes' columns;
//! - per rule: the rows breaking it; per cell: the rows.
//!
//! Every aggregate is an integer sum, a count or a min/max, so the result does not depend on how
//! polars cuts the rows into batches or in which order they arrive: bit-identical for any thread
//! count, morsel size and shard split.

use polars::prelude::*;
use polars_arrow::array::{Array, BooleanArray, PrimitiveArray};
use rayon::prelude::*;

use super::exact::{quanta, split, Sums};
use super::jackknife::GROUPS;
use super::query::{Aggregates, Pilot, Plan};
use super::tail_counts::{self, HashCounts};

/// Column names of the per-realization frame (built in [`super::query`]).
pub(crate) const SLOT: &str = "__slot";
/// the realization's read count k in its cell (1 for its first realization)
pub(crate) const READ: &str = "__read";
pub(crate) fn value(i: usize) -> String {
    format!("__x{i}")
}
pub(crate) fn cut(i: usize) -> String {
    format!("__c{i}")
}
pub(crate) fn flag(f: usize) -> String {
    format!("__f{f}")
}
pub(crate) fn tail_keys(variable: usize) -> String {
    format!("__tv{variable}")
}
pub(crate) fn extreme(j: usize) -> String {
    format!("__e{j}")
}

/// Bits of a histogram bin in a (slot, bin) key: bins at the pilot exponent are below 2^42
/// (a value at most its scale, whose start exponent leaves 2^41 bins; a count is its own bin).
const KEY_BITS: u32 = 42;

/// The map key of `bin` of slot `slot` (cell × 20 + group).
fn bin_key(slot: usize, bin: i64) -> i64 {
    ((slot as i64) << KEY_BITS) + bin
}

/// What one query folds: the observables it owns (positions in the plan's series) and whether it
/// also does the rest (rows, rules, pairs, convergence, tails).
pub(crate) struct Batch {
    pub owned: Vec<usize>,
    pub extras: bool,
}

/// A cell's constants of one observable: the centre and quanta of its exact sums, and 2^−e of
/// its histogram exponent e (the cell's pilot).
#[derive(Clone, Copy)]
struct Grid {
    center: f64,
    quanta: [(f64, f64); 4],
    scale: f64,
    /// the bins of the dense window: those of [c − B, c + B] (B the pilot's bound), at most
    /// [`WINDOW`]
    window: (i64, i64),
}

/// The most bins of a dense window (per jackknife group).
const WINDOW: i64 = 1 << 14;

/// The histogram counts of one observable: those of one cell at a time in a dense window of
/// bins (nearly every value: the window is the pilot's bound about its centre), with the indices
/// touched so that moving them to the map costs what filling them did; the rest, and the other
/// cells', in the map by (slot << [`KEY_BITS`]) + bin. The dense counters are 16 bits: a
/// window of the paper's T_1 fills 4,096 bins × 20 groups, 160 KiB, which stays in a core's L2
/// cache beside the batches polars decodes (with 64-bit counters, the counter's load was a
/// quarter of the fold's time, 19 % with 32-bit ones); a full counter moves to the map.
struct Bins {
    map: PlHashMap<i64, u64>,
    cell: usize,
    lo: i64,
    width: i64,
    dense: Vec<u16>,
    touched: Vec<u32>,
}

impl Bins {
    fn new() -> Bins {
        Bins { map: Default::default(), cell: usize::MAX, lo: 0, width: 0, dense: Vec::new(), touched: Vec::new() }
    }

    /// Count `bin` of jackknife group `g` of cell `cell` (whose window is `window`).
    #[inline]
    fn add(&mut self, cell: usize, g: usize, bin: i64, window: (i64, i64)) {
        if cell != self.cell {
            self.flush();
            (self.cell, self.lo, self.width) = (cell, window.0, window.1 - window.0);
            self.dense.resize(self.width as usize * GROUPS, 0);
        }
        let offset = bin.wrapping_sub(self.lo);
        if (0..self.width).contains(&offset) {
            let i = offset as usize * GROUPS + g;
            let n = &mut self.dense[i];
            if *n == 0 {
                self.touched.push(i as u32);
            } else if *n == u16::MAX {
                // (its key is then in the touched list twice; the second flush of it adds 0)
                *self.map.entry(bin_key(cell * GROUPS + g, bin)).or_insert(0) += u64::from(u16::MAX);
                *n = 0;
                self.touched.push(i as u32);
            }
            *n += 1;
        } else {
            *self.map.entry(bin_key(cell * GROUPS + g, bin)).or_insert(0) += 1;
        }
    }

    /// Move the dense counts to the map.
    fn flush(&mut self) {
        for &i in &self.touched {
            let (b, g) = (i as usize / GROUPS, i as usize % GROUPS);
            let key = bin_key(self.cell * GROUPS + g, self.lo + b as i64);
            *self.map.entry(key).or_insert(0) += u64::from(std::mem::take(&mut self.dense[i as usize]));
        }
        self.touched.clear();
    }
}

/// One observable's aggregates.
struct Observed {
    /// position in the plan's series
    at: usize,
    /// [cell]
    grid: Vec<Grid>,
    /// [slot]
    sums: Vec<Sums>,
    bins: Bins,
    /// its convergence sums, when it is a convergence observable of this query (folded in the
    /// same pass; the others' are in [`Fold::convergence`])
    running: Option<Running>,
}

/// One pair's joint counts.
struct Pair {
    at: (usize, usize),
    /// [cell]: 2^−e of the joint exponents (x, y)
    scale: Vec<(f64, f64)>,
    /// (cell, bin x, bin y) → count
    counts: PlHashMap<(i64, i64, i64), u64>,
}

/// One convergence observable's sums: [cell][bucket] (of position `slot` in the plan's
/// convergence list).
struct Running {
    at: usize,
    slot: usize,
    grid: Vec<Grid>,
    sums: Vec<Vec<Sums>>,
}

/// The running aggregates of one query (module docs).
pub(crate) struct Fold {
    extras: bool,
    /// the convergence table's checkpoints (realizations read), increasing
    checkpoints: Vec<u64>,
    series: Vec<Observed>,
    rest: Rest,
    tails: Tails,
}

/// What the query that does the extras aggregates beside the observables.
struct Rest {
    pairs: Vec<Pair>,
    /// the convergence observables this query does not own ([`Observed::running`])
    convergence: Vec<Running>,
    /// rows breaking each rule
    rules: Vec<u64>,
    /// [cell]
    rows: Vec<u64>,
    /// [cell][group][column]
    extremes: Vec<Vec<Vec<u64>>>,
}

/// The tails' counts: [sink]: packed key (the cell in it, [`tail_counts`]) → count.
struct Tails {
    sinks: Vec<PlHashMap<i64, u64>>,
    max_index: u32,
}

/// A column of the frame as one array (a batch is rechunked if polars split it), typed by
/// `typed` (`Column::f64`, `i64`, `bool`).
fn one_array<'a, T: PolarsDataType>(df: &'a DataFrame, name: &str, typed: impl Fn(&'a Column) -> PolarsResult<&'a ChunkedArray<T>>) -> PolarsResult<T::Array>
where
    T::Array: Clone,
{
    let ca = typed(df.column(name)?)?.rechunk();
    let one = ca.downcast_iter().next().cloned();
    one.ok_or_else(|| polars_err!(ComputeError: "column {name}: no data"))
}

fn floats(df: &DataFrame, name: &str) -> PolarsResult<PrimitiveArray<f64>> {
    one_array(df, name, Column::f64)
}

fn ints(df: &DataFrame, name: &str) -> PolarsResult<PrimitiveArray<i64>> {
    one_array(df, name, Column::i64)
}

fn flags(df: &DataFrame, name: &str) -> PolarsResult<BooleanArray> {
    one_array(df, name, Column::bool)
}

/// 2^−e.
fn inverse_width(e: i32) -> f64 {
    (-e as f64).exp2()
}

impl Fold {
    /// The empty aggregates of one query: `rules` rules and `extremes` extreme columns.
    pub(crate) fn new(plan: &Plan, pilots: &[Pilot], batch: &Batch, rules: usize, extremes: usize) -> Fold {
        let cells = pilots.len();
        let grid = |i: usize| -> Vec<Grid> {
            pilots
                .iter()
                .map(|p| {
                    let (c, b) = (p.center[i], p.bound[i]);
                    let scale = if plan.series[i].is_count() { 1.0 } else { inverse_width(p.exp[i]) };
                    let lo = ((c - b).max(0.0) * scale).floor();
                    let hi = ((c + b) * scale).floor().clamp(lo, lo + (WINDOW - 1) as f64);
                    Grid { center: c, quanta: quanta(b, p.rows), scale, window: (lo as i64, hi as i64 + 1) }
                })
                .collect()
        };
        let (pairs, convergence): (&[(usize, usize)], &[usize]) = if batch.extras { (plan.pairs, plan.convergence) } else { (&[], &[]) };
        let sinks = if batch.extras && plan.tails.is_some() { tail_counts::SINKS } else { 0 };
        let running = |i: usize| {
            let slot = convergence.iter().position(|&c| c == i)?;
            Some(Running { at: i, slot, grid: grid(i), sums: vec![vec![Sums::default(); plan.checkpoints.len() + 1]; cells] })
        };
        let rest = Rest {
            pairs: pairs
                .iter()
                .enumerate()
                .map(|(p, &at)| Pair {
                    at,
                    scale: pilots.iter().map(|c| (inverse_width(c.joint[p].0), inverse_width(c.joint[p].1))).collect(),
                    counts: Default::default(),
                })
                .collect(),
            convergence: convergence.iter().filter(|i| !batch.owned.contains(i)).filter_map(|&i| running(i)).collect(),
            rules: vec![0; rules],
            rows: vec![0; cells],
            extremes: vec![if extremes > 0 { vec![vec![0; extremes]; GROUPS] } else { Vec::new() }; cells],
        };
        Fold {
            extras: batch.extras,
            checkpoints: plan.checkpoints.to_vec(),
            rest,
            tails: Tails { sinks: vec![PlHashMap::default(); sinks], max_index: plan.tails.map_or(0, |t| t[0].max_index) },
            series: batch
                .owned
                .iter()
                .map(|&i| Observed { at: i, grid: grid(i), sums: vec![Sums::default(); cells * GROUPS], bins: Bins::new(), running: running(i) })
                .collect(),
        }
    }

    /// Add one batch of rows of the per-realization frame: the observables (in parallel), the
    /// rest and the tails' counts at once.
    pub(crate) fn add(&mut self, df: &DataFrame) -> PolarsResult<()> {
        if df.height() == 0 {
            return Ok(());
        }
        let slot = ints(df, SLOT)?;
        let slots = slot.values().as_slice();
        // the convergence bucket of each row: how many checkpoints lie below its read count
        let bucket: Option<Vec<i64>> = match df.column(READ) {
            Ok(_) => Some(ints(df, READ)?.values().iter().map(|&k| self.checkpoints.partition_point(|&c| (c as i64) < k) as i64).collect()),
            Err(_) => None,
        };
        let buckets = bucket.as_deref();
        let (series, rest, tails, extras) = (&mut self.series, &mut self.rest, &mut self.tails, self.extras);
        let (a, (b, c)) = rayon::join(
            || series.par_iter_mut().try_for_each(|s| s.add(df, slots, buckets)),
            || rayon::join(|| if extras { rest.add(df, slots, buckets) } else { Ok(()) }, || tails.add(df)),
        );
        a.and(b).and(c)
    }

    /// How many rows broke each rule.
    pub(crate) fn broken(&self) -> &[u64] {
        &self.rest.rules
    }

    /// Add the folded aggregates to each cell's.
    pub(crate) fn finish(self, out: &mut [Aggregates]) {
        let Fold { extras, series, rest, tails, .. } = self;
        if extras {
            for (agg, (rows, extremes)) in out.iter_mut().zip(rest.rows.iter().zip(rest.extremes)) {
                agg.rows += rows;
                agg.tails.extremes = extremes;
            }
        }
        for (sink, counts) in tails.sinks.into_iter().enumerate() {
            let mut per_cell: Vec<&mut HashCounts> = out.iter_mut().map(|a| &mut a.tails.sinks[sink]).collect();
            tail_counts::add_counts(counts, tails.max_index, &mut per_cell);
        }
        let mut running = Vec::new();
        for mut s in series {
            running.extend(s.running.take());
            s.bins.flush();
            for (slot, sums) in s.sums.iter().enumerate() {
                out[slot / GROUPS].sums[s.at][slot % GROUPS].add(sums);
            }
            for (key, n) in s.bins.map {
                let slot = (key >> KEY_BITS) as usize;
                out[slot / GROUPS].bins[s.at][slot % GROUPS].push((key & ((1 << KEY_BITS) - 1), n));
            }
            for agg in out.iter_mut() {
                agg.bins[s.at].iter_mut().for_each(|b| b.sort_unstable());
            }
        }
        for (p, pair) in rest.pairs.into_iter().enumerate() {
            for ((c, x, y), n) in pair.counts {
                out[c as usize].joint[p].push(((x, y), n));
            }
            for agg in out.iter_mut() {
                agg.joint[p].sort_unstable();
            }
        }
        for run in rest.convergence.into_iter().chain(running) {
            for (c, buckets) in run.sums.into_iter().enumerate() {
                for (b, sums) in buckets.iter().enumerate() {
                    out[c].convergence[run.slot][b].add(sums);
                }
            }
        }
    }
}

impl Rest {
    /// Add one batch: rows, broken rules, joint counts, the other convergence sums, extremes.
    fn add(&mut self, df: &DataFrame, slots: &[i64], buckets: Option<&[i64]>) -> PolarsResult<()> {
        let cell_of = |r: usize| slots[r] as usize / GROUPS;
        for r in 0..df.height() {
            self.rows[cell_of(r)] += 1;
        }
        for (f, broken) in self.rules.iter_mut().enumerate() {
            *broken += count_set(&flags(df, &flag(f))?);
        }
        for p in &mut self.pairs {
            let (x, y) = (floats(df, &value(p.at.0))?, floats(df, &value(p.at.1))?);
            let (xs, ys) = (x.values().as_slice(), y.values().as_slice());
            for r in present(&x).filter(|&r| y.is_valid(r)) {
                let c = cell_of(r);
                let (sx, sy) = p.scale[c];
                *p.counts.entry((c as i64, (xs[r] * sx) as i64, (ys[r] * sy) as i64)).or_insert(0) += 1;
            }
        }
        for run in &mut self.convergence {
            let values = floats(df, &value(run.at))?;
            let buckets = buckets.ok_or_else(|| polars_err!(ComputeError: "no convergence buckets"))?;
            for r in present(&values) {
                run.add(values.value(r), cell_of(r), buckets[r]);
            }
        }
        for j in 0..self.extremes.first().and_then(|e| e.first()).map_or(0, Vec::len) {
            let e = ints(df, &extreme(j))?;
            for r in present(&e) {
                let slot = slots[r] as usize;
                self.extremes[slot / GROUPS][slot % GROUPS][j] += e.value(r) as u64;
            }
        }
        Ok(())
    }
}

impl Tails {
    /// Add one batch's (key, count) pairs of every sink (in its first row: [`tail_counts`]).
    fn add(&mut self, df: &DataFrame) -> PolarsResult<()> {
        for (s, counts) in self.sinks.iter_mut().enumerate() {
            let (v, keys, ns) = tail_counts::sink(s);
            let pairs = df.column(&tail_keys(v))?.struct_()?.clone();
            let (keys, ns) = (pairs.field_by_name(&keys)?, pairs.field_by_name(&ns)?);
            for (k, n) in keys.list()?.downcast_iter().zip(ns.list()?.downcast_iter()) {
                // (the pairs of this batch's rows: the lists' values between their offsets)
                let int = |a: &dyn Array| a.as_any().downcast_ref::<PrimitiveArray<i64>>().map(|a| a.values().clone());
                let (Some(kv), Some(nv)) = (int(k.values().as_ref()), int(n.values().as_ref())) else {
                    polars_bail!(ComputeError: "the tails' counts are not int64 lists");
                };
                let (ko, no) = (k.offsets(), n.offsets());
                let (kr, nr) = (*ko.first() as usize..*ko.last() as usize, *no.first() as usize..*no.last() as usize);
                for (&key, &count) in kv[kr].iter().zip(&nv[nr]) {
                    *counts.entry(key).or_insert(0) += count as u64;
                }
            }
        }
        Ok(())
    }
}

impl Running {
    /// Add value x of a row of cell `cell` in convergence bucket `bucket`.
    #[inline]
    fn add(&mut self, x: f64, cell: usize, bucket: i64) {
        let g = &self.grid[cell];
        self.add_parts(x, cell, bucket, split(x - g.center, &g.quanta));
    }

    /// The same with the parts of x already made ([`split`]); only those of p = 1, 2 are kept.
    #[inline]
    fn add_parts(&mut self, x: f64, cell: usize, bucket: i64, [p1, p2, _, _]: [[i64; 2]; 4]) {
        self.sums[cell][bucket as usize].add_value(x, [p1, p2, [0, 0], [0, 0]]);
    }
}

impl Observed {
    /// Add the rows of one batch (`slots`: each row's slot; `buckets`: its convergence bucket,
    /// in the query that does the convergence table).
    fn add(&mut self, df: &DataFrame, slots: &[i64], buckets: Option<&[i64]>) -> PolarsResult<()> {
        let values = floats(df, &value(self.at))?;
        let xs = values.values().as_slice();
        let buckets = match (&self.running, buckets) {
            (Some(_), None) => polars_bail!(ComputeError: "no convergence buckets"),
            (_, b) => b.unwrap_or(&[]),
        };
        let mut fold = |r: usize| {
            let (x, slot) = (xs[r], slots[r] as usize);
            let (cell, g) = (slot / GROUPS, slot % GROUPS);
            let grid = &self.grid[cell];
            let parts = split(x - grid.center, &grid.quanta);
            self.sums[slot].add_value(x, parts);
            // (the cast truncates: the floor, x ≥ 0; a count is its own bin)
            self.bins.add(cell, g, (x * grid.scale) as i64, grid.window);
            if let Some(run) = &mut self.running {
                // (the same centre and quanta: the parts of p = 1, 2 are those just made)
                run.add_parts(x, cell, buckets[r], parts);
            }
        };
        match values.validity() {
            None => (0..xs.len()).for_each(&mut fold),
            Some(valid) => valid.true_idx_iter().for_each(&mut fold),
        }
        if df.column(&cut(self.at)).is_ok() {
            for r in set_rows(&flags(df, &cut(self.at))?).true_idx_iter() {
                self.sums[slots[r] as usize].cut += 1;
            }
        }
        Ok(())
    }
}

/// The rows of an array that hold a value.
fn present<T: polars_arrow::types::NativeType>(a: &PrimitiveArray<T>) -> impl Iterator<Item = usize> + '_ {
    (0..a.len()).filter(move |&r| a.is_valid(r))
}

/// The rows where a flag is set (null: not set), as a bitmap.
fn set_rows(a: &BooleanArray) -> polars_arrow::bitmap::Bitmap {
    match a.validity() {
        Some(valid) => a.values() & valid,
        None => a.values().clone(),
    }
}

/// How many rows have a flag set (null: not set).
fn count_set(a: &BooleanArray) -> u64 {
    set_rows(a).set_bits() as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_histogram_counts_are_those_of_direct_counting_whatever_window_cell_or_overflow() {
        // keys inside and outside each cell's window (below, beyond, negative), cells that
        // alternate (each switch empties the window into the map) and one key counted past a
        // 16-bit counter: the counts per (slot, bin) are those counted here directly
        let windows = [(10, 50), (0, 8)];
        let mut adds: Vec<(usize, usize, i64)> = (0..5000i64).map(|i| (((i / 7) % 2) as usize, (i % GROUPS as i64) as usize, (i * 37) % 70 - 5)).collect();
        adds.extend(std::iter::repeat_n((0, 3, 12), 70_000));
        let mut bins = Bins::new();
        let mut direct = std::collections::HashMap::<i64, u64>::new();
        for &(cell, g, bin) in &adds {
            bins.add(cell, g, bin, windows[cell]);
            *direct.entry((((cell * GROUPS + g) as i64) << KEY_BITS) + bin).or_insert(0) += 1;
        }
        bins.flush();
        let got: std::collections::HashMap<i64, u64> = bins.map.into_iter().filter(|(_, n)| *n > 0).collect();
        assert_eq!(got, direct);
        assert_eq!(direct[&((3i64 << KEY_BITS) + 12)], 70_000 + adds[..5000].iter().filter(|a| **a == (0, 3, 12)).count() as u64);
    }

    #[test]
    fn rows_with_a_flag_are_counted_nulls_not() {
        let a = BooleanArray::from([Some(true), Some(false), None, Some(true)]);
        assert_eq!(count_set(&a), 2);
        assert_eq!(count_set(&BooleanArray::from_slice([true, true, false])), 2);
    }
}
