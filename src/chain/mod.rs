//! A chain of masses between a moving anchor and the friction contact — the lumped torsional
//! drillstring — solved exactly, event to event.
//!
//! N masses m₁…m_N at absolute positions x_i [m] (or angles [rad]: read kg·m², N·m/rad, N·m and
//! rad/s for torsion). The anchor (the top drive) is at a(t), moving at u(t), piecewise constant,
//! a(0) = 0. Spring k_i [N/m] and dashpot c_i [N·s/m] join m_{i−1} to m_i (m₀ is the anchor);
//! the last mass rubs on the belt (the rock) moving at v(t), piecewise constant:
//!
//! ```text
//!     m_i ẍ_i = k_i (x_{i−1} − x_i) + c_i (ẋ_{i−1} − ẋ_i) − k_{i+1} (x_i − x_{i+1}) − c_{i+1} (ẋ_i − ẋ_{i+1})
//!     m_N ẍ_N = k_N (x_{N−1} − x_N) + c_N (ẋ_{N−1} − ẋ_N) + f            (x₀ = a, ẋ₀ = u)
//!     slip (w = v − ẋ_N ≠ 0):  f = σ f_k + σ_v w,   σ = sgn w
//!     stick (ẋ_N = v):  f = F := k_N (x_N − x_{N−1}) + c_N (v − ẋ_{N−1}),   |F| ≤ f_s
//! ```
//!
//! with f_k = μ_k n, f_s = μ_s n. For N = 1 and u = 0 this is [`crate::physics`]'s oscillator
//! (F = k x + c v), whose closed forms the N = 1 scenes keep running.
//!
//! **The rules** (each follows from the equations):
//! - F is taken at the instant, with the dashpot and the other masses' current state.
//! - A stick breaks away when |F| reaches f_s; the slip after it has σ = sgn F (the spring and
//!   dashpot pull the contact mass off the belt against F: m_N ẇ = F − σ f_k has the sign of F).
//!   On a resting belt a breakaway comes from the wind-up alone.
//! - A slip arriving at w = 0 sticks if |F| < f_s, passes through with σ = sgn F if |F| > f_s
//!   (then σ flips: m_N ẇ = F − σ f_k has the sign of F), and at |F| = f_s (relative
//!   [`crate::physics::TOUCH_TOLERANCE`]) is a zero-length touch exactly when F moves outward
//!   under stick dynamics (sgn F · dF/dt > 0): the slip goes on as after a breakaway; else it
//!   sticks.
//! - A belt change ends a stick with σ = sgn(v_new − v_old); an anchor change never does, but
//!   with a dashpot (N = 1) F jumps with u, and a jump past f_s is an immediate breakaway.
//!
//! **Between events the motion is linear** with constant forcing: with the state
//! z = (x₁…x_N, ẋ₁…ẋ_N, a, 1) ∈ ℝ^{2N+2} (the anchor's position and a constant carry the ramp
//! and the forcing), ż = Ã z, so z(τ) = e^{Ãτ} z₀, and every event function — w in a slip,
//! F ∓ f_s in a stick — is a fixed linear form g = c·z. In a stick the contact mass's row is
//! zero (ẍ_N = 0, ẋ_N = v held). How the exact method steps e^{Ãτ} and finds the zeros of g
//! without missing one: [`exact`] and [`roots`].

pub(crate) mod exact;
mod matrix;
pub(crate) mod roots;

pub use exact::ChainExact;

/// Why the stages built on one mass's closed-form law (the exact law, `predict`, the tails'
/// conditional estimator) refuse a chain.
pub const NO_CLOSED_LAW: &str =
    "the scene is a chain of masses or has a moving anchor, and the holding-time law d_s(x) these results are built on holds for one mass on a fixed wall only: simulate the scene instead";

/// One realization's chain: masses [kg], stiffnesses [N/m], dampings [N·s/m], the contact's
/// kinetic and static friction forces f_k = μ_k n, f_s = μ_s n [N] and its viscous coefficient
/// σ_v [N·s/m].
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// m_i > 0
    pub masses: Vec<f64>,
    /// k_i ≥ 0: k₁ ties m₁ to the anchor
    pub stiffnesses: Vec<f64>,
    /// c_i ≥ 0
    pub dampings: Vec<f64>,
    /// f_k = μ_k n ≥ 0 [N]
    pub kinetic: f64,
    /// f_s = μ_s n ≥ f_k [N]
    pub breakaway: f64,
    /// σ_v ≥ 0 [N·s/m]
    pub viscous: f64,
}

