//! The exact event-driven method: closed-form motion in every mode, closed-form event times.
//!
//! Within a belt segment the belt velocity v is constant and each mode has a closed form: the
//! stick is `x = x₀ + v τ` and ends at the breakaway time of [`PerUnitMass::stick_duration`]; the slip
//! is the slip form `K` ([`crate::physics::Undamped`] or [`crate::physics::Damped`]), whose
//! first return to belt speed is found in closed form or bracketed exactly
//! ([`SlipForm::crossing`]). At belt speed the arrival rule of [`PerUnitMass::arrival`] decides:
//! stick (an event), a touch at the breakaway point (the slip goes on as after a breakaway, on the
//! grazing orbit when μ_s = μ_k), or a pass-through with the friction reversed (not an event).
//! After a belt switch the slip goes on from the state at the switch with the friction against
//! the new relative velocity.
//!
//! Event times are `t₀ + τ` where t₀ is the previous event or switch instant: switches come from
//! the belt unchanged, so errors never accumulate beyond one belt segment whatever t_a is.
//!
//! **Grazing orbits across belt changes.** The slip that leaves a breakaway with zero
//! acceleration (μ_s = μ_k) only touches its belt velocity v_g again (undamped) or never reaches
//! it (damped). A belt change that keeps the friction direction σ (possible with more than two
//! belt levels, or a telegraph belt with v_r < v_f) leaves the motion on the same orbit, but the
//! slip restarts from the computed state, a few ulps off the orbit; back under v_g its touch
//! would become a crossing some 1e-8 s before the breakaway point — a stick that does not exist.
//! So a restarted slip carries `graze = v_g` while σ is unchanged and the law has no viscous
//! term (which makes the orbit depend on the belt velocity), and under v_g it is known not to
//! cross. On a symmetric belt σ always changes at a flip of a grazing orbit (ẋ ∈ [−v, v]), so
//! nothing is carried there.

use super::method::{Event, Method, Stop};
use crate::physics::{Arrival, PerUnitMass, SlipForm};

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// Stuck to the belt since `t0` at position `x0`.
    Stick { t0: f64, x0: f64 },
    /// Slipping since `t0` from `(x0, xdot0)` with acceleration `a0` (friction direction folded
    /// in); `graze`: the belt velocity v_g whose grazing orbit this restarted slip lies on (NaN:
    /// none; the module docs) — its friction direction is then sgn(v_g).
    Slip { t0: f64, x0: f64, xdot0: f64, a0: f64, graze: f64 },
}

/// The exact method for one realization's oscillator.
#[derive(Debug, Clone, Copy)]
pub struct Exact<K> {
    p: PerUnitMass,
    form: K,
    /// no friction at all: crossings of belt speed change nothing and are not looked for
    frictionless: bool,
    phase: Phase,
    /// the phase the last advance covered and its belt velocity
    piece: (Phase, f64),
    /// the state `(x, ẋ, ẍ)` where the last advance's slip ended (see [`Exact::slip_end`])
    end: (f64, f64, f64),
    t: f64,
}

impl<K: SlipForm> Exact<K> {
    pub fn new(p: &PerUnitMass) -> Exact<K> {
        let phase = Phase::Stick { t0: 0.0, x0: 0.0 };
        Exact { p: *p, form: K::new(p), frictionless: p.kinetic == 0.0 && p.breakaway == 0.0, phase, piece: (phase, 0.0), end: (0.0, 0.0, 0.0), t: 0.0 }
    }

    /// The mass is at belt velocity `v` at time `t` and position `x` (the arrival rule).
    #[inline(always)]
    fn at_belt_speed(&mut self, t: f64, x: f64, v: f64) -> Stop {
        match self.p.arrival(x, v) {
            Arrival::Reverse { sigma } => {
                self.phase = Phase::Slip { t0: t, x0: x, xdot0: v, a0: self.p.slip_accel(x, v, v, sigma), graze: f64::NAN };
                Stop::Advanced
            }
            Arrival::Touch => {
                self.phase = self.after_breakaway(t, v);
                Stop::Advanced
            }
            Arrival::Stick { x } => {
                self.phase = Phase::Stick { t0: t, x0: x };
                Stop::Event(Event::Stick { t, x })
            }
        }
    }

    /// The slip that leaves the breakaway point at time `t` under belt velocity `v`.
    #[inline(always)]
    fn after_breakaway(&self, t: f64, v: f64) -> Phase {
        Phase::Slip { t0: t, x0: self.p.holding_limit(v, 1.0), xdot0: v, a0: self.p.breakaway_accel(v), graze: f64::NAN }
    }

