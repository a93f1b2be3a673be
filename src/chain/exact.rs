//! The exact method for chains: the state stepped by e^{Ãτ}, every event found as a proven zero
//! of its event function.
//!
//! A phase (a mode under one belt velocity v and one anchor velocity u) has a fixed Ã
//! ([`super::matrix::System`]). Its weighted norm ‖Ã‖_D (velocities weighted by the fastest
//! rate Ω of the chain, the constant by what keeps its column below Ω) fixes the step
//! H = 1/‖Ã‖_D. On each step [τ, τ + h], h ≤ H, the state moves by the Taylor series of
//! e^{Ãh} (25 terms: the rest is below 10⁻²⁵ of ‖z‖), and the event function g = c·z equals
//! its Taylor polynomial P(s) = Σ_j (c Ã^j z(τ)) s^j/j! to within the proven bound
//! δ = ‖c Ã^{25}‖_D* e^{‖Ã‖h} ‖z‖_D h^{25}/25! plus the coefficients' rounding. The zeros of g
//! on the step are those of P within δ, found by the isolation of [`super::roots`], which
//! proves every sub-interval it skips free of zeros: no event is missed, and a simple zero is
//! located to adjacent floats of P (the event time to about 10⁻¹⁶ relative).
//!
//! A phase that starts at a zero of its own event function — the slip after a breakaway or a
//! pass-through (w = 0), with μ_s = μ_k also ẇ = 0 (the grazing departure) — leaves it with a
//! known sign; the search starts past the band where the first non-vanishing derivative of P
//! is proven to have that sign ([`super::roots::Poly::leaves`]), so the start is not found
//! again (the chain's form of the grazing rule of [`crate::solver::exact`]).
//!
//! A tangency of g within its error bound (a *touch*): in a slip, an arrival decided by the
//! arrival rule like any other; in a stick, F touching ±f_s from inside is not a breakaway
//! (|F| ≤ f_s holds).

use super::matrix::{anchor_force, dot, holding, relative_velocity, x, xd, Mode, System};
use super::roots::{Poly, Zero, RESOLUTION};
use super::{Anchor, Chain, ChainSummary};
use crate::physics::TOUCH_TOLERANCE;
use crate::solver::{Event, Method, Stop};

/// The piece of motion one advance covered: its start time and state and its system (kept only
/// for trajectory sampling), the polynomial of w on it with its margin (a slip), and its length.
#[derive(Debug, Clone, Default)]
struct Piece {
    t0: f64,
    z0: Vec<f64>,
    sys: Option<System>,
    slip: Option<(Poly, f64)>,
    len: f64,
}

/// The exact method for one realization's chain.
#[derive(Debug, Clone)]
pub struct ChainExact {
    ch: Chain,
    anchor: Anchor,
    /// the floor of the norm's rate, 1/t_a [1/s]
    rate: f64,
    /// the state (x₁…x_N, ẋ₁…ẋ_N, a, 1) and its time
    z: Vec<f64>,
    t: f64,
    mode: Mode,
    /// the belt velocity of the phase
    v: f64,
    /// the anchor's segment
    segment: usize,
    sys: System,
    /// the row c of the phase's event function (w, or F)
    row: Vec<f64>,
    /// scratch: the powers Ã^j z of a step ([`System::powers`]) and a state
    powers: Vec<f64>,
    scratch: Vec<f64>,
    /// the sign the event function leaves zero with at the phase's start (None: it starts off
    /// zero)
    leave: Option<f64>,
    /// no friction at all: crossings of belt speed change nothing and are not looked for
    frictionless: bool,
    /// the anchor's force T as a row (it depends on u), ∫ T dt so far, its least and greatest
    /// value, and x_N(0)
    tension: Vec<f64>,
    tension_integral: f64,
    tension_range: (f64, f64),
    contact_start: f64,
    /// the piece of motion the last advance covered
    piece: Piece,
    keep: bool,
}

