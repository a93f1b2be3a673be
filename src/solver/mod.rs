//! Solvers: given one realization's belt segments and initial state, report the mode changes on
//! [0, t_a].
//!
//! One driver ([`drive`]) owns the belt segments, the step and event budgets, the emission of
//! events and the trajectory sampling; each method only advances within a segment and says why it
//! stopped ([`Stop`]), so every method is compared, budgeted and sampled the same way. The methods:
//! [`exact`] (closed forms, generic over the slip form: undamped or damped), [`hybrid`] (rk45 and
//! rk4 with located events), [`moreau`] (time stepping of the set-valued law) and [`smooth`] (a
//! regularized law).

pub(crate) mod dop853;
pub(crate) mod exact;
pub(crate) mod hybrid;
mod method;
pub(crate) mod moreau;
mod observer;
pub(crate) mod rk;
pub(crate) mod smooth;

pub use method::{Drive, Event, Method, Numerics, Stop};
pub use observer::{Observer, Release};

use serde::{Deserialize, Serialize};

use crate::physics::{Damped, PerUnitMass, Undamped};

/// Why a realization could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// More than `limit` stops of the driver (a runaway realization).
    #[error("more than {limit} mode events before t = {t} s: the run would not finish (raise the friction or lower the stiffness?)")]
    EventBudget {
        /// the limit, [`EVENT_LIMIT`]
        limit: u64,
        /// the time reached [s]
        t: f64,
    },
    /// More integration steps than `numerics.step_budget`.
    #[error("more than numerics.step_budget = {limit} steps before t = {t} s (loosen the tolerances, raise the step, or raise the budget)")]
    StepBudget {
        /// the budget
        limit: u64,
        /// the time reached [s]
        t: f64,
    },
    /// The state overflowed to a non-finite value.
    #[error("the state became non-finite at t = {t} s (an overflow no step size avoids: the scene lies outside the range the solvers are proven on)")]
    NonFinite {
        /// the time reached [s]
        t: f64,
    },
    /// The events accumulate at an instant (a Zeno point) the event-driven method cannot pass.
    #[error("the contact's events accumulate at t = {t} s ({stops} stops within 1e-6 of the window): a Zeno point of chattering sticks no event-driven solver passes (an undamped stiff mode? give its spring a dashpot)")]
    Chatter {
        /// the time reached [s]
        t: f64,
        /// the stops counted
        stops: u64,
    },
    /// A value of the realization's row is not finite or breaks its column's rule (the writers'
    /// last guard, [`crate::simulation::events::Record::outside`]).
    #[error("column `{column}` would hold {value}, which is not {rule}: the scene lies outside the range the solvers are proven on")]
    Unwritable {
        /// the dataset column
        column: &'static str,
        /// the value, as shown
        value: String,
        /// what the column holds
        rule: &'static str,
    },
    /// A random key's draw cannot run; `drawn` says which and why.
    #[error("drawn parameters: {drawn}")]
    Drawn {
        /// the drawn keys (or values) at fault and why they cannot run
        drawn: String,
    },
}

/// At most this many stops per realization (a guard against runaway input, never reached by
/// physical scenarios: events are bounded by about two per half period and per belt switch).
pub const EVENT_LIMIT: u64 = 200_000_000;

/// Stops per window of the chatter guard of the event-driven methods ([`SolveError::Chatter`]): a
/// window that moves time by less than 1e-6 of t_a ends the run (they stop at events, segment
/// ends and, for chains, steps of 1/‖Ã‖, so a normal run moves far more per window; the
/// numerical methods have their step budget).
pub const CHATTER_STOPS: u64 = 100_000;

/// The one driver: run `method` over the segments of `drive` from `(x₀, ẋ₀)`, reporting every
/// change of mode to `obs` (and grid samples, when `obs` asks for them). Returns the
/// integration steps the method attempted ([`Method::steps`], 0 for `exact`).
pub fn drive<M: Method, O: Observer>(method: &mut M, drive: &Drive<'_>, x0: f64, xdot0: f64, step_budget: u64, obs: &mut O) -> Result<u64, SolveError> {
    let grid = obs.sample_step();
    if grid.is_some() {
        method.keep_pieces();
    }
    let motion = obs.wants_motion();
    let mut v = drive.velocities[0];
    emit(obs, method.start(x0, xdot0, v), v, Release::Start);
    if motion {
        obs.motion(xdot0, xdot0, v);
    }
    let (mut stops, mut sampled, mut window_start) = (0u64, 0.0, 0.0);
    let ends = drive.switches.iter().copied().chain(std::iter::once(drive.t_end));
    for (k, t1) in ends.enumerate() {
        loop {
            let stop = method.advance(t1, v);
            stops += 1;
            if let Some(step) = grid {
                sampled = sample(method, obs, sampled, step, v);
            }
            if motion {
                let (lo, hi) = method.velocity_range();
                obs.motion(lo, hi, v);
            }
            match stop {
                Stop::SegmentEnd => break,
                Stop::Event(e) => emit(obs, e, v, Release::Breakaway),
                Stop::Advanced => {}
            }
            if stops > EVENT_LIMIT {
                return Err(SolveError::EventBudget { limit: EVENT_LIMIT, t: method.time() });
            }
            if method.non_finite() {
                return Err(SolveError::NonFinite { t: method.time() });
            }
            if stops % CHATTER_STOPS == 0 && method.steps() == 0 {
                // (a window of CHATTER_STOPS stops that moved time by less than 1e-6 of the window:
                // the events accumulate)
                if method.time() - window_start < 1e-6 * drive.t_end {
                    return Err(SolveError::Chatter { t: method.time(), stops: CHATTER_STOPS });
                }
                window_start = method.time();
            }
            if method.steps() > step_budget {
                return Err(SolveError::StepBudget { limit: step_budget, t: method.time() });
            }
        }
        if let Some(&v_new) = drive.velocities.get(k + 1) {
            if let Some(e) = method.switch(t1, v, v_new) {
                emit(obs, e, v_new, Release::Flip);
            }
            v = v_new;
        }
    }
    Ok(method.steps())
}

