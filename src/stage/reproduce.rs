//! `reproduce`: a scenario in; the dataset, its analysis, the figures and a report per cell out,
//! by calling the other stages in order into one directory.

use std::path::{Path, PathBuf};

use super::{analyze, figures, report, simulate};
use crate::analysis::{self, tails};
use crate::observables::Target;
use crate::progress::Control;
use crate::scenario::Input;
use crate::simulation::simulate::Shard;

/// Scenario overrides `reproduce` applies first (the user's sets come after and win).
pub const SETS: [&str; 2] = ["output.switch_times=true", "output.trajectories=3"];

/// What to run, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (its list-valued keys make a sweep)
    pub input: Input,
    /// the output directory
    pub out: PathBuf,
    /// overrides `run.realizations`
    pub realizations: Option<u64>,
    /// overrides `run.seed`
    pub seed: Option<u64>,
    /// stop simulating once every standard error is reached
    pub target_se: Vec<Target>,
    /// worker threads (None: all cores)
    pub threads: Option<usize>,
}

/// Where `reproduce --out DIR` puts each stage's output.
pub struct Layout {
    /// `DIR/dataset`, the `simulate` stage's output
    pub dataset: PathBuf,
    /// `DIR/analysis`, the `analyze` stage's output
    pub analysis: PathBuf,
    /// `DIR/figures`, the `figures` stage's output
    pub figures: PathBuf,
}

impl Layout {
    /// The layout below `dir`.
    pub fn new(dir: &Path) -> Layout {
        Layout { dataset: dir.join("dataset"), analysis: dir.join("analysis"), figures: dir.join("figures") }
    }

    /// The report of a sweep cell (`DIR/report.html` for a plain dataset).
    pub fn report(dir: &Path, cell: &str) -> PathBuf {
        if cell.is_empty() {
            dir.join("report.html")
        } else {
            dir.join("reports").join(cell).join("report.html")
        }
    }
}

/// A stage `reproduce` finished, as it finishes (the command line prints each at once).
pub enum Done<'a> {
    /// the dataset
    Simulated(&'a simulate::Outcome),
    /// the analysis
    Analysed(&'a analyze::Outcome),
    /// the figures
    Drew(&'a figures::Outcome),
    /// one cell's report
    Reported(&'a report::Outcome),
}

/// Run the stages; `done` hears each as it finishes. A failure removes what this run created
/// inside the output directory.
pub fn run(req: &Request, ctl: Control, done: &mut dyn FnMut(Done)) -> anyhow::Result<()> {
    let dir = req.out.clone();
    let top = crate::outdir::prepare_reproduce(&dir, &super::request::inputs(&req.input))?;
    let layout = Layout::new(&dir);
    // every later stage's output checked before the first runs (a file of the user's in an
    // earlier run's figures stopped it only after a new dataset and analysis had replaced theirs)
    crate::outdir::check_output(&layout.analysis, crate::outdir::Kind::Analysis, "--out")?;
    crate::outdir::check_output(&layout.figures, crate::outdir::Kind::Figures, "--out")?;
    crate::report::check_replaceable(&Layout::report(&dir, ""))?;
    // what this run creates inside DIR (the entries absent now) is removed again should a later
    // stage fail: a failing reproduce leaves nothing it created
    let fresh: Vec<PathBuf> = ["dataset", "dataset.trajectories", "analysis", "figures", "report.html", "report.md", "reports"]
        .iter()
        .map(|n| dir.join(n))
        .filter(|p| std::fs::symlink_metadata(p).is_err())
        .collect();
    let result = stages(req, &layout, ctl, done);
    if result.is_err() {
        for p in &fresh {
            match std::fs::symlink_metadata(p) {
                Ok(m) if m.is_dir() => drop(std::fs::remove_dir_all(p)),
                Ok(_) => drop(std::fs::remove_file(p)),
                Err(_) => {}
            }
        }
        return result;
    }
    top.keep();
    Ok(())
}

/// The stages in order: simulate, analyze, figures, and a report per cell.
fn stages(req: &Request, layout: &Layout, ctl: Control, done: &mut dyn FnMut(Done)) -> anyhow::Result<()> {
    let mut input = req.input.clone();
    input.sets.splice(0..0, SETS.map(String::from));
    let simulated = simulate::run(
        &simulate::Request {
            input,
            out: layout.dataset.clone(),
            shard: Shard::WHOLE,
            realizations: req.realizations,
            seed: req.seed,
            target_se: req.target_se.clone(),
            threads: req.threads,
        },
        ctl,
    )?;
    done(Done::Simulated(&simulated));
    let tail = tails::TailOptions { times: tails::PAPER_TAIL_TIMES.to_vec(), ..analysis::Options::default().tail };
    let options = analysis::Options { tail, ..Default::default() };
    let analysed = analyze::run(&analyze::Request { dataset: layout.dataset.clone(), out: Some(layout.analysis.clone()), options }, ctl)?;
    done(Done::Analysed(&analysed));
    let drawn = figures::run(&figures::Request { analysis: layout.analysis.clone(), out: layout.figures.clone() }, ctl)?;
    done(Done::Drew(&drawn));
    // one report per sweep cell (a plain dataset is the single cell with the empty path)
    for (cell, _) in &analysed.cells {
        let request = report::Request {
            dataset: layout.dataset.join(cell),
            analysis: layout.analysis.join(cell),
            figures: layout.figures.join(cell),
            out: Layout::report(&req.out, cell),
            exact: None,
        };
        done(Done::Reported(&report::run(&request, ctl)?));
    }
    Ok(())
}
