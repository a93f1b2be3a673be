//! `moreau`: Moreau–Jean time stepping — friction as a set-valued law solved per step, no events.
//!
//! Per step of length h (steps are cut at the known belt flips), with θ = 1/2 and per unit mass
//! (J. J. Moreau, "Unilateral contact and dry friction in finite freedom dynamics", 1988;
//! M. Jean, "The non-smooth contact dynamics method", 1999):
//!
//! ```text
//!   ẋ' = ẋ + h (−ω² (x + h(θ ẋ' + (1−θ) ẋ) θ … ) + f),   f ∈ a_f Sgn(v − ẋ')
//!   ⇔ A ẋ' = b + h f,  A = 1 + h²θ²ω²,  b = ẋ − h ω² (x + h θ(1−θ) ẋ)
//!   x' = x + h (θ ẋ' + (1−θ) ẋ)
//! ```
//!
//! The inclusion is solved exactly: if the force needed to keep ẋ' = v, `f* = (A v − b)/h`,
//! satisfies |f*| ≤ a_f the step sticks; otherwise f = a_f sgn(f*). A stick is a maximal run of
//! sticking steps and is reported at the start of its first step; nothing is located between grid
//! points, so event times carry an O(h) error — the price of never locating an event.

use super::{Drive, SolveError, Solver};
use crate::events::Observer;
use crate::model::{Accel, Model};
use crate::scenario::Numerics;

const THETA: f64 = 0.5;

#[derive(Debug, Clone, Copy)]
pub struct Moreau {
    a: Accel,
    num: Numerics,
}

impl Moreau {
    pub fn new(model: &Model, num: Numerics) -> Moreau {
        Moreau { a: model.per_unit_mass(), num }
    }
}

impl Solver for Moreau {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        let (a, h0) = (self.a, self.num.step);
        let (mut x, mut xd, mut t) = (x0, xdot0, 0.0);
        let mut v = drive.sign0 * drive.speed;
        let mut stuck = false;
        let mut steps = 0u64;
        obs.slip(0.0, x0, xdot0);
        let ends = drive.switches.iter().copied().chain(std::iter::once(drive.t_end));
        for (k, seg_end) in ends.enumerate() {
            while t < seg_end {
                steps += 1;
                if steps > self.num.step_budget {
                    return Err(SolveError::StepBudget { limit: self.num.step_budget, t });
                }
                let h = h0.min(seg_end - t);
                let big_a = 1.0 + h * h * THETA * THETA * a.omega2;
                let b = xd - h * a.omega2 * (x + h * THETA * (1.0 - THETA) * xd);
                let f_star = (big_a * v - b) / h;
                let stick_now = f_star.abs() <= a.friction;
                let xd_new = if stick_now { v } else { (b + h * a.friction * f_star.signum()) / big_a };
                match (stuck, stick_now) {
                    (false, true) => obs.stick(t, x),
                    (true, false) => obs.slip(t, x, xd),
                    _ => {}
                }
                stuck = stick_now;
                x += h * (THETA * xd_new + (1.0 - THETA) * xd);
                xd = xd_new;
                t = if h >= seg_end - t { seg_end } else { t + h };
            }
            if k < drive.switches.len() {
                v = -v;
            }
        }
        Ok(())
    }
}
