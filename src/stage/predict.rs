//! `predict`: a scenario and the state now in; the next stick (the time to its start, its
//! duration, the slip after it, how it ends) out, exact where the scene allows and from
//! conditional Monte Carlo futures ([`crate::predict`]).

use std::path::PathBuf;

use anyhow::Context;

use super::request::{check_resolution, inputs};
use crate::blame::usage;
use crate::outdir::check_separate;
use crate::predict::{Prediction, State};
use crate::progress::Control;
use crate::scenario::Input;
use crate::scenario::Overrides;

/// The exact method's finest resolution by default.
pub const DEFAULT_RESOLUTION: u32 = 40;

/// What to predict from.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (one scene)
    pub input: Input,
    /// the state now: x [m], mass velocity [m/s], belt velocity [m/s] (one of the belt's states)
    pub state: (f64, f64, f64),
    /// the mass is stuck now
    pub stuck: bool,
    /// Monte Carlo futures (None: only where the exact method does not hold, 100,000)
    pub futures: Option<u64>,
    /// the futures' horizon [s] (None: 100 mean times between belt flips, within bounds)
    pub horizon: Option<f64>,
    /// the exact method's finest resolution (8 to 320)
    pub resolution: u32,
    /// overrides `run.seed` (the futures')
    pub seed: Option<u64>,
    /// also write `prediction.parquet` (and `stick_survival.parquet`) here
    pub out: Option<PathBuf>,
    /// also the exact densities, at this finest resolution (8 to 320; needs `out`)
    pub densities: Option<u32>,
}

impl Request {
    /// The defaults from `state` on `input`: exact where it holds, resolution 40, nothing written.
    pub fn new(input: Input, state: (f64, f64, f64)) -> Request {
        Request { input, state, stuck: false, futures: None, horizon: None, resolution: DEFAULT_RESOLUTION, seed: None, out: None, densities: None }
    }
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Prediction> {
    check_resolution("--resolution", req.resolution)?;
    if req.futures == Some(0) {
        return Err(usage("--futures must be at least 1"));
    }
    if let Some(h) = req.horizon.filter(|h| !(h.is_finite() && *h > 0.0)) {
        return Err(usage(format!("--horizon {h}: must be a positive number of seconds")));
    }
    if let Some(out) = &req.out {
        check_separate(out, "--out", &inputs(&req.input))?;
    }
    let mut scenario = req.input.resolve()?;
    Overrides { realizations: None, seed: req.seed }.apply(&mut scenario);
    scenario.check()?;
    scenario.refuse_sweep("predict")?;
    let (x, velocity, belt) = req.state;
    let state = State { x, velocity, belt, stuck: req.stuck };
    if let Some(n) = req.densities {
        check_resolution("--densities", n)?;
    }
    let opts = crate::predict::Options { resolution: req.resolution, futures: req.futures, horizon: req.horizon, densities: req.densities };
    crate::predict::run(&scenario, state, opts, req.out.as_deref(), ctl).context("predict")
}
