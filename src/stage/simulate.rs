//! `simulate`: a scenario (a sweep too) in, dataset part files out
//! ([`crate::simulation::simulate`] runs each cell).

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::request::inputs;
use crate::blame::usage;
use crate::observables::Target;
use crate::outdir::DatasetDir;
use crate::progress::Control;
use crate::scenario::Input;
use crate::scenario::{Cell, Overrides, Scenario};
use crate::simulation::simulate::{self, Shard, Summary};

/// What to simulate, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (its list-valued keys make a sweep)
    pub input: Input,
    /// the dataset directory (`--out`)
    pub out: PathBuf,
    /// which part of the run (`--shard I/N`)
    pub shard: Shard,
    /// overrides `run.realizations` (the cap, with targets)
    pub realizations: Option<u64>,
    /// overrides `run.seed`
    pub seed: Option<u64>,
    /// stop once every standard error is reached (`--target-se`)
    pub target_se: Vec<Target>,
    /// worker threads (None: all cores; the rows do not depend on it)
    pub threads: Option<usize>,
}

/// What `simulate` wrote: one summary per cell (one for a plain scene), in cell order.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// each cell's part file and counts
    pub summaries: Vec<Summary>,
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    if let Some(s) = req.seed.filter(|&s| s > i64::MAX as u64) {
        return Err(usage(format!("--seed {s}: must be at most {}", i64::MAX)));
    }
    if let Some(n) = req.realizations.filter(|&n| n == 0 || n > crate::scenario::MAX_REALIZATIONS) {
        return Err(usage(format!("--realizations {n} (run.realizations): must be between 1 and {}", crate::scenario::MAX_REALIZATIONS)));
    }
    if let Some((_, t)) = req.target_se.iter().enumerate().find(|(i, t)| req.target_se[..*i].iter().any(|u| u.quantity == t.quantity)) {
        return Err(usage(format!("--target-se {}: the quantity is given twice; give one target per quantity", t.quantity)));
    }
    simulate::worker_threads(req.threads)?;
    let cells = req.input.resolve_sweep(Overrides { realizations: req.realizations, seed: req.seed })?;
    same_shape(&req.out, &cells)?;
    let plans = cells.iter().map(|c| Ok((c.path.clone(), c.scenario.plan()?))).collect::<Result<Vec<_>, crate::scenario::ScenarioError>>()?;
    for (path, plan) in &plans {
        simulate::joins(&req.out.join(path), plan, req.shard).map_err(usage)?;
    }
    let dir = DatasetDir::prepare(&req.out, &inputs(&req.input))?;
    if let Some(sc) = cells.first().map(|c| &c.scenario).filter(|sc| slow_default_numerics(sc)) {
        ctl.progress.note(&format!(
            "note: this scene has no closed form, so `auto` runs {} at the default [numerics], the paper's ode45 settings (rtol = atol = 1e-9, max_step = 1e-4): accurate but slow. `stickslip tradeoff` finds the cheapest setting accurate enough for this scene (`stickslip scenes stribeck` shows one)",
            sc.solver().name()
        ));
    }
    let opts = simulate::Options { out: req.out.clone(), shard: req.shard, threads: req.threads };
    let summaries = simulate::sweep(&plans, &req.out, &opts, &Target::tracked(&req.target_se), ctl).context("simulate")?;
    dir.commit();
    Ok(Outcome { summaries })
}

/// Whether `auto` chose a numerical method for a scene without closed forms and the scenario
/// left `[numerics]` at the paper's ode45 settings (a user's first Stribeck run would otherwise
/// take hundreds of times longer than needed without a word).
fn slow_default_numerics(sc: &Scenario) -> bool {
    use crate::solver::SolverKind;
    sc.run.solver == SolverKind::Auto && sc.solver() != SolverKind::Exact && sc.numerics == Scenario::paper().numerics
}

/// A run added to a dataset directory has the shape of what is there: a plain run beside plain
/// parts, a sweep beside the cells of a sweep of the same keys (else `analyze` would refuse the
/// directory afterwards, naming two runs).
fn same_shape(out: &Path, cells: &[Cell]) -> anyhow::Result<()> {
    let Ok(entries) = std::fs::read_dir(out) else { return Ok(()) };
    let keys = |path: &str| path.split('/').next().and_then(|c| c.split_once('=')).map(|(k, _)| k.to_string());
    let ours = cells.first().and_then(|c| keys(&c.path));
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let theirs = if name.starts_with("part-") && name.ends_with(".parquet") {
            None
        } else if entry.path().is_dir() && name.contains('=') && !name.starts_with('.') {
            keys(&name)
        } else {
            continue;
        };
        if theirs != ours {
            let shown = |k: &Option<String>| k.as_ref().map_or("a plain run (part files at the top)".to_string(), |k| format!("a sweep of {k}"));
            return Err(usage(format!(
                "--out {} holds {}, and this run is {}: analyze could not read the two as one dataset; choose another --out",
                out.display(),
                shown(&theirs),
                shown(&ours)
            )));
        }
    }
    Ok(())
}
