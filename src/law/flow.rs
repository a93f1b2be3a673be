//! The flow between two belt flips, in the belt's frame (module docs of [`super`]): slip arcs
//! about ±c_k, sticks on the belt line, the breakaway, and the periodic slips that never reach
//! belt speed — walked in closed form, each piece handed to a [`Visitor`] with its exact times.

use std::f64::consts::TAU;

use crate::physics::{Damped, SlipForm};

/// Walks stop where the weight e^{−λt} of what follows falls below e^{−41.4} ≈ 1e-18.
pub(crate) const HORIZON_DECAYS: f64 = 41.4;

/// The reflected frame's constants (module docs of [`super`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    /// ω [1/s]
    pub omega: f64,
    /// v0 [m/s], the belt speed (+v0 in this frame)
    pub v0: f64,
    /// w0 = v0/ω [m]: the belt line's height in the plane (X, V/ω)
    pub w0: f64,
    /// c_k = a_k/ω² [m]: the slip centres ±c_k
    pub ck: f64,
    /// c_s = a_s/ω² [m]: the stick holds on −c_s ≤ X < c_s
    pub cs: f64,
    /// λ [1/s], the flip rate
    pub lambda: f64,
    /// the damped closed forms (module docs of [`crate::physics::damped`]) when the dashpot
    /// c > 0, else None: the undamped circles
    pub damped: Option<Damped>,
}

/// A slip state: position X, velocity V, on which side of belt speed it moves (the side decides
/// the friction, and so the centre, when V = v0 exactly).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slip {
    pub x: f64,
    pub v: f64,
    /// below belt speed (σ = +1, centre +c_k)
    pub below: bool,
}

impl Slip {
    /// A post-flip state off the belt line: its side from V.
    pub fn at(x: f64, v: f64, v0: f64) -> Slip {
        Slip { x, v, below: v < v0 }
    }
}

/// What the walk reports, every time as an absolute time t from the walk's start; `scale` is the
/// factor of a periodic piece's repetitions where it applies (module docs of [`super`]).
pub(crate) trait Visitor {
    /// A slip sample: the mass is at (x, v) in slip during [t, t + dt) and was age-`age` into its slip at t.
    fn slip(&mut self, x: f64, v: f64, t: f64, dt: f64, age: f64);
    /// A periodic slip piece from time t (state at its start, age at its start, period P): the
    /// walk ends here; the visitor samples it itself (it repeats forever until the next flip).
    fn periodic(&mut self, start: Slip, t: f64, age: f64, period: f64);
    /// A stick entered at x_e at time t (it lasts until the breakaway at c_s unless a flip comes first).
    fn stick(&mut self, x_e: f64, t: f64);
    /// The slip after a breakaway (or after a touch at the breakaway point, which is not a stick)
    /// begins at time t: the walk ends here (what follows is the same for every start: the
    /// visitor adds it); `age` is the slip's age then (0 after a breakaway, which ends a stick;
    /// a touch continues the slip).
    fn breakaway_slip(&mut self, t: f64, age: f64);
}

impl Frame {
    /// γ = c/m [1/s] (0 without a dashpot).
    fn gamma(&self) -> f64 {
        self.damped.map_or(0.0, |d| d.gamma())
    }

    /// The dashpot's shift of the stick region, γ v0/ω² [m]: while stuck the holding force per
    /// unit mass is ω² X + γ v0, within ±a_s on [`Frame::hold_lo`], [`Frame::hold_hi`].
    fn shift(&self) -> f64 {
        self.gamma() * self.v0 / (self.omega * self.omega)
    }

    /// The stick region's lower end −c_s − γ v0/ω² [m] (−c_s without a dashpot): an arrival
    /// below it passes through belt speed.
    pub fn hold_lo(&self) -> f64 {
        -self.cs - self.shift()
    }

    /// The breakaway point x_b = c_s − γ v0/ω² [m] (c_s without a dashpot): a stick entered at
    /// X_e breaks away after (x_b − X_e)/v0.
    pub fn hold_hi(&self) -> f64 {
        self.cs - self.shift()
    }

    /// The centre of the slip's circle: +c_k below belt speed, −c_k above.
    fn centre(&self, below: bool) -> f64 {
        if below {
            self.ck
        } else {
            -self.ck
        }
    }

