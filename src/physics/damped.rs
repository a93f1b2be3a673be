//! Closed-form slip with viscous damping (c > 0): under-, critically and over-damped in one form
//! that is continuous through ζ = 1.
//!
//! In slip the forcing `σ a_k` is constant, so with `a = γ/2` and the signed
//! `q = ω_d² = ω² − a² = (ω − a)(ω + a)` (formed without cancellation), every solution of
//! `ẍ + γ ẋ + ω² x = σ a_k` is a combination of two basis functions of τ:
//!
//! ```text
//!   ψ(τ) = e^{−aτ} S(τ),      S = sin(√q τ)/√q  |  τ  |  sinh(√−q τ)/√−q      (q > 0 | 0 | < 0)
//!   χ(τ) = e^{−aτ} (C(τ) + a S(τ)),   C = cos(√q τ)  |  1  |  cosh(√−q τ)
//!   Ψ(τ) = ∫₀^τ ψ = (1 − χ)/ω²
//!   ψ(0) = 0, ψ'(0) = 1;   χ(0) = 1, χ'(0) = 0;   χ = ψ' + γ ψ,  χ' = −ω² ψ
//! ```
//!
//! S and C are entire functions of `q τ²` (the regimes are one family), and the state after a
//! slip of duration τ from `(x₀, ẋ₀)` with initial acceleration `a₀ = σ a_k − ω² x₀ − γ ẋ₀` is
//!
//! ```text
//!   x(τ) = x₀ + ẋ₀ ψ + (a₀ + γ ẋ₀) Ψ,      ẋ(τ) = ẋ₀ χ + a₀ ψ,      ẍ(τ) = a₀ χ + b₀ ψ,
//!   b₀ = −ω² ẋ₀ − γ a₀   (the velocity solves the homogeneous equation: it oscillates about 0)
//! ```
//!
//! Evaluation, each without cancellation in its range (ψ and χ, all the velocity and the search
//! for belt speed need, by the last two forms at every τ; Ψ by the first at small τ):
//! - `max(a, ω) τ ≤ ½`: the Taylor series of ψ (recurrence from the equation) and Ψ;
//! - `q ≥ 0`, or `|q| τ² ≤ 1/16` (near critical): `e^{−aτ}` times sin/cos, or times the series
//!   of S and C in `q τ²` (through ζ = 1: ζ = 1 ± 1e-9 differs from ζ = 1 by O(1e-9) relative,
//!   never by a cancelled difference); Ψ = (1 − χ)/ω² with ω τ > ¼ here;
//! - over-damped `√−q τ > ¼`: with the decay rates `r₂ = a + √−q`, `r₁ = ω²/r₂` (the slow one,
//!   never formed as a − √−q): `ψ = e^{−r₁τ}(1 − e^{−2√−q τ})/(2√−q)`,
//!   `Ψ = (g(r₁) − g(r₂))/(2√−q)` with `g(r) = (1 − e^{−rτ})/r` by `expm1`, and
//!   `χ = (r₂ e^{−r₁τ} − r₁ e^{−r₂τ})/(2√−q)`.
//!
//! ## The first return to belt speed
//! The velocity's turning points (zeros of ẍ) are known in closed form: with
//! `ρ = −a₀/(a a₀ + b₀)`, under-damped `τ₁ = atan(ρ √q)/√q` (taken in (0, π/√q]) and then every
//! π/√q; otherwise at most one, `τ₁ = atanh(ρ √−q)/√−q` (→ ρ at ζ = 1) when `0 < ρ √−q < 1`.
//! Between consecutive turning points ẋ is monotone, so each bracket holds at most one crossing
//! of belt speed, decided by the signs at its ends — a shallow dip across belt speed between two
//! step ends cannot be missed, because there are no steps. The root is then polished by Newton's
//! method safeguarded by bisection to 1e-15 relative (≤ 1e-12 s for τ ≤ 1000 s). Extrema of the
//! velocity shrink by `e^{−aπ/√q}` per half period, so once one lies inside ±|v| no later crossing
//! exists and the search stops.

use super::model::{PerUnitMass, SlipForm};

/// The damped closed forms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damped {
    omega2: f64,
    gamma: f64,
    /// a = γ/2, 1/s
    a: f64,
    /// q = ω² − a², 1/s² (signed)
    q: f64,
    /// √|q|, 1/s
    h: f64,
    /// over-damped decay rates r₁ ≤ r₂ (r₁ r₂ = ω², r₁ + r₂ = γ)
    r1: f64,
    r2: f64,
    /// max(a, ω): the Taylor series is used while max(a, ω) τ ≤ ½
    scale: f64,
}

