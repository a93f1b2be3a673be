//! The oscillator's parameters, the friction law as data, the equation of motion per unit mass
//! and the stick, arrival and breakaway rules (module docs of [`crate::physics`]).

use serde::{Deserialize, Serialize};

/// Relative width of the band around `p = a_s` treated as a touch at the breakaway point.
pub const TOUCH_TOLERANCE: f64 = 1e-12;

/// The name of a friction law in a scenario (`model.friction_law`); the law with its parameters
/// is [`Law`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionLaw {
    /// Dry friction: μ_s n holds a stick, μ_k n opposes a slip (μ_s ≥ μ_k; equal in the paper).
    Coulomb,
    /// Velocity weakening from μ_s n at |u| = 0⁺ to μ_k n, over the Stribeck velocity v_s.
    Stribeck,
}

impl FrictionLaw {
    /// Whether a slip under this law has closed forms, given whether μ_s equals μ_k for every
    /// realization: Coulomb's constant friction (with any viscous term: a dashpot towards the
    /// belt) always; Stribeck only when μ_s = μ_k, where it is Coulomb.
    pub fn has_closed_forms(self, static_is_kinetic: bool) -> bool {
        match self {
            FrictionLaw::Coulomb => true,
            FrictionLaw::Stribeck => static_is_kinetic,
        }
    }

    /// Its name in prose (`Stribeck`).
    pub fn title(self) -> &'static str {
        match self {
            FrictionLaw::Coulomb => "Coulomb",
            FrictionLaw::Stribeck => "Stribeck",
        }
    }
}

/// The friction law with its parameters, as data: every solver asks the law (through
/// [`PerUnitMass`]) for the slip friction, the acceleration after a breakaway, its regularized form
/// and the step limit near its peak; none branches on which law it is. A new law is a new variant
/// here and its answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Dry friction: μ_s n holds a stick, μ_k n opposes a slip (μ_s ≥ μ_k; equal in the paper).
    Coulomb,
    /// Velocity weakening from μ_s n at |u| = 0⁺ to μ_k n, with the shape v_s, δ.
    Stribeck(Stribeck),
}

impl Law {
    /// Its name in a scenario.
    pub fn name(&self) -> FrictionLaw {
        match self {
            Law::Coulomb => FrictionLaw::Coulomb,
            Law::Stribeck(_) => FrictionLaw::Stribeck,
        }
    }

    /// The half-width in |u| of the window around belt speed where the law changes fast (the
    /// Stribeck peak: [`Stribeck::window`]); 0 for a law without a peak.
    pub fn peak_window(&self) -> f64 {
        match self {
            Law::Coulomb => 0.0,
            Law::Stribeck(s) => s.window(),
        }
    }
}

/// The Stribeck law's shape: v_s [m/s] (> 0) and δ (> 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stribeck {
    /// v_s, the Stribeck velocity [m/s] (> 0)
    pub velocity: f64,
    /// δ, the Stribeck exponent (> 0)
    pub exponent: f64,
}

/// Beyond `(|u|/v_s)^δ > PEAK_CUTOFF` the peak term `exp(−(|u|/v_s)^δ) < 4e-18` is dropped: the
/// friction is μ_k n to the last bit (for any μ_s/μ_k below about 50).
pub const PEAK_CUTOFF: f64 = 40.0;

impl Stribeck {
    /// `exp(−(|u|/v_s)^δ)`, the peak term of the law at relative velocity u.
    #[inline]
    pub fn peak(&self, u: f64) -> f64 {
        self.peak_along(u.abs())
    }

