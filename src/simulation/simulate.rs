//! The simulate path's driver: a run plan in, one Parquet part file out (the `simulate` stage
//! above resolves the scenario and its sweep into plans).
//!
//! Realizations are cut into fixed chunks ([`Ensemble::chunk_len`]); windows of chunks run in
//! parallel on a rayon pool while a writer thread streams the previous window to Parquet, so
//! memory stays bounded by a few windows whatever the number of realizations.

use std::path::PathBuf;
use std::str::FromStr;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

use rayon::prelude::*;

use arrow_schema::Schema;

use crate::metadata as meta;
use crate::outdir::{Created, DatasetDir, Lock, OutDirError, TempFile};
use crate::progress::{Cancelled, Control};
use crate::simulation::dataset::{DatasetError, Finished, Layout, PartWriter, Rows, SCHEMA_VERSION};
use crate::simulation::ensemble::{Ensemble, Outcome, RunError};
use crate::simulation::plan::Plan;
use crate::simulation::precision::{Targets, Tracker};
use crate::simulation::rng::GENERATOR;
use crate::simulation::trajectory;

/// Shard `index` of `count` (`--shard I/N`): the contiguous realization range
/// `[⌊index·total/count⌋, ⌊(index+1)·total/count⌋)` of the whole run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// I, 0-based (< `count`)
    pub index: u64,
    /// N, the number of shards (1..=99,999)
    pub count: u64,
}

