//! What the analysis' main pass counts for the tails ([`super::tails`]): integer keys — one per
//! stick or slip (its time cell, index k, whether it is the censored one and its jackknife
//! group), one per stick entry (the bin of its holding time and its belt state) — counted per
//! key over each batch of realizations polars hands over (a partial aggregate, in dense arrays:
//! [`element_counts`]), whose (key, count) lists the fold ([`super::fold`]) sums per key over
//! the batches; and the per-realization columns of the extremes that it sums per jackknife
//! group. The tails are thus counted in the same scan as the moments and histograms (the lists
//! are decoded once).
//!
//! Why a partial aggregate: 10^6 paper realizations have 8.3·10^7 keys, while a batch of 131,072
//! realizations has only ~5·10^4 distinct keys per sink (2.8·10^6 pairs in all), and the keys
//! are made on polars' threads, batch by batch, in parallel.

use polars::prelude::*;

use super::jackknife::GROUPS;
use crate::physics::PerUnitMass;
use crate::simulation::dataset::columns as name;

/// Time cells per t_a ([`super::tails`]' module docs).
pub(crate) const CELLS_PER_WINDOW: f64 = 65_536.0;
/// Time cells per cell of the leave-one-group-out curves ([`super::tails`]' module docs).
pub(crate) const COARSE: i64 = 32;

/// What the user asks of the tails.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TailOptions {
    /// t [s] at which every curve is also evaluated, and the thresholds T of P(longest stick > T)
    pub times: Vec<f64>,
    /// thresholds of P(severity > s)
    pub severity: Vec<f64>,
}

/// Counts per (group, index, cell, flag) as the queries return them.
pub(crate) type Counts = Vec<(usize, u32, i64, bool, u64)>;

/// The flip rates (λ forward, λ reverse) and speeds (v_f, v_r) of a two-state belt.
pub(crate) type BeltRates = ((f64, f64), (f64, f64));

/// What the main pass counts for the tails of one cell, fixed before it (the tails' module docs;
/// the keys and columns are this file's; built by `TailPlan::new` in [`super::tails`]).
pub(crate) struct TailPlan {
    pub max_index: u32,
    /// the width ρ of the time cells [s]
    pub rho: f64,
    /// the user's times: positive, sorted, distinct
    pub times: Vec<f64>,
    /// the scene of the conditional estimator, or why it is refused
    pub scene: Result<(crate::simulation::keys::Scene, BeltRates), String>,
    /// the D curve's evaluation points, on which the entries are binned (with the scene)
    pub entry_grid: Option<Vec<(f64, i64)>>,
    /// whether the dataset has the tails' state (schema v3): then the extremes are counted
    pub tails_state: bool,
    pub opts: TailOptions,
}

/// Count sinks per cell, in this order: D on fine cells (groups pooled), D on coarse cells (per
/// group), D's entries (none where the conditional estimator is refused), H fine, H coarse.
pub(crate) const SINKS: usize = 5;

/// The struct columns of one part of cell `cell` (of `cells` in the scan), one per variable
/// (D, H), whose fields are the counted keys of the sinks (see [`sink`]): every stick's or slip's
/// keys made in one pass over its lists and counted per batch ([`element_counts`]).
pub(crate) fn keys(plan: &TailPlan, cell: usize, cells: usize) -> [Expr; 2] {
    let (max_index, rho, at) = (plan.max_index, plan.rho, (cell, cells));
    let durations = |stick: bool| {
        let (list, count) = if stick { (name::STICK_DURATION, name::N_STICK) } else { (name::SLIP_DURATION, name::N_SLIP) };
        (list, vec![col(name::REALIZATION), col(count), crate::observables::last_cut(stick)])
    };
    // the time cells a duration in [0, t_a] can fall in (module docs of `super::tails`), fine and
    // coarse
    let split = plan.times.len() as i64;
    let fine = Space::new(CELLS_PER_WINDOW as i64 + 1 + split, max_index, 1);
    let coarse = Space::new(CELLS_PER_WINDOW as i64 / COARSE + 1 + split, max_index, GROUPS as i64);
    let times = plan.times.clone();
    let (list, rows) = durations(true);
    let sticks = match (&plan.scene, &plan.entry_grid) {
        (Ok((scene, (_, speeds))), Some(grid)) => {
            let entry = EntryBin::new(scene.params.per_unit_mass(), *speeds, grid.iter().map(|g| g.0).collect());
            let bins = Space::new(grid.len() as i64 + 1, max_index, GROUPS as i64);
            let lists = [list, name::STICK_ENTRY_POSITION, name::STICK_ENTRY_VELOCITY];
            element_counts(lists, rows, [fine, coarse, bins], (max_index, at), move |e, k, row| {
                let [fine, coarse] = duration_keys(e[0], k, row, rho, &times);
                let entry = e[1].zip(e[2]).map(|(x, v)| {
                    let (bin, forward) = entry.bin(x, v);
                    (bin, k, forward, group_of(row[0]))
                });
                [fine, coarse, entry]
            })
        }
        _ => element_counts([list], rows, [fine, coarse, Space::new(0, max_index, 1)], (max_index, at), move |e, k, row| {
            let [fine, coarse] = duration_keys(e[0], k, row, rho, &times);
            [fine, coarse, None]
        }),
    };
    let times = plan.times.clone();
    let (list, rows) = durations(false);
    let slips = element_counts([list], rows, [fine, coarse], (max_index, at), move |e, k, row| duration_keys(e[0], k, row, rho, &times));
    [sticks, slips]
}

