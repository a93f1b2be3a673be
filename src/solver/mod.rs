//! Solvers: given one belt path and initial state, report the mode changes on [0, t_a].
//!
//! Every solver answers the same question through the same interface, [`Solver::solve`], so the
//! ensemble, the dataset and any comparison between solvers are written once.

pub mod exact;
pub mod hybrid;
pub mod moreau;
pub mod rk;
pub mod smooth;

pub use exact::Exact;

use crate::model::Model;
use crate::scenario::Numerics;

use crate::events::Observer;

/// The deterministic input of one realization: belt sign at t = 0⁺, the effective switch
/// instants in (0, t_end) (sorted, no duplicates, see `BeltPath::effective_switches`), the belt
/// speed v0 [m/s] and the end of the window t_end = t_a [s].
#[derive(Debug, Clone, Copy)]
pub struct Drive<'a> {
    pub sign0: f64,
    pub switches: &'a [f64],
    pub speed: f64,
    pub t_end: f64,
}

/// Why a realization could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error("more than {limit} mode events before t = {t} s: the run would not finish (raise the friction or lower the stiffness?)")]
    EventBudget { limit: u64, t: f64 },
    #[error("more than numerics.step_budget = {limit} steps before t = {t} s (loosen the tolerances, raise the step, or raise the budget)")]
    StepBudget { limit: u64, t: f64 },
}

/// A method that integrates the oscillator over one realization.
pub trait Solver: Sync {
    /// Report every mode change of the realization with initial position `x0` [m] and velocity
    /// `xdot0` [m/s] to `obs`, in time order. Slip → slip reversals and grazing touches are not
    /// mode changes.
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError>;
}

/// The solver a scenario names (`run.solver`), ready to run.
#[derive(Debug, Clone, Copy)]
pub enum AnySolver {
    Exact(Exact),
    Hybrid(hybrid::Hybrid),
    Moreau(moreau::Moreau),
    Smooth(smooth::Smooth),
}

impl AnySolver {
    /// `name` is one of `scenario::SOLVERS` (validated there).
    pub fn new(name: &str, model: &Model, numerics: Numerics) -> AnySolver {
        match name {
            "rk45" => AnySolver::Hybrid(hybrid::Hybrid::new(model, hybrid::Method::Rk45, numerics)),
            "rk4" => AnySolver::Hybrid(hybrid::Hybrid::new(model, hybrid::Method::Rk4, numerics)),
            "moreau" => AnySolver::Moreau(moreau::Moreau::new(model, numerics)),
            "smooth" => AnySolver::Smooth(smooth::Smooth::new(model, numerics)),
            _ => AnySolver::Exact(Exact::new(model)),
        }
    }
}

impl Solver for AnySolver {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        match self {
            AnySolver::Exact(s) => s.solve(drive, x0, xdot0, obs),
            AnySolver::Hybrid(s) => s.solve(drive, x0, xdot0, obs),
            AnySolver::Moreau(s) => s.solve(drive, x0, xdot0, obs),
            AnySolver::Smooth(s) => s.solve(drive, x0, xdot0, obs),
        }
    }
}
