//! A run plan: everything the simulate path needs, resolved from a scenario by
//! [`crate::scenario::Scenario::plan`] — the scene (its parameters, belt process and random
//! keys), the initial-condition law, the solver, the seed, the run's size, what is recorded and
//! the provenance written with it. Nothing in `simulation/` reads a scenario's keys; the
//! scenario layer above builds this once and hands it down.

use crate::simulation::keys::{Key, Scene};
use crate::solver::{Numerics, SolverKind};

/// What to run.
#[derive(Debug, Clone)]
pub struct Plan {
    /// the scene each realization is drawn from
    pub scene: Scene,
    /// X0 [m] drawn uniformly on [lo, hi] (a point when lo = hi)
    pub position: [f64; 2],
    /// Ẋ0 [m/s] drawn uniformly on [lo, hi]
    pub velocity: [f64; 2],
    /// the solver (resolved: never `auto`)
    pub solver: SolverKind,
    /// the numerical solvers' settings
    pub numerics: Numerics,
    /// the run's seed (every realization's streams derive from it and the index)
    pub seed: u64,
    /// realizations in the run (the cap, with targets)
    pub realizations: u64,
    /// the largest natural rate ω [rad/s] a drawn realization may have, and the rule as words
    pub max_rate: (f64, String),
    /// store the instants of the belt's changes (column `switch_times`)
    pub switch_times: bool,
    /// realizations 0..N sampled as trajectories (0: none), every `trajectory_step` seconds
    pub trajectories: u64,
    /// s
    pub trajectory_step: f64,
    /// the resolved scenario as TOML (the provenance every part records)
    pub scenario_toml: String,
    /// a recorded belt's log (its digest is recorded too)
    pub belt_file: Option<String>,
}

/// The rate [1/s] that sets a realization's work, the key that sets it and its symbol: ω = √(k/m)
/// for `exact` (closed forms absorb any damping), the fastest of ω and the slip's damping
/// (c + σ_v)/m for a `numerical` solver (the largest eigenvalue of the linear part is at most
/// max(ω, (c + σ_v)/m): the step must resolve it); `damping_key` names the larger of c and σ_v.
pub fn fastest_rate(numerical: bool, omega: f64, damping_per_m: f64, damping_key: Key) -> (f64, Key, &'static str) {
    if numerical && damping_per_m > omega {
        (damping_per_m, damping_key, "(c + sigma_v)/m")
    } else {
        (omega, Key::Stiffness, "ω = √(k/m)")
    }
}