/// The rate of mass i [1/s]: the larger of √((k_i + k_{i+1})/m_i) and
/// (c_i + c_{i+1} (+ σ_v at the contact))/m_i, the weight of its row in the norm of the linear
/// part ([`matrix`]).
pub fn mass_rate(masses: &[f64], stiffnesses: &[f64], dampings: &[f64], viscous: f64, i: usize) -> f64 {
    let n = masses.len();
    let next = |v: &[f64]| v.get(i + 1).copied().unwrap_or(0.0);
    let k = stiffnesses[i] + next(stiffnesses);
    let c = dampings[i] + next(dampings) + if i + 1 == n { viscous } else { 0.0 };
    (k / masses[i]).sqrt().max(c / masses[i])
}

/// The fastest rate Ω [1/s] of a chain: the largest [`mass_rate`].
pub fn rate(masses: &[f64], stiffnesses: &[f64], dampings: &[f64], viscous: f64) -> f64 {
    (0..masses.len()).map(|i| mass_rate(masses, stiffnesses, dampings, viscous, i)).fold(0.0, f64::max)
}

/// What a realization of a chain adds to its row: the anchor's force T = k₁ (a − x₁) + c₁ (u − ẋ₁)
/// (the torque the top drive feels) over [0, t_a] — its time average, least and greatest value —
/// and the contact mass's mean velocity (x_N(t_a) − x_N(0))/t_a.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ChainSummary {
    /// (1/t_a) ∫ T dt [N]
    pub anchor_force_mean: f64,
    /// min T [N]
    pub anchor_force_min: f64,
    /// max T [N]
    pub anchor_force_max: f64,
    /// (x_N(t_a) − x_N(0))/t_a [m/s]
    pub mean_velocity: f64,
}

/// The anchor's motion: its velocity on each segment and the instants it changes (sorted, in
/// (0, t_a)); a(0) = 0.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Anchor {
    /// u on each segment [m/s] (`switches.len() + 1` of them)
    pub velocities: Vec<f64>,
    /// the instants u changes [s]
    pub switches: Vec<f64>,
}

impl Anchor {
    /// An anchor moving at a constant speed (0: the fixed wall).
    pub fn constant(u: f64) -> Anchor {
        Anchor { velocities: vec![u], switches: Vec::new() }
    }
}

/// The mean of |u − v| over [0, t_a] [m/s] for the belt's and the anchor's segments
/// (velocities, switch instants): how fast the string slides against the rock on average — a
/// chain's severity unit.
pub fn mean_slide(belt: (&[f64], &[f64]), anchor: (&[f64], &[f64]), t_a: f64) -> f64 {
    let (mut t, mut total, mut i, mut j) = (0.0, 0.0, 0, 0);
    while t < t_a {
        let next = belt.1.get(i).copied().unwrap_or(t_a).min(anchor.1.get(j).copied().unwrap_or(t_a)).min(t_a);
        total += (belt.0[i] - anchor.0[j]).abs() * (next - t);
        if belt.1.get(i) == Some(&next) {
            i += 1;
        }
        if anchor.1.get(j) == Some(&next) {
            j += 1;
        }
        t = next;
    }
    total / t_a
}

impl Chain {
    /// The number of masses.
    pub fn len(&self) -> usize {
        self.masses.len()
    }

    /// Whether it has no mass (never, for a checked chain).
    pub fn is_empty(&self) -> bool {
        self.masses.is_empty()
    }

    /// The total mechanical energy of state `z` (kinetic + springs, the anchor's spring
    /// included) [J] — for the energy balance.
    pub fn energy(&self, z: &[f64]) -> f64 {
        let n = self.len();
        let (x, xd, a) = (&z[..n], &z[n..2 * n], z[2 * n]);
        let mut e = 0.0;
        for i in 0..n {
            let prev = if i == 0 { a } else { x[i - 1] };
            e += 0.5 * self.masses[i] * xd[i] * xd[i] + 0.5 * self.stiffnesses[i] * (x[i] - prev) * (x[i] - prev);
        }
        e
    }
}
