//! The `simulate` stage: a scenario in, one Parquet part file out.
//!
//! Realizations are cut into fixed chunks ([`Ensemble::chunk_len`]); windows of chunks run in
//! parallel on a rayon pool while a writer thread streams the previous window to Parquet, so
//! memory stays bounded by a few windows whatever the number of realizations.

use std::path::PathBuf;
use std::str::FromStr;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::dataset::{DatasetError, PartWriter, Rows, SCHEMA_VERSION};
use crate::ensemble::{Ensemble, Outcome, RunError};
use crate::rng::GENERATOR;
use crate::scenario::Scenario;
use crate::trajectory;

/// Shard `index` of `count` (`--shard I/N`): the contiguous realization range
/// `[⌊index·total/count⌋, ⌊(index+1)·total/count⌋)` of the whole run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    pub fn range(&self, total: u64) -> std::ops::Range<u64> {
        let at = |i: u64| (i as u128 * total as u128 / self.count as u128) as u64;
        at(self.index)..at(self.index + 1)
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s:?}: expected I/N with 0 <= I < N, e.g. 0/4");
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
    pub out: PathBuf,
    pub shard: Shard,
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
    pub progress: bool,
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct Summary {
    pub path: PathBuf,
    pub realizations: u64,
    pub seconds: f64,
    pub total_sticks: u64,
}

#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(transparent)]
    Run(#[from] RunError),
    #[error("--threads: {0}")]
    Threads(String),
}

/// Key-value metadata recorded in every part file.
pub fn provenance(scenario: &Scenario, shard: Shard) -> Vec<(String, String)> {
    let range = shard.range(scenario.realizations);
    [
        ("stickslip.schema_version", SCHEMA_VERSION.to_string()),
        ("stickslip.version", env!("CARGO_PKG_VERSION").to_string()),
        ("stickslip.scenario", scenario.to_toml()),
        ("stickslip.seed", scenario.seed.to_string()),
        ("stickslip.solver", scenario.solver.clone()),
        ("stickslip.generator", GENERATOR.to_string()),
        ("stickslip.poisson", "rand_distr 0.6.0 Poisson (Knuth for mean < 12, Ahrens-Dieter 1982 otherwise)".into()),
        ("stickslip.realizations", scenario.realizations.to_string()),
        ("stickslip.shard", format!("{}/{}", shard.index, shard.count)),
        ("stickslip.realization_range", format!("{}..{}", range.start, range.end)),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

/// Run the stage.
pub fn run(scenario: &Scenario, opts: &Options) -> Result<Summary, SimulateError> {
    let start = Instant::now();
    let threads = match opts.threads {
        Some(0) => return Err(SimulateError::Threads("must be at least 1".into())),
        Some(t) => t,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SimulateError::Threads(e.to_string()))?;
    let range = opts.shard.range(scenario.realizations);
    let ensemble = Ensemble::new(scenario);
    let writer = PartWriter::create(
        &opts.out,
        opts.shard.index,
        opts.shard.count,
        scenario.store_switch_times,
        provenance(scenario, opts.shard),
    )?;
    let progress = progress_bar(range.end - range.start, opts.progress);

    let chunk = ensemble.chunk_len();
    let chunks: Vec<std::ops::Range<u64>> = (range.start..range.end)
        .step_by(chunk as usize)
        .map(|lo| lo..(lo + chunk).min(range.end))
        .collect();
    let mut total_sticks = 0u64;
    let (computed, written) = std::thread::scope(|scope| {
        let (tx, rx) = sync_channel::<Rows>(2 * threads);
        let writer_thread = scope.spawn(move || -> Result<PartWriter, DatasetError> {
            let mut writer = writer;
            for rows in rx {
                writer.write(rows)?;
            }
            Ok(writer)
        });
        let computed = (|| -> Result<(), RunError> {
            for window in chunks.chunks(4 * threads) {
                let rows: Vec<Result<Rows, RunError>> =
                    pool.install(|| window.par_iter().map(|r| ensemble.rows(r.clone())).collect());
                for r in rows {
                    let r = r?;
                    progress.inc(r.len() as u64);
                    total_sticks += r.total_sticks();
                    if tx.send(r).is_err() {
                        return Ok(()); // the writer failed; its error is reported below
                    }
                }
            }
            Ok(())
        })();
        drop(tx);
        (computed, writer_thread.join().expect("writer thread does not panic"))
    });
    progress.finish_and_clear();
    computed?;
    let writer = written?;
    // Trajectories (Fig. 4) of realizations 0..N, written by the shard that holds realization 0.
    let trajectories = if scenario.trajectories > 0 && range.start == 0 {
        Some(write_trajectories(&ensemble, scenario, &opts.out)?)
    } else {
        None
    };
    let path = writer.commit().inspect_err(|_| {
        if let Some((tmp, _)) = &trajectories {
            let _ = std::fs::remove_file(tmp);
        }
    })?;
    if let Some((tmp, path)) = trajectories {
        std::fs::rename(&tmp, &path).map_err(|e| DatasetError::Write { path, source: Box::new(e) })?;
    }
    Ok(Summary { path, realizations: range.end - range.start, seconds: start.elapsed().as_secs_f64(), total_sticks })
}

/// Sample the first `output.trajectories` realizations into a temporary CSV in `dir`; returns
/// (temporary path, final path).
fn write_trajectories(ensemble: &Ensemble, scenario: &Scenario, dir: &std::path::Path) -> Result<(PathBuf, PathBuf), SimulateError> {
    let mut csv = String::from(trajectory::CSV_HEADER);
    let mut out = Outcome::default();
    for index in 0..scenario.trajectories.min(scenario.realizations) {
        let sampler = ensemble.trajectory(index, scenario.trajectory_step, &mut out)?;
        trajectory::csv_rows(&mut csv, index, &sampler.samples, out.switches(), &out.record);
    }
    let path = dir.join("trajectories.csv");
    let tmp = dir.join(".trajectories.csv.tmp");
    std::fs::write(&tmp, csv).map_err(|e| DatasetError::Write { path: path.clone(), source: Box::new(e) })?;
    Ok((tmp, path))
}

fn progress_bar(len: u64, enabled: bool) -> ProgressBar {
    if !enabled {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("simulate {bar:40} {pos}/{len} realizations  {per_sec}  eta {eta}")
            .expect("valid template"),
    );
    bar
}