/// Report `e` under belt velocity `v`; a slip was started `by` the cause of its stop.
#[inline]
fn emit<O: Observer>(obs: &mut O, e: Event, v: f64, by: Release) {
    match e {
        Event::Stick { t, x } => obs.stick(t, x, v),
        Event::Slip { t, x, xdot } => obs.slip(t, x, xdot, by),
    }
}

/// Sample the grid instants `j·step` in `[from, method.time())`; the next `from`.
fn sample<M: Method, O: Observer>(method: &M, obs: &mut O, from: f64, step: f64, v: f64) -> f64 {
    let to = method.time();
    let mut j = (from / step).ceil() as u64;
    loop {
        let t = j as f64 * step;
        if t >= to {
            return to;
        }
        let (x, xdot) = method.state_at(t);
        obs.sample(t, x, xdot, v);
        j += 1;
    }
}

/// The solver `run.solver` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Closed forms where the scene has them (today: every scene).
    Auto,
    /// Closed forms, event to event (undamped or damped).
    Exact,
    /// Dormand–Prince 5(4) with adaptive steps and located events.
    Rk45,
    /// Dormand–Prince 8(5,3) with adaptive steps and located events (the accurate end).
    Dop853,
    /// Classical Runge–Kutta with a fixed step and located events.
    Rk4,
    /// Moreau time stepping of the set-valued friction law.
    Moreau,
    /// Dormand–Prince on a regularized (tanh) friction law.
    Smooth,
}

impl SolverKind {
    /// Every name, for messages.
    pub const NAMES: [&'static str; 7] = ["auto", "exact", "rk45", "dop853", "rk4", "moreau", "smooth"];

    /// Its name in a scenario (`run.solver`).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Right-hand-side evaluations per attempted step: Dormand–Prince 5(4) 6 (FSAL), DOP853 15
    /// (12 per trial, FSAL, and 3 for the dense output of an accepted one: counted on every
    /// trial, an upper bound), RK4 4, one projection per Moreau step; 0 for the event-driven
    /// `exact` (the deterministic work measure `tradeoff` ranks settings by).
    pub fn evaluations_per_step(self) -> u64 {
        match self {
            SolverKind::Dop853 => 15,
            SolverKind::Rk45 | SolverKind::Smooth => 6,
            SolverKind::Rk4 => 4,
            SolverKind::Moreau => 1,
            SolverKind::Auto | SolverKind::Exact => 0,
        }
    }
}

/// A solver ready to run one realization of given parameters.
#[derive(Debug, Clone, Copy)]
pub struct Solver {
    kind: SolverKind,
    numerics: Numerics,
    /// the damped closed forms even at c = 0 (the damping is drawn per realization)
    damped: bool,
}

impl Solver {
    /// `kind`: the method actually run (`auto` already resolved for the scene, see
    /// `Scenario::solver`); `damped`: use the damped closed forms (the damping may be nonzero).
    pub fn new(kind: SolverKind, numerics: Numerics, damped: bool) -> Solver {
        Solver { kind, numerics, damped }
    }

    /// Solve one realization of the oscillator `p` (per unit mass, [`crate::physics::Params::per_unit_mass`]);
    /// returns the integration steps attempted (see [`drive`]).
    pub fn solve<O: Observer>(&self, p: &PerUnitMass, d: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<u64, SolveError> {
        let (p, num, budget) = (*p, &self.numerics, self.numerics.step_budget);
        match self.kind {
            SolverKind::Exact | SolverKind::Auto if self.damped || p.slip_damping() != 0.0 => {
                drive(&mut exact::Exact::<Damped>::new(&p), d, x0, xdot0, budget, obs)
            }
            SolverKind::Exact | SolverKind::Auto => drive(&mut exact::Exact::<Undamped>::new(&p), d, x0, xdot0, budget, obs),
            SolverKind::Rk45 => drive(&mut hybrid::Hybrid::new(&p, hybrid::Scheme::Rk45, num), d, x0, xdot0, budget, obs),
            SolverKind::Dop853 => drive(&mut hybrid::Hybrid::new(&p, hybrid::Scheme::Dop853, num), d, x0, xdot0, budget, obs),
            SolverKind::Rk4 => drive(&mut hybrid::Hybrid::new(&p, hybrid::Scheme::Rk4, num), d, x0, xdot0, budget, obs),
            SolverKind::Moreau => drive(&mut moreau::Moreau::new(&p, num), d, x0, xdot0, budget, obs),
            SolverKind::Smooth => drive(&mut smooth::Smooth::new(&p, num), d, x0, xdot0, budget, obs),
        }
    }
}
