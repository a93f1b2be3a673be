//! `smooth`: a regularized friction law integrated by Dormand–Prince — what many users do.
//!
//! `ẍ = f_ε(v − ẋ) − ω² x − γ ẋ` is an ordinary ODE (stiff for small ε: the friction's slope
//! a_k/ε bounds the explicit step), integrated through each belt segment with `rk45`'s
//! tolerances. The regularized law, per unit mass, with w = u/ε:
//!
//! ```text
//!   Coulomb:  f_ε(u) = a_k tanh(w) + (a_s − a_k) · w e^{(1 − w²)/2}
//!   Stribeck: f_ε(u) = f(|u|) tanh(w)
//! ```
//!
//! (for Coulomb the second term, present only when μ_s > μ_k, is a bump of height a_s − a_k at
//! |u| = ε, so that the largest friction the law can exert is about the static limit; the Stribeck
//! law reaches it by itself; the law answers for its form: [`crate::physics::PerUnitMass::regularized_friction`]).
//! Classification rule:
//! the mass is *stuck* while `|v − ẋ| < δ` (`stick_velocity`), slipping otherwise; the crossings
//! of `|v − ẋ| = δ` are located on the dense output. With a smooth law the mass never moves
//! exactly with the belt: it creeps at a relative speed of about ε·|F|/a_k, so stick durations
//! and breakaway depend on ε and δ.

use super::method::Numerics;
use super::method::{step_end, Event, Method, Stop};
use super::rk::{Dopri, State, Step};
use crate::physics::PerUnitMass;

/// One realization's regularized integration.
#[derive(Debug, Clone)]
pub struct Smooth {
    p: PerUnitMass,
    epsilon: f64,
    delta: f64,
    dopri: Dopri,
    steps: u64,
    stuck: bool,
    t: f64,
    y: State,
    piece: Option<Step>,
}

impl Smooth {
    pub fn new(p: &PerUnitMass, num: &Numerics) -> Smooth {
        Smooth {
            p: *p,
            epsilon: num.epsilon,
            delta: num.stick_velocity,
            dopri: Dopri { budget: num.step_budget, ..Dopri::new(num.rtol, num.atol, num.max_step) },
            steps: 0,
            stuck: false,
            t: 0.0,
            y: [0.0, 0.0],
            piece: None,
        }
    }

    fn mode_event(&mut self, now: bool) -> Option<Event> {
        let was = std::mem::replace(&mut self.stuck, now);
        let [x, xdot] = self.y;
        match (was, now) {
            (false, true) => Some(Event::Stick { t: self.t, x }),
            (true, false) => Some(Event::Slip { t: self.t, x, xdot }),
            _ => None,
        }
    }
}

impl Method for Smooth {
    fn start(&mut self, x0: f64, xdot0: f64, v: f64) -> Event {
        self.y = [x0, xdot0];
        self.stuck = (v - xdot0).abs() < self.delta;
        if self.stuck {
            Event::Stick { t: 0.0, x: x0 }
        } else {
            Event::Slip { t: 0.0, x: x0, xdot: xdot0 }
        }
    }

    fn advance(&mut self, t1: f64, v: f64) -> Stop {
        if self.t >= t1 {
            return Stop::SegmentEnd;
        }
        let (p, eps) = (self.p, self.epsilon);
        let acc = |y: State| p.regularized_friction(eps, v - y[1]) - p.omega2 * y[0] - p.gamma * y[1];
        let step = self.dopri.step(&acc, self.t, self.y, t1 - self.t, &mut self.steps);
        self.piece = Some(step);
        // g > 0 in the current mode; a sign change is a transition
        let (delta, stuck) = (self.delta, self.stuck);
        let g = |y: State| {
            let d = delta - (v - y[1]).abs();
            if stuck {
                d
            } else {
                -d
            }
        };
        if let Some(theta) = step.first_zero(g, false) {
            (self.t, self.y) = (step.t0 + theta * step.h, step.at(theta));
            return self.mode_event(!stuck).into();
        }
        let stop;
        (self.t, self.y, stop) = step_end(&step, t1);
        stop
    }

    fn switch(&mut self, _t: f64, _v_old: f64, v_new: f64) -> Option<Event> {
        let now = (v_new - self.y[1]).abs() < self.delta;
        self.mode_event(now)
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn velocity_range(&self) -> (f64, f64) {
        match &self.piece {
            Some(s) => s.velocity_range(((self.t - s.t0) / s.h).clamp(0.0, 1.0)),
            None => (self.y[1], self.y[1]),
        }
    }

    fn state_at(&self, t: f64) -> (f64, f64) {
        match &self.piece {
            Some(s) => {
                let y = s.at(((t - s.t0) / s.h).clamp(0.0, 1.0));
                (y[0], y[1])
            }
            None => (self.y[0], self.y[1]),
        }
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn non_finite(&self) -> bool {
        self.dopri.failed || !(self.y[0].is_finite() && self.y[1].is_finite())
    }
}
