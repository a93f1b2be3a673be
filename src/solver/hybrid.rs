//! `rk45` and `rk4`: the slip integrated numerically, transitions located as events.
//!
//! The mode logic is the exact solver's (see [`super::exact`]): a slip ends where the relative
//! velocity `g = σ(v − ẋ)` falls from positive to zero, and there the mass sticks, touches or
//! reverses by the same rule ([`arrival`]). The stick itself (`x = x₀ + v τ`) and its breakaway
//! at `s k x = f_max` are linear, which any Runge–Kutta method integrates exactly, so they are
//! evaluated directly; belt flips are integration stops, as in a piecewise ode45 run.
//!
//! Where the numerical velocity reaches belt speed is located on each step's dense output
//! ([`Step::first_zero`]) from three signs, so that a whole excursion inside one long step is not
//! stepped over:
//! - `g` positive at the start and ≤ 0 at the end: bisection;
//! - `g` zero at the start (the step begins at a reversal) and ≤ 0 at the end: it rose and fell
//!   back, so the root after the interior maximum (a reversal followed within the step by a stick);
//! - `g` positive at both ends while `g′ = −σ ẍ` goes from − to +: the interior minimum, and the
//!   root before it if the minimum is ≤ 0 (a near-graze crossing and recrossing within one step).
//! The orbit that leaves a breakaway at belt speed with zero acceleration only touches belt speed
//! (exactly, in the exact solver); it is marked `grazing` and no crossing is looked for on it until
//! the next flip, so round-off at a touch is never taken for a stick. What this solver cannot see
//! exactly — and the trade-off measures — is the crossing time itself, located only as well as the
//! step's error allows.

use super::rk::{rk4, Dopri, State, Step};
use super::exact::{arrival, Arrival};
use super::{Drive, SolveError, Solver};
use crate::events::Observer;
use crate::model::{Accel, Model};
use crate::scenario::Numerics;

/// Which integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Dormand–Prince 5(4), adaptive (rtol, atol, max_step)
    Rk45,
    /// classical RK4 at a fixed step
    Rk4,
}

#[derive(Debug, Clone, Copy)]
pub struct Hybrid {
    a: Accel,
    method: Method,
    num: Numerics,
}

enum Mode {
    Stick { t0: f64, x0: f64 },
    /// Slipping with the friction `σ f_max`; `grazing`: on the orbit that leaves a breakaway (or a
    /// touch) at belt speed with zero acceleration, which only touches belt speed until the next
    /// flip — no crossing is looked for, as in the exact solver.
    Slip { sigma: f64, grazing: bool },
}

impl Hybrid {
    pub fn new(model: &Model, method: Method, num: Numerics) -> Hybrid {
        Hybrid { a: model.per_unit_mass(), method, num }
    }

    /// The mass reaches belt velocity `v = s v0` at time `t` at position `x`: stick, touch or
    /// reverse (the exact solver's rule, [`arrival`]); the mode and the state to go on from.
    fn classify<O: Observer>(&self, t: f64, x: f64, s: f64, v: f64, obs: &mut O) -> (Mode, State) {
        match arrival(&self.a, x, s) {
            Arrival::Stick { x } => {
                obs.stick(t, x);
                (Mode::Stick { t0: t, x0: x }, [x, v])
            }
            Arrival::Touch => (Mode::Slip { sigma: s, grazing: true }, [self.a.breakaway_position(s), v]),
            Arrival::Reverse { sigma } => (Mode::Slip { sigma, grazing: false }, [x, v]),
        }
    }

    /// Go on from state `y` at time `t` under belt velocity `v = s v0` (at t = 0 or just after a
    /// flip): classified if the mass moves at belt speed, else a slip against the relative velocity.
    fn resume<O: Observer>(&self, t: f64, y: State, s: f64, v: f64, obs: &mut O) -> (Mode, State) {
        if y[1] == v {
            self.classify(t, y[0], s, v, obs)
        } else {
            (Mode::Slip { sigma: (v - y[1]).signum(), grazing: false }, y)
        }
    }
}

impl Solver for Hybrid {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        let a = self.a;
        let num = &self.num;
        let (mut s, mut t) = (drive.sign0, 0.0);
        let mut v = s * drive.speed;
        let mut dopri = Dopri::new(num.rtol, num.atol, num.max_step);
        let mut steps = 0u64;
        let (mut mode, mut y) = self.resume(0.0, [x0, xdot0], s, v, obs);
        if let Mode::Slip { .. } = mode {
            obs.slip(0.0, x0, xdot0);
        }
        let ends = drive.switches.iter().copied().chain(std::iter::once(drive.t_end));
        for (k, seg_end) in ends.enumerate() {
            while t < seg_end {
                match mode {
                    Mode::Stick { t0, x0 } => {
                        let t_b = t0 + a.stick_duration(x0, s, drive.speed);
                        if t_b < seg_end {
                            (t, y) = (t_b, [a.breakaway_position(s), v]);
                            obs.slip(t, y[0], v);
                            mode = Mode::Slip { sigma: s, grazing: true };
                        } else {
                            (t, y) = (seg_end, [x0 + v * (seg_end - t0), v]);
                        }
                    }
                    Mode::Slip { sigma, grazing } => {
                        let acc = |y: State| sigma * a.friction - a.omega2 * y[0];
                        let step: Step = match self.method {
                            Method::Rk45 => dopri.step(&acc, t, y, seg_end - t, &mut steps),
                            Method::Rk4 => {
                                steps += 1;
                                rk4(&acc, t, y, num.step.min(seg_end - t))
                            }
                        };
                        if steps > num.step_budget {
                            return Err(SolveError::StepBudget { limit: num.step_budget, t });
                        }
                        // g = σ(v − ẋ) > 0 in this slip, g′ = −σ ẍ: a velocity extremum inside the
                        // step (g′ from − to +) may hide a crossing and its return (a near-graze)
                        let g = |y: State| sigma * (v - y[1]);
                        let dips = sigma * step.f0[1] > 0.0 && sigma * step.f1[1] < 0.0;
                        if let Some(theta) = (!grazing).then(|| step.first_zero(g, dips)).flatten() {
                            t = step.t0 + theta * step.h;
                            (mode, y) = self.classify(t, step.at(theta)[0], s, v, obs);
                        } else {
                            t = if step.h >= seg_end - step.t0 { seg_end } else { step.t0 + step.h };
                            y = step.y1;
                        }
                    }
                }
            }
            if k < drive.switches.len() {
                if let Mode::Stick { .. } = mode {
                    obs.slip(t, y[0], v);
                }
                (s, v) = (-s, -v);
                (mode, y) = self.resume(t, y, s, v, obs);
            }
        }
        Ok(())
    }
}