    /// The peak term along a slip, as a function of its sliding speed `s = σ u` (positive while
    /// the slip lasts): `exp(−(s/v_s)^δ)` (δ = 2 and δ = 1 without `powf`; 0 past the cutoff).
    ///
    /// For s < 0 — past the slip's arrival at belt speed, where only an integrator's stages and
    /// dense output look — the law is continued *smoothly* instead of by |s|: for an integer δ
    /// with `(s/v_s)^δ` itself (analytic; for odd δ held at ≥ −1, so the continuation stays
    /// within e of the peak however far a step reaches), else by `|s/v_s|^δ`. With |s| the
    /// right-hand side of δ = 1 would have a kink exactly at the event, which a Runge–Kutta step
    /// and its interpolant straddle: its error estimate then does not bound the located event
    /// time (seen: 3e-8 s at rtol = 1e-11). For s ≥ 0 this is `peak(s)` to the bit.
    #[inline]
    pub fn peak_along(&self, s: f64) -> f64 {
        // times 1/v_s rather than over v_s: the solvers evaluate the law several times per
        // step with the same v_s, and the reciprocal is computed once (a division's latency
        // sits on the integrator's critical path)
        let r = s * (1.0 / self.velocity);
        let d = self.exponent;
        let z = if d == 2.0 {
            r * r
        } else if d == 1.0 {
            r.max(-1.0)
        } else if r >= 0.0 {
            r.powf(d)
        } else if d.fract() == 0.0 && d <= 64.0 {
            r.powi(d as i32).max(-1.0)
        } else {
            (-r).powf(d)
        };
        if z > PEAK_CUTOFF {
            0.0
        } else {
            (-z).exp()
        }
    }

    /// The half-width of the window in which the peak term exceeds e^−12 (6e-6): `v_s 12^{1/δ}`.
    pub fn window(&self) -> f64 {
        self.velocity * 12f64.powf(1.0 / self.exponent)
    }
}

/// Physical parameters of one realization's oscillator (SI units), as in `[model]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// m, kg (> 0)
    pub mass: f64,
    /// k, N/m (≥ 0)
    pub stiffness: f64,
    /// c, N·s/m (≥ 0)
    pub damping: f64,
    /// n, N (≥ 0)
    pub normal_force: f64,
    /// μ_k (≥ 0)
    pub kinetic: f64,
    /// μ_s (≥ μ_k)
    pub static_: f64,
    /// σ_v, N·s/m (≥ 0): the viscous term of the slip friction, σ_v u
    pub viscous: f64,
    /// the friction law with its parameters
    pub law: Law,
}

impl Params {
    /// The paper's parameters: m = 1 kg, k = 4 N/m, c = 0, n = 9.8 N, μ_s = μ_k = 0.51.
    pub const PAPER: Params =
        Params { mass: 1.0, stiffness: 4.0, damping: 0.0, normal_force: 9.8, kinetic: 0.51, static_: 0.51, viscous: 0.0, law: Law::Coulomb };

    /// The per-unit-mass constants the solvers work with.
    #[inline]
    pub fn per_unit_mass(&self) -> PerUnitMass {
        let omega2 = self.stiffness / self.mass;
        PerUnitMass {
            omega2,
            omega: omega2.sqrt(),
            gamma: self.damping / self.mass,
            kinetic: self.kinetic * self.normal_force / self.mass,
            breakaway: self.static_ * self.normal_force / self.mass,
            viscous: self.viscous / self.mass,
            law: self.law,
        }
    }
}

impl Default for Params {
    fn default() -> Params {
        Params::PAPER
    }
}

/// The model per unit mass: `ω²`, `ω`, `γ = c/m`, `a_k`, `a_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PerUnitMass {
    /// ω² = k/m [1/s²]
    pub omega2: f64,
    /// ω = √(k/m) [rad/s]
    pub omega: f64,
    /// γ = c/m [1/s]
    pub gamma: f64,
    /// a_k = μ_k n/m, m/s²
    pub kinetic: f64,
    /// a_s = μ_s n/m, m/s²
    pub breakaway: f64,
    /// β = σ_v/m, 1/s: the viscous term of the slip friction per unit mass, β u
    pub viscous: f64,
    /// the friction law (its parameters in SI units: they are velocities, not forces)
    pub law: Law,
}

