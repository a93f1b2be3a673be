//! What every method shares: the drive it integrates over, the events it reports, how a step
//! stops, the method trait the driver calls, and the numerical settings.

use serde::{Deserialize, Serialize};

use super::rk;

/// The deterministic input of one realization: the belt velocity of each segment
/// (`switches.len() + 1` of them, [`crate::simulation::belt::BeltPath::segments`]), the switch
/// instants in (0, t_end) (sorted, no duplicates) and the end of the window t_end = t_a [s].
#[derive(Debug, Clone, Copy)]
pub struct Drive<'a> {
    /// the belt velocity of each segment [m/s] (`switches.len() + 1` of them)
    pub velocities: &'a [f64],
    /// the switch instants in (0, t_end) [s], sorted, no duplicates
    pub switches: &'a [f64],
    /// t_a, the end of the window [s]
    pub t_end: f64,
}

/// A change of mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// A stick begins at `t` [s] at position `x` [m].
    Stick {
        /// when [s]
        t: f64,
        /// position [m]
        x: f64,
    },
    /// A slip begins at `t` [s] from `(x, ẋ)`.
    Slip {
        /// when [s]
        t: f64,
        /// position [m]
        x: f64,
        /// velocity ẋ [m/s]
        xdot: f64,
    },
}

/// Why a method's [`Method::advance`] returned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// It took a step (or passed through belt speed) without a change of mode.
    Advanced,
    /// A change of mode.
    Event(Event),
    /// It reached the end of the belt segment.
    SegmentEnd,
}

impl From<Option<Event>> for Stop {
    /// A change of mode, or a step without one.
    fn from(e: Option<Event>) -> Stop {
        e.map_or(Stop::Advanced, Stop::Event)
    }
}

/// Where an integration step that found no event leaves a method: the step's end, or the
/// segment's end `t1` when the step reaches it (exactly, whatever the rounding of `t0 + h`).
pub(crate) fn step_end(step: &rk::Step, t1: f64) -> (f64, rk::State, Stop) {
    if step.h >= t1 - step.t0 {
        (t1, step.y1, Stop::SegmentEnd)
    } else {
        (step.t0 + step.h, step.y1, Stop::Advanced)
    }
}

/// One realization's integration by one method (see the module docs).
pub trait Method {
    /// Begin at t = 0 in `(x₀, ẋ₀)` under belt velocity `v`: the initial mode.
    fn start(&mut self, x0: f64, xdot0: f64, v: f64) -> Event;
    /// Advance within the segment that ends at `t1` under belt velocity `v`.
    fn advance(&mut self, t1: f64, v: f64) -> Stop;
    /// The belt switches at `t` from `v_old` to `v_new`: a stick ends, a slip goes on (and may
    /// land exactly at the new belt speed).
    fn switch(&mut self, t: f64, v_old: f64, v_new: f64) -> Option<Event>;
    /// The time reached.
    fn time(&self) -> f64;
    /// Ask the method to keep what [`Method::state_at`] needs (the driver samples a trajectory).
    fn keep_pieces(&mut self) {}
    /// The state at `t` on the piece of motion covered by the last [`Method::advance`] (after
    /// [`Method::keep_pieces`]).
    fn state_at(&self, t: f64) -> (f64, f64);
    /// Integration steps taken so far (0 for an event-driven method).
    fn steps(&self) -> u64 {
        0
    }
    /// Whether the method's state became non-finite (an overflow no step size avoids).
    fn non_finite(&self) -> bool {
        false
    }
    /// The least and greatest velocity ẋ over the motion the last [`Method::advance`] covered:
    /// exact for the closed forms (their turning points), located on the dense output for the
    /// integrators, the step ends for time stepping.
    fn velocity_range(&self) -> (f64, f64);
}

/// The numerical methods' settings (the scenario's `[numerics]`, see `pipelines/paper.toml`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Numerics {
    /// rk45, dop853 and smooth: relative tolerance
    pub rtol: f64,
    /// rk45, dop853 and smooth: absolute tolerance
    pub atol: f64,
    /// rk45, dop853 and smooth: largest step [s]
    pub max_step: f64,
    /// rk4 and moreau: fixed step [s]
    pub step: f64,
    /// smooth: ε, the width of the regularized law f_max tanh((v − ẋ)/ε) [m/s]
    pub epsilon: f64,
    /// smooth: |v − ẋ| below this counts as stick [m/s]
    pub stick_velocity: f64,
    /// integration steps per realization before a solver gives up with an error
    pub step_budget: u64,
    /// rk45/dop853/rk4 keep the Stribeck peak resolved (see [`hybrid`]); false only to see what an
    /// unguarded controller does
    #[serde(default = "yes")]
    pub peak_guard: bool,
}

fn yes() -> bool {
    true
}
