//! Closed-form slip without damping (c = 0: the paper's system).
//!
//! Per unit mass (see [`super`]), with `a₀ = σ a_k − ω² x₀` the acceleration at τ = 0:
//!
//! ```text
//!  slip:   x(τ) = x₀ + ẋ₀ S(τ) + a₀ C(τ),   ẋ(τ) = ẋ₀ cos ωτ + a₀ S(τ)
//!          S(τ) = sin(ωτ)/ω,    C(τ) = (1 − cos ωτ)/ω² = 2 sin²(ωτ/2)/ω²
//! ```
//!
//! `S` and `C` are evaluated from `sin`/`cos` of the half angle ωτ/2, which keeps full relative
//! accuracy for small ωτ (no `1 − cos` cancellation) and has the exact limits `S → τ`,
//! `C → τ²/2` as ω → 0 (a spring-less mass: uniformly decelerated slip).
//!
//! ## When does a slip reach belt speed?
//! With the tangent half-angle substitution `tan(ωτ/2) = ω r / 2` (r → τ as ω → 0), the relative
//! velocity `u(τ) = ẋ(τ) − v` satisfies
//!
//! ```text
//!     u(τ) · (1 + ω² r²/4) = u₀ + a₀ r − (ẋ₀ + v) (ω²/4) r²
//! ```
//!
//! so the crossings `u = 0` are the roots of the quadratic `α r² + β r + γ = 0` with
//! `α = (ẋ₀ + v) ω²/4`, `β = −a₀`, `γ = −u₀` and discriminant `a₀² + ω² u₀ (ẋ₀ + v)`
//! (written so that `ẋ₀² − v²` is never formed by cancellation). The roots are taken with the
//! cancellation-free formula `q = −(β + sgn β √Δ)/2`, `r₁ = q/α`, `r₂ = γ/q` (Press et al.,
//! *Numerical Recipes*, 3rd ed., §5.6), mapped back by `ωτ = 2 atan(ω r / 2)` (plus 2π for a
//! negative angle: the motion is 2π/ω-periodic, so the first crossing lies within one period or
//! there is none). At a root the state needs no trigonometry: with `c² = 1/(1 + ω²r²/4)`,
//! `S = r c²` and `C = (r²/2) c²` (r = ±∞ is the half period: `S = 0`, `C = 2/ω²`).
//! Where the solution is a double root the velocity only touches belt speed (grazing).

use std::f64::consts::{PI, TAU};

use super::model::{PerUnitMass, SlipForm};

/// The undamped closed forms: `ω² = k/m`, `ω`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Undamped {
    /// ω² = k/m [1/s²]
    pub omega2: f64,
    /// ω = √(k/m) [rad/s]
    pub omega: f64,
}

/// Below this ωτ the series of `S` and `C` are used (their first dropped terms are below
/// 1e-17 relative), which also makes ω = 0 and an underflowing ω² exact.
const SERIES_BELOW: f64 = 1e-4;

impl SlipForm for Undamped {
    fn new(p: &PerUnitMass) -> Undamped {
        Undamped { omega2: p.omega2, omega: p.omega }
    }

    fn state(&self, x0: f64, xdot0: f64, a0: f64, tau: f64) -> (f64, f64) {
        self.slip_state(x0, xdot0, a0, tau)
    }

    fn crossing(&self, x0: f64, xdot0: f64, a0: f64, v: f64, horizon: f64) -> Option<(f64, f64)> {
        self.belt_speed_crossing(x0, xdot0, a0, v, horizon)
    }

