//! What the analysis' main pass counts for the tails ([`super::tails`]): per part file, for
//! every realization, lists of integer keys — one per stick or slip (its time cell, index k,
//! whether it is the censored one and its jackknife group), one per stick entry (the bin of its
//! holding time and its belt state) — that the query explodes and counts per key, and the
//! per-realization columns of the extremes that it sums per jackknife group. The tails are thus
//! counted in the same scan as the moments and histograms (the lists are decoded once).

use polars::prelude::*;

use super::jackknife::GROUPS;
use super::tails::{Counts, TailPlan, COARSE};
use crate::physics::PerUnitMass;
use crate::simulation::dataset::columns as name;

/// Count sinks per cell, in this order: D on fine cells (groups pooled), D on coarse cells (per
/// group), D's entries (none where the conditional estimator is refused), H fine, H coarse.
pub(crate) const SINKS: usize = 5;

/// The struct columns of one part of cell `cell` (of `cells` in the scan), one per variable
/// (D, H), whose fields are the key lists of the sinks (see [`sink`]): every stick's or slip's
/// keys made in one pass over its lists.
pub(crate) fn keys(plan: &TailPlan, cell: usize, cells: usize) -> [Expr; 2] {
    let (max_index, rho, at) = (plan.max_index, plan.rho, (cell, cells));
    let durations = |stick: bool| {
        let (list, count) = if stick { (name::STICK_DURATION, name::N_STICK) } else { (name::SLIP_DURATION, name::N_SLIP) };
        (list, vec![col(name::REALIZATION), col(count), crate::observables::last_cut(stick)])
    };
    let times = plan.times.clone();
    let (list, rows) = durations(true);
    let sticks = match (&plan.scene, &plan.entry_grid) {
        (Ok((scene, (_, speeds))), Some(grid)) => {
            let entry = EntryBin::new(scene.params.per_unit_mass(), *speeds, grid.iter().map(|g| g.0).collect());
            let lists = vec![list, name::STICK_ENTRY_POSITION, name::STICK_ENTRY_VELOCITY];
            element_keys(lists, rows, move |e, k, row| {
                let [fine, coarse] = duration_keys(e[0], k, row, rho, &times, max_index, at);
                let entry = e[1].zip(e[2]).map(|(x, v)| {
                    let (bin, forward) = entry.bin(x, v);
                    pack(max_index, bin, k, forward, group_of(row[0]), at)
                });
                [fine, coarse, entry]
            })
        }
        _ => element_keys(vec![list], rows, move |e, k, row| {
            let [fine, coarse] = duration_keys(e[0], k, row, rho, &times, max_index, at);
            [fine, coarse, None]
        }),
    };
    let times = plan.times.clone();
    let (list, rows) = durations(false);
    let slips = element_keys(vec![list], rows, move |e, k, row| duration_keys(e[0], k, row, rho, &times, max_index, at));
    [sticks, slips]
}

/// Sink `s`'s key list: (the variable of [`keys`], the field of its struct).
pub(crate) fn sink(s: usize) -> (usize, String) {
    let (variable, i) = if s < 3 { (0, s) } else { (1, s - 3) };
    (variable, field(i))
}