/// `(ψ, χ, Ψ)` at one τ.
#[derive(Debug, Clone, Copy)]
struct Basis {
    psi: f64,
    chi: f64,
    int: f64,
}

impl SlipForm for Damped {
    fn new(p: &PerUnitMass) -> Damped {
        let a = 0.5 * p.slip_damping();
        let q = (p.omega - a) * (p.omega + a);
        let h = q.abs().sqrt();
        let r2 = a + h;
        Damped { omega2: p.omega2, gamma: p.slip_damping(), a, q, h, r1: if r2 > 0.0 { p.omega2 / r2 } else { 0.0 }, r2, scale: a.max(p.omega) }
    }

    fn state(&self, x0: f64, xdot0: f64, a0: f64, tau: f64) -> (f64, f64) {
        let b = self.basis(tau);
        (x0 + xdot0 * b.psi + (a0 + self.gamma * xdot0) * b.int, xdot0 * b.chi + a0 * b.psi)
    }

    fn crossing(&self, x0: f64, xdot0: f64, a0: f64, v: f64, horizon: f64) -> Option<(f64, f64)> {
        let u0 = xdot0 - v;
        // the sign of u just after τ = 0 (a slip starting at belt speed leaves it with a₀)
        let sign0 = if u0 != 0.0 {
            u0.signum()
        } else if a0 != 0.0 {
            a0.signum()
        } else {
            return None; // the grazing orbit: ẋ = v is a velocity extremum, later ones are smaller
        };
        let b0 = -self.omega2 * xdot0 - self.gamma * a0;
        let (first, period) = self.turning_points(a0, b0);
        let velocity = |tau: f64| {
            let (psi, chi) = self.velocity_basis(tau);
            xdot0 * chi + a0 * psi
        };
        let mut lo = 0.0;
        let mut k = 0.0;
        loop {
            let tp = first.map(|t1| t1 + k * period.unwrap_or(0.0)).filter(|_| k == 0.0 || period.is_some());
            let hi = match tp {
                Some(t) if t < horizon => t,
                _ => horizon,
            };
            if !(hi > lo) || !hi.is_finite() {
                return None;
            }
            let w = velocity(hi);
            let u = w - v;
            if u == 0.0 || u.signum() != sign0 {
                let tau = self.root(lo, hi, sign0, xdot0, a0, b0, v);
                return (tau < horizon).then(|| (tau, self.state(x0, xdot0, a0, tau).0));
            }
            if hi >= horizon || w.abs() < v.abs() {
                // the end of the window, or an extremum inside ±|v|: later ones are smaller
                return None;
            }
            lo = hi;
            k += 1.0;
        }
    }

    /// The ends and the first two turning points ([`Damped::turning_points`]: a maximum and a
    /// minimum, or one of them): later extrema are smaller by `e^{−aπ/√q}` per half period.
    fn velocity_range(&self, xdot0: f64, a0: f64, tau: f64, xdot1: f64, _a1: f64) -> (f64, f64) {
        let velocity = |t: f64| {
            let (psi, chi) = self.velocity_basis(t);
            xdot0 * chi + a0 * psi
        };
        let (mut lo, mut hi) = (xdot0.min(xdot1), xdot0.max(xdot1));
        let (first, period) = self.turning_points(a0, -self.omega2 * xdot0 - self.gamma * a0);
        let turns = [first, first.zip(period).map(|(t, p)| t + p)];
        for t in turns.into_iter().flatten().filter(|&t| t > 0.0 && t < tau) {
            let w = velocity(t);
            (lo, hi) = (lo.min(w), hi.max(w));
        }
        (lo, hi)
    }
}

impl Damped {
    /// The slip's damping γ (+ β with a viscous term) [1/s].
    pub(crate) fn gamma(&self) -> f64 {
        self.gamma
    }

    fn basis(&self, tau: f64) -> Basis {
        if self.scale * tau <= 0.5 {
            return self.taylor(tau);
        }
        let (psi, chi) = self.velocity_basis(tau);
        if self.q >= 0.0 || self.q * tau * tau >= -0.0625 {
            return Basis { psi, chi, int: (1.0 - chi) / self.omega2 };
        }
        let g = |r: f64| if r == 0.0 { tau } else { -(-r * tau).exp_m1() / r };
        Basis { psi, chi, int: (g(self.r1) - g(self.r2)) / (2.0 * self.h) }
    }

