//! The fold of `analyze`'s main pass: every batch of rows polars hands over (the per-realization
//! frame of [`super::query`]: slot, convergence bucket, each observable's value, censoring and
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
pub(crate) const BUCKET: &str = "__bucket";
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
/// cells', in the map by (slot << [`KEY_BITS`]) + bin. The dense counters are 32 bits (a
/// window of the paper's T_1 fills 4,096 bins × 20 groups: 320 KiB, which stays in a core's L2
/// cache where 64-bit counters did not — the counter's load was a quarter of the fold's time);
/// they move to the map before any could overflow.
struct Bins {
    map: PlHashMap<i64, u64>,
    cell: usize,
    lo: i64,
    width: i64,
    dense: Vec<u32>,
    touched: Vec<u32>,
    /// counts added to `dense` since it was last emptied
    added: u32,
}

impl Bins {
    fn new() -> Bins {
        Bins { map: Default::default(), cell: usize::MAX, lo: 0, width: 0, dense: Vec::new(), touched: Vec::new(), added: 0 }
    }

    /// Count `bin` of jackknife group `g` of cell `cell` (whose window is `window`).
    #[inline]
    fn add(&mut self, cell: usize, g: usize, bin: i64, window: (i64, i64)) {
        if cell != self.cell || self.added == u32::MAX {
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
            }
            *n += 1;
            self.added += 1;
        } else {
            *self.map.entry((((cell * GROUPS + g) as i64) << KEY_BITS) + bin).or_insert(0) += 1;
        }
    }

    /// Move the dense counts to the map.
    fn flush(&mut self) {
        for &i in &self.touched {
            let (b, g) = (i as usize / GROUPS, i as usize % GROUPS);
            let key = (((self.cell * GROUPS + g) as i64) << KEY_BITS) + self.lo + b as i64;
            *self.map.entry(key).or_insert(0) += u64::from(std::mem::take(&mut self.dense[i as usize]));
        }
        self.touched.clear();
        self.added = 0;
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
}

/// One pair's joint counts.
struct Pair {
    at: (usize, usize),
    /// [cell]: 2^−e of the joint exponents (x, y)
    scale: Vec<(f64, f64)>,
    /// (cell, bin x, bin y) → count
    counts: PlHashMap<(i64, i64, i64), u64>,
}

/// One convergence observable's sums: [cell][bucket].
struct Running {
    at: usize,
    grid: Vec<Grid>,
    sums: Vec<Vec<Sums>>,
}

/// The running aggregates of one query (module docs).
pub(crate) struct Fold {
    extras: bool,
    series: Vec<Observed>,
    pairs: Vec<Pair>,
    convergence: Vec<Running>,
    /// rows breaking each rule
    rules: Vec<u64>,
    /// [cell]
    rows: Vec<u64>,
    /// [cell][group][column]
    extremes: Vec<Vec<Vec<u64>>>,
    /// [sink]: packed key (the cell in it, [`tail_counts`]) → count
    tails: Vec<PlHashMap<i64, u64>>,
    max_index: u32,
}

/// A float column of the frame as one array (a batch is rechunked if polars split it).
fn floats(df: &DataFrame, name: &str) -> PolarsResult<PrimitiveArray<f64>> {
    let ca = df.column(name)?.f64()?.rechunk();
    let one = ca.downcast_iter().next().cloned();
    one.ok_or_else(|| polars_err!(ComputeError: "column {name}: no data"))
}

/// An integer column of the frame as one array.
fn ints(df: &DataFrame, name: &str) -> PolarsResult<PrimitiveArray<i64>> {
    let ca = df.column(name)?.i64()?.rechunk();
    let one = ca.downcast_iter().next().cloned();
    one.ok_or_else(|| polars_err!(ComputeError: "column {name}: no data"))
}