/// The name of field `i` of an [`element_keys`] struct.
fn field(i: usize) -> String {
    format!("k{i}")
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

/// Add the counts of one sink's table (`key`, `n`: [`keys`] exploded and counted) to the cells'
/// counts of that sink.
pub(crate) fn add_counts(df: &DataFrame, key: &str, n: &str, max_index: u32, out: &mut [HashCounts]) -> PolarsResult<()> {
    let cells = out.len() as i64;
    let ks = i64::from(max_index) + 2;
    let keys = df.column(key)?.cast(&DataType::Int64)?;
    let ns = df.column(n)?.cast(&DataType::Int64)?;
    for (key, n) in keys.i64()?.iter().zip(ns.i64()?.iter()) {
        // (realizations without a value: the null key)
        let (Some(key), Some(n)) = (key, n) else { continue };
        let (cell, key) = (key % cells, key / cells);
        let (g, rest) = (key % GROUPS as i64, key / GROUPS as i64);
        let (flag, rest) = (rest % 2 == 1, rest / 2);
        *out[cell as usize].entry((g as usize, (rest % ks) as u32, rest / ks, flag)).or_insert(0) += n as u64;
    }
    Ok(())
}

/// The counts of one sink of one cell per (group, k, cell, flag).
pub(crate) type HashCounts = std::collections::HashMap<(usize, u32, i64, bool), u64>;

/// The counts of one sink as rows.
pub(crate) fn rows(counts: &HashCounts) -> Counts {
    counts.iter().map(|(&(g, k, c, flag), &n)| (g, k, c, flag, n)).collect()
}

/// The one int64 key of a counted interval or entry of cell `cell` of `cells` (a group-by on one
/// integer column is a flat hash table; on several it encodes rows as bytes):
/// key = (((t·(K+1) + k)·2 + flag)·GROUPS + g)·cells + cell, with t the time cell (or holding-time
/// bin), K = `max_index` + 1 and k clamped to K (the indices past the curves per k, kept for the
/// pooled curve); t ≥ 0 is below 2^17 (a window's 2^16 cells and the user's times), so the key
/// stays far below 2^63 for any index and sweep a user can run. Decoded by [`add_counts`].
fn pack(max_index: u32, t: i64, k: i64, flag: bool, g: i64, (cell, cells): (usize, usize)) -> i64 {
    let top = i64::from(max_index) + 1;
    (((t * (top + 1) + k.min(top)) * 2 + i64::from(flag)) * GROUPS as i64 + g) * cells as i64 + cell as i64
}

/// The jackknife group of a realization.
fn group_of(realization: i64) -> i64 {
    realization % GROUPS as i64
}

/// A struct of N list<int64> fields (`k0`, `k1`, …) beside the lists `lists` (of equal lengths,
/// as validated): for element j of a row, `key(the lists' j-th values, k = j + 1, the row's values
/// of `rows`; a null element is None)` gives one key per field (None: no key in that field). One
/// pass per row, so that polars explodes integer lists instead of several lists and the columns
/// of an arithmetic expression per step. A row with a null input gets null lists (no keys).
fn element_keys<F, const N: usize>(lists: Vec<&'static str>, rows: Vec<Expr>, key: F) -> Expr
where
    F: Fn(&[Option<f64>], i64, &[i64]) -> [Option<i64>; N] + Send + Sync + 'static,
{
    use polars_arrow::array::{Array, ListArray, PrimitiveArray};
    use polars_arrow::datatypes::ArrowDataType;
    let n_lists = lists.len();
    let mut inputs: Vec<Expr> = lists[1..].iter().map(|l| col(*l)).collect();
    inputs.extend(rows);
    let fields = move || (0..N).map(|i| Field::new(field(i).into(), DataType::List(Box::new(DataType::Int64)))).collect::<Vec<_>>();
    col(lists[0]).map_many(
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
                let empty: Vec<Column> = (0..N).map(|i| ListChunked::full_null_with_dtype(field(i).into(), height, &DataType::Int64).into_column()).collect();
                return Ok(StructChunked::from_columns(name, height, &empty)?.into_column());
            };
            let vals: Vec<&PrimitiveArray<f64>> = arrs
                .iter()
                .map(|a| a.values().as_any().downcast_ref::<PrimitiveArray<f64>>())
                .collect::<Option<_>>()
                .ok_or_else(|| polars_err!(ComputeError: "{name}: a list of floats was expected"))?;
            let offs: Vec<&[i64]> = arrs.iter().map(|a| a.offsets().as_slice()).collect();
            let slices: Vec<&[f64]> = vals.iter().map(|v| v.values().as_slice()).collect();
            let dense = vals.iter().all(|v| v.null_count() == 0);
            let elements_total = (offs[0][height] - offs[0][0]) as usize;
            let mut keys: [Vec<i64>; N] = std::array::from_fn(|_| Vec::with_capacity(elements_total));
            let mut offsets: [Vec<i64>; N] = std::array::from_fn(|_| {
                let mut o = Vec::with_capacity(height + 1);
                o.push(0);
                o
            });
            let mut valid = polars_arrow::bitmap::MutableBitmap::with_capacity(height);
            let (mut elements, mut row, mut starts) = (vec![None; n_lists], vec![0i64; ints.len()], vec![0usize; n_lists]);
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
                    starts.iter_mut().zip(&offs).for_each(|(s, o)| *s = o[r] as usize);
                    for j in 0..len {
                        for (((e, x), s), v) in elements.iter_mut().zip(&slices).zip(&starts).zip(&vals) {
                            *e = (dense || v.is_valid(s + j)).then(|| x[s + j]);
                        }
                        for (out, k) in keys.iter_mut().zip(key(&elements, j as i64 + 1, &row)) {
                            if let Some(k) = k {
                                out.push(k);
                            }
                        }
                    }
                }
                for (o, k) in offsets.iter_mut().zip(&keys) {
                    o.push(k.len() as i64);
                }
                valid.push(ok);
            }
            let validity: Option<polars_arrow::bitmap::Bitmap> = valid.into();
            let mut columns = Vec::with_capacity(N);
            for (i, (k, o)) in keys.into_iter().zip(offsets).enumerate() {
                let o = polars_arrow::offset::Offsets::<i64>::try_from(o)?.into();
                let list = ListArray::<i64>::new(dtype.clone(), o, PrimitiveArray::from_vec(k).boxed(), validity.clone());
                columns.push(ListChunked::from_chunk_iter(field(i).into(), [list]).into_column());
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
fn duration_keys(d: Option<f64>, k: i64, row: &[i64], rho: f64, times: &[f64], max_index: u32, at: (usize, usize)) -> [Option<i64>; 2] {
    let Some((uniform, split)) = d.and_then(|d| cell(d, rho, times)) else { return [None, None] };
    let flag = row[2] != 0 && k == row[1];
    // ⌊d/(32ρ)⌋ = ⌊⌊d/ρ⌋/32⌋ exactly: 32ρ is exact, and dividing by a power of two commutes
    // with rounding
    [Some(pack(max_index, uniform + split, k, flag, 0, at)), Some(pack(max_index, uniform / COARSE + split, k, flag, group_of(row[0]), at))]
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
    step: f64,
    start: Vec<usize>,
}

impl Below {
    fn new(ts: Vec<f64>) -> Below {
        let top = ts.last().copied().unwrap_or(0.0);
        let buckets = 4 * ts.len().max(1);
        let step = if top > 0.0 && top.is_finite() { top / buckets as f64 } else { 1.0 };
        let start = (0..buckets).map(|b| ts.partition_point(|&t| t < b as f64 * step)).collect();
        Below { ts, step, start }
    }

    fn count(&self, d: f64) -> usize {
        // (`as` saturates: negative and NaN to bucket 0, +∞ to the last)
        let mut i = self.start[((d / self.step) as usize).min(self.start.len() - 1)];
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
            let [fine, coarse] = duration_keys(Some(d), k, &[r, n, cut], rho, &times, max_index, (c, cells));
            keys.extend([fine.unwrap(), coarse.unwrap()]);
            let split = times.iter().filter(|&&t| d >= t).count() as i64;
            let (kk, flag) = (k.min(i64::from(max_index) + 1) as u32, cut == 1 && k == n);
            *per_cell[c].entry((0, kk, (d / rho).floor() as i64 + split, flag)).or_insert(0) += 1;
            *per_cell[c].entry(((r % 20) as usize, kk, (d / (32.0 * rho)).floor() as i64 + split, flag)).or_insert(0) += 1;
        }
        let n = keys.len();
        let df = DataFrame::new_infer_height(vec![Column::new("key".into(), keys), Column::new("n".into(), vec![1i64; n])]).unwrap();
        let mut out = vec![HashCounts::new(); cells];
        add_counts(&df, "key", "n", max_index, &mut out).unwrap();
        assert_eq!(out, per_cell);
        // a duration past the cells' range (refused by validation) makes no key, not an overflow
        assert_eq!(duration_keys(Some(f64::INFINITY), 1, &[0, 1, 0], rho, &times, max_index, (0, 1)), [None, None]);
        assert_eq!(duration_keys(None, 1, &[0, 1, 0], rho, &times, max_index, (0, 1)), [None, None]);
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