/// Sink `s`'s lists: (the variable of [`keys`], the field of its struct with the keys, the field
/// with their counts).
pub(crate) fn sink(s: usize) -> (usize, String, String) {
    let (variable, i) = if s < 3 { (0, s) } else { (1, s - 3) };
    (variable, key_field(i), count_field(i))
}

/// The name of the keys of field `i` of an [`element_counts`] struct.
fn key_field(i: usize) -> String {
    format!("k{i}")
}

/// The name of the counts of field `i` of an [`element_counts`] struct.
fn count_field(i: usize) -> String {
    format!("n{i}")
}

/// Per realization, the columns the extremes sum per jackknife group (with the tails' state):
/// 1 (realizations), its sticks, those ending by breakaway, and whether its longest stick
/// exceeds each T and its severity each s of the options — in the order [`super::tails`] reads.
pub(crate) fn extreme_columns(plan: &TailPlan) -> Vec<Expr> {
    let mut out = vec![lit(1i64), col(name::N_STICK).cast(DataType::Int64), crate::observables::breakaways()];
    out.extend(plan.opts.times.iter().map(|t| col(name::LONGEST_STICK).gt(lit(*t)).cast(DataType::Int64)));
    out.extend(plan.opts.severity.iter().map(|s| col(name::SEVERITY).gt(lit(*s)).cast(DataType::Int64)));
    out
}

/// Add one sink's counts by packed key (the (key, count) pairs of [`keys`], summed over the
/// batches) to the cells' counts of that sink.
pub(crate) fn add_counts(pairs: impl IntoIterator<Item = (i64, u64)>, max_index: u32, out: &mut [&mut HashCounts]) {
    let (cells, packing) = (out.len() as i64, Space::packing(max_index));
    for (key, n) in pairs {
        let (cell, key) = (key % cells, key / cells);
        let (t, k, flag, g) = packing.decode(key);
        *out[cell as usize].entry((g as usize, k as u32, t, flag)).or_insert(0) += n;
    }
}

/// The counts of one sink of one cell per (group, k, cell, flag).
pub(crate) type HashCounts = std::collections::HashMap<(usize, u32, i64, bool), u64>;

/// The counts of one sink as rows.
pub(crate) fn rows(counts: &HashCounts) -> Counts {
    counts.iter().map(|(&(g, k, c, flag), &n)| (g, k, c, flag, n)).collect()
}

/// The one int64 key of a counted interval or entry of cell `cell` of `cells` (a group-by on one
/// integer column is a flat hash table; on several it encodes rows as bytes):
/// key = (((t·(K+1) + k)·2 + flag)·GROUPS + g)·cells + cell ([`Space::packing`]), with t the
/// time cell (or holding-time bin), K = `max_index` + 1 and k clamped to K (the indices past the
/// curves per k, kept for the pooled curve); t ≥ 0 is below 2^17 (a window's 2^16 cells and the
/// user's times), so the key stays far below 2^63 for any index and sweep a user can run.
/// Decoded by [`add_counts`] (the dense arrays of [`element_counts`] index (t, k, flag, g) alone:
/// the cell is one per call).
fn pack(max_index: u32, key: Key, (cell, cells): (usize, usize)) -> i64 {
    Space::packing(max_index).encode(key) * cells as i64 + cell as i64
}

