//! What an atom of the passage ([`super::passage`]) carries besides its place: its clocks, in
//! one of two algebras behind one trait, [`Clocks`].
//!
//! - [`Moments`]: the mass and the first two moments of t (the time since the origin) and of
//!   a (the time since the last stick ended) — Table 1's means and variances.
//! - [`Laplace`]: the mass and the Laplace transform of t, E[e^{−z t}; atom], at the fixed
//!   points z_j of [`Points`] — from which [`Points::cdf`] inverts P(t ≤ t_a) (Euler summation
//!   of the Fourier series, Abate & Whitt 2006). That is what the laws of the counts need:
//!   P(S_T ≥ k) = P(T_k ≤ t_a). At the points ω_j = πj/P instead ([`Points::cosine`]), the
//!   characteristic function, whose cosine series gives the densities of T_k, L_k and — with
//!   the clock restarted at each stick's end ([`Points::restart`]) — H_k
//!   ([`super::densities`]).
//!
//! **The operations.** A flip of a walk in [s, s + dt) (u = t − s ∝ e^{−λu} on [0, dt), the
//! flip's probability w) moves an atom's clocks later by s + u: the moments by the shift rule of
//! [`super::passage`], the transform by the factor
//!
//! ```text
//!     E[e^{−z(s+u)}] = e^{−zs} ψ(z),   ψ(z) = λ (1 − e^{−(λ+z)dt}) / ((λ + z)(1 − e^{−λdt}))   (ψ = 1 for dt = 0)
//! ```
//!
//! and a periodic slip's repetitions s + jP (weights q^j, q = e^{−λP}) by Σ_j q^j e^{−zjP} =
//! 1/(1 − e^{−(λ+z)P}) (the mass by Σ q^j = 1/(1 − q)). The transforms are linear in the
//! measure and every operation maps a probability measure of times to one, so the discretised
//! passage has the exact transform of a discretised law: the inversion sees no noise, only the
//! discretisation (which the three resolutions extrapolate).
//!
//! **Where the inversion holds.** Euler summation assumes a smooth law: P(t ≤ t_a) is exact to
//! about 1e-9 for a continuous law, but a point mass at τ is read with an error of about 1e-9
//! at τ = 0.1 t_a, 3e-6 at 0.2 t_a, 4e-3 at 0.4 t_a and up to 0.1 within [0.5, 1.5] t_a (M = 13).
//! The passage's laws have point masses only on paths without a flip (a deterministic walk from
//! a start; after a flip every time has a density), whose mass at τ is at most e^{−λτ}: with
//! λ t_a ≥ [`MIN_RATE_WINDOW`] their error stays below about 1e-6 (λ t_a = 20: e^{−8}·4e-3 at
//! 0.4 t_a), and shorter windows are refused.

use super::flow::{centroid, second_moment};

/// The algebra of an atom's clocks.
pub(crate) trait Clocks: Copy + Send + Sync {
    /// What the operations need besides the clocks (the transform's points).
    type Ctx: Sync;
    /// How many reals [`Clocks::write`] writes.
    fn len(ctx: &Self::Ctx) -> usize;
    fn zero() -> Self;
    /// Mass w at t = a = 0.
    fn unit(w: f64) -> Self;
    fn mass(&self) -> f64;
    /// ∫ t dμ where the algebra has it (0 otherwise): the passage's unit of time for mixing.
    fn time_sum(&self) -> f64;
    /// self += f · other
    fn add(&mut self, other: &Self, f: f64);
    /// Later by s + u (u ∝ e^{−λu} on [0, dt); dt = 0: exactly s), weight w.
    fn later(&self, ctx: &Self::Ctx, w: f64, s: f64, lambda: f64, dt: f64) -> Self;
    /// Σ_{j≥0} q^j × (later by s + jP + u), q = e^{−λP}, weight w.
    fn repeating(&self, ctx: &Self::Ctx, w: f64, s: f64, lambda: f64, dt: f64, period: f64) -> Self;
    /// a restarted: a stick has just ended (the transforms restart t itself where the context
    /// says so: [`Points::restart`]).
    fn restart(&self, ctx: &Self::Ctx) -> Self;
    /// Whether any component is non-zero (above 1e-300 in size).
    fn nonzero(&self) -> bool;
    /// The components as reals, times `unit`^−p for a moment of order p (so that the mixing
    /// weighs them alike; the transforms are dimensionless).
    fn write(&self, unit: f64, out: &mut Vec<f64>);
    fn read(ctx: &Self::Ctx, unit: f64, from: &[f64]) -> Self;
}