impl Shard {
    /// The whole run as one shard (`0/1`).
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// The realization range of this shard in a run of `total` realizations.
    pub fn range(&self, total: u64) -> std::ops::Range<u64> {
        let at = |i: u64| (i as u128 * total as u128 / self.count as u128) as u64;
        at(self.index)..at(self.index + 1)
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s:?}: expected I/N with 0 <= I < N <= 99999, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (i.trim().parse::<u64>().map_err(|_| bad())?, n.trim().parse::<u64>().map_err(|_| bad())?);
        if count == 0 || index >= count || count > 99_999 {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// How to run the stage.
#[derive(Debug, Clone)]
pub struct Options {
    /// the dataset directory (`--out`)
    pub out: PathBuf,
    /// which part of the run to simulate
    pub shard: Shard,
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct Summary {
    /// the part file written
    pub path: PathBuf,
    /// realizations written (fewer than asked when `--target-se` stopped the run early)
    pub realizations: u64,
    /// wall-clock time of the run [s]
    pub seconds: f64,
    /// Σ S_T over the realizations written
    pub total_sticks: u64,
    /// with `--target-se`: whether every target was met (else the cap was reached), and the SEs
    pub targets: Option<(bool, String)>,
}

/// Why `simulate` failed.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// Writing the dataset failed.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// The output directory could not be prepared.
    #[error(transparent)]
    Out(#[from] OutDirError),
    /// A realization could not be solved.
    #[error(transparent)]
    Run(#[from] RunError),
    /// `--threads` out of range.
    #[error("--threads {0}: must be between 1 and {MAX_THREADS}")]
    Threads(usize),
    /// The worker thread pool could not be started.
    #[error("cannot start worker threads: {0}")]
    Pool(String),
    /// The caller cancelled the run (Ctrl-C in a Python session).
    #[error("interrupted")]
    Cancelled(#[from] Cancelled),
    /// A cell of a sweep failed.
    #[error("sweep cell {cell}: {source}")]
    Cell {
        /// the cell's hive path (`name=value/...`)
        cell: String,
        /// why it failed
        source: Box<SimulateError>,
    },
}

impl crate::blame::Blame for SimulateError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            SimulateError::Threads(_) => Some(crate::blame::Culprit::Usage),
            SimulateError::Dataset(d) => d.blame(),
            SimulateError::Out(o) => o.blame(),
            SimulateError::Run(_) | SimulateError::Pool(_) | SimulateError::Cancelled(_) => None,
            SimulateError::Cell { source, .. } => source.blame(),
        }
    }
}

/// Most worker threads accepted (`--threads`).
pub const MAX_THREADS: usize = 1024;

/// The worker threads for `--threads` (None: all cores), checked.
pub fn worker_threads(asked: Option<usize>) -> Result<usize, SimulateError> {
    match asked {
        Some(t) if t == 0 || t > MAX_THREADS => Err(SimulateError::Threads(t)),
        Some(t) => Ok(t),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// The provenance a part added to `dir` must share with the parts already there (but the one it
/// replaces): another seed, scenario (its size included), solver, generator or schema would make
/// a directory `analyze` refuses afterwards. `Err` names the other part and the first key.
pub fn joins(dir: &std::path::Path, plan: &Plan, shard: Shard) -> Result<(), String> {
    const SHARED: [&str; 5] = ["stickslip.seed", "stickslip.solver", "stickslip.generator", meta::SCHEMA_VERSION, meta::SCENARIO];
    let Ok(entries) = std::fs::read_dir(dir) else { return Ok(()) };
    let all = provenance(plan, shard);
    let ours: Vec<(String, String)> = SHARED.iter().filter_map(|key| all.iter().find(|(k, _)| k == key).cloned()).collect();
    let own = crate::simulation::dataset::part_name(shard.index, shard.count);
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if !(name.starts_with("part-") && name.ends_with(".parquet")) || name == own {
            continue;
        }
        let Some(theirs) = crate::metadata::footer(&entry.path()) else { continue };
        for (key, value) in &ours {
            let other = theirs.iter().find(|(k, _)| k == key).and_then(|(_, v)| v.clone());
            if other.as_deref() != Some(value.as_str()) {
                let what = if key == meta::SCENARIO {
                    "its scenario differs (another scene or size)".to_string()
                } else {
                    format!("its {key} is {}, this run's {value}", other.as_deref().unwrap_or("(absent)"))
                };
                return Err(format!(
                    "--out {} holds {name}, a part of another run ({what}): analyze could not read the two as one dataset; choose another --out",
                    dir.display()
                ));
            }
        }
    }
    Ok(())
}

/// Key-value metadata recorded in every part file.
pub fn provenance(plan: &Plan, shard: Shard) -> Vec<(String, String)> {
    let range = shard.range(plan.realizations);
    [
        (meta::SCHEMA_VERSION, SCHEMA_VERSION.to_string()),
        (meta::VERSION, env!("CARGO_PKG_VERSION").to_string()),
        (meta::SCENARIO, plan.scenario_toml.clone()),
        ("stickslip.seed", plan.seed.to_string()),
        ("stickslip.solver", plan.solver.name().to_string()),
        ("stickslip.generator", GENERATOR.to_string()),
        ("stickslip.poisson", "rand_distr 0.6.0 Poisson (Knuth for mean < 12, Ahrens-Dieter 1982 otherwise)".into()),
        (meta::REALIZATIONS, plan.realizations.to_string()),
        ("stickslip.shard", format!("{}/{}", shard.index, shard.count)),
        (meta::REALIZATION_RANGE, format!("{}..{}", range.start, range.end)),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .chain(plan.belt_file.as_deref().and_then(log_digest).map(|d| ("stickslip.belt_file_fnv1a64".to_string(), d)))
    .collect()
}

/// The content of a recorded belt's log, as FNV-1a 64 of its bytes in hex: the provenance says
/// which log a dataset was simulated from (the scenario records only its path), and the parts
/// of one run must agree on it. (Not a cryptographic digest: it tells edits apart, not forgeries.)
fn log_digest(path: &str) -> Option<String> {
    let bytes = std::fs::read(path).ok()?;
    let h = bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
    Some(format!("{h:016x}"))
}

/// A simulated part, complete under temporary names: [`Pending::commit`] moves it into place
/// (a sweep commits its cells only when all of them are complete).
#[derive(Debug)]
pub struct Pending {
    part: Finished,
    /// the trajectory tables under temporary names, and the directories made for them
    trajectories: Option<(Vec<(TempFile, Lock)>, Created)>,
    summary: Summary,
}

impl Pending {
    /// Rename the part (and trajectories) into place.
    pub fn commit(self) -> Result<Summary, SimulateError> {
        let path = self.part.commit()?;
        if let Some((tables, created)) = self.trajectories {
            for (tmp, _lock) in tables {
                tmp.commit()?;
            }
            created.keep();
        }
        Ok(Summary { path, ..self.summary })
    }
}

/// Simulate every cell of a sweep (the one cell of a plain run: empty path) into `out`, and
/// commit them together: each cell is simulated into a temporary part first, and the parts are
/// renamed into place only when all cells succeeded, so a failure leaves the previous sweep, if
/// any, untouched (each pending part's temporary and the cell directories it created go).
/// `opts.out` is replaced by each cell's directory.
pub fn sweep(cells: &[(String, Plan)], out: &std::path::Path, opts: &Options, targets: &Targets, ctl: Control) -> Result<Vec<Summary>, SimulateError> {
    let mut pending = Vec::with_capacity(cells.len());
    for (path, plan) in cells {
        let opts = Options { out: if path.is_empty() { out.to_path_buf() } else { out.join(path) }, ..opts.clone() };
        match compute_until(plan, &opts, targets, ctl) {
            Ok(p) => pending.push(p),
            Err(e) if path.is_empty() => return Err(e),
            Err(e) => return Err(SimulateError::Cell { cell: path.clone(), source: Box::new(e) }),
        }
    }
    pending.into_iter().map(Pending::commit).collect()
}

/// Run the stage: simulate and commit the part file into `opts.out`.
pub fn run(plan: &Plan, opts: &Options) -> Result<Summary, SimulateError> {
    let dir = DatasetDir::prepare(&opts.out, &[])?;
    let summary = compute_until(plan, opts, &Targets::none(), Control::silent())?.commit()?;
    dir.commit();
    Ok(summary)
}

/// Simulate into a finished, uncommitted part file (`opts.out` is a prepared dataset directory),
/// stopping at the first chunk boundary where every `targets` standard error is met
/// ([`crate::simulation::precision`]; `run.realizations` is the cap). A shard applies the targets to its own
/// block of realizations and records the block (`stickslip.shard_block`).
/// `ctl` is told each window of chunks written and asked between windows.
pub fn compute_until(plan: &Plan, opts: &Options, targets: &Targets, ctl: Control) -> Result<Pending, SimulateError> {
    let start = Instant::now();

    let threads = worker_threads(opts.threads)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| SimulateError::Pool(e.to_string()))?;
    let range = opts.shard.range(plan.realizations);
    let ensemble = Ensemble::new(plan);
    let layout = Layout { switch_times: plan.switch_times, drawn: ensemble.scene().columns(), chain: ensemble.has_chain() };
    // with targets, the realizations written are known only at the end: their metadata is
    // appended when the part is finished
    // (sharded: each shard stops within its block at its own targets; the run's size stays the
    // index space the blocks split, and the block is recorded for the reader)
    let sharded = opts.shard != Shard::WHOLE;
    let mut metadata = provenance(plan, opts.shard);
    if !targets.is_empty() {
        metadata.retain(|(k, _)| k != meta::REALIZATION_RANGE && (sharded || k != meta::REALIZATIONS));
    }
    let writer = PartWriter::create(&opts.out, opts.shard.index, opts.shard.count, layout, metadata)?;
    let progress = ctl.progress;
    progress.start("simulate", range.end - range.start);

    // chunks of realizations, generated lazily (a run may have ~10^12 of them)
    let chunk = ensemble.chunk_len();
    let mut chunks = (range.start..range.end).step_by(chunk as usize).map(|lo| lo..(lo + chunk).min(range.end)).peekable();
    let mut total_sticks = 0u64;
    let mut tracker = Tracker::new(targets);
    let mut reached = range.end;
    let (computed, written) = std::thread::scope(|scope| {
        // The writer runs beside the workers; the queue holds about four windows, so the workers
        // never wait for the encoder while it catches up.
        let (tx, rx) = sync_channel::<Rows>(16 * threads);
        let writer_thread = scope.spawn(move || -> Result<PartWriter, DatasetError> {
            let mut writer = writer;
            for rows in rx {
                writer.write(rows)?;
            }
            Ok(writer)
        });
        let computed = (|| -> Result<(), SimulateError> {
            while chunks.peek().is_some() {
                ctl.check()?;
                let window: Vec<std::ops::Range<u64>> = chunks.by_ref().take(8 * threads).collect();
                let rows: Vec<Result<(Rows, Tracker), RunError>> = pool.install(|| window.par_iter().map(|r| rows(&ensemble, r.clone(), targets)).collect());
                for (r, range) in rows.into_iter().zip(&window) {
                    let (r, t) = r?;
                    progress.advance(r.len() as u64);
                    total_sticks += r.total_sticks();
                    if tx.send(r).is_err() {
                        return Ok(()); // the writer failed; its error is reported below
                    }
                    if !targets.is_empty() {
                        tracker.merge(&t);
                        progress.message(&tracker.describe(targets));
                        if tracker.met(targets) {
                            reached = range.end;
                            return Ok(());
                        }
                    }
                }
            }
            Ok(())
        })();
        drop(tx);
        (computed, writer_thread.join().expect("writer thread does not panic"))
    });
    progress.finish();
    computed?;
    let mut written = written?;
    if !targets.is_empty() {
        let rule = targets.names.iter().zip(&targets.se).map(|(t, se)| format!("{t}={}", crate::shown::short(*se))).collect::<Vec<_>>().join(", ");
        let reached_se = targets
            .names
            .iter()
            .zip(tracker.errors())
            .map(|(t, se)| format!("{t}={}", se.map_or("none".into(), |x| format!("{x:e}"))))
            .collect::<Vec<_>>()
            .join(", ");
        let mut written_meta = vec![(meta::REALIZATION_RANGE, format!("{}..{reached}", range.start))];
        if sharded {
            written_meta.push((meta::SHARD_BLOCK, format!("{}..{}", range.start, range.end)));
        } else {
            written_meta.push((meta::REALIZATIONS, reached.to_string()));
        }
        for (k, v) in written_meta.into_iter().chain([
            ("stickslip.target_se", rule),
            ("stickslip.target_se_reached", reached_se),
            ("stickslip.target_se_met", tracker.met(targets).to_string()),
            ("stickslip.target_se_cap", plan.realizations.to_string()),
        ]) {
            written.append_metadata(k, &v);
        }
    }
    let part = written.finish()?;
    // Trajectories (Fig. 4) of realizations 0..N, written by the shard that holds realization 0.
    let trajectories = if plan.trajectories > 0 && range.start == 0 { Some(write_trajectories(&ensemble, plan, &opts.out)?) } else { None };
    let summary = Summary {
        path: part.path().to_owned(),
        realizations: reached - range.start,
        seconds: start.elapsed().as_secs_f64(),
        total_sticks,
        targets: (!targets.is_empty()).then(|| (tracker.met(targets), tracker.describe(targets))),
    };
    Ok(Pending { part, trajectories, summary })
}

/// Simulate one scene into memory: the dataset's Arrow record batches (its schema carries the
/// provenance as metadata), in realization order — the rows `simulate` writes, chunk for chunk.
/// `ctl` is told each window of chunks and asked between them (how a Python session's Ctrl-C
/// reaches the run).
pub fn batches(plan: &Plan, threads: Option<usize>, ctl: Control) -> Result<Vec<arrow_array::RecordBatch>, SimulateError> {
    let threads = worker_threads(threads)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| SimulateError::Pool(e.to_string()))?;
    let ensemble = Ensemble::new(plan);
    let layout = Layout { switch_times: plan.switch_times, drawn: ensemble.scene().columns(), chain: ensemble.has_chain() };
    let metadata: std::collections::HashMap<String, String> = provenance(plan, Shard::WHOLE).into_iter().collect();
    let chunk = ensemble.chunk_len();
    let total = plan.realizations;
    let mut chunks = (0..total).step_by(chunk as usize).map(|lo| lo..(lo + chunk).min(total)).peekable();
    let mut out = Vec::new();
    ctl.progress.start("simulate", total);
    while chunks.peek().is_some() {
        ctl.check()?;
        let window: Vec<std::ops::Range<u64>> = chunks.by_ref().take(8 * threads).collect();
        let rows: Vec<Result<(Rows, Tracker), RunError>> = pool.install(|| window.par_iter().map(|r| rows(&ensemble, r.clone(), &Targets::none())).collect());
        for r in rows {
            let rows = r?.0;
            ctl.progress.advance(rows.len() as u64);
            let batch = rows.into_batch(&layout);
            let schema = std::sync::Arc::new(batch.schema().as_ref().clone().with_metadata(metadata.clone()));
            out.push(batch.with_schema(schema).expect("the same fields"));
        }
    }
    ctl.progress.finish();
    Ok(out)
}

/// Write record batches made by [`batches`] as the dataset directory `out` — the part file
/// `simulate --out` writes for the same scene, with the same provenance. `plan` is the batches'
/// own (from their schema's `stickslip.scenario`).
pub fn write_batches(batches: &[arrow_array::RecordBatch], plan: &Plan, out: &std::path::Path) -> Result<PathBuf, SimulateError> {
    let dir = DatasetDir::prepare(out, &[])?;
    let ensemble = Ensemble::new(plan);
    let layout = Layout { switch_times: plan.switch_times, drawn: ensemble.scene().columns(), chain: ensemble.has_chain() };
    let mut writer = PartWriter::create(out, 0, 1, layout, provenance(plan, Shard::WHOLE))?;
    for b in batches {
        // (the schema without the provenance the batches carry: the file holds it in its footer)
        let plain = arrow_array::RecordBatch::try_new(std::sync::Arc::new(Schema::new(b.schema().fields().clone())), b.columns().to_vec())
            .map_err(|e| DatasetError::Write { path: out.to_owned(), source: Box::new(e) })?;
        writer.write_batch(&plain)?;
    }
    let path = writer.commit()?;
    dir.commit();
    Ok(path)
}

/// Simulate a contiguous range of realizations into dataset rows, and the targets' quantities.
fn rows(ensemble: &Ensemble, range: std::ops::Range<u64>, targets: &Targets) -> Result<(Rows, Tracker), RunError> {
    let mut rows = Rows::new(
        (ensemble.store_switch_times(), ensemble.has_chain()),
        ensemble.scene().columns().len(),
        (range.end - range.start) as usize,
        ensemble.list_len_hint(),
    );
    let mut tracker = Tracker::new(targets);
    let mut out = Outcome::default();
    for index in range {
        ensemble.realization(index, &mut out)?;
        rows.push(index, &out);
        if !targets.is_empty() {
            tracker.add(targets, &out);
        }
    }
    Ok((rows, tracker))
}

/// Sample the first `output.trajectories` realizations into the trajectory tables beside the
/// dataset ([`trajectory::dir_for`]), under temporary names (committed with the part).
fn write_trajectories(ensemble: &Ensemble, plan: &Plan, dir: &std::path::Path) -> Result<(Vec<(TempFile, Lock)>, Created), SimulateError> {
    let place = trajectory::dir_for(dir).ok_or_else(|| OutDirError {
        path: dir.to_owned(),
        message: "has no parent to put its trajectories beside".into(),
        refused: true,
    })?;
    let created = Created::dir_all(&place)?;
    let mut tables = trajectory::Tables::default();
    let mut out = Outcome::default();
    for index in 0..plan.trajectories.min(plan.realizations) {
        let sampler = ensemble.trajectory(index, plan.trajectory_step, &mut out)?;
        tables.push(index, &sampler.samples, out.switches(), out.velocities(), &out.record);
    }
    Ok((tables.write(&place, &plan.scenario_toml)?, created))
}