/// The jackknife group of a realization.
fn group_of(realization: i64) -> i64 {
    realization % GROUPS as i64
}

/// What one interval or entry is counted under before [`pack`]: (time cell or holding-time bin
/// t, index k, flag, jackknife group g).
type Key = (i64, i64, bool, i64);

/// The layout of (t, k, flag, g) as one integer, ((t·ks + k)·2 + flag)·groups + g with k clamped
/// to `top` = `max_index` + 1 ([`Space::encode`]): of [`pack`], all k and groups and any t; of
/// one field's dense array, t in [0, `times`), g in [0, `groups`) and k below `ks`. Anything
/// outside the dense array is counted in a map by its packed key.
#[derive(Clone, Copy)]
struct Space {
    times: i64,
    ks: i64,
    top: i64,
    groups: i64,
}

/// Dense arrays are used up to this many entries per field (16 MiB); a larger space (a
/// very large `--max-index`) is counted in the map alone.
const DENSE_MAX: i64 = 1 << 23;

/// Indices k counted densely: k ≤ 16 (a paper realization has 16.5 sticks on average), so that
/// a large `--max-index` does not make the arrays larger, only its rarer indices go to the map.
const DENSE_INDICES: i64 = 17;

impl Space {
    /// The layout of [`pack`] (no dense array).
    fn packing(max_index: u32) -> Space {
        let top = i64::from(max_index) + 1;
        Space { times: 0, ks: top + 1, top, groups: GROUPS as i64 }
    }

    fn new(times: i64, max_index: u32, groups: i64) -> Space {
        let top = i64::from(max_index) + 1;
        let ks = (top + 1).min(DENSE_INDICES);
        let times = if times.saturating_mul(ks * 2 * groups) <= DENSE_MAX { times } else { 0 };
        Space { times, ks, top, groups }
    }

    /// The space for a batch of `keys` keys: the map alone when the array would be more than
    /// four times larger than the keys (a small sweep cell: allocating and emptying the array
    /// would cost more than the counting).
    fn for_batch(self, keys: usize) -> Space {
        if keys.saturating_mul(4) < self.len() {
            Space { times: 0, ..self }
        } else {
            self
        }
    }

    fn len(&self) -> usize {
        (self.times * self.ks * 2 * self.groups) as usize
    }

    #[inline]
    fn encode(&self, (t, k, flag, g): Key) -> i64 {
        ((t * self.ks + k.min(self.top)) * 2 + i64::from(flag)) * self.groups + g
    }

    fn decode(&self, i: i64) -> Key {
        let (g, rest) = (i % self.groups, i / self.groups);
        let (flag, rest) = (rest % 2 == 1, rest / 2);
        (rest / self.ks, rest % self.ks, flag, g)
    }

    /// The key's place in the dense array, if it has one.
    #[inline]
    fn index(&self, key: Key) -> Option<usize> {
        let (t, k, g) = (key.0, key.1.min(self.top), key.3);
        ((0..self.times).contains(&t) && (0..self.groups).contains(&g) && (0..self.ks).contains(&k)).then(|| self.encode(key) as usize)
    }
}

/// A dense counter: 16 bits keep the arrays of the paper scene's hot cells (durations below 1-2 s)
/// in a core's L2 cache (2 bytes a key; a key counted 65,535 times in one batch moves its count
/// to the map and starts again).
type Count = u16;

/// The counts of one field over one batch of rows: a dense array over its [`Space`] (with the
/// indices touched, so that reading it out costs what filling it did) and a map for the rest.
struct Tally {
    space: Space,
    dense: Vec<Count>,
    touched: Vec<u32>,
    over: PlHashMap<i64, i64>,
}

impl Tally {
    fn new(space: Space) -> Tally {
        Tally { space, dense: vec![0; space.len()], touched: Vec::new(), over: Default::default() }
    }

    #[inline]
    fn add(&mut self, key: Key, max_index: u32, at: (usize, usize)) {
        match self.space.index(key) {
            Some(i) => {
                let c = &mut self.dense[i];
                if *c == 0 {
                    self.touched.push(i as u32);
                }
                if *c == Count::MAX {
                    // (a full counter moves to the map; its key is then emitted twice, which the
                    // sums over keys add up)
                    *self.over.entry(pack(max_index, key, at)).or_insert(0) += i64::from(Count::MAX);
                    *c = 0;
                }
                *c += 1;
            }
            None => *self.over.entry(pack(max_index, key, at)).or_insert(0) += 1,
        }
    }