/// [mass, ∫t, ∫t², ∫a, ∫a²] ([`super::passage`]).
pub(crate) type Moments = [f64; 5];

/// The clocks `m` moved later by a random delay δ (independent of them), given its total
/// weight k0, k0 E[δ] and k0 E[δ²]: E(A + δ)² = E A² + 2 E δ E A + E δ².
pub(crate) fn shift(m: Moments, k0: f64, k1: f64, k2: f64) -> Moments {
    [k0 * m[0], k0 * m[1] + k1 * m[0], k0 * m[2] + 2.0 * k1 * m[1] + k2 * m[0], k0 * m[3] + k1 * m[0], k0 * m[4] + 2.0 * k1 * m[3] + k2 * m[0]]
}

/// Σ_{j≥0} q^j, Σ j q^j, Σ j² q^j for q = e^{−x} (x = λP > 0): 1/(1 − q), q/(1 − q)²,
/// q(1 + q)/(1 − q)³, with 1 − q = −expm1(−x) (no cancellation for small x).
pub(crate) fn repeats(x: f64) -> (f64, f64, f64) {
    let (q, one_minus_q) = ((-x).exp(), -(-x).exp_m1());
    (1.0 / one_minus_q, q / one_minus_q.powi(2), q * (1.0 + q) / one_minus_q.powi(3))
}

impl Clocks for Moments {
    type Ctx = ();

    fn len(_: &()) -> usize {
        5
    }

    fn zero() -> Self {
        [0.0; 5]
    }

    fn unit(w: f64) -> Self {
        [w, 0.0, 0.0, 0.0, 0.0]
    }

    fn mass(&self) -> f64 {
        self[0]
    }

    fn time_sum(&self) -> f64 {
        self[1]
    }

    fn add(&mut self, other: &Self, f: f64) {
        self.iter_mut().zip(other).for_each(|(x, y)| *x += f * y);
    }

    fn later(&self, _: &(), w: f64, s: f64, lambda: f64, dt: f64) -> Self {
        let (c, q) = if dt > 0.0 { (centroid(lambda, dt), second_moment(lambda, dt)) } else { (0.0, 0.0) };
        shift(*self, w, w * (s + c), w * (s * s + 2.0 * s * c + q))
    }

    fn repeating(&self, _: &(), w: f64, s: f64, lambda: f64, dt: f64, period: f64) -> Self {
        let (a0, a1, a2) = repeats(lambda * period);
        let (c, u2) = (centroid(lambda, dt), second_moment(lambda, dt));
        // Σ_j q^j × (the clock later by s + jP + u)
        let first = a0 * (s + c) + period * a1;
        let second = a0 * (s * s + 2.0 * s * c + u2) + 2.0 * period * a1 * (s + c) + period * period * a2;
        shift(*self, w * a0, w * first, w * second)
    }

    fn restart(&self, _: &()) -> Self {
        [self[0], self[1], self[2], 0.0, 0.0]
    }

    fn nonzero(&self) -> bool {
        self.iter().any(|v| v.abs() > 1e-300)
    }

    fn write(&self, unit: f64, out: &mut Vec<f64>) {
        out.extend([self[0], self[1] / unit, self[2] / (unit * unit), self[3] / unit, self[4] / (unit * unit)]);
    }

    fn read(_: &(), unit: f64, c: &[f64]) -> Self {
        [c[0], c[1] * unit, c[2] * unit * unit, c[3] * unit, c[4] * unit * unit]
    }
}

/// Euler summation's order M: 2M + 1 transform values per inverted time, about 0.6 M
/// significant digits, roundoff amplified by about 10^{M/3} (Abate & Whitt 2006, §5).
pub(crate) const EULER_M: usize = 13;
/// The least λ t_a (the smallest flip rate times the window) the inversion accepts (module docs).
pub(crate) const MIN_RATE_WINDOW: f64 = 20.0;
/// The number of transform points: 2M + 1.
pub(crate) const POINTS: usize = 2 * EULER_M + 1;

