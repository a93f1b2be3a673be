//! `sensitivity`: a scenario with random keys in, first-order and total Sobol indices with
//! bootstrap intervals out ([`crate::sensitivity`]).

use std::path::PathBuf;

use anyhow::Context;

use super::request::inputs;
use crate::blame::usage;
use crate::outdir::check_separate;
use crate::progress::Control;
use crate::scenario::Input;
use crate::scenario::Overrides;
use crate::sensitivity::Index;

/// Pick-freeze samples by default.
pub const DEFAULT_REALIZATIONS: u64 = 2000;

/// What to estimate, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (one scene; some key a distribution)
    pub input: Input,
    /// the output directory
    pub out: PathBuf,
    /// pick-freeze samples N (the run simulates N·(d+3) realizations for d random keys)
    pub realizations: u64,
    /// overrides `run.seed`
    pub seed: Option<u64>,
}

/// What `sensitivity` estimated.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// one row per (output, input)
    pub rows: Vec<Index>,
    /// the pick-freeze samples
    pub realizations: u64,
}

impl Outcome {
    /// The tables written, with their definitions.
    pub fn tables(&self) -> Vec<(&'static crate::table::Def, crate::table::Table)> {
        crate::sensitivity::tables(&self.rows)
    }
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    if req.realizations < 2 || req.realizations > 100_000_000 {
        return Err(usage(format!("--realizations {}: must be between 2 and 100000000", req.realizations)));
    }
    check_separate(&req.out, "--out", &inputs(&req.input))?;
    let mut scenario = req.input.resolve()?;
    Overrides { realizations: None, seed: req.seed }.apply(&mut scenario);
    scenario.check()?;
    scenario.refuse_sweep("sensitivity")?;
    let rows = crate::sensitivity::run(&scenario, req.realizations, &req.out, ctl).context("sensitivity")?;
    Ok(Outcome { rows, realizations: req.realizations })
}