    /// `ẋ(τ) = ẋ₀ cos ωτ + a₀ S(τ) = R cos(ωτ − φ)`, `R = √(ẋ₀² + (a₀/ω)²)`, and
    /// `ẍ(τ) = a₀ cos ωτ − ω² ẋ₀ S(τ)`. Turning points are π/ω apart, and `ẍ(π/ω) = −a₀`, so each
    /// half period [0, π/ω], [π/ω, 2π/ω] holds at most one; it lies inside a part of it exactly
    /// when ẍ changes sign there (from + to −: a maximum, +R; from − to +: a minimum, −R). No
    /// trigonometric call (the end state is given); without a spring the velocity is linear.
    fn velocity_range(&self, xdot0: f64, a0: f64, tau: f64, xdot1: f64, a1: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (xdot0.min(xdot1), xdot0.max(xdot1));
        let theta = self.omega * tau;
        if self.omega == 0.0 || !(theta > 0.0) {
            return (lo, hi);
        }
        // ẋ² + (ẍ/ω)² = R² along the slip
        let r = || (xdot0 * xdot0 + (a0 / self.omega) * (a0 / self.omega)).sqrt();
        if theta >= TAU {
            return (-r(), r());
        }
        let mut turn = |from: f64, to: f64| {
            if from > 0.0 && to < 0.0 {
                hi = hi.max(r());
            } else if from < 0.0 && to > 0.0 {
                lo = lo.min(-r());
            }
        };
        if theta < PI {
            turn(a0, a1);
        } else {
            turn(a0, -a0);
            turn(-a0, a1);
            // ẋ(π/ω) = −ẋ₀ (an extremum itself when a₀ = 0)
            (lo, hi) = (lo.min(-xdot0), hi.max(-xdot0));
        }
        (lo, hi)
    }
}

impl Undamped {
    /// `(S(τ), C(τ), cos ωτ)` for a slip lasting τ (see the module docs).
    pub fn slip_basis(&self, tau: f64) -> (f64, f64, f64) {
        let theta = self.omega * tau;
        if theta < SERIES_BELOW {
            let t2 = theta * theta;
            let s = tau * (1.0 - t2 / 6.0);
            let c = 0.5 * tau * tau * (1.0 - t2 / 12.0);
            return (s, c, 1.0 - 0.5 * t2);
        }
        let (sh, ch) = (0.5 * theta).sin_cos();
        let s = 2.0 * sh * ch / self.omega;
        let c = 2.0 * sh * sh / self.omega2;
        (s, c, 1.0 - 2.0 * sh * sh)
    }

    /// State `(x, ẋ)` after a slip of duration τ from `(x₀, ẋ₀)` with initial acceleration `a₀`.
    pub fn slip_state(&self, x0: f64, xdot0: f64, a0: f64, tau: f64) -> (f64, f64) {
        let (s, c, cos) = self.slip_basis(tau);
        (x0 + xdot0 * s + a0 * c, xdot0 * cos + a0 * s)
    }

    /// The first τ > 0 at which a slip from `(x₀, ẋ₀)` with acceleration `a₀` reaches belt
    /// velocity `v`, and the position there; `None` if it never does (the velocity oscillation
    /// stays on one side of `v`, or a spring-less mass moves away from it).
    ///
    /// A slip that starts exactly at belt speed with zero acceleration (`u₀ = a₀ = 0`, the orbit
    /// right after a breakaway) only touches belt speed once per period, tangentially; that
    /// touch is not a crossing and `None` is returned.
    ///
    /// Crossings at or after `horizon` (e.g. the next belt flip) are reported as `None`; most are
    /// ruled out without an `atan` by the bound `ωτ = 2 atan h ≥ 2h/√(1+h²)` (as sin α ≤ α).
    pub fn belt_speed_crossing(&self, x0: f64, xdot0: f64, a0: f64, v: f64, horizon: f64) -> Option<(f64, f64)> {
        let u0 = xdot0 - v;
        let alpha = 0.25 * (xdot0 + v) * self.omega2;
        let beta = -a0;
        let gamma = -u0;
        let disc = a0 * a0 + self.omega2 * u0 * (xdot0 + v);
        if !(disc >= 0.0) {
            return None;
        }
        let q = -0.5 * (beta + beta.signum() * disc.sqrt());
        if q == 0.0 {
            // β = 0 and Δ = 0: either the touch-only orbit (u₀ = 0) or ẋ₀ = −v, a₀ = 0, whose
            // only root is at the half period (r = ∞).
            return if u0 == 0.0 { None } else { self.at_root(x0, xdot0, a0, f64::INFINITY, horizon) };
        }
        // Of the two roots, the first in time: ωτ = 2 atan(ω r/2) lies in (0, π) for r > 0 and in
        // (π, 2π) for r < 0 (after the 2π shift), and grows with r within each sign; only the
        // chosen root is mapped back (one `atan`).
        // (q ≠ 0 here, so neither root is NaN; r₁ = ±∞ when α = 0 is the half period.)
        let (r1, r2) = (q / alpha, gamma / q);
        let key = |r: f64| if r > 0.0 { (0, r) } else { (1, r) };
        let r = if key(r2) < key(r1) { r2 } else { r1 };
        self.at_root(x0, xdot0, a0, r, horizon)
    }