/// A complex number (re, im): the little arithmetic the transforms need.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct C64 {
    pub re: f64,
    pub im: f64,
}

impl C64 {
    pub(crate) const fn new(re: f64, im: f64) -> C64 {
        C64 { re, im }
    }
    fn mul(self, o: C64) -> C64 {
        C64::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    fn scale(self, f: f64) -> C64 {
        C64::new(self.re * f, self.im * f)
    }
    fn div(self, o: C64) -> C64 {
        let d = o.re * o.re + o.im * o.im;
        C64::new((self.re * o.re + self.im * o.im) / d, (self.im * o.re - self.re * o.im) / d)
    }
    /// e^{−x s} for x = self
    pub(crate) fn exp_neg(self, s: f64) -> C64 {
        let (sin, cos) = (self.im * s).sin_cos();
        C64::new(cos, -sin).scale((-self.re * s).exp())
    }
}

/// Transform points z_j = α + iπj/t, j = 0 … N − 1: all of them powers of one step, so
/// e^{−z_j s} = e^{−α s} (e^{−iπs/t})^j. Euler's inversion at t ([`Points::at`], N = [`POINTS`],
/// α = M ln 10 / (3t)) and the cosine series of a density on [0, t] ([`Points::cosine`], α = 0,
/// [`super::densities`]) both use them.
#[derive(Debug, Clone)]
pub(crate) struct Points<const N: usize> {
    /// the time the points invert at (Euler), or the cosine series' half-period
    pub t: f64,
    pub z: [C64; N],
    /// whether t restarts at a stick's end: the transform is then of the time since the last
    /// stick ended (of H_k), not since the origin
    pub restart: bool,
    /// per flip rate λ of the scene: λ / (λ + z_j) (ψ's factor, computed once)
    rates: Vec<(f64, [C64; N])>,
}

impl<const N: usize> Points<N> {
    fn new(alpha: f64, t: f64, lambdas: &[f64], restart: bool) -> Points<N> {
        let z: [C64; N] = std::array::from_fn(|j| C64::new(alpha, std::f64::consts::PI * j as f64 / t));
        let rates = lambdas.iter().map(|&l| (l, std::array::from_fn(|j| C64::new(l, 0.0).div(C64::new(l + z[j].re, z[j].im))))).collect();
        Points { t, z, restart, rates }
    }

    /// The points of the cosine series on [0, `half_period`] (α = 0: the characteristic
    /// function at ω_j = πj/half_period), for walks with the flip rates `lambdas`; with
    /// `restart`, of the time since the last stick ended.
    pub(crate) fn cosine(half_period: f64, lambdas: &[f64], restart: bool) -> Points<N> {
        Points::new(0.0, half_period, lambdas, restart)
    }

    /// λ / (λ + z_j) for every j.
    fn rate(&self, lambda: f64) -> [C64; N] {
        match self.rates.iter().find(|(l, _)| *l == lambda) {
            Some((_, r)) => *r,
            None => std::array::from_fn(|j| C64::new(lambda, 0.0).div(C64::new(lambda + self.z[j].re, self.z[j].im))),
        }
    }

    /// e^{−z_j s} for every j, by the powers of one step.
    fn delays(&self, s: f64) -> [C64; N] {
        let base = C64::new((-self.z[0].re * s).exp(), 0.0);
        let step = C64::new(0.0, std::f64::consts::PI / self.t).exp_neg(s);
        // four chains j ≡ 0, 1, 2, 3 (mod 4), each stepped by step⁴: independent products
        let (s2, mut out) = (step.mul(step), [C64::default(); N]);
        let s4 = s2.mul(s2);
        let mut p = [base, base.mul(step), base.mul(s2), base.mul(s2).mul(step)];
        for j in (0..N).step_by(4) {
            for (r, p) in p.iter_mut().enumerate() {
                if j + r < N {
                    out[j + r] = *p;
                }
                *p = p.mul(s4);
            }
        }
        out
    }
}

impl Points<POINTS> {
    /// The points inverting at t, for walks with the flip rates `lambdas`.
    pub(crate) fn at(t: f64, lambdas: &[f64]) -> Points<POINTS> {
        Points::new(EULER_M as f64 * std::f64::consts::LN_10 / 3.0 / t, t, lambdas, false)
    }

