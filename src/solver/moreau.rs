//! `moreau`: Moreau–Jean time stepping — friction as a set-valued law solved per step, no events.
//!
//! Per step of length h (steps are cut at the known belt switches), with θ = 1/2 and per unit mass
//! (J. J. Moreau, "Unilateral contact and dry friction in finite freedom dynamics", 1988;
//! M. Jean, "The non-smooth contact dynamics method", 1999), the forces at the θ-point
//! `x_θ = x + θ h ẋ_θ`, `ẋ_θ = θ ẋ' + (1−θ) ẋ`:
//!
//! ```text
//!   ẋ' = ẋ + h (f + β (v − ẋ_θ) − ω² x_θ − γ ẋ_θ),   f ∈ a_k Sgn(v − ẋ')  (|f| ≤ a_s in a stick)
//!   ⇔ A ẋ' = b + h f,  A = 1 + h²θ²ω² + hθ(γ + β),
//!                      b = ẋ − h ω² (x + h θ(1−θ) ẋ) − h (γ + β)(1−θ) ẋ + h β v
//!   x' = x + h (θ ẋ' + (1−θ) ẋ)
//! ```
//!
//! (β = σ_v/m, the viscous term of the law, is linear in ẋ and so taken implicitly with the
//! dashpot; it is 0 at belt speed, but at the θ-point it is not quite, an O(h) effect.)
//!
//! The inclusion is solved exactly: if the force needed to keep ẋ' = v, `f* = (A v − b)/h`,
//! satisfies |f*| ≤ a_s the step sticks; otherwise it slips with f = f(|v − ẋ|) sgn(f*), the slip
//! friction of [`PerUnitMass::slip_friction`] at the step's starting relative velocity (a_k for
//! Coulomb; semi-implicit for the Stribeck law). A stick is a
//! maximal run of sticking steps and is reported at the start of its first step; nothing is
//! located between grid points, so event times carry an O(h) error — the price of never locating
//! an event.

use super::method::{Event, Method, Numerics, Stop};
use crate::physics::PerUnitMass;

const THETA: f64 = 0.5;

/// One realization's Moreau–Jean integration.
#[derive(Debug, Clone, Copy)]
pub struct Moreau {
    p: PerUnitMass,
    h0: f64,
    steps: u64,
    stuck: bool,
    t: f64,
    x: f64,
    xd: f64,
    /// the last step: (t, x, ẋ) at its start, for linear interpolation
    prev: (f64, f64, f64),
}

impl Moreau {
    pub fn new(p: &PerUnitMass, num: &Numerics) -> Moreau {
        Moreau { p: *p, h0: num.step, steps: 0, stuck: false, t: 0.0, x: 0.0, xd: 0.0, prev: (0.0, 0.0, 0.0) }
    }
}

impl Method for Moreau {
    fn start(&mut self, x0: f64, xdot0: f64, _v: f64) -> Event {
        (self.x, self.xd) = (x0, xdot0);
        self.prev = (0.0, x0, xdot0);
        Event::Slip { t: 0.0, x: x0, xdot: xdot0 }
    }

    fn advance(&mut self, t1: f64, v: f64) -> Stop {
        let (p, t) = (&self.p, self.t);
        if t >= t1 {
            return Stop::SegmentEnd;
        }
        self.steps += 1;
        let h = self.h0.min(t1 - t);
        let damping = p.slip_damping();
        let big_a = 1.0 + h * h * THETA * THETA * p.omega2 + h * THETA * damping;
        let mut b = self.xd - h * p.omega2 * (self.x + h * THETA * (1.0 - THETA) * self.xd) - h * damping * (1.0 - THETA) * self.xd;
        if p.viscous != 0.0 {
            b += h * p.viscous * v;
        }
        let f_star = (big_a * v - b) / h;
        let stick_now = f_star.abs() <= p.breakaway;
        let xd_new = if stick_now { v } else { (b + h * p.slip_friction(v - self.xd) * f_star.signum()) / big_a };
        let event = match (self.stuck, stick_now) {
            (false, true) => Some(Event::Stick { t, x: self.x }),
            (true, false) => Some(Event::Slip { t, x: self.x, xdot: self.xd }),
            _ => None,
        };
        self.stuck = stick_now;
        self.prev = (t, self.x, self.xd);
        self.x += h * (THETA * xd_new + (1.0 - THETA) * self.xd);
        self.xd = xd_new;
        self.t = if h >= t1 - t { t1 } else { t + h };
        match event {
            Some(e) => Stop::Event(e),
            None if self.t >= t1 => Stop::SegmentEnd,
            None => Stop::Advanced,
        }
    }

    fn switch(&mut self, _t: f64, _v_old: f64, _v_new: f64) -> Option<Event> {
        None // the next step decides with the new belt velocity
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn velocity_range(&self) -> (f64, f64) {
        (self.prev.2.min(self.xd), self.prev.2.max(self.xd))
    }

    fn state_at(&self, t: f64) -> (f64, f64) {
        let (t0, x0, xd0) = self.prev;
        let w = if self.t > t0 { (t - t0) / (self.t - t0) } else { 0.0 };
        (x0 + w * (self.x - x0), xd0 + w * (self.xd - xd0))
    }

    fn steps(&self) -> u64 {
        self.steps
    }
}