/// What a slip that reaches belt velocity v at position x does next (the module docs' rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arrival {
    /// The static friction holds: a stick starts at `x` (clamped onto `|F| ≤ a_s` within the
    /// touch band).
    Stick {
        /// position where the stick starts [m]
        x: f64,
    },
    /// A touch at the breakaway point: the slip goes on from `x_b` as after a breakaway.
    Touch,
    /// The mass passes through belt speed; the friction becomes `σ`.
    Reverse {
        /// σ = sgn(ω² x + γ v) = ±1, the friction's sign in the new slip
        sigma: f64,
    },
}

impl PerUnitMass {
    /// The slip friction per unit mass at relative speed |u| [m/s²]: `a_k` (Coulomb), or
    /// `a_k + (a_s − a_k) exp(−(|u|/v_s)^δ)` (Stribeck).
    #[inline]
    pub fn slip_friction(&self, u: f64) -> f64 {
        match self.law {
            Law::Coulomb => self.kinetic,
            Law::Stribeck(s) => self.kinetic + (self.breakaway - self.kinetic) * s.peak(u),
        }
    }

    /// The equation of motion in slip under belt velocity v with friction direction σ:
    /// `ẍ = σ f_dry(|v − ẋ|)/m + β (v − ẋ) − ω² x − γ ẋ` [m/s²] (past the slip's arrival,
    /// σ(v − ẋ) < 0, the Stribeck peak continued smoothly: [`Stribeck::peak_along`]).
    #[inline]
    pub fn slip_accel(&self, x: f64, xdot: f64, v: f64, sigma: f64) -> f64 {
        // σ a_k − (ω² x + γ ẋ) + σ (a_s − a_k) P(u): the peak term P enters last, through one
        // multiply and one add (it is the integrators' longest chain, through `exp`)
        let mut coulomb = sigma * self.kinetic - (self.omega2 * x + self.gamma * xdot);
        if self.viscous != 0.0 {
            // (added only when present: without it the sum is the paper's to the bit)
            coulomb += self.viscous * (v - xdot);
        }
        match self.law {
            Law::Coulomb => coulomb,
            Law::Stribeck(s) => coulomb + sigma * (self.breakaway - self.kinetic) * s.peak_along(sigma * (v - xdot)),
        }
    }

    /// The damping a slip sees, per unit mass [1/s]: γ + β (the dashpot and the viscous term).
    #[inline]
    pub fn slip_damping(&self) -> f64 {
        self.gamma + self.viscous
    }

    /// Whether the slip after a breakaway only touches belt speed until the next switch (the
    /// grazing orbit: μ_s = μ_k, when every law is Coulomb's constant; with damping it never even
    /// touches again). A Stribeck slip with μ_s > μ_k also leaves tangentially, but velocity
    /// weakening can bring it back.
    #[inline]
    pub fn grazes_after_breakaway(&self) -> bool {
        self.kinetic == self.breakaway
    }

    /// The holding force per unit mass in a stick at x under belt velocity v: `ω² x + γ v`.
    #[inline]
    pub fn holding(&self, x: f64, v: f64) -> f64 {
        self.omega2 * x + self.gamma * v
    }

    /// Where the holding force reaches `side · a_s` along the belt (side = +1: the breakaway
    /// point ahead, −1: the limit behind): `x = (side·s a_s − γ v)/ω²` (±∞ without a spring).
    #[inline]
    pub fn holding_limit(&self, v: f64, side: f64) -> f64 {
        (side * v.signum() * self.breakaway - self.gamma * v) / self.omega2
    }

    /// How long a stick at `x₀` under belt velocity v lasts until breakaway:
    /// `(a_s − s(ω² x₀ + γ v))/(ω² |v|)` (∞ without a spring, or when the dashpot alone cannot
    /// reach the limit).
    #[inline]
    pub fn stick_duration(&self, x0: f64, v: f64) -> f64 {
        (self.breakaway - v.signum() * self.holding(x0, v)) / (self.omega2 * v.abs())
    }