    /// Slipping from `(x, ẋ)` at time `t` under belt velocity `v` (classified if at belt speed);
    /// the grazing velocity of the slip before a belt change is carried if σ stays sgn(v_g)
    /// (module docs).
    #[inline(always)]
    fn slip_from(&mut self, t: f64, x: f64, xdot: f64, v: f64, graze: f64) -> Option<Event> {
        let u0 = xdot - v;
        if u0 == 0.0 {
            return match self.at_belt_speed(t, x, v) {
                Stop::Event(e) => Some(e),
                _ => None,
            };
        }
        let sigma = -u0.signum();
        let graze = if sigma == graze.signum() && self.p.viscous == 0.0 { graze } else { f64::NAN };
        self.phase = Phase::Slip { t0: t, x0: x, xdot0: xdot, a0: self.p.slip_accel(x, xdot, v, sigma), graze };
        None
    }

    /// Keep the state `(x, ẋ)` at the end of a slip of duration τ from `(x₀, ẋ₀)` with `a₀`, and
    /// its acceleration there: the dry friction is constant along a slip and the rest is linear,
    /// so `ẍ = a₀ − ω² (x − x₀) − (γ + β) (ẋ − ẋ₀)` exactly.
    #[inline(always)]
    fn slip_end(&mut self, x0: f64, xdot0: f64, a0: f64, x: f64, xdot: f64) {
        self.end = (x, xdot, a0 - self.p.omega2 * (x - x0) - self.p.slip_damping() * (xdot - xdot0));
    }

    fn state_in(&self, phase: Phase, t: f64, v: f64) -> (f64, f64) {
        match phase {
            Phase::Stick { t0, x0 } => (x0 + v * (t - t0), v),
            Phase::Slip { t0, x0, xdot0, a0, .. } => self.form.state(x0, xdot0, a0, t - t0),
        }
    }
}

impl<K: SlipForm> Method for Exact<K> {
    fn start(&mut self, x0: f64, xdot0: f64, v: f64) -> Event {
        match self.slip_from(0.0, x0, xdot0, v, f64::NAN) {
            Some(e) => e,
            None => Event::Slip { t: 0.0, x: x0, xdot: xdot0 },
        }
    }

    #[inline(always)]
    fn advance(&mut self, t1: f64, v: f64) -> Stop {
        self.piece = (self.phase, v);
        match self.phase {
            Phase::Stick { t0, x0 } => {
                let t_b = t0 + self.p.stick_duration(x0, v);
                if t_b < t1 {
                    self.t = t_b;
                    self.phase = self.after_breakaway(t_b, v);
                    return Stop::Event(Event::Slip { t: t_b, x: self.p.holding_limit(v, 1.0), xdot: v });
                }
            }
            Phase::Slip { t0, x0, xdot0, a0, graze, .. } => {
                // (a restarted grazing orbit under its own belt velocity only touches it)
                if !self.frictionless && v != graze {
                    if let Some((tau, x1)) = self.form.crossing(x0, xdot0, a0, v, t1 - t0) {
                        if t0 + tau < t1 {
                            self.t = t0 + tau;
                            self.slip_end(x0, xdot0, a0, x1, v);
                            return self.at_belt_speed(t0 + tau, x1, v);
                        }
                    }
                }
                // the state at the segment's end (the switch goes on from it)
                let (x, xdot) = self.form.state(x0, xdot0, a0, t1 - t0);
                self.slip_end(x0, xdot0, a0, x, xdot);
            }
        }
        self.t = t1;
        Stop::SegmentEnd
    }

    #[inline(always)]
    fn switch(&mut self, t: f64, v_old: f64, v_new: f64) -> Option<Event> {
        match self.phase {
            Phase::Stick { t0, x0 } => {
                let x = x0 + v_old * (t - t0);
                let stuck_end = Event::Slip { t, x, xdot: v_old };
                // v_new ≠ v_old: the slip starts off belt speed
                self.slip_from(t, x, v_old, v_new, f64::NAN);
                Some(stuck_end)
            }
            Phase::Slip { xdot0, a0, graze, .. } => {
                // the last advance ended this slip at the switch instant t; a slip that left a
                // breakaway with zero acceleration under v_old is on v_old's grazing orbit
                let (x, xdot, _) = self.end;
                let graze = if !graze.is_nan() {
                    graze
                } else if xdot0 == v_old && a0 == 0.0 {
                    v_old
                } else {
                    f64::NAN
                };
                self.slip_from(t, x, xdot, v_new, graze)
            }
        }
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn state_at(&self, t: f64) -> (f64, f64) {
        self.state_in(self.piece.0, t, self.piece.1)
    }

    fn velocity_range(&self) -> (f64, f64) {
        match self.piece.0 {
            Phase::Stick { .. } => (self.piece.1, self.piece.1),
            Phase::Slip { t0, xdot0, a0, .. } => self.form.velocity_range(xdot0, a0, self.t - t0, self.end.1, self.end.2),
        }
    }
}
