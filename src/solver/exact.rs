//! The exact event-driven solver: closed-form motion in every mode, closed-form event times.
//!
//! Between belt flips the belt velocity `v = s v0` is constant (s = ±1) and each mode has a
//! closed form ([`crate::model`]). The solver walks from event to event, never stepping time:
//!
//! - **stick → slip by breakaway**: in a stick `x = x₀ + v τ`, so `s ω² x` reaches `a_f` after
//!   `τ_b = (a_f − s ω² x₀)/(ω² v0)` (∞ without a spring). The slip that follows starts at
//!   `x_b = s a_f/ω²`, `ẋ = v` with zero acceleration: its velocity `v cos ωτ` touches belt speed
//!   only tangentially, once per period 2π/ω (the *grazing* orbit), and never crosses it. This
//!   orbit is represented exactly (`a₀ = 0`), so no touch is mistaken for a stick.
//! - **stick → slip by a belt flip**: a flip always ends a stick (`u = ẋ − v` jumps to ±2v0).
//! - **slip reaches belt speed** (first root of `u`, [`Accel::belt_speed_crossing`]) at position
//!   x with `p = s ω² x` (the spring force per unit mass, signed along the belt):
//!   - `−a_f ≤ p < a_f`: the static friction can hold the spring → **stick**;
//!   - `p ≈ a_f` (within a relative 1e-12): a touch at the breakaway point, a stick of zero
//!     length → continue on the grazing orbit from `x_b`;
//!   - `|p| > a_f`: the mass passes through belt speed → slip continues with the friction
//!     reversed, `σ = s·sgn(p)`, `a₀ = σ a_f − ω² x` (not a mode change; not reported).
//! - **belt flip during a slip**: the slip continues with the state at the flip and
//!   `σ = −sgn(ẋ − v)` for the new belt velocity.
//!
//! Event times are `t₀ + τ` where t₀ is the previous event or flip instant: flips come from the
//! excitation unchanged, so errors never accumulate beyond one belt segment whatever t_a is.

use super::{Drive, SolveError, Solver};
use crate::events::{Observer, Segment};
use crate::model::{Accel, Model};

/// Relative width of the band around `p = a_f` treated as a touch at the breakaway point.
const TOUCH_TOLERANCE: f64 = 1e-12;

/// At most this many mode events per realization (a guard against runaway input, never reached
/// by physical scenarios: events are bounded by about two per half period and per belt flip).
const EVENT_LIMIT: u64 = 200_000_000;

/// The exact solver for one model.
#[derive(Debug, Clone, Copy)]
pub struct Exact {
    a: Accel,
}

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// Stuck to the belt since `t0` at position `x0`.
    Stick { t0: f64, x0: f64 },
    /// Slipping since `t0` from `(x0, xdot0)` with acceleration `a0` (friction direction folded in).
    Slip { t0: f64, x0: f64, xdot0: f64, a0: f64 },
}

impl Exact {
    pub fn new(model: &Model) -> Exact {
        Exact { a: model.per_unit_mass() }
    }

    /// The mass is at belt velocity `v = s v0` at time `t` and position `x`: stick, touch or
    /// reverse (see the module docs).
    fn at_belt_speed<O: Observer>(&self, t: f64, x: f64, v: f64, s: f64, obs: &mut O) -> Phase {
        match arrival(&self.a, x, s) {
            Arrival::Reverse { sigma } => Phase::Slip { t0: t, x0: x, xdot0: v, a0: sigma * self.a.friction - self.a.omega2 * x },
            Arrival::Touch => Phase::Slip { t0: t, x0: self.a.breakaway_position(s), xdot0: v, a0: 0.0 },
            Arrival::Stick { x } => {
                obs.stick(t, x);
                Phase::Stick { t0: t, x0: x }
            }
        }
    }

    /// A slip phase from `(x, xdot)` at time `t` under belt velocity `v = s v0`.
    fn slip_from<O: Observer>(&self, t: f64, x: f64, xdot: f64, v: f64, s: f64, obs: &mut O) -> Phase {
        let u0 = xdot - v;
        if u0 == 0.0 {
            return self.at_belt_speed(t, x, v, s, obs);
        }
        let sigma = -u0.signum();
        Phase::Slip { t0: t, x0: x, xdot0: xdot, a0: sigma * self.a.friction - self.a.omega2 * x }
    }
}