    /// The acceleration of the slip that starts at a breakaway (or a touch) under belt velocity
    /// v: `s (f(0⁺) − a_s)` — exactly 0 when μ_s = μ_k (the grazing orbit), `s (a_k − a_s)` for
    /// Coulomb, 0 for Stribeck (f(0⁺) = a_s).
    #[inline]
    pub fn breakaway_accel(&self, v: f64) -> f64 {
        match self.law {
            Law::Coulomb => v.signum() * (self.kinetic - self.breakaway) + 0.0,
            Law::Stribeck(_) => 0.0,
        }
    }

    /// The law regularized for the smooth method, per unit mass, at relative velocity u with
    /// width ε (`solver::smooth`'s module docs): Coulomb `a_k tanh(u/ε) + (a_s − a_k) w
    /// exp((1 − w²)/2)` with w = u/ε (a bump that reaches the static level at |u| = ε);
    /// Stribeck `f(|u|) tanh(u/ε)` (its own peak is the static level); plus the viscous term β u,
    /// smooth already.
    #[inline]
    pub fn regularized_friction(&self, epsilon: f64, u: f64) -> f64 {
        let w = u / epsilon;
        let dry = match self.law {
            Law::Stribeck(_) => self.slip_friction(u) * w.tanh(),
            Law::Coulomb => {
                let excess = self.breakaway - self.kinetic;
                let bump = if excess > 0.0 { excess * w * (0.5 * (1.0 - w * w)).exp() } else { 0.0 };
                self.kinetic * w.tanh() + bump
            }
        };
        if self.viscous != 0.0 {
            dry + self.viscous * u
        } else {
            dry
        }
    }

    /// The longest step up to `want` that keeps the law's peak resolved at state `y = (x, ẋ)`
    /// under belt velocity `v`, with slip acceleration `acc` and the law's [`Law::peak_window`]
    /// `window` (`solver::hybrid`'s module docs): the change of u one step may make, bounded by
    /// |u̇| h + |ü| h²/2 with ü = −(ω² ẋ + (γ + β) ẍ), stays within what is left to the window plus
    /// v_s. `want` for a law without a peak, or when `want` already keeps it.
    #[inline]
    pub fn peak_step_limit(&self, window: f64, y: [f64; 2], v: f64, acc: f64, want: f64) -> f64 {
        let Law::Stribeck(s) = self.law else { return want };
        let u = v - y[1];
        let allowed = (u.abs() - window).max(0.0) + s.velocity;
        let (du, ddu) = (acc.abs(), (self.omega2 * y[1] + self.slip_damping() * acc).abs());
        if (du + 0.5 * ddu * want) * want <= allowed {
            return want;
        }
        // the positive root of |ü| h²/2 + |u̇| h = allowed, without cancellation
        let h = 2.0 * allowed / (du + (du * du + 2.0 * ddu * allowed).sqrt());
        if h > 0.0 {
            h.min(want)
        } else {
            want
        }
    }

    /// The arrival rule at belt velocity v and position x.
    #[inline]
    pub fn arrival(&self, x: f64, v: f64) -> Arrival {
        let s = v.signum();
        let p = s * self.holding(x, v);
        let a_s = self.breakaway;
        if p > a_s * (1.0 + TOUCH_TOLERANCE) || p < -a_s * (1.0 + TOUCH_TOLERANCE) {
            Arrival::Reverse { sigma: s * p.signum() }
        } else if p >= a_s * (1.0 - TOUCH_TOLERANCE) {
            Arrival::Touch
        } else {
            // Within [−a_s(1+tol), a_s): clamp the lower edge so that |F| ≤ a_s holds exactly.
            Arrival::Stick { x: if p < -a_s { self.holding_limit(v, -1.0) } else { x } }
        }
    }
}