    /// `(ψ, χ)` alone — all the velocity needs, accurate at every τ without the Taylor series
    /// (only Ψ, the position's integral, cancels at small τ): `e^{−aτ}` times sin/cos or the
    /// series of S and C, or the over-damped two-exponential form.
    #[inline]
    fn velocity_basis(&self, tau: f64) -> (f64, f64) {
        let y = self.q * tau * tau;
        if self.q >= 0.0 || y >= -0.0625 {
            let (s, c) = if y.abs() <= 0.0625 {
                sc_series(y, tau)
            } else {
                let (sin, cos) = (self.h * tau).sin_cos();
                (sin / self.h, cos)
            };
            let e = (-self.a * tau).exp();
            return (e * s, e * (c + self.a * s));
        }
        let two_h = 2.0 * self.h;
        let e1 = (-self.r1 * tau).exp();
        let d = -(-two_h * tau).exp_m1(); // 1 − e^{−2hτ}
        (e1 * d / two_h, (self.r2 * e1 - self.r1 * e1 * (1.0 - d)) / two_h)
    }

    /// ψ and Ψ by their Taylor series: with `d_n = c_n τⁿ`, `d₁ = τ` and
    /// `d_{n+1} = −(γ τ n d_n + ω² τ² d_{n−1}) / ((n+1) n)`; `Ψ = τ Σ d_n/(n+1)`.
    fn taylor(&self, tau: f64) -> Basis {
        let (g, w2) = (self.gamma * tau, self.omega2 * tau * tau);
        let (mut prev, mut d) = (0.0, tau);
        let (mut psi, mut int) = (tau, 0.5 * tau);
        for n in 1..60 {
            let nf = n as f64;
            let next = -(g * nf * d + w2 * prev) / ((nf + 1.0) * nf);
            psi += next;
            int += next / (nf + 2.0);
            if next.abs() <= 1e-18 * psi.abs() && d.abs() <= 1e-18 * psi.abs() {
                break;
            }
            (prev, d) = (d, next);
        }
        let int = tau * int;
        Basis { psi, chi: 1.0 - self.omega2 * int, int }
    }

    /// The first turning point of the velocity (zero of `a₀ χ + b₀ ψ`) after τ = 0, and the
    /// spacing of the later ones (under-damped only).
    fn turning_points(&self, a0: f64, b0: f64) -> (Option<f64>, Option<f64>) {
        let d = self.a * a0 + b0;
        if a0 == 0.0 && d == 0.0 {
            return (None, None);
        }
        let rho = -a0 / d;
        if self.q > 0.0 {
            let mut theta = (rho * self.h).atan();
            if theta <= 0.0 {
                theta += std::f64::consts::PI;
            }
            return (Some(theta / self.h), Some(std::f64::consts::PI / self.h));
        }
        let x = rho * self.h;
        if !(rho > 0.0 && x < 1.0) {
            return (None, None);
        }
        // atanh(x)/h = ln1p(2x/(1−x))/(2h) → ρ as h → 0
        (Some(if self.h == 0.0 { rho } else { 0.5 * (2.0 * x / (1.0 - x)).ln_1p() / self.h }), None)
    }

    /// The crossing of `ẋ = v` in `(lo, hi]`, where u = ẋ − v has sign `sign0` after lo and not
    /// at hi: Newton's method on ẋ − v (derivative ẍ) kept inside the bracket, else bisection.
    #[allow(clippy::too_many_arguments)]
    fn root(&self, lo: f64, hi: f64, sign0: f64, xdot0: f64, a0: f64, b0: f64, v: f64) -> f64 {
        let (mut lo, mut hi) = (lo, hi);
        let mut t = 0.5 * (lo + hi);
        for _ in 0..200 {
            let (psi, chi) = self.velocity_basis(t);
            let u = xdot0 * chi + a0 * psi - v;
            if u == 0.0 {
                return t;
            }
            if u.signum() == sign0 {
                lo = t;
            } else {
                hi = t;
            }
            let newton = t - u / (a0 * chi + b0 * psi);
            let next = if newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
            if (next - t).abs() <= 1e-15 * t || hi - lo <= 1e-15 * hi {
                return next;
            }
            t = next;
        }
        hi
    }
}