/// A boolean column as one array.
fn flags(df: &DataFrame, name: &str) -> PolarsResult<BooleanArray> {
    let ca = df.column(name)?.bool()?.rechunk();
    let one = ca.downcast_iter().next().cloned();
    one.ok_or_else(|| polars_err!(ComputeError: "column {name}: no data"))
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
        Fold {
            extras: batch.extras,
            series: batch.owned.iter().map(|&i| Observed { at: i, grid: grid(i), sums: vec![Sums::default(); cells * GROUPS], bins: Bins::new() }).collect(),
            pairs: pairs
                .iter()
                .enumerate()
                .map(|(p, &at)| Pair {
                    at,
                    scale: pilots.iter().map(|c| (inverse_width(c.joint[p].0), inverse_width(c.joint[p].1))).collect(),
                    counts: Default::default(),
                })
                .collect(),
            convergence: convergence
                .iter()
                .map(|&i| Running { at: i, grid: grid(i), sums: vec![vec![Sums::default(); plan.checkpoints.len() + 1]; cells] })
                .collect(),
            rules: vec![0; rules],
            rows: vec![0; cells],
            extremes: vec![if extremes > 0 { vec![vec![0; extremes]; GROUPS] } else { Vec::new() }; cells],
            tails: vec![PlHashMap::default(); sinks],
            max_index: plan.tails.map_or(0, |t| t[0].max_index),
        }
    }

    /// Add one batch of rows of the per-realization frame.
    pub(crate) fn add(&mut self, df: &DataFrame) -> PolarsResult<()> {
        if df.height() == 0 {
            return Ok(());
        }
        let slot = ints(df, SLOT)?;
        let slots = slot.values().as_slice();
        let cell_of = |r: usize| slots[r] as usize / GROUPS;
        self.series.par_iter_mut().try_for_each(|s| s.add(df, slots))?;
        if !self.extras {
            return Ok(());
        }
        for r in 0..df.height() {
            self.rows[cell_of(r)] += 1;
        }
        for (f, broken) in self.rules.iter_mut().enumerate() {
            *broken += set(&flags(df, &flag(f))?).count() as u64;
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
        if !self.convergence.is_empty() {
            let bucket = ints(df, BUCKET)?;
            let buckets = bucket.values().as_slice();
            for run in &mut self.convergence {
                let values = floats(df, &value(run.at))?;
                let xs = values.values().as_slice();
                for r in present(&values) {
                    let c = cell_of(r);
                    let g = &run.grid[c];
                    let [p1, p2, _, _] = split(xs[r] - g.center, &g.quanta);
                    run.sums[c][buckets[r] as usize].add_value(xs[r], [p1, p2, [0, 0], [0, 0]]);
                }
            }
        }
        for j in 0..self.extremes.first().and_then(|e| e.first()).map_or(0, Vec::len) {
            let e = ints(df, &extreme(j))?;
            for r in present(&e) {
                let slot = slots[r] as usize;
                self.extremes[slot / GROUPS][slot % GROUPS][j] += e.value(r) as u64;
            }
        }
        for (s, counts) in self.tails.iter_mut().enumerate() {
            let (v, keys, ns) = tail_counts::sink(s);
            let pairs = df.column(&tail_keys(v))?.struct_()?.clone();
            let exploded = |field: &str| -> PolarsResult<Series> {
                let list = pairs.field_by_name(field)?;
                list.explode(ExplodeOptions { empty_as_null: false, keep_nulls: false })
            };
            let (keys, ns) = (exploded(&keys)?, exploded(&ns)?);
            for (k, n) in keys.i64()?.iter().zip(ns.i64()?.iter()) {
                if let (Some(k), Some(n)) = (k, n) {
                    *counts.entry(k).or_insert(0) += n as u64;
                }
            }
        }
        Ok(())
    }

    /// How many rows broke each rule.
    pub(crate) fn broken(&self) -> &[u64] {
        &self.rules
    }

    /// Add the folded aggregates to each cell's.
    pub(crate) fn finish(self, out: &mut [Aggregates]) {
        if self.extras {
            for (agg, (rows, extremes)) in out.iter_mut().zip(self.rows.iter().zip(self.extremes)) {
                agg.rows += rows;
                agg.tails.extremes = extremes;
            }
        }
        for (sink, counts) in self.tails.into_iter().enumerate() {
            let mut per_cell: Vec<&mut HashCounts> = out.iter_mut().map(|a| &mut a.tails.sinks[sink]).collect();
            tail_counts::add_counts(counts, self.max_index, &mut per_cell);
        }
        for mut s in self.series {
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
        for (p, pair) in self.pairs.into_iter().enumerate() {
            for ((c, x, y), n) in pair.counts {
                out[c as usize].joint[p].push(((x, y), n));
            }
            for agg in out.iter_mut() {
                agg.joint[p].sort_unstable();
            }
        }
        for (slot, run) in self.convergence.into_iter().enumerate() {
            for (c, buckets) in run.sums.into_iter().enumerate() {
                for (b, sums) in buckets.iter().enumerate() {
                    out[c].convergence[slot][b].add(sums);
                }
            }
        }
    }
}

impl Observed {
    /// Add the rows of one batch (`slots`: each row's slot).
    fn add(&mut self, df: &DataFrame, slots: &[i64]) -> PolarsResult<()> {
        let values = floats(df, &value(self.at))?;
        let xs = values.values().as_slice();
        let mut fold = |r: usize| {
            let (x, slot) = (xs[r], slots[r] as usize);
            let (cell, g) = (slot / GROUPS, slot % GROUPS);
            let grid = &self.grid[cell];
            self.sums[slot].add_value(x, split(x - grid.center, &grid.quanta));
            // (the cast truncates: the floor, x ≥ 0; a count is its own bin)
            self.bins.add(cell, g, (x * grid.scale) as i64, grid.window);
        };
        match values.validity() {
            None => (0..xs.len()).for_each(&mut fold),
            Some(valid) => valid.true_idx_iter().for_each(&mut fold),
        }
        if let Ok(censored) = df.column(&cut(self.at)) {
            let censored = censored.bool()?;
            for (r, c) in censored.iter().enumerate() {
                if c == Some(true) {
                    self.sums[slots[r] as usize].cut += 1;
                }
            }
        }
        Ok(())
    }
}

/// The rows of an array that hold a value.
fn present<T: polars_arrow::types::NativeType>(a: &PrimitiveArray<T>) -> impl Iterator<Item = usize> + '_ {
    (0..a.len()).filter(move |&r| a.is_valid(r))
}

/// The rows where a flag is set (null: not set).
fn set(a: &BooleanArray) -> impl Iterator<Item = usize> + '_ {
    (0..a.len()).filter(move |&r| a.is_valid(r) && a.value(r))
}