impl ChainExact {
    /// The method for `ch` from the state `x0`, `xd0` (every mass's position and velocity at
    /// t = 0), under the anchor's motion `anchor`, over a window of `t_a` seconds.
    pub fn new(ch: &Chain, anchor: &Anchor, x0: &[f64], xd0: &[f64], t_a: f64) -> ChainExact {
        let n = ch.len();
        let mut z = vec![0.0; 2 * n + 2];
        z[..n].copy_from_slice(x0);
        z[n..2 * n].copy_from_slice(xd0);
        z[2 * n + 1] = 1.0;
        let rate = 1.0 / t_a;
        let sys = System::new(ch, Mode::Slip(1.0), 0.0, anchor.velocities[0], rate);
        ChainExact {
            ch: ch.clone(),
            anchor: anchor.clone(),
            rate,
            z,
            t: 0.0,
            mode: Mode::Slip(1.0),
            v: 0.0,
            segment: 0,
            sys,
            row: Vec::new(),
            powers: Vec::new(),
            scratch: Vec::new(),
            leave: None,
            frictionless: ch.kinetic == 0.0 && ch.breakaway == 0.0,
            tension: anchor_force(ch, anchor.velocities[0]),
            tension_integral: 0.0,
            tension_range: (f64::INFINITY, f64::NEG_INFINITY),
            contact_start: x0[n - 1],
            piece: Piece::default(),
            keep: false,
        }
    }

    /// The whole state (x₁…x_N, ẋ₁…ẋ_N, a, 1) at the time reached.
    pub fn state(&self) -> &[f64] {
        &self.z
    }

    /// The whole state at `t` on the piece of motion the last advance covered (after
    /// [`Method::keep_pieces`]; before any advance, the state reached).
    pub fn state_of_all_at(&self, t: f64) -> Vec<f64> {
        match &self.piece.sys {
            Some(sys) => sys.step(&self.piece.z0, t - self.piece.t0),
            None => self.z.clone(),
        }
    }

    /// The contact's mode now: stuck (true) or slipping.
    pub fn stuck(&self) -> bool {
        self.mode == Mode::Stick
    }

    /// What the realization adds to its row ([`ChainSummary`]), once the driver reached t_a.
    pub fn summary(&self) -> ChainSummary {
        let n = self.ch.len();
        ChainSummary {
            anchor_force_mean: self.tension_integral / self.t,
            anchor_force_min: self.tension_range.0,
            anchor_force_max: self.tension_range.1,
            mean_velocity: (self.z[x(n - 1)] - self.contact_start) / self.t,
        }
    }

    /// Add the anchor's force over the piece [0, s] of this step (its integral, its ends and
    /// turning points).
    fn tension_over(&mut self, h: f64, s: f64) {
        let (p, margin) = self.sys.taylor(&self.tension, &self.powers, h);
        self.tension_integral += p.integral(s);
        let (lo, hi) = p.range(s, margin);
        self.tension_range = (self.tension_range.0.min(lo), self.tension_range.1.max(hi));
    }

    fn u(&self) -> f64 {
        self.anchor.velocities[self.segment]
    }

    fn contact(&self) -> (f64, f64) {
        let n = self.ch.len();
        (self.z[x(n - 1)], self.z[xd(n, n - 1)])
    }

    /// Begin the phase `mode` at the current state.
    fn enter(&mut self, mode: Mode, leave: Option<f64>) {
        let n = self.ch.len();
        self.mode = mode;
        self.leave = leave;
        self.sys = System::new(&self.ch, mode, self.v, self.u(), self.rate);
        let row = match mode {
            Mode::Slip(_) => relative_velocity(n, self.v),
            Mode::Stick => {
                self.z[xd(n, n - 1)] = self.v;
                holding(&self.ch, self.v, self.u())
            }
        };
        self.row = row;
    }

    /// The holding force F at the current state (contact at belt speed).
    fn force(&self) -> f64 {
        dot(&holding(&self.ch, self.v, self.u()), &self.z)
    }