/// `(S, C)` by their series in `y = q τ²` (|y| ≤ 1/16: the first dropped term is below 1e-19
/// relative): `S = τ Σ (−y)^k/(2k+1)!`, `C = Σ (−y)^k/(2k)!`.
fn sc_series(y: f64, tau: f64) -> (f64, f64) {
    let (mut s, mut c) = (0.0, 0.0);
    for k in (0..8).rev() {
        let k = k as f64;
        s = 1.0 - y * s / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
        c = 1.0 - y * c / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
    }
    (tau * s, c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Params;

    fn form(k: f64, c: f64) -> (Damped, PerUnitMass) {
        let p = Params { stiffness: k, damping: c, ..Params::PAPER }.per_unit_mass();
        (Damped::new(&p), p)
    }

    /// The direct textbook solution about the equilibrium x* = f/ω² (f = a₀ + ω² x₀ + γ ẋ₀).
    fn direct(k: f64, c: f64, x0: f64, xd0: f64, a0: f64, t: f64) -> (f64, f64) {
        let (w2, a) = (k, 0.5 * c);
        let xs = (a0 + w2 * x0 + c * xd0) / w2;
        let y0 = x0 - xs;
        if a * a < w2 {
            let wd = (w2 - a * a).sqrt();
            let (bb, e) = ((xd0 + a * y0) / wd, (-a * t).exp());
            let (s, co) = (wd * t).sin_cos();
            let y = e * (y0 * co + bb * s);
            let yd = e * ((-a * y0 + wd * bb) * co + (-a * bb - wd * y0) * s);
            (xs + y, yd)
        } else if a * a == w2 {
            let e = (-a * t).exp();
            let b = xd0 + a * y0;
            (xs + e * (y0 + b * t), e * (b - a * (y0 + b * t)))
        } else {
            let hh = (a * a - w2).sqrt();
            let (l1, l2) = (-a + hh, -a - hh);
            let c2 = (xd0 - l1 * y0) / (l2 - l1);
            let c1 = y0 - c2;
            (xs + c1 * (l1 * t).exp() + c2 * (l2 * t).exp(), c1 * l1 * (l1 * t).exp() + c2 * l2 * (l2 * t).exp())
        }
    }

    #[test]
    fn free_response_matches_the_direct_formula_in_all_regimes() {
        // c = 0.5 (ζ = 1/8), c = 4 (ζ = 1), c = 10 (ζ = 2.5), on both sides of every regime switch
        for &c in &[0.5, 4.0, 10.0] {
            let (f, _) = form(4.0, c);
            for &t in &[1e-6, 0.01, 0.1, 0.124, 0.126, 0.3, 1.0, 2.7, 9.0] {
                let (x, xd) = f.state(0.3, -0.7, 2.1, t);
                let (xr, xdr) = direct(4.0, c, 0.3, -0.7, 2.1, t);
                assert!((x - xr).abs() < 1e-13, "c {c} t {t}: x {x} vs {xr}");
                assert!((xd - xdr).abs() < 1e-13, "c {c} t {t}: xdot {xd} vs {xdr}");
            }
        }
    }

    #[test]
    fn critical_damping_is_continuous_with_its_neighbours() {
        let (crit, _) = form(4.0, 4.0);
        for &c in &[4.0 * (1.0 - 1e-9), 4.0 * (1.0 + 1e-9)] {
            let (near, _) = form(4.0, c);
            for &t in &[0.05, 0.2, 1.0, 3.0, 20.0] {
                let (x, xd) = near.state(0.3, -0.7, 2.1, t);
                let (xc, xdc) = crit.state(0.3, -0.7, 2.1, t);
                // the exact difference is O(1e-9); a cancelled formula would be off by ~1e-8..1
                assert!((x - xc).abs() < 1e-8 && (xd - xdc).abs() < 1e-8, "c {c} t {t}: {x} vs {xc}, {xd} vs {xdc}");
            }
            // ẋ = e^{−2τ}(−1 + 18τ) at ζ = 1 peaks at 2.96 > v = 1
            let t1 = near.crossing(0.0, -1.0, 20.0, 1.0, 100.0).unwrap().0;
            let tc = crit.crossing(0.0, -1.0, 20.0, 1.0, 100.0).unwrap().0;
            assert!((t1 - tc).abs() < 1e-8, "{t1} vs {tc}");
        }
    }

    #[test]
    fn velocity_range_is_the_extreme_of_a_fine_grid() {
        // under-damped, critical, over-damped
        for &c in &[0.5, 4.0, 10.0] {
            let (f, p) = form(4.0, c);
            for &(x0, xd0, sig) in &[(0.2, -1.0, 1.0), (-0.9, 3.0, -1.0), (1.25, 0.0, 1.0)] {
                let a0 = sig * 5.0 - p.omega2 * x0 - p.gamma * xd0;
                for &tau in &[1e-3, 0.5, 1.2, 2.0, 3.3, 9.0] {
                    let xd1 = f.state(x0, xd0, a0, tau).1;
                    let (lo, hi) = f.velocity_range(xd0, a0, tau, xd1, f64::NAN);
                    let (mut glo, mut ghi) = (f64::INFINITY, f64::NEG_INFINITY);
                    for i in 0..=20_000 {
                        let xd = direct(4.0, c, x0, xd0, a0, tau * i as f64 / 20_000.0).1;
                        (glo, ghi) = (glo.min(xd), ghi.max(xd));
                    }
                    let tol = 1e-12 + 1e-7 * (glo.abs() + ghi.abs());
                    assert!(lo <= glo + 1e-11 && hi >= ghi - 1e-11, "c {c} ({x0}, {xd0}, {tau}): [{lo}, {hi}] vs [{glo}, {ghi}]");
                    assert!(glo - lo <= tol && hi - ghi <= tol, "c {c} ({x0}, {xd0}, {tau}): [{lo}, {hi}] vs [{glo}, {ghi}]");
                }
            }
        }
    }

    #[test]
    fn crossing_is_the_first_root_of_the_relative_velocity() {
        for &c in &[0.05, 0.5, 4.0, 12.0] {
            let (f, p) = form(4.0, c);
            for &(x0, xd0, sig, v) in &[(0.2, -1.0, 1.0, 1.0), (-0.9, 3.0, -1.0, 1.0), (0.4, 0.9, 1.0, -1.0), (-2.0, 0.0, 1.0, 0.3)] {
                let a0 = p.slip_accel(x0, xd0, v, sig);
                let Some((tau, x)) = f.crossing(x0, xd0, a0, v, 50.0) else { continue };
                let (xr, xdr) = direct(4.0, c, x0, xd0, a0, tau);
                assert!((xdr - v).abs() < 1e-12, "c {c}: u = {} at tau {tau}", xdr - v);
                assert!((x - xr).abs() < 1e-12);
                let s0 = (xd0 - v).signum();
                for i in 1..2000 {
                    let (_, xd) = direct(4.0, c, x0, xd0, a0, tau * i as f64 / 2000.0);
                    assert_eq!((xd - v).signum(), s0, "c {c}: an earlier crossing before {tau}");
                }
                assert!(f.crossing(x0, xd0, a0, v, tau * (1.0 - 1e-12)).is_none());
            }
        }
    }

    #[test]
    fn a_shallow_dip_across_belt_speed_is_found() {
        // Under-damped, belt v = 1: start below belt speed so that the first velocity maximum
        // exceeds v by 1e-9 only (a crossing and a return a few 1e-5 s apart).
        let (f, p) = form(4.0, 0.5);
        let (x0, sig) = (1.0, 1.0);
        // find ẋ₀ whose first maximum is exactly v + 1e-9 by bisection on the closed form
        let peak = |xd0: f64| {
            let a0 = p.slip_accel(x0, xd0, 1.0, sig);
            let b0 = -p.omega2 * xd0 - p.gamma * a0;
            let t1 = f.turning_points(a0, b0).0.unwrap();
            f.state(x0, xd0, a0, t1).1
        };
        let (mut lo, mut hi) = (0.0, 0.999);
        assert!(peak(lo) < 1.0 && peak(hi) > 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if peak(mid) > 1.0 + 1e-9 {
                hi = mid
            } else {
                lo = mid
            }
        }
        let a0 = p.slip_accel(x0, hi, 1.0, sig);
        let (tau, _) = f.crossing(x0, hi, a0, 1.0, 10.0).expect("the dip is found");
        assert!((f.state(x0, hi, a0, tau).1 - 1.0).abs() < 1e-12);
        // and just below the peak there is none
        let a0 = p.slip_accel(x0, lo - 1e-6, 1.0, sig);
        assert!(f.crossing(x0, lo - 1e-6, a0, 1.0, 10.0).is_none());
    }

    #[test]
    fn huge_damping_and_no_spring_stay_finite() {
        // c = 1e8 (ζ = 2.5e7): the fast mode dies in ~1e-8 s, then the mass creeps at
        // ẋ = (f − ω² x)/γ, here f − ω² x₀ = 5 (a₀ = 5 − γ ẋ₀)
        let (f, _) = form(4.0, 1e8);
        let (x, xd) = f.state(0.1, 1.0, 5.0 - 1e8, 1.0);
        let creep = (5.0 + 4.0 * 0.1 - 4.0 * x) / 1e8;
        assert!((x - (0.1 + 1e-8 + 5e-8)).abs() < 1e-12, "{x}");
        assert!((xd - creep).abs() < 1e-15, "{xd} vs {creep}");
        let (f, p) = form(0.0, 2.0);
        // ẍ = a_k − 2 ẋ from rest: ẋ → a_k/2
        let (_, xd) = f.state(0.0, 0.0, p.kinetic, 30.0);
        assert!((xd - p.kinetic / 2.0).abs() < 1e-12);
    }
}