    /// Map a root `r` of the crossing quadratic to `(τ, x(τ))`, τ ∈ (0, 2π/ω], if τ < horizon.
    fn at_root(&self, x0: f64, xdot0: f64, a0: f64, r: f64, horizon: f64) -> Option<(f64, f64)> {
        if r.is_nan() {
            return None;
        }
        let h = 0.5 * self.omega * r; // tan(ωτ/2)
        if self.omega == 0.0 || h == 0.0 && r != 0.0 {
            // No spring (or ω r below resolution): uniformly accelerated motion, τ = r.
            return (r > 0.0 && r.is_finite() && r < horizon).then_some((r, x0 + xdot0 * r + 0.5 * a0 * r * r));
        }
        let phi = self.omega * horizon;
        if phi <= PI && (h <= 0.0 || h.is_infinite() || 2.0 * h >= phi * (1.0 + h * h).sqrt()) {
            // ωτ > π ≥ ωΔ for a wrapped root, else ωτ ≥ 2h/√(1+h²) ≥ ωΔ: beyond the horizon
            return None;
        }
        let mut theta = 2.0 * h.atan();
        if theta <= 0.0 {
            theta += TAU;
        }
        let tau = theta / self.omega;
        if !(tau < horizon) {
            return None;
        }
        let x = if h.is_infinite() || h.abs() > 1e150 {
            // ωτ = π: S = 0, C = 2/ω².
            debug_assert!((theta - PI).abs() < 1e-9);
            x0 + a0 * 2.0 / self.omega2
        } else {
            let c2 = 1.0 / (1.0 + h * h);
            x0 + (xdot0 * r + 0.5 * a0 * r * r) * c2
        };
        Some((tau, x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed forms for k (m = 1) and the kinetic friction acceleration `fmax`.
    fn accel(k: f64, fmax: f64) -> (Undamped, f64) {
        (Undamped::new(&crate::physics::Params { stiffness: k, ..crate::physics::Params::PAPER }.per_unit_mass()), fmax)
    }

    /// Reference: direct trigonometric solution x = xe + A cos ωτ + B sin ωτ.
    fn direct(a: &Undamped, x0: f64, xd0: f64, a0: f64, tau: f64) -> (f64, f64) {
        let xe = x0 + a0 / a.omega2;
        let (s, c) = (a.omega * tau).sin_cos();
        let (aa, bb) = (x0 - xe, xd0 / a.omega);
        (xe + aa * c + bb * s, a.omega * (-aa * s + bb * c))
    }

    #[test]
    fn slip_state_matches_direct_trigonometric_solution() {
        let (a, _) = accel(4.0, 5.0);
        for &tau in &[1e-7, 1e-3, 0.3, 1.7, 12.0] {
            let (x, xd) = a.slip_state(0.3, -0.7, 2.1, tau);
            let (xr, xdr) = direct(&a, 0.3, -0.7, 2.1, tau);
            assert!((x - xr).abs() < 1e-13 * (1.0 + xr.abs()), "tau {tau}: {x} vs {xr}");
            assert!((xd - xdr).abs() < 1e-13 * (1.0 + xdr.abs()));
        }
    }

    #[test]
    fn slip_state_without_spring_is_uniform_acceleration() {
        let (a, _) = accel(0.0, 5.0);
        let (x, xd) = a.slip_state(0.5, 2.0, -5.0, 0.3);
        assert_eq!(x, 0.5 + 2.0 * 0.3 - 2.5 * 0.09);
        assert!((xd - (2.0 - 1.5)).abs() < 1e-15);
    }

    #[test]
    fn crossing_is_a_root_of_relative_velocity() {
        let (a, friction) = accel(4.0, 5.0);
        for &(x0, xd0, sig, v) in &[(0.2, -1.0, 1.0, 1.0), (-0.9, 3.0, -1.0, 1.0), (0.4, 0.9, 1.0, -1.0)] {
            let a0 = sig * friction - a.omega2 * x0;
            let (tau, x) = a.belt_speed_crossing(x0, xd0, a0, v, f64::INFINITY).expect("crossing");
            let (xr, xdr) = direct(&a, x0, xd0, a0, tau);
            assert!((xdr - v).abs() < 1e-12, "u = {} at tau {tau}", xdr - v);
            assert!((x - xr).abs() < 1e-12);
            // a horizon just before it hides it, one just after keeps it
            assert!(a.belt_speed_crossing(x0, xd0, a0, v, tau * (1.0 - 1e-12)).is_none());
            assert_eq!(a.belt_speed_crossing(x0, xd0, a0, v, tau * (1.0 + 1e-12)).map(|c| c.0), Some(tau));
            // and it is the first one: u keeps its sign on a fine grid before tau
            let s0 = (xd0 - v).signum();
            for i in 1..1000 {
                let (_, xd) = direct(&a, x0, xd0, a0, tau * i as f64 / 1000.0);
                assert_eq!((xd - v).signum(), s0);
            }
        }
    }

    #[test]
    fn velocity_range_is_the_extreme_of_a_fine_grid() {
        let (a, friction) = accel(4.0, 5.0);
        for &(x0, xd0, sig) in &[(0.2, -1.0, 1.0), (-0.9, 3.0, -1.0), (0.4, 0.9, 1.0), (1.25, 0.0, 1.0), (0.0, 0.7, 0.0)] {
            let a0 = sig * friction - a.omega2 * x0;
            for &tau in &[1e-3, 0.4, 0.8, 1.2, 1.6, 2.0, 2.6, 3.0, 3.2, 7.0] {
                let (x1, xd1) = a.slip_state(x0, xd0, a0, tau);
                let (lo, hi) = a.velocity_range(xd0, a0, tau, xd1, a0 - a.omega2 * (x1 - x0));
                let (mut glo, mut ghi) = (f64::INFINITY, f64::NEG_INFINITY);
                for i in 0..=20_000 {
                    let xd = direct(&a, x0, xd0, a0, tau * i as f64 / 20_000.0).1;
                    (glo, ghi) = (glo.min(xd), ghi.max(xd));
                }
                // the grid's extremes lie inside the range and within the grid's resolution of it
                let tol = 1e-12 + 1e-7 * (glo.abs() + ghi.abs());
                assert!(lo <= glo + 1e-12 && hi >= ghi - 1e-12, "({x0}, {xd0}, {tau}): [{lo}, {hi}] vs [{glo}, {ghi}]");
                assert!(glo - lo <= tol && hi - ghi <= tol, "({x0}, {xd0}, {tau}): [{lo}, {hi}] vs [{glo}, {ghi}]");
            }
        }
        // without a spring: linear
        let (b, _) = accel(0.0, 5.0);
        assert_eq!(b.velocity_range(2.0, -5.0, 0.3, 0.5, -5.0), (2.0 - 1.5, 2.0));
    }

    #[test]
    fn no_crossing_when_velocity_amplitude_is_below_belt_speed() {
        let (a, _) = accel(4.0, 0.0);
        // free oscillation with velocity amplitude 0.5 < v = 1
        assert!(a.belt_speed_crossing(0.0, 0.5, 0.0, 1.0, f64::INFINITY).is_none());
    }

    #[test]
    fn tiny_omega_crossing_tends_to_uniform_deceleration() {
        // k = 1e-20: ω = 1e-10; the crossing time must approach u₀/a_f without cancellation.
        let (a, friction) = accel(1e-20, 5.0);
        let a0 = friction - a.omega2 * 0.3;
        let (tau, x) = a.belt_speed_crossing(0.3, -1.0, a0, 1.0, f64::INFINITY).unwrap();
        assert!((tau - 2.0 / a0).abs() < 1e-14, "{tau}");
        assert!((x - (0.3 - 2.0 / a0 + 0.5 * a0 * (2.0 / a0).powi(2))).abs() < 1e-14);
    }
}