    /// The state after the time τ on the circle of centre `c` started at angle φ0, radius r:
    /// X = C + r sin φ, V = ω r cos φ, φ = φ0 + ω τ (the harmonic slip ẍ = −ω²(x − C)).
    pub fn on_circle(&self, c: f64, r: f64, phi0: f64, tau: f64) -> (f64, f64) {
        let (s, co) = (phi0 + self.omega * tau).sin_cos();
        (c + r * s, self.omega * r * co)
    }

    /// Polar coordinates (r, φ) of a state about the centre `c`.
    pub fn polar(&self, c: f64, x: f64, v: f64) -> (f64, f64) {
        let (dx, dw) = (x - c, v / self.omega);
        (dx.hypot(dw), dx.atan2(dw))
    }

    /// Walk from the slip state `z` (age `age` into its slip) until the next stick, breakaway
    /// slip or periodic slip, reporting each piece to `visit`; pieces later than `horizon` are
    /// not walked (their weight e^{−λt} is below what the caller keeps). Slip arcs are cut into
    /// samples at most `spacing` long in the plane (X, V/ω).
    pub fn walk(&self, mut z: Slip, age: f64, spacing: f64, horizon: f64, visit: &mut impl Visitor) {
        if let Some(form) = self.damped {
            return self.walk_damped(&form, z, age, spacing, horizon, visit);
        }
        let mut t = 0.0;
        // each pass-through loses 2 c_k of amplitude (Coulomb), so the walk ends; the bound only
        // guards against c_k = 0, where an arc can pass through belt speed forever
        for _ in 0..100_000 {
            if t > horizon {
                return;
            }
            if z.v == self.v0 && (if z.below { z.x < self.ck } else { z.x > -self.ck }) {
                // on the belt line and moving across it: arrives now
                match self.arrive(z, t, age, visit) {
                    Some(next) => {
                        z = next;
                        continue;
                    }
                    None => return,
                }
            }
            let c = self.centre(z.below);
            let (r, phi0) = self.polar(c, z.x, z.v);
            if z.below && r < self.w0 {
                // a circle under the belt line: slips forever (until a flip)
                visit.periodic(z, t, age + t, TAU / self.omega);
                return;
            }
            // the arrival at belt speed: rising on the circle's left side (below), falling on
            // its right side (above), where r cos φ = w0
            let half = (self.w0 / r).min(1.0).acos();
            let target = if z.below { TAU - half } else { half };
            let mut turn = (target - phi0).rem_euclid(TAU);
            if turn == 0.0 {
                turn = TAU;
            }
            let duration = turn / self.omega;
            self.sample_arc(c, r, phi0, t, duration, age, spacing, horizon, visit);
            t += duration;
            let reach = (r * r - self.w0 * self.w0).max(0.0).sqrt();
            let xa = if z.below { c - reach } else { c + reach };
            match self.arrive(Slip { x: xa, v: self.v0, below: z.below }, t, age, visit) {
                Some(next) => z = next,
                None => return,
            }
        }
    }

    /// The arrival at belt speed of `z` (on the belt line) at time t: a stick, a touch at the
    /// breakaway point (the walk ends in both), or the slip passing belt speed, whose state on
    /// the other side is returned.
    fn arrive(&self, z: Slip, t: f64, age: f64, visit: &mut impl Visitor) -> Option<Slip> {
        if (self.hold_lo()..self.hold_hi()).contains(&z.x) {
            visit.stick(z.x, t);
            return None;
        }
        if z.below && z.x >= self.hold_hi() {
            // (only c_k = c_s, r = w0: a touch at the breakaway point)
            visit.breakaway_slip(t, age + t);
            return None;
        }
        // passes through belt speed: the friction reverses
        Some(Slip { below: !z.below, ..z })
    }