    /// The counts as (packed key, count) lists.
    fn into_pairs(self, max_index: u32, at: (usize, usize)) -> (Vec<i64>, Vec<i64>) {
        let n = self.touched.len() + self.over.len();
        let (mut keys, mut counts) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for &i in &self.touched {
            keys.push(pack(max_index, self.space.decode(i64::from(i)), at));
            counts.push(i64::from(self.dense[i as usize]));
        }
        for (key, n) in self.over {
            keys.push(key);
            counts.push(n);
        }
        (keys, counts)
    }
}

/// A struct of N pairs of list<int64> fields (`k0`, `n0`, `k1`, `n1`, …) beside the lists
/// `lists` (of equal lengths, as validated): for element j of a row, `key(the lists' j-th values,
/// k = j + 1, the row's values of `rows`; a null element is None)` gives one [`Key`] per field
/// (None: none in that field), and each batch of rows polars hands over is counted per key
/// (a partial aggregate) into dense arrays whose space `spaces` gives ([`Space::for_batch`];
/// allocated per batch, so that memory follows the batches in flight, not the cells of a sweep
/// or the files of a run). The batch's first row
/// holds its keys (packed, [`pack`]) and their counts, the other rows empty lists, so that
/// polars' explode and a sum per key add the batches' counts: a sum that does not depend on how
/// polars cuts the rows into batches. A row with a null input has no keys.
fn element_counts<F, const M: usize, const N: usize>(
    lists: [&'static str; M],
    rows: Vec<Expr>,
    spaces: [Space; N],
    (max_index, at): (u32, (usize, usize)),
    key: F,
) -> Expr
where
    F: Fn(&[Option<f64>; M], i64, &[i64]) -> [Option<Key>; N] + Send + Sync + 'static,
{
    use polars_arrow::array::{Array, ListArray, PrimitiveArray};
    use polars_arrow::datatypes::ArrowDataType;
    let n_lists = M;
    let mut inputs: Vec<Expr> = lists[1..].iter().map(|l| col(*l)).collect();
    inputs.extend(rows);
    let fields = move || {
        (0..N).flat_map(|i| [key_field(i), count_field(i)]).map(|f| Field::new(f.into(), DataType::List(Box::new(DataType::Int64)))).collect::<Vec<_>>()
    };
    col(lists[0]).map_many(
        move |c: &mut [Column]| {
            let height = c[0].len();
            let name = c[0].name().clone();
            let ls: Vec<ListChunked> = c[..n_lists].iter().map(|c| Ok(c.list()?.rechunk().into_owned())).collect::<PolarsResult<_>>()?;
            let rs: Vec<Int64Chunked> =
                c[n_lists..].iter().map(|c| Ok(c.cast(&DataType::Int64)?.i64()?.rechunk().into_owned())).collect::<PolarsResult<_>>()?;
            // (keys of the batch: at most one per element of the first list and field)
            let elements = ls[0].downcast_iter().next().map_or(0, |a| (a.offsets().last() - a.offsets().first()) as usize);
            let mut tallies = spaces.map(|s| Tally::new(s.for_batch(elements)));
            if let (Some(arrs), Some(ints)) = (
                ls.iter().map(|l| l.downcast_iter().next()).collect::<Option<Vec<&ListArray<i64>>>>(),
                rs.iter().map(|r| r.downcast_iter().next()).collect::<Option<Vec<&PrimitiveArray<i64>>>>(),
            ) {
                let vals: Vec<&PrimitiveArray<f64>> = arrs
                    .iter()
                    .map(|a| a.values().as_any().downcast_ref::<PrimitiveArray<f64>>())
                    .collect::<Option<_>>()
                    .ok_or_else(|| polars_err!(ComputeError: "{name}: a list of floats was expected"))?;
                // (arrays of the lists' count M, so that the loop over an element's lists unrolls)
                let offs: [&[i64]; M] = std::array::from_fn(|i| arrs[i].offsets().as_slice());
                let slices: [&[f64]; M] = std::array::from_fn(|i| vals[i].values().as_slice());
                let vals: [&PrimitiveArray<f64>; M] = std::array::from_fn(|i| vals[i]);
                let dense = vals.iter().all(|v| v.null_count() == 0);
                let (mut elements, mut row, mut starts) = ([None; M], vec![0i64; ints.len()], [0usize; M]);
                for r in 0..height {
                    let mut ok = arrs.iter().all(|a| a.is_valid(r));
                    for (x, a) in row.iter_mut().zip(&ints) {
                        match a.get(r) {
                            Some(v) => *x = v,
                            None => ok = false,
                        }
                    }
                    if !ok {
                        continue;
                    }
                    // (the lists have equal lengths in a validated dataset)
                    let len = offs.iter().map(|o| o[r + 1] - o[r]).min().unwrap_or(0) as usize;
                    starts.iter_mut().zip(&offs).for_each(|(s, o)| *s = o[r] as usize);
                    for j in 0..len {
                        for (((e, x), s), v) in elements.iter_mut().zip(&slices).zip(&starts).zip(&vals) {
                            *e = (dense || v.is_valid(s + j)).then(|| x[s + j]);
                        }
                        for (t, k) in tallies.iter_mut().zip(key(&elements, j as i64 + 1, &row)) {
                            if let Some(k) = k {
                                t.add(k, max_index, at);
                            }
                        }
                    }
                }
            }
            let dtype = ListArray::<i64>::default_datatype(ArrowDataType::Int64);
            let mut columns = Vec::with_capacity(2 * N);
            for (i, t) in tallies.into_iter().enumerate() {
                let (keys, counts) = t.into_pairs(max_index, at);
                // the first row holds every pair (a batch of no rows has none)
                let offsets: Vec<i64> = std::iter::once(0).chain((0..height).map(|_| keys.len() as i64)).collect();
                for (f, values) in [(key_field(i), keys), (count_field(i), counts)] {
                    let o = polars_arrow::offset::Offsets::<i64>::try_from(offsets.clone())?.into();
                    let list = ListArray::<i64>::new(dtype.clone(), o, PrimitiveArray::from_vec(values).boxed(), None);
                    columns.push(ListChunked::from_chunk_iter(f.into(), [list]).into_column());
                }
            }
            Ok(StructChunked::from_columns(name, height, &columns)?.into_column())
        },
        &inputs,
        move |_, f| Ok(Field::new(f[0].name().clone(), DataType::Struct(fields()))),
    )
}

/// The fine and coarse keys of a stick's or slip's duration d, its k-th (row: realization,
/// count of its kind, whether the last interval is cut): the time cells of width ρ (groups
/// pooled) and 32ρ (per group), split at `times` ([`cell`]); flag = it is the censored interval
/// (the one rule of `observables::last_cut`: the last interval cut at t_a). No keys for a null
/// duration or one past 2^40 cells (validation refuses either: a duration lies in [0, t_a]).
fn duration_keys(d: Option<f64>, k: i64, row: &[i64], rho: f64, times: &[f64]) -> [Option<Key>; 2] {
    let Some((uniform, split)) = d.and_then(|d| cell(d, rho, times)) else { return [None, None] };
    let flag = row[2] != 0 && k == row[1];
    // ⌊d/(32ρ)⌋ = ⌊⌊d/ρ⌋/32⌋ exactly: 32ρ is exact, and dividing by a power of two commutes
    // with rounding
    [Some((uniform + split, k, flag, 0)), Some((uniform / COARSE + split, k, flag, group_of(row[0])))]
}

/// The time cell of a duration d ≥ 0 on cells of width ρ split at the user's times τ (sorted,
/// distinct): φ(d) = ⌊d/ρ⌋ + #{τ ≤ d}, returned as its two terms, so that every cell edge and
/// every τ is a boundary and a curve is exact at each τ as at each cell edge (module docs of
/// [`super::tails`]); None past 2^40 cells (+∞ included), where the key would overflow.
fn cell(d: f64, rho: f64, times: &[f64]) -> Option<(i64, i64)> {
    let q = if d > 0.0 { d / rho } else { 0.0 };
    (q < (1u64 << 40) as f64).then(|| (q as i64, times.iter().filter(|&&t| d >= t).count() as i64))
}

/// The bin of a stick entry (position x, belt velocity v: `v_f` forward, −`v_r` reverse): how
/// many of the evaluation times `ts` (increasing) lie below its holding time d_s(x), so that the
/// entry is held past `ts[j]` exactly when its bin exceeds j; and whether the belt is forward.
struct EntryBin {
    p: PerUnitMass,
    speeds: (f64, f64),
    below: Below,
}

impl EntryBin {
    fn new(p: PerUnitMass, speeds: (f64, f64), ts: Vec<f64>) -> EntryBin {
        EntryBin { p, speeds, below: Below::new(ts) }
    }

    fn bin(&self, x: f64, v: f64) -> (i64, bool) {
        let d = self.p.stick_duration(x, if v > 0.0 { self.speeds.0 } else { -self.speeds.1 });
        (self.below.count(d) as i64, v > 0.0)
    }
}

/// #{t ∈ ts : t < d} for sorted times ts ≥ 0 in a step or two (a binary search of the ~200 times
/// was a third of the keys' cost): the count at the start of each of 4·|ts| equal buckets over
/// [0, max ts], then a walk from the bucket of d to the exact count — forward past the times
/// below d, back over those at or above it, so a bucket index off by rounding costs a step, not a
/// wrong count (NaN: 0, as the search gives).
struct Below {
    ts: Vec<f64>,
    /// buckets per unit of d: 1 / the bucket width
    per_step: f64,
    start: Vec<usize>,
}

impl Below {
    fn new(ts: Vec<f64>) -> Below {
        let top = ts.last().copied().unwrap_or(0.0);
        let buckets = 4 * ts.len().max(1);
        let step = if top > 0.0 && top.is_finite() { top / buckets as f64 } else { 1.0 };
        let start = (0..buckets).map(|b| ts.partition_point(|&t| t < b as f64 * step)).collect();
        Below { ts, per_step: 1.0 / step, start }
    }

    fn count(&self, d: f64) -> usize {
        // (`as` saturates: negative and NaN to bucket 0, +∞ to the last)
        let mut i = self.start[((d * self.per_step) as usize).min(self.start.len() - 1)];
        while i < self.ts.len() && self.ts[i] < d {
            i += 1;
        }
        while i > 0 && !(self.ts[i - 1] < d) {
            i -= 1;
        }
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn below_counts_as_a_binary_search_does() {
        // uneven times (a grid with the user's times among them), values on, between and
        // beyond them, and the special values
        let mut ts: Vec<f64> = (0..=200).map(|j| (j * 16_001 / 200) as f64 * 1.5e-4).chain([0.5, 1.0, 2.4]).collect();
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        let below = Below::new(ts.clone());
        let mut values: Vec<f64> = ts.iter().flat_map(|&t| [t, t.next_down(), t.next_up()]).collect();
        values.extend([-1.0, 0.0, 1e-300, 0.3, 2.39, 2.41, 1e9, f64::INFINITY, f64::NEG_INFINITY, f64::NAN]);
        for d in values {
            assert_eq!(below.count(d), ts.partition_point(|&t| t < d), "d = {d}");
        }
        assert_eq!(Below::new(Vec::new()).count(1.0), 0);
    }

    #[test]
    fn keys_decode_to_the_cells_groups_indices_and_flags_they_were_made_from() {
        // durations on both sides of a user's time and of cell edges, k past max_index (pooled into
        // K = max_index + 1), the censored flag only on the last interval of a cut realization,
        // and five cells of a sweep; the expected cells are computed here from d directly
        let (max_index, cells, rho, times) = (3u32, 5usize, 10.0 / 65_536.0, [0.5, 1.0]);
        // (d, k, realization, count of its kind, last interval cut, cell)
        let cases = [(0.0, 1, 0, 4, 0, 0), (0.4999, 2, 7, 4, 0, 1), (0.5, 3, 19, 3, 1, 4), (1.7, 4, 21, 4, 1, 2), (2.4, 9, 40, 9, 0, 3), (0.05, 6, 3, 6, 1, 1)];
        let mut keys = Vec::new();
        let mut per_cell = vec![HashCounts::new(); cells];
        for (d, k, r, n, cut, c) in cases {
            let [fine, coarse] = duration_keys(Some(d), k, &[r, n, cut], rho, &times);
            keys.extend([fine.unwrap(), coarse.unwrap()].map(|key| pack(max_index, key, (c, cells))));
            let split = times.iter().filter(|&&t| d >= t).count() as i64;
            let (kk, flag) = (k.min(i64::from(max_index) + 1) as u32, cut == 1 && k == n);
            *per_cell[c].entry((0, kk, (d / rho).floor() as i64 + split, flag)).or_insert(0) += 1;
            *per_cell[c].entry(((r % 20) as usize, kk, (d / (32.0 * rho)).floor() as i64 + split, flag)).or_insert(0) += 1;
        }
        let mut out = vec![HashCounts::new(); cells];
        add_counts(keys.into_iter().map(|k| (k, 1)), max_index, &mut out.iter_mut().collect::<Vec<_>>());
        assert_eq!(out, per_cell);
        // a duration past the cells' range (refused by validation) makes no key, not an overflow
        assert_eq!(duration_keys(Some(f64::INFINITY), 1, &[0, 1, 0], rho, &times), [None, None]);
        assert_eq!(duration_keys(None, 1, &[0, 1, 0], rho, &times), [None, None]);
    }

    #[test]
    fn a_tally_counts_each_key_once_per_add_whether_dense_or_in_the_map() {
        // keys inside the dense space and past it (t beyond its cells, g beyond its groups, k
        // beyond its dense indices with a large max_index), a space too large to be dense, one
        // left to the map for a small batch, and a counter that fills up: the (packed key,
        // count) pairs summed per key are the adds counted directly, and no pair has a count of 0
        let at = (2usize, 5usize);
        let keys: Vec<Key> = (0..4000i64).map(|i| ((i * 7919) % 61, 1 + (i * 31) % 25, i % 3 == 0, (i * 13) % 23)).collect();
        let cases = [
            (3, Space::new(50, 3, 20)),
            (20, Space::new(50, 20, 20)),
            (3, Space::new(1 << 40, 3, 20)),
            (3, Space::new(0, 3, 1)),
            (3, Space::new(50, 3, 20).for_batch(100)),
        ];
        assert_eq!(cases.map(|(_, s)| s.len()), [50 * 5 * 2 * 20, 50 * 17 * 2 * 20, 0, 0, 0]);
        assert_eq!(Space::new(50, 3, 20).for_batch(2500).len(), 10_000);
        for (max_index, space) in cases {
            let mut tally = Tally::new(space);
            let mut expected = std::collections::HashMap::<i64, i64>::new();
            if let Some(i) = space.index(keys[0]) {
                // a full counter: the next add of its key moves it to the map
                tally.add(keys[0], max_index, at);
                tally.dense[i] = Count::MAX;
                expected.insert(pack(max_index, keys[0], at), i64::from(Count::MAX));
            }
            // (every key twice, the second time on counters already touched)
            for &(t, k, flag, g) in keys.iter().chain(&keys) {
                tally.add((t, k, flag, g), max_index, at);
                *expected.entry(pack(max_index, (t, k, flag, g), at)).or_insert(0) += 1;
            }
            let (packed, counts) = tally.into_pairs(max_index, at);
            assert!(counts.iter().all(|&n| n > 0), "a pair with no count");
            let mut got = std::collections::HashMap::<i64, i64>::new();
            for (k, n) in packed.into_iter().zip(counts) {
                *got.entry(k).or_insert(0) += n;
            }
            assert_eq!(got, expected, "max_index {max_index}, dense length {}", space.len());
        }
        // the index and its inverse
        for (max_index, space) in cases {
            for &key in &keys {
                if let Some(i) = space.index(key) {
                    assert_eq!(space.decode(i as i64), (key.0, key.1.min(i64::from(max_index) + 1), key.2, key.3));
                }
            }
        }
    }

    #[test]
    fn the_coarse_cell_is_the_fine_cell_over_32() {
        // ⌊d/(32ρ)⌋ = ⌊⌊d/ρ⌋/32⌋ for durations on and around the cell edges
        let rho = 10.0 / 65_536.0;
        for c in [0i64, 1, 31, 32, 33, 1023, 1024, 16_000, 65_535] {
            let edge = c as f64 * rho;
            for d in [edge, edge.next_down(), edge.next_up(), edge + 0.5 * rho] {
                let fine = cell(d, rho, &[]).unwrap().0;
                assert_eq!(fine / COARSE, cell(d, rho * COARSE as f64, &[]).unwrap().0, "d = {d}");
            }
        }
    }
}
