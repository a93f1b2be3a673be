//! `rk45`, `dop853` and `rk4`: the slip integrated numerically, transitions located as events.
//!
//! The mode logic is the physics home's ([`PerUnitMass::arrival`]): a slip ends where the relative
//! velocity `g = σ(v − ẋ)` falls from positive to zero, and there the mass sticks, touches or
//! passes through. The stick itself (`x = x₀ + v τ`) and its breakaway are linear, which any
//! Runge–Kutta method integrates exactly, so they are evaluated directly; belt switches are
//! segment ends, as in a piecewise ode45 run. The slip's right-hand side is the equation of
//! motion of [`PerUnitMass::slip_accel`] (damping included).
//!
//! Where the numerical velocity reaches belt speed is located on each step's dense output
//! ([`Step::first_zero`]) from three signs, so that a whole excursion inside one long step is not
//! stepped over:
//! - `g` positive at the start and ≤ 0 at the end: bisection;
//! - `g` zero at the start (the step begins at a reversal or a breakaway with μ_s > μ_k) and ≤ 0
//!   at the end: it rose and fell back, so the root after the interior maximum;
//! - `g` positive at both ends while `g′ = −σ ẍ` goes from − to +: the interior minimum, and the
//!   root before it if the minimum is ≤ 0 (a near-graze crossing and recrossing within one step).
//!
//! The orbit that leaves a breakaway at belt speed with zero acceleration (μ_s = μ_k) only
//! touches belt speed (exactly, in the exact method; with damping not even that); it is marked
//! `grazing` and no crossing is looked for on it until the next switch, so round-off at a touch is
//! never taken for a stick. What this method cannot see exactly — and the trade-off measures — is
//! the crossing time itself, located only as well as the step's error allows.
//!
//! **The Stribeck peak.** With velocity weakening the friction has a peak of width v_s around
//! u = 0 (for δ = 2, `exp(−(u/v_s)²)`); an adaptive controller's error estimate can step over it,
//! and then the law silently acts as plain Coulomb with μ_k (a near-graze whose dip into the peak
//! falls between two stages is the typical case). So every step is kept short enough that, on the
//! local quadratic `|u̇| h + |ü| h²/2 ≤ Δ` with `u̇ = −ẍ`, `ü ≈ ω² ẋ + γ ẍ`, u cannot move by more
//! than `Δ = (|u| − w)₊ + v_s`, where `w = v_s 12^{1/δ}` bounds the window in which the peak term
//! exceeds e^−12: far from the peak steps are free, approaching it they shrink, and inside it u
//! moves by at most v_s per step — each step's six stages then sample the peak every ~v_s/5
//! (`h = 2Δ / (|u̇| + √(u̇² + 2|ü|Δ))`, the cancellation-free root). The law computes that limit
//! ([`crate::physics::PerUnitMass::peak_step_limit`]; a law without a peak leaves the step alone), so
//! this method never asks which law it runs. `numerics.peak_guard = false` turns it off, only to
//! see what an unguarded controller does.

use super::method::Numerics;
use super::method::{step_end, Event, Method, Stop};
use super::rk::{rk4, Dopri, Pair, State, Step};
use crate::physics::{Arrival, PerUnitMass};

/// Which Runge–Kutta scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scheme {
    /// Dormand–Prince 5(4), adaptive (rtol, atol, max_step)
    Rk45,
    /// Dormand–Prince 8(5,3), adaptive (rtol, atol, max_step)
    Dop853,
    /// classical RK4 at a fixed step
    Rk4,
}

#[derive(Debug, Clone, Copy)]
enum Mode {
    Stick {
        t0: f64,
        x0: f64,
    },
    /// Slipping with the friction `σ a_k`; `grazing`: on the orbit that leaves a breakaway (or a
    /// touch) at belt speed with zero acceleration, which never crosses belt speed again before
    /// the next switch — no crossing is looked for, as in the exact method.
    Slip {
        sigma: f64,
        grazing: bool,
    },
}

/// One realization's integration by rk45, dop853 or rk4.
#[derive(Debug, Clone)]
pub struct Hybrid {
    p: PerUnitMass,
    scheme: Scheme,
    step: f64,
    peak_guard: bool,
    /// the law's peak window half-width ([`crate::physics::Law::peak_window`]; 0 without a peak)
    peak_window: f64,
    dopri: Dopri,
    steps: u64,
    mode: Mode,
    t: f64,
    y: State,
    /// f(y) for the current slip's right-hand side, kept from the last step's final stage (FSAL);
    /// None whenever the state, the mode or the belt velocity changed otherwise
    f: Option<State>,
    /// the last piece: a stick `(t0, x0, v)` or a step's dense output
    piece: Piece,
    /// every step's dense output is completed (the driver samples a trajectory)
    keep: bool,
}

