//! `rk45` and `rk4`: the slip integrated numerically, transitions located as events.
//!
//! The mode logic is the exact solver's (see [`super::exact`]): a slip ends where the relative
//! velocity `g = σ(v − ẋ)` falls from positive to zero — located on the step's dense output by
//! bisection — and there the mass sticks if `|k x| ≤ f_max`, else the friction reverses. The stick
//! itself (`x = x₀ + v τ`) and its breakaway at `s k x = f_max` are linear, which any Runge–Kutta
//! method integrates exactly, so they are evaluated directly; belt flips are integration stops, as
//! in a piecewise ode45 run. What this solver cannot see exactly — and the trade-off measures — is
//! where the numerical velocity crosses belt speed: a graze or a near-miss may be taken for a
//! crossing, and crossings are located only as well as the step's error allows.

use super::rk::{rk4, Dopri, State, Step};
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
    Slip { sigma: f64 },
}

impl Hybrid {
    pub fn new(model: &Model, method: Method, num: Numerics) -> Hybrid {
        Hybrid { a: model.per_unit_mass(), method, num }
    }

    /// At belt velocity `v = s v0` with position `x`: stick, or slip on with the friction `σ`.
    fn classify<O: Observer>(&self, t: f64, x: f64, s: f64, obs: &mut O) -> Mode {
        let p = s * self.a.omega2 * x;
        if p >= -self.a.friction && p < self.a.friction {
            obs.stick(t, x);
            Mode::Stick { t0: t, x0: x }
        } else {
            Mode::Slip { sigma: if p == 0.0 { s } else { s * p.signum() } }
        }
    }
}

impl Solver for Hybrid {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        let a = self.a;
        let num = &self.num;
        let (mut s, mut t) = (drive.sign0, 0.0);
        let mut v = s * drive.speed;
        let mut y: State = [x0, xdot0];
        let mut dopri = Dopri::new(num.rtol, num.atol, num.max_step);
        let mut steps = 0u64;
        let mut mode = if xdot0 == v {
            self.classify(0.0, x0, s, obs)
        } else {
            Mode::Slip { sigma: (v - xdot0).signum() }
        };
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
                            mode = Mode::Slip { sigma: s };
                        } else {
                            (t, y) = (seg_end, [x0 + v * (seg_end - t0), v]);
                        }
                    }
                    Mode::Slip { sigma } => {
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
                        let g = |y: State| sigma * (v - y[1]);
                        if g(step.y0) > 0.0 && g(step.y1) <= 0.0 {
                            let theta = step.root(g);
                            let at = step.at(theta);
                            t = if theta >= 1.0 { step.t0 + step.h } else { step.t0 + theta * step.h };
                            y = [at[0], v];
                            mode = self.classify(t, y[0], s, obs);
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
                mode = if y[1] == v { self.classify(t, y[0], s, obs) } else { Mode::Slip { sigma: (v - y[1]).signum() } };
            }
        }
        Ok(())
    }
}