    /// The contact is at belt speed: the arrival rule (module docs of [`super`]).
    fn arrive(&mut self) -> Stop {
        let n = self.ch.len();
        self.z[xd(n, n - 1)] = self.v;
        let (f, fs) = (self.force(), self.ch.breakaway);
        let band = TOUCH_TOLERANCE * fs;
        let stick = if f.abs() < fs - band {
            true
        } else if f.abs() > fs + band {
            false
        } else {
            // at the limit: a stick unless F moves outward under stick dynamics
            let stuck = System::new(&self.ch, Mode::Stick, self.v, self.u(), self.rate);
            let rate = dot(&stuck.left(&holding(&self.ch, self.v, self.u())), &self.z);
            f.signum() * rate <= 0.0
        };
        if stick {
            self.enter(Mode::Stick, None);
            Stop::Event(Event::Stick { t: self.t, x: self.z[x(n - 1)] })
        } else {
            self.enter(Mode::Slip(f.signum()), Some(f.signum()));
            Stop::Advanced
        }
    }

    /// The step's length from the current time towards `t_stop`.
    fn step_len(&self, t_stop: f64) -> f64 {
        let h = 1.0 / self.sys.norm;
        (t_stop - self.t).min(h)
    }

    /// Move the state by s and the time to t + s (to `t_stop` exactly when s reaches it).
    fn go(&mut self, s: f64, t_stop: f64) {
        self.sys.at(&self.powers, s, &mut self.scratch);
        std::mem::swap(&mut self.z, &mut self.scratch);
        if self.mode == Mode::Stick {
            let n = self.ch.len();
            self.z[xd(n, n - 1)] = self.v;
        }
        self.t = if s >= t_stop - self.t { t_stop } else { self.t + s };
    }

    /// The anchor changes velocity at the current time.
    fn anchor_switch(&mut self) -> Stop {
        self.segment += 1;
        self.tension = anchor_force(&self.ch, self.u());
        match self.mode {
            Mode::Slip(sigma) => {
                self.enter(Mode::Slip(sigma), None);
                Stop::Advanced
            }
            Mode::Stick => {
                let f = self.force();
                if f.abs() > self.ch.breakaway * (1.0 + TOUCH_TOLERANCE) {
                    let (xn, _) = self.contact();
                    self.enter(Mode::Slip(f.signum()), Some(f.signum()));
                    Stop::Event(Event::Slip { t: self.t, x: xn, xdot: self.v })
                } else {
                    self.enter(Mode::Stick, None);
                    Stop::Advanced
                }
            }
        }
    }

    /// Where the search for the phase's next zero starts on this step (past the band of the
    /// zero it starts at, if it does).
    fn search_from(&self, p: &Poly, h: f64, sign: Option<f64>) -> f64 {
        match sign {
            Some(s) => p.leaves(s, h).max(RESOLUTION * h),
            None => 0.0,
        }
    }
}

impl Method for ChainExact {
    fn start(&mut self, _x0: f64, _xdot0: f64, v: f64) -> Event {
        self.v = v;
        let (xn, xdn) = self.contact();
        let w = v - xdn;
        if w == 0.0 {
            if let Stop::Event(e) = self.arrive() {
                return e;
            }
        } else {
            self.enter(Mode::Slip(w.signum()), None);
        }
        Event::Slip { t: 0.0, x: xn, xdot: xdn }
    }

