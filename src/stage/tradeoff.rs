//! `tradeoff`: a scenario in; the solvers' speed against accuracy on the same realizations, and
//! the cheapest setting accurate enough, out ([`crate::tradeoff`]).

use std::path::PathBuf;

use anyhow::Context;

use super::request::inputs;
use crate::blame::usage;
use crate::outdir::check_separate;
use crate::progress::Control;
use crate::scenario::Input;
use crate::tradeoff::Row;

/// Realizations per setting by default.
pub const DEFAULT_REALIZATIONS: u64 = 100;

/// What to measure, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (one scene)
    pub input: Input,
    /// the output directory
    pub out: PathBuf,
    /// realizations per setting
    pub realizations: u64,
    /// recommend the cheapest setting whose bias on every Table 1 statistic is below this
    /// fraction of its standard error at the scenario's `run.realizations`
    pub bias_fraction: f64,
}

/// What `tradeoff` measured.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// one row per setting
    pub rows: Vec<Row>,
    /// the scenario's `run.realizations`, at which the biases are scored
    pub scored_at: u64,
    /// the realizations each setting ran
    pub realizations: u64,
}

impl Outcome {
    /// The tables written, with their definitions.
    pub fn tables(&self) -> Vec<(&'static crate::table::Def, crate::table::Table)> {
        crate::tradeoff::tables(&self.rows, self.realizations)
    }
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    if req.realizations == 0 {
        return Err(usage("--realizations must be at least 1"));
    }
    if !(req.bias_fraction > 0.0 && req.bias_fraction.is_finite()) {
        return Err(usage(format!("--bias-fraction {}: must be a positive number", req.bias_fraction)));
    }
    check_separate(&req.out, "--out", &inputs(&req.input))?;
    let scenario = req.input.resolve()?;
    scenario.refuse_sweep("tradeoff")?;
    let rows = crate::tradeoff::run(&scenario, req.realizations, req.bias_fraction, &req.out, ctl).context("tradeoff")?;
    Ok(Outcome { rows, scored_at: scenario.run.realizations, realizations: req.realizations })
}