    /// The walk of [`Frame::walk`] with a dashpot: the slip spirals (ẍ = σ a_k − ω² X − γ Ẋ,
    /// σ = +1 below belt speed, −1 above, in this frame), and its arrival at belt speed is
    /// [`Damped::crossing`]'s first root of Ẋ = v0 (closed-form turning points bracket it: no
    /// step can miss a shallow crossing). The arrival rule is the undamped one on the shifted
    /// stick region [`Frame::hold_lo`] ≤ X < [`Frame::hold_hi`]. A spiral that does not reach
    /// belt speed again never will (the energy ω²(X − σc_k)² + Ẋ² only falls), so there is no
    /// periodic piece: the walk samples it up to the horizon, capped at [`HORIZON_DECAYS`]/λ
    /// (a breakaway slip, walked with an infinite horizon, would otherwise not end). With
    /// μ_s = μ_k the breakaway slip leaves (x_b, v0) with zero acceleration: a velocity
    /// maximum, the spiral never touches belt speed again.
    fn walk_damped(&self, form: &Damped, mut z: Slip, age: f64, spacing: f64, horizon: f64, visit: &mut impl Visitor) {
        let horizon = horizon.min(HORIZON_DECAYS / self.lambda);
        let (w2, gamma, ak) = (self.omega * self.omega, self.gamma(), self.ck * self.omega * self.omega);
        let accel = |z: &Slip| (if z.below { ak } else { -ak }) - w2 * z.x - gamma * z.v;
        // a start on the belt line moving across it arrives at once
        let a0 = accel(&z);
        if z.v == self.v0 && (if z.below { a0 > 0.0 } else { a0 < 0.0 }) {
            match self.arrive_damped(z, 0.0, visit) {
                Some(next) => z = next,
                None => return,
            }
        }
        let mut t = 0.0;
        // each pass through belt speed loses amplitude (Coulomb and the dashpot): the walk ends
        for _ in 0..100_000 {
            if t > horizon {
                return;
            }
            let a0 = accel(&z);
            match form.crossing(z.x, z.v, a0, self.v0, horizon - t) {
                Some((tau, xa)) => {
                    self.sample_damped(form, z, a0, t, tau, age, spacing, visit);
                    t += tau;
                    match self.arrive_damped(Slip { x: xa, v: self.v0, below: z.below }, t, visit) {
                        Some(next) => z = next,
                        None => return,
                    }
                }
                None => {
                    self.sample_damped(form, z, a0, t, horizon - t, age, spacing, visit);
                    return;
                }
            }
        }
    }

    /// A damped arrival at belt speed: a stick on the shifted region, else the slip goes on on
    /// the other side (a rising arrival at X ≥ x_b, a tangent touch only reached by rounding,
    /// goes on below: [`Damped::crossing`] then finds where it comes back, if it does).
    fn arrive_damped(&self, z: Slip, t: f64, visit: &mut impl Visitor) -> Option<Slip> {
        if (self.hold_lo()..self.hold_hi()).contains(&z.x) {
            visit.stick(z.x, t);
            return None;
        }
        Some(if z.below && z.x >= self.hold_hi() { z } else { Slip { below: !z.below, ..z } })
    }

    /// Samples of the damped slip from `z` (acceleration a0) over [t0, t0 + duration), at most
    /// `spacing` apart in the plane (X, V/ω): the plane speed is at most R(ω + γ) with R the
    /// start's radius about its centre σ c_k (the energy only falls: |X − σc_k|, |V|/ω ≤ R, and
    /// |Ẍ|/ω ≤ ωR + γR).
    #[allow(clippy::too_many_arguments)]
    fn sample_damped(&self, form: &Damped, z: Slip, a0: f64, t0: f64, duration: f64, age: f64, spacing: f64, visit: &mut impl Visitor) {
        let (r, _) = self.polar(self.centre(z.below), z.x, z.v);
        let n = ((r * (self.omega + self.gamma()) * duration / spacing).ceil() as usize).max(1);
        let dt = duration / n as f64;
        let mid = centroid(self.lambda, dt);
        for i in 0..n {
            let (x, v) = form.state(z.x, z.v, a0, i as f64 * dt + mid);
            visit.slip(x, v, t0 + i as f64 * dt, dt, age + t0 + i as f64 * dt);
        }
    }

    /// Samples of the arc of centre `c`, radius r from angle φ0 over [t0, t0 + duration).
    #[allow(clippy::too_many_arguments)]
    fn sample_arc(&self, c: f64, r: f64, phi0: f64, t0: f64, duration: f64, age: f64, spacing: f64, horizon: f64, visit: &mut impl Visitor) {
        let n = ((self.omega * r * duration / spacing).ceil() as usize).max(1);
        let dt = duration / n as f64;
        for i in 0..n {
            let t = t0 + i as f64 * dt;
            if t > horizon {
                return;
            }
            let (x, v) = self.on_circle(c, r, phi0, i as f64 * dt + centroid(self.lambda, dt));
            visit.slip(x, v, t, dt, age + t);
        }
    }