#[derive(Debug, Clone, Copy)]
enum Piece {
    Stick { t0: f64, x0: f64, v: f64 },
    Step(Step),
}

impl Hybrid {
    pub fn new(p: &PerUnitMass, scheme: Scheme, num: &Numerics) -> Hybrid {
        Hybrid {
            p: *p,
            scheme,
            step: num.step,
            peak_guard: num.peak_guard,
            peak_window: p.law.peak_window(),
            dopri: Dopri {
                budget: num.step_budget,
                pair: if scheme == Scheme::Dop853 { Pair::Dop853 } else { Pair::Dp54 },
                ..Dopri::new(num.rtol, num.atol, num.max_step)
            },
            steps: 0,
            mode: Mode::Stick { t0: 0.0, x0: 0.0 },
            t: 0.0,
            y: [0.0, 0.0],
            f: None,
            piece: Piece::Stick { t0: 0.0, x0: 0.0, v: 0.0 },
            keep: false,
        }
    }

    /// The mass reaches belt velocity `v` at time `t` at position `x`: stick, touch or pass
    /// through; the stick event, if any.
    fn classify(&mut self, t: f64, x: f64, v: f64) -> Option<Event> {
        (self.t, self.f) = (t, None);
        match self.p.arrival(x, v) {
            Arrival::Stick { x } => {
                (self.mode, self.y) = (Mode::Stick { t0: t, x0: x }, [x, v]);
                return Some(Event::Stick { t, x });
            }
            Arrival::Touch => self.leave_breakaway(v),
            Arrival::Reverse { sigma } => (self.mode, self.y) = (Mode::Slip { sigma, grazing: false }, [x, v]),
        }
        None
    }

    /// Slip away from the breakaway point under belt velocity `v`.
    fn leave_breakaway(&mut self, v: f64) {
        self.f = None;
        let grazing = self.p.grazes_after_breakaway();
        (self.mode, self.y) = (Mode::Slip { sigma: v.signum(), grazing }, [self.p.holding_limit(v, 1.0), v]);
    }

    /// Go on from state `y` at time `t` under belt velocity `v` (at t = 0 or after a switch).
    fn resume(&mut self, t: f64, y: State, v: f64) -> Option<Event> {
        self.f = None;
        if y[1] == v {
            return self.classify(t, y[0], v);
        }
        (self.t, self.y, self.mode) = (t, y, Mode::Slip { sigma: (v - y[1]).signum(), grazing: false });
        None
    }
}

impl Method for Hybrid {
    fn start(&mut self, x0: f64, xdot0: f64, v: f64) -> Event {
        self.resume(0.0, [x0, xdot0], v).unwrap_or(Event::Slip { t: 0.0, x: x0, xdot: xdot0 })
    }

    fn advance(&mut self, t1: f64, v: f64) -> Stop {
        match self.mode {
            Mode::Stick { t0, x0 } => {
                self.piece = Piece::Stick { t0, x0, v };
                let t_b = t0 + self.p.stick_duration(x0, v);
                if t_b < t1 {
                    self.t = t_b;
                    self.leave_breakaway(v);
                    return Stop::Event(Event::Slip { t: t_b, x: self.y[0], xdot: v });
                }
                (self.t, self.y) = (t1, [x0 + v * (t1 - t0), v]);
                Stop::SegmentEnd
            }
            Mode::Slip { sigma, grazing } => {
                let p = self.p;
                let acc = |y: State| p.slip_accel(y[0], y[1], v, sigma);
                let f0 = self.f.take().unwrap_or_else(|| [self.y[1], acc(self.y)]);
                let rest = t1 - self.t;
                let limit = if self.peak_guard {
                    // the step rk45 would try (rk4's fixed step), unless the peak needs a shorter one
                    let want = match self.scheme {
                        Scheme::Rk45 | Scheme::Dop853 => self.dopri.next(),
                        Scheme::Rk4 => self.step,
                    };
                    p.peak_step_limit(self.peak_window, self.y, v, f0[1], want.min(rest))
                } else {
                    rest
                };
                let mut step: Step = match self.scheme {
                    Scheme::Rk45 | Scheme::Dop853 => self.dopri.step_from(&acc, self.t, self.y, f0, limit, &mut self.steps),
                    Scheme::Rk4 => {
                        self.steps += 1;
                        rk4(&acc, self.t, self.y, self.step.min(limit))
                    }
                };
                // g = σ(v − ẋ) > 0 in this slip, g′ = −σ ẍ: a velocity extremum inside the step
                // (g′ from − to +) may hide a crossing and its return (a near-graze)
                let g = |y: State| sigma * (v - y[1]);
                let dips = sigma * step.f0[1] > 0.0 && sigma * step.f1[1] < 0.0;
                // the dense output is looked inside only where a crossing may lie, where the
                // velocity turns (its range), or for the trajectory's samples
                if self.keep || g(step.y1) <= 0.0 || dips || step.turns_before(1.0) {
                    self.dopri.complete(&acc, &mut step);
                }
                self.piece = Piece::Step(step);
                if let Some(theta) = (!grazing).then(|| step.first_zero(g, dips)).flatten() {
                    let t = step.t0 + theta * step.h;
                    return self.classify(t, step.at(theta)[0], v).into();
                }
                let stop;
                (self.t, self.y, stop) = step_end(&step, t1);
                self.f = Some(step.f1);
                stop
            }
        }
    }