impl Solver for Exact {
    fn solve<O: Observer>(&self, drive: &Drive<'_>, x0: f64, xdot0: f64, obs: &mut O) -> Result<(), SolveError> {
        let a = self.a;
        let t_end = drive.t_end;
        let mut s = drive.sign0;
        let mut v = s * drive.speed;
        if a.friction == 0.0 {
            // No friction: the mass never sticks and nothing is counted; between flips it
            // oscillates freely (a slip with a0 = −ω² x).
            obs.slip(0.0, x0, xdot0);
            let (mut t, mut x, mut xdot) = (0.0, x0, xdot0);
            for t1 in drive.switches.iter().copied().chain(std::iter::once(t_end)) {
                let seg = Phase::Slip { t0: t, x0: x, xdot0: xdot, a0: -a.omega2 * x };
                emit(obs, &seg, t1, v);
                (x, xdot) = a.slip_state(x, xdot, -a.omega2 * x, t1 - t);
                (t, v) = (t1, -v);
            }
            return Ok(());
        }
        let mut phase = self.slip_from(0.0, x0, xdot0, v, s, obs);
        if let Phase::Slip { .. } = phase {
            obs.slip(0.0, x0, xdot0);
        }
        let mut next = 0usize;
        let mut events = 0u64;
        loop {
            events += 1;
            if events > EVENT_LIMIT {
                return Err(SolveError::EventBudget { limit: EVENT_LIMIT, t: phase_start(&phase) });
            }
            let flip = drive.switches.get(next).copied();
            let t_stop = flip.unwrap_or(t_end).min(t_end);
            match phase {
                Phase::Stick { t0, x0 } => {
                    let t_b = t0 + a.stick_duration(x0, s, drive.speed);
                    if t_b < t_stop {
                        emit(obs, &phase, t_b, v);
                        let x_b = a.breakaway_position(s);
                        obs.slip(t_b, x_b, v);
                        phase = Phase::Slip { t0: t_b, x0: x_b, xdot0: v, a0: 0.0 };
                        continue;
                    }
                    emit(obs, &phase, t_stop, v);
                    if flip.is_none() || t_stop >= t_end {
                        break;
                    }
                    let x = x0 + v * (t_stop - t0);
                    obs.slip(t_stop, x, v);
                    (s, v, next) = (-s, -v, next + 1);
                    phase = self.slip_from(t_stop, x, -v, v, s, obs);
                }
                Phase::Slip { t0, x0, xdot0, a0 } => {
                    if let Some((tau, x1)) = a.belt_speed_crossing(x0, xdot0, a0, v, t_stop - t0) {
                        if t0 + tau < t_stop {
                            emit(obs, &phase, t0 + tau, v);
                            phase = self.at_belt_speed(t0 + tau, x1, v, s, obs);
                            continue;
                        }
                    }
                    emit(obs, &phase, t_stop, v);
                    if flip.is_none() || t_stop >= t_end {
                        break;
                    }
                    let (x, xdot) = a.slip_state(x0, xdot0, a0, t_stop - t0);
                    (s, v, next) = (-s, -v, next + 1);
                    phase = self.slip_from(t_stop, x, xdot, v, s, obs);
                }
            }
        }
        Ok(())
    }
}

/// What a slip that reaches belt velocity `s v0` at position `x` does next (the module docs'
/// rule, shared with the numerical solvers), from `p = s ω² x`, the spring force per unit mass
/// signed along the belt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Arrival {
    /// `−a_f ≤ p < a_f`: the static friction holds the spring; the stick starts at `x` (clamped
    /// onto `|k x| ≤ f_max` within the touch band)
    Stick { x: f64 },
    /// `p ≈ a_f` (relative [`TOUCH_TOLERANCE`]): a touch at the breakaway point; the slip goes on
    /// along the grazing orbit from `x_b`, which never crosses belt speed
    Touch,
    /// `|p| > a_f`: the mass passes through belt speed; the friction becomes `σ = s sgn p`
    Reverse { sigma: f64 },
}

pub(crate) fn arrival(a: &Accel, x: f64, s: f64) -> Arrival {
    let p = s * a.omega2 * x;
    if p > a.friction * (1.0 + TOUCH_TOLERANCE) || p < -a.friction * (1.0 + TOUCH_TOLERANCE) {
        Arrival::Reverse { sigma: s * p.signum() }
    } else if p >= a.friction * (1.0 - TOUCH_TOLERANCE) {
        Arrival::Touch
    } else {
        // Within [−a_f(1+tol), a_f): clamp the lower edge so that |k x| ≤ f_max holds exactly.
        Arrival::Stick { x: if p < -a.friction { a.breakaway_position(-s) } else { x } }
    }
}

/// Report the piece of motion of `phase` up to `t1` under belt velocity `v`.
fn emit<O: Observer>(obs: &mut O, phase: &Phase, t1: f64, v: f64) {
    let segment = match *phase {
        Phase::Stick { t0, x0 } => Segment { t0, t1, stick: true, x0, xdot0: v, a0: 0.0, v },
        Phase::Slip { t0, x0, xdot0, a0 } => Segment { t0, t1, stick: false, x0, xdot0, a0, v },
    };
    obs.segment(&segment);
}

fn phase_start(p: &Phase) -> f64 {
    match *p {
        Phase::Stick { t0, .. } | Phase::Slip { t0, .. } => t0,
    }
}