    /// One period of the periodic slip from `start` (a circle under the belt line), cut into
    /// intervals at most `spacing` long in the plane: (the interval's start from `start`, its
    /// length, the state at its e^{−λτ}-weighted centre) — the samples a visitor's
    /// [`Visitor::periodic`] repeats.
    pub fn period_samples(&self, start: Slip, period: f64, spacing: f64) -> impl Iterator<Item = (f64, f64, (f64, f64))> + '_ {
        let c = self.centre(start.below);
        let (r, phi0) = self.polar(c, start.x, start.v);
        let n = ((self.omega * r * period / spacing).ceil() as usize).max(8);
        let dt = period / n as f64;
        let mid = centroid(self.lambda, dt);
        (0..n).map(move |i| (i as f64 * dt, dt, self.on_circle(c, r, phi0, i as f64 * dt + mid)))
    }

    /// Half the side of the box of the plane (X, V/ω) that holds the chain's post-flip states,
    /// m: they stay within |X| < 2(c_s + c_k) + w0 on the paper scene but for a mass ~1e-12
    /// pumped further by flips at the turning points.
    pub fn box_half(&self) -> f64 {
        2.0 * (self.cs + self.shift() + self.ck + self.w0)
    }

    /// The slip right after a breakaway at (x_b, v0), below belt speed.
    pub fn breakaway(&self) -> Slip {
        Slip { x: self.hold_hi(), v: self.v0, below: true }
    }
}

/// The e^{−λτ}-weighted mean of τ over [0, dt): where a sample of that interval is placed.
pub(crate) fn centroid(lambda: f64, dt: f64) -> f64 {
    let x = lambda * dt;
    if x < 1e-4 {
        dt * (0.5 - x / 12.0)
    } else {
        1.0 / lambda - dt / x.exp_m1()
    }
}

/// The e^{−λτ}-weighted mean of τ² over [0, dt): with x = λ dt, integrating by parts,
/// E[u²] = (2/λ) E[u] − dt²/(e^x − 1) = dt² [2/x² − (2/x + 1)/(e^x − 1)] (the subtraction loses
/// under 1e-13 for x ≥ 0.1), and below x = 0.1 the series from the Bernoulli expansion of
/// 1/(e^x − 1): dt² (1/3 − x/12 + x²/360 + x³/720 − x⁴/15120 − x⁵/30240 + x⁶/604800 +
/// x⁷/1209600 − …), whose next term is below 1e-15 there; dt²/3 for λ → 0.
pub(crate) fn second_moment(lambda: f64, dt: f64) -> f64 {
    let x = lambda * dt;
    let scaled = if x < 0.1 {
        1.0 / 3.0
            + x * (-1.0 / 12.0 + x * (1.0 / 360.0 + x * (1.0 / 720.0 + x * (-1.0 / 15120.0 + x * (-1.0 / 30240.0 + x * (1.0 / 604800.0 + x / 1209600.0))))))
    } else {
        2.0 / (x * x) - (2.0 / x + 1.0) / x.exp_m1()
    };
    dt * dt * scaled
}

/// ∫_{t0}^{t1} e^{−λt} dt.
pub(crate) fn decay(lambda: f64, t0: f64, t1: f64) -> f64 {
    (-lambda * t0).exp() * -(-lambda * (t1 - t0)).exp_m1() / lambda
}

/// ∫_{t0}^{t1} e^{−λt} (a + t − t0) dt: the age integral of an interval that starts at age a.
pub(crate) fn aged_decay(lambda: f64, t0: f64, t1: f64, a: f64) -> f64 {
    let d = t1 - t0;
    let e = (-lambda * d).exp();
    // ∫_0^d e^{−λs}(a + s) ds = a(1 − e)/λ + (1 − e(1 + λd))/λ²
    let second = if lambda * d < 1e-3 {
        // (1 − e^{−x}(1 + x))/λ² = d²(1/2 − x/3 + x²/8 − x³/30 + …)
        let x = lambda * d;
        d * d * (0.5 - x / 3.0 + x * x / 8.0 - x * x * x / 30.0)
    } else {
        (1.0 - e * (1.0 + lambda * d)) / (lambda * lambda)
    };
    (-lambda * t0).exp() * (a * -(-lambda * d).exp_m1() / lambda + second)
}

