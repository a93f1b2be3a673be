//! The polars queries of `analyze`: every statistic starts as a lazy query over `scan_parquet`
//! of the part files, run on polars' streaming engine; Rust finishes on the small aggregated
//! tables (see [`super`]). polars' Rust API changes between minor versions; it is pinned in
//! Cargo.toml.
//!
//! **One pass, every aggregate.** The part files of every cell (one plain dataset, or the cells
//! of a sweep) are scanned into one per-realization frame: its slot (cell × 20 + its jackknife
//! group, realization mod 20), its read count (for the convergence table), the value of every analysed observable
//! ([`Observable::expr`], the one censoring rule), one flag per validation rule, and the tails'
//! per-batch counts and extremes ([`super::tail_counts`]). polars decodes each column once and
//! evaluates these expressions on its threads, batch by batch; each batch is handed over as it
//! comes ([`LazyFrame::sink_batches`]) and folded into every aggregate it feeds in one pass over
//! its columns ([`super::fold`]: exact integer power sums, dyadic histogram counts, joint
//! counts, convergence sums, tails' counts, broken rules). The aggregates are integer sums,
//! counts and extremes, so they do not depend on the order the batches come in: the tables are
//! bit-identical for any thread count, batch size and shard split.
//!
//! The rows are scanned in runs of [`RUN_ROWS`] (one query each, so that memory stays that of
//! a run, whatever N), and the observables in batches of at most [`SERIES_PER_QUERY`] (each a
//! full pass: a frame's width is a column per observable).
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
//! **Validation** is in the same scan: the rules are flags counted by the fold; only when one is
//! broken does [`locate`] look for the first offending file, row and column, to name them
//! ([`super::rules`]).

use polars::prelude::*;

use super::exact::Sums;
use super::fold::{cut, extreme, flag, tail_keys, value, Batch, Fold, READ, SLOT};
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

/// The jackknife group's column in the pilot.
const GROUP: &str = "__group";