    fn advance(&mut self, t1: f64, v: f64) -> Stop {
        debug_assert_eq!(v, self.v);
        let u_end = self.anchor.switches.get(self.segment).copied().unwrap_or(f64::INFINITY);
        let t_stop = t1.min(u_end);
        if self.t >= t_stop {
            return if t_stop < t1 { self.anchor_switch() } else { Stop::SegmentEnd };
        }
        let h = self.step_len(t_stop);
        if self.keep {
            self.piece.t0 = self.t;
            self.piece.z0.clone_from(&self.z);
            self.piece.sys = Some(self.sys.clone());
        }
        self.sys.powers(&self.z, &mut self.powers);
        let (p, margin) = self.sys.taylor(&self.row, &self.powers, h);
        let leave = self.leave.take();
        match self.mode {
            Mode::Slip(_) => {
                let from = self.search_from(&p, h, leave);
                let zero = if self.frictionless { None } else { p.first_zero(from, h, margin) };
                let s = zero.map_or(h, |z| z.s);
                self.piece.slip = Some((p, margin));
                self.piece.len = s;
                self.tension_over(h, s);
                self.go(s, t_stop);
                if zero.is_some() {
                    return self.arrive();
                }
            }
            Mode::Stick => {
                self.piece.slip = None;
                let p_force = p.c[0];
                let fs = self.ch.breakaway;
                let mut first: Option<(Zero, f64)> = None;
                let (mut g, force) = (p, p_force);
                for side in [1.0, -1.0] {
                    // g = F − side·f_s, ≤ 0 (side +) or ≥ 0 (side −) while stuck
                    g.c[0] = force - side * fs;
                    let at_limit = g.c[0].abs() <= TOUCH_TOLERANCE * fs;
                    let from = self.search_from(&g, h, if at_limit { Some(-side) } else { None });
                    let mut found = None;
                    g.zeros(from, h, margin, &mut |z| {
                        if z.touch {
                            return false;
                        }
                        found = Some(z);
                        true
                    });
                    if let Some(z) = found {
                        if first.is_none_or(|(f, _)| z.s < f.s) {
                            first = Some((z, side));
                        }
                    }
                }
                let s = first.map_or(h, |(z, _)| z.s);
                self.piece.len = s;
                self.tension_over(h, s);
                self.go(s, t_stop);
                if let Some((_, side)) = first {
                    let (xn, _) = self.contact();
                    self.enter(Mode::Slip(side), Some(side));
                    return Stop::Event(Event::Slip { t: self.t, x: xn, xdot: self.v });
                }
            }
        }
        if self.t >= t_stop {
            return if t_stop < t1 { self.anchor_switch() } else { Stop::SegmentEnd };
        }
        Stop::Advanced
    }

    fn switch(&mut self, t: f64, v_old: f64, v_new: f64) -> Option<Event> {
        debug_assert_eq!(t, self.t);
        self.v = v_new;
        match self.mode {
            Mode::Stick => {
                let (xn, _) = self.contact();
                self.enter(Mode::Slip((v_new - v_old).signum()), None);
                Some(Event::Slip { t, x: xn, xdot: v_old })
            }
            Mode::Slip(_) => {
                let (_, xdn) = self.contact();
                let w = v_new - xdn;
                if w == 0.0 {
                    match self.arrive() {
                        Stop::Event(e) => Some(e),
                        _ => None,
                    }
                } else {
                    self.enter(Mode::Slip(w.signum()), None);
                    None
                }
            }
        }
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn keep_pieces(&mut self) {
        self.keep = true;
    }

    fn state_at(&self, t: f64) -> (f64, f64) {
        let n = self.ch.len();
        match &self.piece.sys {
            Some(sys) => {
                let z = sys.step(&self.piece.z0, t - self.piece.t0);
                (z[x(n - 1)], z[xd(n, n - 1)])
            }
            None => self.contact(),
        }
    }

    fn non_finite(&self) -> bool {
        !self.z.iter().all(|v| v.is_finite())
    }

    fn velocity_range(&self) -> (f64, f64) {
        let (_, xdn) = self.contact();
        match &self.piece.slip {
            // ẋ_N = v − w on the slip's piece [0, s]: its ends and the turning points inside
            Some((w, margin)) => {
                let (lo, hi) = w.range(self.piece.len, *margin);
                ((self.v - hi).min(xdn), (self.v - lo).max(xdn))
            }
            None => (self.v.min(xdn), self.v.max(xdn)),
        }
    }
}