/// 1 − e^{−x}(1 + x), accurate for small x (x²/2 − x³/3 + x⁴/8 − …).
pub(crate) fn one_minus_exp_poly(x: f64) -> f64 {
    if x < 1e-3 {
        x * x * (0.5 - x / 3.0 + x * x / 8.0 - x * x * x / 30.0)
    } else {
        1.0 - (-x).exp() * (1.0 + x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER: Frame = Frame { omega: 2.0, v0: 1.0, w0: 0.5, ck: 1.2495, cs: 1.2495, lambda: 5.0, damped: None };

    #[derive(Default)]
    struct Log {
        slip: f64,
        last: Option<(f64, f64)>,
        stick: Option<(f64, f64)>,
        periodic: bool,
        breakaway: Option<f64>,
    }

    impl Visitor for Log {
        fn slip(&mut self, x: f64, v: f64, _t: f64, dt: f64, _age: f64) {
            self.slip += dt;
            self.last = Some((x, v));
        }
        fn periodic(&mut self, _start: Slip, _t: f64, _age: f64, _period: f64) {
            self.periodic = true;
        }
        fn stick(&mut self, x_e: f64, t: f64) {
            self.stick = Some((x_e, t));
        }
        fn breakaway_slip(&mut self, t: f64, _age: f64) {
            self.breakaway = Some(t);
        }
    }

    #[test]
    fn a_stick_ended_by_a_flip_resticks_at_the_same_place() {
        // stuck at y on the belt, the belt flips: in the new frame the mass is at (−y, −v0) on
        // the circle about +c_k of radius √((y + c_k)² + w0²), which meets V = v0 at the mirror
        // point −y (the same place on the ground) after (2/ω) atan(w0/(y + c_k))
        for y in [-1.2, -0.3, 0.0, 0.7, 1.2] {
            let mut log = Log::default();
            PAPER.walk(Slip::at(-y, -1.0, 1.0), 0.0, 1e-3, 100.0, &mut log);
            let (xe, t) = log.stick.expect("a stick");
            assert!((xe + y).abs() < 1e-12, "{xe} {y}");
            let expect = 2.0 / PAPER.omega * (PAPER.w0 / (PAPER.ck + y)).atan();
            assert!((t - expect).abs() < 1e-12 && (log.slip - t).abs() < 1e-12, "{t} {expect}");
        }
    }

    #[test]
    fn a_large_oscillation_loses_2ck_per_half_turn_until_it_sticks() {
        // from rest at X = −5 (below belt speed, centre +c_k, r = 6.2495 > w0): it rises to belt
        // speed at c_k − √(r² − w0²) < −c_s, passes, turns about −c_k and comes down at
        // −2c_k − X_a; the energy check: the walk ends in a stick inside [−c_s, c_s)
        let mut log = Log::default();
        PAPER.walk(Slip::at(-5.0, 0.0, 1.0), 0.0, 1e-3, 100.0, &mut log);
        let r: f64 = 5.0 + PAPER.ck;
        let xa = PAPER.ck - (r * r - 0.25).sqrt();
        assert!(xa < -PAPER.cs);
        let (xe, _) = log.stick.expect("a stick");
        assert!((xe - (-2.0 * PAPER.ck - xa)).abs() < 1e-12 || xe.abs() < PAPER.cs, "{xe}");
        assert!((-PAPER.cs..PAPER.cs).contains(&xe));
    }

    #[test]
    fn inside_the_belt_line_the_slip_is_periodic_and_the_breakaway_grazes() {
        let mut log = Log::default();
        PAPER.walk(Slip::at(1.3, 0.2, 1.0), 0.0, 1e-3, 100.0, &mut log);
        assert!(log.periodic && log.stick.is_none());
        // μ_s = μ_k: after a breakaway the circle of radius w0 about c_k touches the belt line
        // after one period and the walk hands over to the breakaway slip
        let mut log = Log::default();
        PAPER.walk(PAPER.breakaway(), 0.0, 1e-3, 100.0, &mut log);
        let t = log.breakaway.expect("a touch");
        assert!((t - TAU / PAPER.omega).abs() < 1e-12, "{t}");
        // μ_s > μ_k: the mass falls behind and sticks at 2c_k − c_s
        let f = Frame { cs: 1.5, ..PAPER };
        let mut log = Log::default();
        f.walk(f.breakaway(), 0.0, 1e-3, 100.0, &mut log);
        assert!((log.stick.unwrap().0 - (2.0 * f.ck - f.cs)).abs() < 1e-12);
    }

    /// The paper's frame with the dashpot c = 0.5 N·s/m (γ = 0.5/s) and μ_s = `mu_s`.
    fn damped(mu_s: f64) -> Frame {
        let u = crate::physics::Params { damping: 0.5, static_: mu_s, ..crate::physics::Params::PAPER }.per_unit_mass();
        Frame { cs: u.breakaway / u.omega2, damped: Some(<Damped as SlipForm>::new(&u)), ..PAPER }
    }

    /// The first stick of the damped slip from (x, v) by an independent integration: classical
    /// RK4 of ẍ = σ a_k − ω² x − γ ẋ (σ = +1 below belt speed, −1 above) in steps of 1e-4 s, a
    /// crossing of belt speed located within its step by bisection on the step's fraction, the
    /// arrival rule applied there (a stick on [−c_s − γ v0/ω², c_s − γ v0/ω²), else the friction
    /// reverses). Returns (time, position) of the stick.
    fn rk4_first_stick(f: &Frame, x: f64, v: f64, below: bool, gamma: f64) -> (f64, f64) {
        let (w2, ak) = (f.omega * f.omega, f.ck * f.omega * f.omega);
        let shift = gamma * f.v0 / w2;
        let step = |y: [f64; 2], sigma: f64, h: f64| {
            let d = |y: [f64; 2]| [y[1], sigma * ak - w2 * y[0] - gamma * y[1]];
            let k1 = d(y);
            let k2 = d([y[0] + 0.5 * h * k1[0], y[1] + 0.5 * h * k1[1]]);
            let k3 = d([y[0] + 0.5 * h * k2[0], y[1] + 0.5 * h * k2[1]]);
            let k4 = d([y[0] + h * k3[0], y[1] + h * k3[1]]);
            [y[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]), y[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])]
        };
        let (mut y, mut t, mut sigma) = ([x, v], 0.0, if below { 1.0 } else { -1.0 });
        let h = 1e-4;
        for _ in 0..10_000_000 {
            let next = step(y, sigma, h);
            // the side the step started on (on the line: the side it leaves to)
            let side = if y[1] == f.v0 { -sigma } else { (y[1] - f.v0).signum() };
            if (next[1] - f.v0).signum() != side {
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (step(y, sigma, mid * h)[1] - f.v0).signum() == side {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                let at = step(y, sigma, hi * h);
                let tc = t + hi * h;
                if (-f.cs - shift..f.cs - shift).contains(&at[0]) {
                    return (tc, at[0]);
                }
                sigma = -sigma;
                (y, t) = ([at[0], f.v0], tc);
                continue;
            }
            (y, t) = (next, t + h);
        }
        panic!("no stick")
    }

    #[test]
    fn the_damped_walk_sticks_where_an_independent_integration_does() {
        for (mu_s, x, v, below) in [
            (0.51, -2.0, 0.0, true),
            (0.51, -3.5, -2.0, true),
            (0.51, 0.4, -0.8, true),
            (0.51, -0.9, -1.0, true),
            (0.51, 3.0, 2.5, false),
            (1.2, 0.0, 0.0, true),
        ] {
            // (from (−5, 0) it passes belt speed twice and then slips below it for good: the
            // second arrival, at 1.236 > x_b = 1.1245, leaves a spiral of radius ≈ w0 that the
            // dashpot shrinks — no stick; the last case is the μ_s > μ_k breakaway slip)
            let f = damped(mu_s);
            let mut log = Log::default();
            let start = if mu_s > 0.51 { f.breakaway() } else { Slip { x, v, below } };
            f.walk(start, 0.0, 1e-3, 100.0, &mut log);
            let (xe, t) = log.stick.unwrap_or_else(|| panic!("from ({x}, {v}): no stick"));
            let (tr, xr) = rk4_first_stick(&f, start.x, start.v, start.below, 0.5);
            assert!((t - tr).abs() < 1e-8 && (xe - xr).abs() < 1e-8, "from ({x}, {v}): walk ({t}, {xe}), RK4 ({tr}, {xr})");
            // the slip samples cover the time to the stick
            assert!((log.slip - t).abs() < 1e-9 * t, "{} vs {t}", log.slip);
            assert!(!log.periodic && log.breakaway.is_none());
        }
        // μ_s = μ_k: the breakaway slip leaves at a velocity maximum and never comes back to belt
        // speed; the walk samples it up to e^{−41.4} (41.4/λ) and stops
        let f = damped(0.51);
        let mut log = Log::default();
        f.walk(f.breakaway(), 0.0, 1e-3, f64::INFINITY, &mut log);
        assert!(log.stick.is_none() && !log.periodic && log.breakaway.is_none());
        assert!((log.slip - HORIZON_DECAYS / f.lambda).abs() < 1e-9, "{}", log.slip);
        let (x, v) = log.last.unwrap();
        assert!(v < f.v0 && (x - f.ck).hypot(v / f.omega) < f.w0, "spiralling in: ({x}, {v})");
    }

    #[test]
    fn samples_follow_the_harmonic_slip() {
        // the last sample before the stick lies on the circle and near the arrival point
        let mut log = Log::default();
        PAPER.walk(Slip::at(0.4, -0.8, 1.0), 0.0, 1e-4, 100.0, &mut log);
        let (x, v) = log.last.unwrap();
        let (xe, _) = log.stick.unwrap();
        assert!((x - xe).abs() < 1e-3 && (v - 1.0).abs() < 1e-3, "{x} {v} {xe}");
    }

    #[test]
    fn decay_integrals_match_quadrature() {
        for (lambda, t0, t1, a) in [(5.0, 0.3, 0.9, 0.2), (1e-3, 2.0, 2.5, 1.0), (5.0, 1.0, 1.0 + 1e-6, 0.0)] {
            let n = 200_000;
            let h = (t1 - t0) / n as f64;
            let (mut q, mut qa) = (0.0, 0.0);
            for i in 0..n {
                let t = t0 + (i as f64 + 0.5) * h;
                q += (-lambda * t).exp() * h;
                qa += (-lambda * t).exp() * (a + t - t0) * h;
            }
            assert!((decay(lambda, t0, t1) - q).abs() < 1e-9 * q.abs().max(1e-300), "{lambda}");
            assert!((aged_decay(lambda, t0, t1, a) - qa).abs() < 1e-8 * qa.abs().max(1e-300), "{lambda} {qa}");
        }
        // the centroid: ∫_0^dt e^{−λτ} τ dτ / ∫_0^dt e^{−λτ} dτ
        let (lambda, dt): (f64, f64) = (5.0, 0.3);
        let num = (1.0 - (-lambda * dt).exp() * (1.0 + lambda * dt)) / (lambda * lambda);
        let den = -(-lambda * dt).exp_m1() / lambda;
        assert!((centroid(lambda, dt) - num / den).abs() < 1e-14);
        assert!((centroid(1e-9, 0.3) - 0.15).abs() < 1e-9);
        // the second moment ∫_0^dt τ² e^{−λτ} dτ / ∫_0^dt e^{−λτ} dτ, by quadrature, on both
        // sides of the switch between the series and the closed form (x = 0.1)
        for (lambda, dt) in [(5.0, 0.3), (5.0, 0.021), (5.0, 0.019), (1e-6, 0.3), (30.0, 1.0), (1.0, 0.099)] {
            let n = 200_000;
            let h = dt / n as f64;
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..n {
                let t = (i as f64 + 0.5) * h;
                num += t * t * (-lambda * t).exp();
                den += (-lambda * t).exp();
            }
            let m2 = second_moment(lambda, dt);
            assert!((m2 - num / den).abs() < 1e-8 * num / den, "{lambda} {dt} {m2} {}", num / den);
        }
    }
}