    /// Euler's weights η_j: ξ_0 = 1/2, ξ_j = 1 (1 ≤ j ≤ M), ξ_2M = 2^−M, ξ_{2M−j} = ξ_{2M−j+1} +
    /// 2^−M C(M, j) (0 < j < M); η_j = (−1)^j ξ_j.
    fn weights() -> [f64; POINTS] {
        let m = EULER_M;
        let mut xi = [0.0; POINTS];
        xi[0] = 0.5;
        xi[1..=m].iter_mut().for_each(|x| *x = 1.0);
        let two_m = 2f64.powi(-(m as i32));
        xi[2 * m] = two_m;
        let mut binom = 1.0; // C(M, j)
        for j in 1..m {
            binom *= (m - j + 1) as f64 / j as f64;
            xi[2 * m - j] = xi[2 * m - j + 1] + two_m * binom;
        }
        std::array::from_fn(|j| if j % 2 == 0 { xi[j] } else { -xi[j] })
    }

    /// P(t' ≤ t) of a law on [0, ∞) of total mass `mass` from its transform E[e^{−z_j t'}] at
    /// these points: F(t) ≈ (10^{M/3}/t) Σ_j η_j Re(F̂(β_j/t)), F̂(z) = E[e^{−z t'}]/z.
    pub(crate) fn cdf(&self, transform: &[C64; POINTS]) -> f64 {
        let scale = 10f64.powf(EULER_M as f64 / 3.0) / self.t;
        let eta = Points::weights();
        scale * transform.iter().zip(&self.z).zip(eta).map(|((f, z), e)| e * f.div(*z).re).sum::<f64>()
    }
}

/// The mass and the transform of t at the [`Points`]: E[e^{−z_j t}; atom] (N = [`POINTS`]:
/// Euler's, [`Euler`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Laplace<const N: usize> {
    pub mass: f64,
    pub t: [C64; N],
}

/// The transform at Euler's points ([`Points::at`]).
pub(crate) type Euler = Laplace<POINTS>;

impl<const N: usize> Laplace<N> {
    /// The factor of a delay s + u (u ∝ e^{−λu} on [0, dt)) at every point: e^{−z s} ψ(z).
    fn factors(ctx: &Points<N>, s: f64, lambda: f64, dt: f64) -> [C64; N] {
        let mut f = ctx.delays(s);
        if dt > 0.0 {
            // a walk's samples share their dt (an arc, a stick's intervals): ψ is kept per thread
            // for the last (points, λ, dt)
            thread_local! {
                static LAST: std::cell::RefCell<((f64, f64, f64, f64), Vec<C64>)> = const { std::cell::RefCell::new(((f64::NAN, f64::NAN, f64::NAN, f64::NAN), Vec::new())) };
            }
            LAST.with_borrow_mut(|(key, psi)| {
                let want = (lambda, dt, ctx.t, ctx.z[0].re);
                if *key != want || psi.len() != N {
                    let e_dt = ctx.delays(dt);
                    let norm = -(-lambda * dt).exp_m1();
                    let decay = (-lambda * dt).exp();
                    // ψ = λ(1 − e^{−λdt} e^{−z dt}) / ((λ + z)(1 − e^{−λdt}))
                    *psi = ctx.rate(lambda).iter().zip(e_dt).map(|(r, e)| C64::new(1.0 - decay * e.re, -decay * e.im).scale(1.0 / norm).mul(*r)).collect();
                    *key = want;
                }
                f.iter_mut().zip(psi.iter()).for_each(|(f, p)| *f = f.mul(*p));
            });
        }
        f
    }
}

impl<const N: usize> Clocks for Laplace<N> {
    type Ctx = Points<N>;

    fn len(_: &Points<N>) -> usize {
        1 + 2 * N
    }

    fn zero() -> Self {
        Laplace { mass: 0.0, t: [C64::default(); N] }
    }

    fn unit(w: f64) -> Self {
        Laplace { mass: w, t: [C64::new(w, 0.0); N] }
    }

    fn mass(&self) -> f64 {
        self.mass
    }

    fn time_sum(&self) -> f64 {
        0.0
    }