/// Closed-form slip under constant forcing, from `(x₀, ẋ₀)` with initial acceleration `a₀`.
pub trait SlipForm: Copy + Send + Sync + std::fmt::Debug {
    /// The closed forms of `p`.
    fn new(p: &PerUnitMass) -> Self;
    /// State `(x, ẋ)` after a slip of duration τ.
    fn state(&self, x0: f64, xdot0: f64, a0: f64, tau: f64) -> (f64, f64);
    /// The first τ ∈ (0, horizon) at which the velocity reaches `v`, and the position there;
    /// `None` if it does not (a touch of the grazing orbit, `ẋ₀ = v` with `a₀ = 0`, is not a
    /// crossing).
    fn crossing(&self, x0: f64, xdot0: f64, a0: f64, v: f64, horizon: f64) -> Option<(f64, f64)>;
    /// The least and the greatest velocity ẋ over a slip of duration τ from `ẋ₀` with initial
    /// acceleration `a₀` that ends with velocity `ẋ₁` and acceleration `a₁` (the velocity solves
    /// a homogeneous equation, so its extrema are at the ends or at its turning points, known in
    /// closed form).
    fn velocity_range(&self, xdot0: f64, a0: f64, tau: f64, xdot1: f64, a1: f64) -> (f64, f64);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stribeck_law_falls_from_static_to_kinetic() {
        let stribeck = Stribeck { velocity: 0.1, exponent: 2.0 };
        let p = Params { static_: 0.6, law: Law::Stribeck(stribeck), ..Params::PAPER }.per_unit_mass();
        let (a_s, a_k) = (0.6 * 9.8, 0.51 * 9.8);
        assert!((p.slip_friction(0.0) - a_s).abs() < 1e-12);
        assert!((p.slip_friction(-0.1) - (a_k + (a_s - a_k) / std::f64::consts::E)).abs() < 1e-12);
        assert!((p.slip_friction(1.0) - a_k).abs() < 1e-12 * a_k + (a_s - a_k) * 1e-40);
        assert_eq!(p.breakaway_accel(1.0), 0.0);
        assert!(!p.grazes_after_breakaway());
        // mu_s = mu_k: the law is Coulomb's constant
        let c = Params { law: Law::Stribeck(stribeck), ..Params::PAPER }.per_unit_mass();
        assert_eq!(c.slip_friction(0.05), 0.51 * 9.8);
    }

    #[test]
    fn rules_reduce_to_the_paper_without_damping_and_static_excess() {
        let p = Params::PAPER.per_unit_mass();
        let a_f = 0.51 * 9.8;
        assert_eq!(p.holding_limit(1.0, 1.0), a_f / 4.0);
        assert_eq!(p.holding_limit(-1.0, 1.0), -a_f / 4.0);
        assert_eq!(p.stick_duration(0.0, 1.0), a_f / 4.0);
        assert_eq!(p.breakaway_accel(1.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(p.breakaway_accel(-1.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(p.arrival(0.3, 1.0), Arrival::Stick { x: 0.3 });
        assert_eq!(p.arrival(a_f / 4.0, 1.0), Arrival::Touch);
        assert_eq!(p.arrival(2.0, 1.0), Arrival::Reverse { sigma: 1.0 });
        assert_eq!(p.arrival(-2.0, 1.0), Arrival::Reverse { sigma: -1.0 });
    }

    #[test]
    fn damping_and_static_friction_enter_the_holding_force() {
        let p = Params { damping: 0.5, static_: 0.6, ..Params::PAPER }.per_unit_mass();
        let (a_s, v) = (0.6 * 9.8, -2.0);
        // stick under v < 0: breakaway where −(4 x + 0.5 v) = a_s
        let xb = p.holding_limit(v, 1.0);
        assert!((-(4.0 * xb + 0.5 * v) - a_s).abs() < 1e-12);
        let x0 = 0.2;
        let tb = p.stick_duration(x0, v);
        assert!(((x0 + v * tb) - xb).abs() < 1e-12);
        // after breakaway the mass falls behind: relative acceleration s (a_s − a_k) ≠ 0
        assert!((p.breakaway_accel(v) - (-(0.51 - 0.6) * 9.8)).abs() < 1e-12);
        assert!((p.slip_accel(xb, v, v, -1.0) - p.breakaway_accel(v)).abs() < 1e-12);
        // between a_k and a_s an arrival sticks
        let x = (-(0.55 * 9.8) - 0.5 * v) / 4.0; // p = 0.55 n
        assert!(matches!(p.arrival(x, v), Arrival::Stick { .. }));
    }
}