    fn switch(&mut self, t: f64, v_old: f64, v_new: f64) -> Option<Event> {
        self.f = None;
        if let Mode::Stick { .. } = self.mode {
            let x = self.y[0];
            self.resume(t, [x, v_old], v_new);
            return Some(Event::Slip { t, x, xdot: v_old });
        }
        self.resume(t, self.y, v_new)
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn keep_pieces(&mut self) {
        self.keep = true;
    }

    fn state_at(&self, t: f64) -> (f64, f64) {
        match self.piece {
            Piece::Stick { t0, x0, v } => (x0 + v * (t - t0), v),
            Piece::Step(s) => {
                let y = s.at(((t - s.t0) / s.h).clamp(0.0, 1.0));
                (y[0], y[1])
            }
        }
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn velocity_range(&self) -> (f64, f64) {
        match self.piece {
            Piece::Stick { v, .. } => (v, v),
            Piece::Step(s) => s.velocity_range(((self.t - s.t0) / s.h).clamp(0.0, 1.0)),
        }
    }

    fn non_finite(&self) -> bool {
        self.dopri.failed || !(self.y[0].is_finite() && self.y[1].is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::{Law, Params, Stribeck};

    /// One forced Dormand–Prince step of length `h` of a Stribeck slip (σ = +1, belt v = 1) from
    /// (x0, ẋ0), and g = v − ẋ on it.
    fn step(xd0: f64, h: f64) -> (Step, impl Fn(State) -> f64) {
        let stribeck = Stribeck { velocity: 0.1, exponent: 2.0 };
        let p = Params { static_: 0.6, law: Law::Stribeck(stribeck), ..Params::PAPER }.per_unit_mass();
        let acc = move |y: State| p.slip_accel(y[0], y[1], 1.0, 1.0);
        let mut dp = Dopri::new(1.0, 1.0, h);
        dp.h = h;
        let x0 = 0.51 * 9.8 / 4.0 - 0.25;
        (dp.step(&acc, 0.0, [x0, xd0], h, &mut 0), |y: State| 1.0 - y[1])
    }

    #[test]
    fn a_stribeck_dip_between_step_ends_is_found() {
        // One long step (0.6 s) around the velocity maximum: find ẋ0 where the dense output just
        // dips below belt speed. Both step ends are below belt speed, so the naive end-sign test
        // sees nothing; the three-sign search finds the crossing.
        let h = 0.6;
        let dips = |xd0: f64| {
            let (s, g) = step(xd0, h);
            s.first_zero(&g, g(s.y1) > 0.0 && s.f0[1] > 0.0 && s.f1[1] < 0.0).is_some()
        };
        let (mut lo, mut hi) = (0.3, 0.99);
        assert!(!dips(lo) && dips(hi));
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if dips(mid) {
                hi = mid
            } else {
                lo = mid
            }
        }
        let (s, g) = step(hi, h);
        assert!(g(s.y0) > 0.0 && g(s.y1) > 0.0, "both ends below belt speed");
        assert_eq!(s.first_zero(&g, false), None, "the naive end-sign test misses it");
        let theta = s.first_zero(&g, true).expect("the three-sign search finds it");
        assert!(theta > 0.0 && theta < 1.0 && g(s.at(theta)).abs() < 1e-9, "θ = {theta}, g = {}", g(s.at(theta)));
    }
}