    fn add(&mut self, other: &Self, f: f64) {
        self.mass += f * other.mass;
        for (a, b) in self.t.iter_mut().zip(&other.t) {
            a.re += f * b.re;
            a.im += f * b.im;
        }
    }

    fn later(&self, ctx: &Points<N>, w: f64, s: f64, lambda: f64, dt: f64) -> Self {
        let f = Laplace::factors(ctx, s, lambda, dt);
        Laplace { mass: w * self.mass, t: std::array::from_fn(|j| self.t[j].mul(f[j]).scale(w)) }
    }

    fn repeating(&self, ctx: &Points<N>, w: f64, s: f64, lambda: f64, dt: f64, period: f64) -> Self {
        let f = Laplace::factors(ctx, s, lambda, dt);
        let q = ctx.delays(period);
        let decay = (-lambda * period).exp();
        let a0 = repeats(lambda * period).0;
        // Σ_j q^j e^{−z jP} = 1 / (1 − e^{−λP} e^{−zP})
        let t = std::array::from_fn(|j| self.t[j].mul(f[j]).div(C64::new(1.0 - decay * q[j].re, -decay * q[j].im)).scale(w));
        Laplace { mass: w * a0 * self.mass, t }
    }

    fn restart(&self, ctx: &Points<N>) -> Self {
        if ctx.restart {
            Laplace::unit(self.mass)
        } else {
            *self
        }
    }

    fn nonzero(&self) -> bool {
        self.mass.abs() > 1e-300 || self.t.iter().any(|c| c.re.abs() > 1e-300 || c.im.abs() > 1e-300)
    }

    fn write(&self, _: f64, out: &mut Vec<f64>) {
        out.push(self.mass);
        out.extend(self.t.iter().flat_map(|c| [c.re, c.im]));
    }

