//! `smooth`: a regularized friction law integrated by Dormand–Prince — what many users do.
//!
//! `m ẍ + k x = f_max tanh((v − ẋ)/ε)` is an ordinary ODE (stiff for small ε: the friction's
//! slope f_max/ε bounds the explicit step), integrated through each belt segment with `rk45`'s
//! tolerances. Classification rule: the mass is *stuck* while `|v − ẋ| < δ` (`stick_velocity`),
//! slipping otherwise; the crossings of `|v − ẋ| = δ` are located on the dense output. With a
//! smooth law the mass never moves exactly with the belt: it creeps at a relative speed of about
//! ε·|k x|/f_max, so stick durations and breakaway depend on ε and δ.

use super::rk::{Dopri, State};
use super::{Drive, SolveError, Solver};
use crate::events::Observer;
use crate::model::{Accel, Model};
use crate::scenario::Numerics;

#[derive(Debug, Clone, Copy)]
pub struct Smooth {
    a: Accel,
    num: Numerics,
}

impl Smooth {
    pub fn new(model: &Model, num: Numerics) -> Smooth {
        Smooth { a: model.per_unit_mass(), num }
    }
}

impl Solver for Smooth {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        let (a, num) = (self.a, &self.num);
        let (mut t, mut y): (f64, State) = (0.0, [x0, xdot0]);
        let mut v = drive.sign0 * drive.speed;
        let mut dopri = Dopri::new(num.rtol, num.atol, num.max_step);
        let mut steps = 0u64;
        let mut stuck = (v - xdot0).abs() < num.stick_velocity;
        if stuck {
            obs.stick(0.0, x0);
        } else {
            obs.slip(0.0, x0, xdot0);
        }
        let ends = drive.switches.iter().copied().chain(std::iter::once(drive.t_end));
        for (k, seg_end) in ends.enumerate() {
            while t < seg_end {
                let acc = |y: State| a.friction * ((v - y[1]) / num.epsilon).tanh() - a.omega2 * y[0];
                let step = dopri.step(&acc, t, y, seg_end - t, &mut steps);
                if steps > num.step_budget {
                    return Err(SolveError::StepBudget { limit: num.step_budget, t });
                }
                // g > 0 in the current mode; a sign change is a transition
                let g = |y: State| {
                    let d = num.stick_velocity - (v - y[1]).abs();
                    if stuck { d } else { -d }
                };
                if let Some(theta) = step.first_zero(g, false) {
                    t = step.t0 + theta * step.h;
                    y = step.at(theta);
                    stuck = !stuck;
                    if stuck {
                        obs.stick(t, y[0]);
                    } else {
                        obs.slip(t, y[0], y[1]);
                    }
                } else {
                    t = if step.h >= seg_end - step.t0 { seg_end } else { step.t0 + step.h };
                    y = step.y1;
                }
            }
            if k < drive.switches.len() {
                v = -v;
                let now = (v - y[1]).abs() < num.stick_velocity;
                match (stuck, now) {
                    (true, false) => obs.slip(t, y[0], y[1]),
                    (false, true) => obs.stick(t, y[0]),
                    _ => {}
                }
                stuck = now;
            }
        }
        Ok(())
    }
}
