//! The physics home: the oscillator's parameters, its friction law, its equation of motion and
//! the stick, arrival and breakaway rules — written once, called by every solver.
//!
//! Conventions (Lima & Sampaio, eq. 1–2, extended by damping and static friction): x is the
//! absolute position [m], the spring k and the dashpot c tie the mass m to the fixed frame, the
//! belt moves at v(t) [m/s], u = v − ẋ is the relative (sliding) velocity.
//!
//! ```text
//!     m ẍ + c ẋ + k x = f
//!     slip:  f = f_dry(|u|) · σ + σ_v u,   σ = sgn(u)
//!            Coulomb:  f_dry = μ_k n
//!            Stribeck: f_dry = n [μ_k + (μ_s − μ_k) exp(−(|u|/v_s)^δ)]    (velocity weakening)
//!     stick: ẋ = v,  f = F := k x + c v,  |F| ≤ μ_s n           (static coefficient μ_s ≥ μ_k)
//! ```
//!
//! The viscous term σ_v u [N·s/m · m/s] (the static friction map of Armstrong-Hélouvry et al.,
//! below) acts only while the mass slides: in a stick u = 0, so the holding force, the breakaway
//! and the arrival rule do not see it. In a slip it is a dashpot towards the *belt*: the
//! equation is `ẍ = σ a_k + β v − ω² x − (γ + β) ẋ` with β = σ_v/m, a linear oscillator with
//! damping γ + β ([`PerUnitMass::slip_damping`]) under constant forcing while v is constant — so
//! Coulomb with a viscous term keeps its closed forms (the damped ones).
//!
//! The Stribeck law (R. Stribeck 1902; the exponential form of B. Armstrong-Hélouvry, P. Dupont,
//! C. Canudas de Wit, "A survey of models, analysis tools and compensation methods for the
//! control of machines with friction", Automatica 30, 1994) starts at f(0⁺) = μ_s n, so right
//! after a breakaway the relative acceleration is zero and the mass leaves belt speed tangentially;
//! it has no closed-form slip and is integrated numerically. With μ_s = μ_k it is Coulomb.
//!
//! Everything is written per unit mass, in `ω² = k/m` [1/s²], `γ = c/m` [1/s], the kinetic and
//! static friction accelerations `a_k = μ_k n/m`, `a_s = μ_s n/m` [m/s²], so that m → 0 or
//! m → ∞ never forms k x − f out of two huge forces. With the belt at constant velocity v (sign
//! s = sgn v), the rules are:
//!
//! - **stick** at x₀: x = x₀ + v τ, the holding force per unit mass `F/m = ω² x + γ v` grows
//!   along the belt (s·F/m increases at ω²|v|); it **breaks away** when `s (ω² x + γ v) = a_s`,
//!   after `τ_b = (a_s − s(ω² x₀ + γ v)) / (ω² |v|)`, at `x_b = (s a_s − γ v)/ω²`;
//! - the slip after a breakaway leaves belt speed with the friction `σ = s` and the
//!   acceleration `ẍ = s (a_k − a_s)`: zero when μ_s = μ_k (the *grazing* orbit, which only
//!   touches belt speed), else the mass falls behind the belt at once;
//! - **arrival** of a slip at belt speed at x, with `p = s (ω² x + γ v)`:
//!   `−a_s ≤ p < a_s` → stick; `p ≈ a_s` (relative [`TOUCH_TOLERANCE`]) → a touch at the
//!   breakaway point, a stick of zero length that is not counted (the slip goes on as after a
//!   breakaway); `|p| > a_s` → the mass passes through, the friction becomes `σ = sgn(ω² x + γ v)`;
//! - a belt switch always ends a stick (u jumps to v_new − v_old ≠ 0).
//!
//! In slip the motion is linear with constant forcing `σ a_k`; its closed forms live in
//! [`undamped`] (c = 0: the paper's system, trigonometric) and [`damped`] (c > 0: under-,
//! critically and over-damped in one form continuous through ζ = 1). A scene without damping
//! runs the undamped forms and pays nothing for damping support.

pub(crate) mod damped;
mod model;
pub(crate) mod undamped;

pub use damped::Damped;
pub use model::*;
pub use undamped::Undamped;
