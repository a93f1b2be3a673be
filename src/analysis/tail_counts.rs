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

/// The key lists of one part of cell `cell` (of `cells` in the scan), one per sink ([`SINKS`]).
pub(crate) fn keys(plan: &TailPlan, cell: usize, cells: usize) -> [Expr; SINKS] {
    let on = |coarse: bool| if coarse { plan.rho * COARSE as f64 } else { plan.rho };
    let entries = match (&plan.scene, &plan.entry_grid) {
        (Ok((scene, (_, speeds))), Some(grid)) => {
            entry_keys(scene.params.per_unit_mass(), *speeds, plan.max_index, grid.iter().map(|g| g.0).collect(), (cell, cells))
        }
        _ => element_keys(vec![name::STICK_DURATION], Vec::new(), |_, _, _| None),
    };
    let durations = |stick: bool, coarse: bool| duration_keys(stick, plan.max_index, on(coarse), plan.times.clone(), !coarse, (cell, cells));
    [durations(true, false), durations(true, true), entries, durations(false, false), durations(false, true)]
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

/// A list<int64> beside the lists `lists` (of equal lengths, as validated): for element j of a
/// row, `key(the lists' j-th values, k = j + 1, the row's values of `rows`)` (None: no key). One pass per row,
/// so that polars explodes one integer list instead of several lists and the columns of an
/// arithmetic expression per step. A row with a null input gets a null list (no key); a null
/// element, no key.
fn element_keys<F>(lists: Vec<&'static str>, rows: Vec<Expr>, key: F) -> Expr
where
    F: Fn(&[f64], i64, &[i64]) -> Option<i64> + Send + Sync + 'static,
{
    use polars_arrow::array::{Array, ListArray, PrimitiveArray};
    use polars_arrow::datatypes::ArrowDataType;
    let n_lists = lists.len();
    let mut inputs: Vec<Expr> = lists[1..].iter().map(|l| col(*l)).collect();
    inputs.extend(rows);
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
                        if let Some(k) = key(&elements, j as i64 + 1, &row) {
                            keys.push(k);
                        }
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
}

/// The keys of the stick (`stick`) or slip durations on the time cells of width `width` split at
/// `times` ([`cell`]): flag = the interval is the censored one (the one rule of
/// `observables::last_cut`: the last interval cut at t_a), g = 0 when `pooled`.
fn duration_keys(stick: bool, max_index: u32, width: f64, times: Vec<f64>, pooled: bool, cell_of: (usize, usize)) -> Expr {
    let (list, count) = if stick { (name::STICK_DURATION, name::N_STICK) } else { (name::SLIP_DURATION, name::N_SLIP) };
    let rows = vec![col(name::REALIZATION), col(count), crate::observables::last_cut(stick)];
    element_keys(vec![list], rows, move |d, k, row| {
        let g = if pooled { 0 } else { group_of(row[0]) };
        Some(pack(max_index, cell(d[0], width, &times), k, row[2] != 0 && k == row[1], g, cell_of))
    })
}

/// The time cell of a duration d ≥ 0: φ(d) = ⌊d/width⌋ + #{τ ∈ `times` : τ ≤ d}, the cells of
/// width `width` split at the user's times τ (sorted, distinct), so that a curve is exact at
/// each τ as at each cell edge (module docs).
fn cell(d: f64, width: f64, times: &[f64]) -> i64 {
    let uniform = if d > 0.0 { (d / width) as i64 } else { 0 };
    uniform + times.iter().filter(|&&t| d >= t).count() as i64
}

/// The keys of the stick entries (position x, belt velocity v: `v_f` forward, −`v_r` reverse):
/// cell = the bin of the holding time d_s(x) on the evaluation times `ts` (increasing), how many
/// of them lie below it, so that the entry is held past `ts[j]` exactly when its bin exceeds j;
/// flag = the belt state is forward.
fn entry_keys(p: PerUnitMass, (v_f, v_r): (f64, f64), max_index: u32, ts: Vec<f64>, cell_of: (usize, usize)) -> Expr {
    element_keys(vec![name::STICK_ENTRY_POSITION, name::STICK_ENTRY_VELOCITY], vec![col(name::REALIZATION)], move |e, k, row| {
        let (x, v) = (e[0], e[1]);
        let d = p.stick_duration(x, if v > 0.0 { v_f } else { -v_r });
        Some(pack(max_index, ts.partition_point(|&t| t < d) as i64, k, v > 0.0, group_of(row[0]), cell_of))
    })
}