    fn read(_: &Points<N>, _: f64, c: &[f64]) -> Self {
        Laplace { mass: c[0], t: std::array::from_fn(|j| C64::new(c[1 + 2 * j], c[2 + 2 * j])) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The moments later by s + u with E u = c, E u² = q, weight w (the shift rule).
    fn shifted(m: Moments, w: f64, s: f64, c: f64, q: f64) -> Moments {
        shift(m, w, w * (s + c), w * (s * s + 2.0 * s * c + q))
    }

    #[test]
    fn a_clock_moved_later_keeps_its_moments() {
        // a clock A ∈ {1, 3} (equal masses) moved later by s = 2 with no spread: A + 2 ∈ {3, 5}
        let c = shifted([2.0, 4.0, 10.0, 0.0, 0.0], 0.5, 2.0, 0.0, 0.0);
        assert_eq!(c, [1.0, 4.0, 17.0, 2.0, 4.0]);
    }

    #[test]
    fn a_spread_delay_and_the_repetitions_sum_as_they_should() {
        // clocks A ∈ {1, 3} (mass 1 each) later by s + u, E u = c, E u² = q, weight w: mass 2w,
        // Σ E(A + s + u) = 4 + 2(s + c), Σ E(A + s + u)² = 10 + 2·4(s + c) + 2(s² + 2sc + q)
        let (w, s, c, q) = (0.5, 0.5, 0.2, 0.1);
        let got = shifted([2.0, 4.0, 10.0, 4.0, 10.0], w, s, c, q);
        let (m1, m2) = (4.0 + 2.0 * (s + c), 10.0 + 8.0 * (s + c) + 2.0 * (s * s + 2.0 * s * c + q));
        for (g, want) in got.iter().zip([2.0 * w, w * m1, w * m2, w * m1, w * m2]) {
            assert!((g - want).abs() < 1e-14, "{got:?}");
        }
        assert_eq!(got.restart(&())[3..], [0.0, 0.0]);
        // the repetitions' sums against the series summed term by term
        for x in [1e-3, 0.7, 5.0] {
            let (a0, a1, a2) = repeats(x);
            let (mut b0, mut b1, mut b2) = (0.0, 0.0, 0.0);
            for j in 0..200_000 {
                let t = (-x * f64::from(j)).exp();
                (b0, b1, b2) = (b0 + t, b1 + f64::from(j) * t, b2 + f64::from(j) * f64::from(j) * t);
            }
            for (a, b) in [(a0, b0), (a1, b1), (a2, b2)] {
                assert!((a - b).abs() < 1e-9 * b, "{x}: {a} against {b}");
            }
        }
    }

    #[test]
    fn euler_inverts_laws_whose_distribution_is_known() {
        // Exp(λ): E e^{−zT} = λ/(λ + z), P(T ≤ t) = 1 − e^{−λt}; Erlang(3, λ): (λ/(λ+z))³,
        // P(T ≤ t) = 1 − e^{−λt}(1 + λt + (λt)²/2); a point mass at 1.3: e^{−1.3 z}
        for t in [0.3, 2.0, 10.0] {
            let p = Points::at(t, &[0.5, 5.0]);
            for lambda in [0.5, 5.0] {
                let exp: [C64; POINTS] = std::array::from_fn(|j| C64::new(lambda, 0.0).div(C64::new(lambda + p.z[j].re, p.z[j].im)));
                let want = -(-lambda * t).exp_m1();
                assert!((p.cdf(&exp) - want).abs() < 1e-7, "Exp({lambda}) at {t}: {} against {want}", p.cdf(&exp));
                let erlang: [C64; POINTS] = std::array::from_fn(|j| exp[j].mul(exp[j]).mul(exp[j]));
                let x = lambda * t;
                let want = 1.0 - (-x).exp() * (1.0 + x + x * x / 2.0);
                assert!((p.cdf(&erlang) - want).abs() < 1e-7, "Erlang at {t}: {} against {want}", p.cdf(&erlang));
            }
            // a point mass far from t (below 0.1 t, beyond 2 t): the inversion's limit (module docs)
            for (at, want) in [(0.1 * t, 1.0), (2.0 * t, 0.0)] {
                let atom: [C64; POINTS] = std::array::from_fn(|j| p.z[j].exp_neg(at));
                assert!((p.cdf(&atom) - want).abs() < 1e-8, "a point mass at {at}, read at {t}: {}", p.cdf(&atom));
            }
        }
    }

    #[test]
    fn the_transform_clock_moves_as_its_delays() {
        // an atom at t = 0.4 moved later by s + u (u ∝ e^{−λu} on [0, dt)): its transform is
        // e^{−z(0.4 + s)} E e^{−zu}, with E e^{−zu} integrated here by the midpoint rule
        let p = Points::at(3.0, &[]);
        let p: Points<POINTS> = p;
        let (lambda, s, dt, w) = (5.0, 0.7, 0.2, 0.3);
        let start = Laplace { mass: 1.0, t: std::array::from_fn(|j| p.z[j].exp_neg(0.4)) };
        let got = start.later(&p, w, s, lambda, dt);
        let n = 200_000;
        for j in [0, 5, POINTS - 1] {
            let z = p.z[j];
            let (mut num, mut den) = (C64::default(), 0.0);
            for i in 0..n {
                let u = (i as f64 + 0.5) * dt / n as f64;
                let g = (-lambda * u).exp();
                let e = z.exp_neg(u).scale(g);
                (num.re, num.im, den) = (num.re + e.re, num.im + e.im, den + g);
            }
            let want = z.exp_neg(0.4 + s).mul(num.scale(w / den));
            assert!((got.t[j].re - want.re).abs() < 1e-9 && (got.t[j].im - want.im).abs() < 1e-9, "{j}: {:?} against {want:?}", got.t[j]);
        }
        assert!((got.mass - w).abs() < 1e-15);
        // the repetitions: Σ_j q^j (later by s + jP)
        let period = 0.9;
        let rep = start.repeating(&p, w, s, lambda, dt, period);
        for j in [0, 7] {
            let (mut sum, mut mass) = (C64::default(), 0.0);
            for r in 0..400 {
                let q = (-lambda * period * r as f64).exp();
                let one = start.later(&p, w * q, s + r as f64 * period, lambda, dt);
                (sum.re, sum.im, mass) = (sum.re + one.t[j].re, sum.im + one.t[j].im, mass + one.mass);
            }
            assert!((rep.t[j].re - sum.re).abs() < 1e-12 && (rep.t[j].im - sum.im).abs() < 1e-12, "{j}: {:?} against {sum:?}", rep.t[j]);
            assert!((rep.mass - mass).abs() < 1e-12);
        }
    }
}