/// The per-realization frame of one part file for the main query (see [`super::fold`]; its
/// read position of row 0 in its cell is `position`), and the number of its rules.
fn file_frame(
    data: &Dataset,
    file: usize,
    cell: usize,
    (offset, rows, position): (u64, u64, u64),
    plan: &Plan,
    batch: &Batch,
) -> PolarsResult<(LazyFrame, usize)> {
    let t_a = data.scenario.run.duration;
    let rules = if batch.extras { rules(data.file_starts[file], data) } else { Vec::new() };
    let n_rules = rules.len();
    // the observables whose values this batch needs: its own, and those of the pairs and the
    // convergence table in the batch that does them
    let mut members: Vec<usize> = batch.owned.clone();
    if batch.extras {
        members.extend(plan.pairs.iter().flat_map(|&(i, j)| [i, j]).chain(plan.convergence.iter().copied()));
    }
    members.sort_unstable();
    members.dedup();
    let group = (col(crate::simulation::dataset::columns::REALIZATION) % lit(GROUPS as i64)).cast(DataType::Int64);
    let mut cols = vec![(group + lit((cell * GROUPS) as i64)).alias(SLOT)];
    if batch.extras && !plan.convergence.is_empty() {
        // the realization's read count k in its cell (its convergence bucket is found by the fold)
        cols.push((col(ROW).cast(DataType::Int64) + lit(position as i64 + 1)).alias(READ));
    }
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
    // the tails' per-batch counts and extremes (module docs of `tail_counts`)
    if let (true, Some(tails)) = (batch.extras, plan.tails) {
        let keys = tail_counts::keys(&tails[cell], cell, tails.len());
        cols.extend(keys.into_iter().enumerate().map(|(v, k)| k.alias(tail_keys(v))));
        if tails[cell].tails_state {
            let extremes = tail_counts::extreme_columns(&tails[cell]);
            cols.extend(extremes.into_iter().enumerate().map(|(j, e)| e.cast(DataType::Int64).alias(extreme(j))));
        }
    }
    Ok((scan(&data.files[file], None, true)?.slice(offset as i64, rows as IdxSize).select(cols), n_rules))
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
    let rows: u64 = cells.iter().map(|d| d.rows).sum();
    loop {
        ctl.progress.start("analyze", rows * batches(plan).len() as u64);
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
    let mut out: Vec<Aggregates> = cells.iter().map(|_| Aggregates::new(plan)).collect();
    for batch in batches(plan) {
        let fold = scan_batch(cells, plan, pilots, &batch, ctl)?;
        if fold.broken().iter().any(|&b| b > 0) {
            return Err(locate(cells));
        }
        fold.finish(&mut out);
    }
    unchanged(cells)?;
    Ok(out)
}

/// Realizations per query: polars keeps what a query decoded until the query ends (measured:
/// one query over 10^6 realizations peaked at 1.9 GiB, whatever the allocator and however fast
/// the fold took the batches), so the rows are scanned in runs, one query each, whose folds add
/// up exactly. A run is one row group of the files `simulate` writes
/// ([`crate::simulation::dataset`]), decoded on every core ([`super::decode_on_every_core`]).
const RUN_ROWS: u64 = 131_072;

/// Observables per query: a query's frame holds a column per observable for each batch of rows
/// in flight, so more observables (a large `--max-index`) are split over queries, each a full
/// scan.
const SERIES_PER_QUERY: usize = 64;

/// The queries of the main pass: the observables of each, the first doing the rest too.
fn batches(plan: &Plan) -> Vec<Batch> {
    let n = plan.series.len();
    (0..n.max(1))
        .step_by(SERIES_PER_QUERY)
        .enumerate()
        .map(|(b, start)| Batch { owned: (start..(start + SERIES_PER_QUERY).min(n)).collect(), extras: b == 0 })
        .collect()
}

/// One query of the main pass: every part file of every cell scanned, run by run, into the
/// per-realization frame, whose batches polars hands over (in any order) to be folded
/// ([`super::fold`]) while it reads on. The fold runs on this thread; the runs' queries, one
/// after the other, on another, so that decoding and folding overlap (the channel holds two
/// batches). When the fold stops (an error, a cancel), the query running stops at its next
/// batch and no other starts.
fn scan_batch(cells: &[&Dataset], plan: &Plan, pilots: &[Pilot], batch: &Batch, ctl: Control) -> PolarsResult<Fold> {
    // runs of at most RUN_ROWS rows: (cell, file, first row, rows, read position of the file's
    // row 0 in its cell)
    let mut runs: Vec<Vec<(usize, usize, u64, u64, u64)>> = vec![Vec::new()];
    let mut filled = 0;
    for (c, data) in cells.iter().enumerate() {
        let mut position = 0;
        for f in 0..data.files.len() {
            let rows = data.file_rows[f];
            let mut offset = 0;
            while offset < rows {
                if filled == RUN_ROWS {
                    runs.push(Vec::new());
                    filled = 0;
                }
                let take = (RUN_ROWS - filled).min(rows - offset);
                runs.last_mut().expect("a run").push((c, f, offset, take, position));
                (offset, filled) = (offset + take, filled + take);
            }
            position += rows;
        }
    }
    let args =
        UnionArgs { parallel: true, rechunk: false, to_supertypes: false, diagonal: false, strict: true, from_partitioned_ds: false, maintain_order: false };
    let (send, receive) = std::sync::mpsc::sync_channel::<DataFrame>(2);
    let mut queries = Vec::new();
    let mut n_rules = 0;
    for run in runs.iter().filter(|r| !r.is_empty()) {
        let mut frames = Vec::new();
        for &(c, f, offset, rows, position) in run {
            let (frame, rules) = file_frame(cells[c], f, c, (offset, rows, position), plan, batch)?;
            n_rules = rules;
            frames.push(frame);
        }
        let send = send.clone();
        // (a batch that cannot be sent: the fold stopped, so the query stops too)
        queries.push(concat(frames, args)?.sink_batches(PlanCallback::new(move |df: DataFrame| Ok(send.send(df).is_err())), false, None)?);
    }
    drop(send);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let query = || -> PolarsResult<()> {
        for q in queries {
            if stop.load(std::sync::atomic::Ordering::Relaxed) {
                break;
            }
            q.collect_with_engine(Engine::Streaming)?;
        }
        Ok(())
    };
    let extremes = match plan.tails {
        Some(t) if batch.extras && t[0].tails_state => tail_counts::extreme_columns(&t[0]).len(),
        _ => 0,
    };
    let mut fold = Fold::new(plan, pilots, batch, n_rules, extremes);
    std::thread::scope(|scope| {
        let running = scope.spawn(query);
        let mut stopped: PolarsResult<()> = Ok(());
        loop {
            let df = match receive.recv_timeout(std::time::Duration::from_millis(50)) {
                Ok(df) => df,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) if !running.is_finished() => continue,
                // (the query is done: what it sent before is still queued)
                Err(_) => match receive.try_recv() {
                    Ok(df) => df,
                    Err(_) => break,
                },
            };
            if ctl.check().is_err() {
                stopped = Err(polars_err!(ComputeError: "interrupted"));
                break;
            }
            if let Err(e) = fold.add(&df) {
                stopped = Err(e);
                break;
            }
            ctl.progress.advance(df.height() as u64);
        }
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        drop(receive);
        let ran = running.join().unwrap_or_else(|_| Err(polars_err!(ComputeError: "the scan failed")));
        stopped.and(ran)
    })?;
    Ok(fold)
}
