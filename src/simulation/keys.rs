//! Random parameters: any numeric `[model]` or `[belt]` key may be a distribution, drawn per
//! realization.
//!
//! Each random key draws from its own sub-stream of the realization's generator
//! ([`crate::simulation::rng::substream`], purpose = the key), never from the stream of the initial
//! conditions and the belt: making a key random does not shift the belt's draws (the same seed
//! keeps the same belt), and making a second key random does not shift the first one's.
//!
//! Distributions (rand_distr 0.6, pinned):
//! - `uniform (low, high)`: `low + (high − low) U`, U a 53-bit uniform on [0, 1);
//! - `normal (mean, sd)`: truncated to the key's range ([`Key::range`]) by rejection;
//! - `lognormal (mean, cv)`: `exp(μ + σ Z)` with `σ² = ln(1 + cv²)`, `μ = ln mean − σ²/2`;
//! - `gamma (mean, cv)`: shape `1/cv²`, scale `mean·cv²`.
//!
//! Every draw lies in the key's range: one outside is drawn again, which samples the law
//! truncated to the range exactly. The door refuses a law whose share inside the range
//! ([`Dist::share_in`], computed exactly) is below [`Dist::min_share`] — half for a normal,
//! 99 % for lognormal and gamma — naming the share: no value the law did not produce is ever
//! substituted.

use rand::Rng;
use rand_distr::{Distribution, Gamma, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::physics::{Law, Params};
use crate::simulation::belt::{Belt, Process};
use crate::simulation::rng::{substream, unit_f64};

/// The numeric scene keys (the ones that may be swept or random).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// `model.mass`: m [kg]
    Mass,
    /// `model.stiffness`: k [N/m]
    Stiffness,
    /// `model.damping`: c [N·s/m]
    Damping,
    /// `model.normal_force`: n [N]
    NormalForce,
    /// `model.friction_coefficient`: μ_k
    Kinetic,
    /// `model.static_friction_coefficient`: μ_s
    Static,
    /// `belt.speed`: v0 = v_f [m/s]
    Speed,
    /// `belt.switch_rate`: λ = λ_f [1/s]
    SwitchRate,
    /// `belt.reverse_speed`: v_r [m/s] (telegraph belt)
    ReverseSpeed,
    /// `belt.reverse_switch_rate`: λ_r [1/s] (telegraph belt)
    ReverseSwitchRate,
    /// `model.stribeck_velocity`: v_s [m/s] (Stribeck law)
    StribeckVelocity,
    /// `model.stribeck_exponent`: δ (Stribeck law)
    StribeckExponent,
    /// `model.viscous_friction`: σ_v [N·s/m]
    Viscous,
    /// `anchor.speed`: U [m/s], a constant anchor's speed (a chain's top drive)
    /// (last: a key's sub-stream is its place here, so new keys go at the end)
    AnchorSpeed,
}

/// Everything the program knows about one numeric scene key, in one row of [`KEYS`]: its name
/// as written, its unit, the range the solvers are proven on, which law or belt process uses it,
/// and how a value drawn for a realization is applied. A new key is a new row (and its field in
/// the scenario's typed `[model]` or `[belt]`).
pub struct KeyInfo {
    /// as written, e.g. `model.friction_coefficient`
    pub dotted: &'static str,
    /// for messages, e.g. " (kg)"
    pub unit: &'static str,
    /// `[lo, hi]`: `tests/it/extremes.rs` runs every solver at both ends of every key; a value,
    /// sweep or distribution support outside it is refused at the door. Combinations are bounded
    /// too (ω·t_a, see [`crate::scenario::Scenario::max_rate`]).
    pub range: (f64, f64),
    /// the law or the belt processes that use it (empty: every scene)
    pub used_by: &'static str,
    /// set a value drawn for a realization into the parameters, the belt's process or the
    /// anchor's (on a process that does not use it: nothing; the scenario refuses that
    /// combination)
    apply: fn(&mut Params, &mut Process, &mut Process, f64),
}

/// The table of numeric scene keys, in [`Key`] order.
#[rustfmt::skip]
pub const KEYS: [KeyInfo; 14] = [
    KeyInfo { dotted: "model.mass", unit: " (kg)", range: (1e-9, 1e6), used_by: "", apply: |p, _, _, x| p.mass = x },
    KeyInfo { dotted: "model.stiffness", unit: " (N/m)", range: (0.0, 1e9), used_by: "", apply: |p, _, _, x| p.stiffness = x },
    KeyInfo { dotted: "model.damping", unit: " (N·s/m)", range: (0.0, 1e9), used_by: "", apply: |p, _, _, x| p.damping = x },
    KeyInfo { dotted: "model.normal_force", unit: " (N)", range: (0.0, 1e9), used_by: "", apply: |p, _, _, x| p.normal_force = x },
    KeyInfo { dotted: "model.friction_coefficient", unit: "", range: (0.0, 1e6), used_by: "", apply: |p, _, _, x| p.kinetic = x },
    KeyInfo { dotted: "model.static_friction_coefficient", unit: "", range: (0.0, 1e6), used_by: "", apply: |p, _, _, x| p.static_ = x },
    KeyInfo { dotted: "belt.speed", unit: " (m/s)", range: (1e-9, 1e6), used_by: "symmetric, telegraph", apply: |_, b, _, x| match b {
        Process::Symmetric(s) => s.speed = x,
        Process::Telegraph(t) => t.forward_speed = x,
        _ => {}
    } },
    KeyInfo { dotted: "belt.switch_rate", unit: " (1/s)", range: (0.0, 1e6), used_by: "symmetric, telegraph", apply: |_, b, _, x| match b {
        Process::Symmetric(s) => s.switch_rate = x,
        Process::Telegraph(t) => t.forward_rate = x,
        _ => {}
    } },
    KeyInfo { dotted: "belt.reverse_speed", unit: " (m/s)", range: (1e-9, 1e6), used_by: "telegraph", apply: |_, b, _, x| if let Process::Telegraph(t) = b { t.reverse_speed = x } },
    KeyInfo { dotted: "belt.reverse_switch_rate", unit: " (1/s)", range: (0.0, 1e6), used_by: "telegraph", apply: |_, b, _, x| if let Process::Telegraph(t) = b { t.reverse_rate = x } },
    KeyInfo { dotted: "model.stribeck_velocity", unit: " (m/s)", range: (1e-9, 1e6), used_by: "stribeck", apply: |p, _, _, x| if let Law::Stribeck(s) = &mut p.law { s.velocity = x } },
    KeyInfo { dotted: "model.stribeck_exponent", unit: "", range: (0.3, 20.0), used_by: "stribeck", apply: |p, _, _, x| if let Law::Stribeck(s) = &mut p.law { s.exponent = x } },
    KeyInfo { dotted: "model.viscous_friction", unit: " (N·s/m)", range: (0.0, 1e9), used_by: "", apply: |p, _, _, x| p.viscous = x },
    KeyInfo { dotted: "anchor.speed", unit: " (m/s)", range: (-1e6, 1e6), used_by: "constant anchor", apply: |_, _, a, x| if let Process::Constant(u) = a { *u = x } },
];

impl Key {
    /// Every key, in [`KEYS`] order.
    pub const ALL: [Key; 14] = [
        Key::Mass,
        Key::Stiffness,
        Key::Damping,
        Key::NormalForce,
        Key::Kinetic,
        Key::Static,
        Key::Speed,
        Key::SwitchRate,
        Key::ReverseSpeed,
        Key::ReverseSwitchRate,
        Key::StribeckVelocity,
        Key::StribeckExponent,
        Key::Viscous,
        Key::AnchorSpeed,
    ];

    /// Its row of [`KEYS`].
    pub fn info(self) -> &'static KeyInfo {
        &KEYS[self as usize]
    }

    /// The key as written, e.g. `model.friction_coefficient`.
    pub fn dotted(self) -> &'static str {
        self.info().dotted
    }

    /// Its last component: the hive name of a swept key, the column of a random one.
    pub fn name(self) -> &'static str {
        if self == Key::AnchorSpeed {
            // (`speed` is the belt's)
            return "anchor_speed";
        }
        let d = self.dotted();
        &d[d.find('.').map_or(0, |i| i + 1)..]
    }

    /// The range in which the solvers are proven to work ([`KeyInfo::range`]).
    pub fn range(self) -> (f64, f64) {
        self.info().range
    }

    /// The unit, for messages.
    pub fn unit(self) -> &'static str {
        self.info().unit
    }

    /// The sub-stream purpose of this key's draws (0 is the initial conditions and the belt).
    fn purpose(self) -> u64 {
        1 + self as u64
    }
}

/// A distribution of a random key.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "dist", rename_all = "lowercase", deny_unknown_fields)]
pub enum Dist {
    /// `uniform`: `low + (high − low) U`.
    Uniform {
        /// lower end, in the key's unit
        low: f64,
        /// upper end, in the key's unit (≥ `low`)
        high: f64,
    },
    /// `normal`, truncated to the key's range.
    Normal {
        /// mean before truncation, in the key's unit
        mean: f64,
        /// standard deviation before truncation, in the key's unit (> 0)
        sd: f64,
    },
    /// `lognormal`, given by its mean and coefficient of variation.
    Lognormal {
        /// mean, in the key's unit (> 0)
        mean: f64,
        /// coefficient of variation, sd/mean (> 0)
        cv: f64,
    },
    /// `gamma`, given by its mean and coefficient of variation.
    Gamma {
        /// mean, in the key's unit (> 0)
        mean: f64,
        /// coefficient of variation, sd/mean (> 0)
        cv: f64,
    },
}

impl Dist {
    /// Its own parameters' checks (the key's range is checked against [`Dist::support`]).
    pub fn check(&self) -> Result<(), String> {
        let fin = |x: f64| x.is_finite();
        match *self {
            Dist::Uniform { low, high } if !(fin(low) && fin(high) && low <= high && fin(high - low)) => Err("uniform needs finite low <= high".into()),
            Dist::Normal { mean, sd } if !(fin(mean) && fin(sd) && sd > 0.0) => Err("normal needs a finite mean and sd > 0".into()),
            Dist::Lognormal { mean, cv } | Dist::Gamma { mean, cv } if !(fin(mean) && mean > 0.0 && fin(cv) && cv > 0.0) => {
                Err("lognormal and gamma need mean > 0 and cv > 0".into())
            }
            _ => Ok(()),
        }
    }

    /// The smallest and largest value it can draw (before any truncation).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Dist::Uniform { low, high } => (low, high),
            Dist::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Dist::Lognormal { .. } | Dist::Gamma { .. } => (0.0, f64::INFINITY),
        }
    }

    /// Whether it is truncated to the key's range by design (normal).
    pub fn truncated(&self) -> bool {
        matches!(self, Dist::Normal { .. })
    }

    /// The least share of the law that must lie in the key's range: a draw outside the range is
    /// drawn again (exact sampling of the law truncated to the range), which for a normal is its
    /// documented use (at least half kept), and for lognormal and gamma may only trim tails the
    /// solvers are not proven on (at least 99 % kept). A law mostly outside is refused, never
    /// silently replaced.
    pub fn min_share(&self) -> f64 {
        if self.truncated() {
            0.5
        } else {
            0.99
        }
    }

    /// The probability that one draw lies in `[lo, hi]` (exact: Φ for normal and lognormal,
    /// the regularized incomplete gamma for gamma).
    pub fn share_in(&self, (lo, hi): (f64, f64)) -> f64 {
        use crate::special::{gamma_p, normal_cdf};
        // Φ(b) − Φ(a), a ≤ b, taken in the tail it lies in (no cancellation above the mean)
        let between = |a: f64, b: f64| if a > 0.0 { normal_cdf(-a) - normal_cdf(-b) } else { normal_cdf(b) - normal_cdf(a) };
        let p = match *self {
            Dist::Uniform { low, high } if high > low => ((hi.min(high) - lo.max(low)) / (high - low)).max(0.0),
            Dist::Uniform { low, .. } => f64::from(u8::from(low >= lo && low <= hi)),
            Dist::Normal { mean, sd } => between((lo - mean) / sd, (hi - mean) / sd),
            // below cv = 1e-150, cv² underflows: the law is a point mass at the mean in f64
            Dist::Lognormal { mean, .. } | Dist::Gamma { mean, .. } if self.point_mass() => f64::from(u8::from(mean >= lo && mean <= hi)),
            Dist::Lognormal { mean, cv } => {
                // ln X ~ N(μ, σ²), σ² = ln(1 + cv²) (written to stay finite for any finite cv)
                let s2 = if cv < 1e150 { (cv * cv).ln_1p() } else { 2.0 * cv.ln() };
                let mu = mean.ln() - 0.5 * s2;
                let z = |x: f64| if x > 0.0 { (x.ln() - mu) / s2.sqrt() } else { f64::NEG_INFINITY };
                between(z(lo), z(hi))
            }
            Dist::Gamma { mean, cv } => {
                let (shape, scale) = (1.0 / (cv * cv), mean * cv * cv);
                gamma_p(shape, hi / scale) - gamma_p(shape, lo / scale)
            }
        };
        p.clamp(0.0, 1.0)
    }

    /// A lognormal or gamma law whose spread is below f64's resolution (cv < 1e-150, where cv²
    /// underflows: a gamma's shape 1/cv² is infinite, a lognormal's σ is 0): every draw is the mean.
    fn point_mass(&self) -> bool {
        matches!(*self, Dist::Lognormal { cv, .. } | Dist::Gamma { cv, .. } if cv < 1e-150)
    }

    /// The mean (of the untruncated law).
    pub fn mean(&self) -> f64 {
        match *self {
            Dist::Uniform { low, high } => low + 0.5 * (high - low),
            Dist::Normal { mean, .. } | Dist::Lognormal { mean, .. } | Dist::Gamma { mean, .. } => mean,
        }
    }

    /// One draw of the law truncated to `[lo, hi]`, by rejection (exact; the door has checked
    /// that the range holds at least [`Dist::min_share`] of the law). `None` only if 10,000
    /// draws in a row fell outside — a probability below 1e-3000 for a law the door accepted;
    /// never a value the law did not produce.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R, (lo, hi): (f64, f64)) -> Option<f64> {
        (0..10_000).map(|_| self.raw(rng)).find(|&x| x >= lo && x <= hi)
    }

    fn raw<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match *self {
            Dist::Uniform { low, high } => low + (high - low) * unit_f64(rng),
            Dist::Normal { mean, sd } => {
                let z: f64 = StandardNormal.sample(rng);
                mean + sd * z
            }
            Dist::Lognormal { mean, cv } => {
                let s2 = cv.mul_add(cv, 1.0).ln();
                let z: f64 = StandardNormal.sample(rng);
                (mean.ln() - 0.5 * s2 + s2.sqrt() * z).exp()
            }
            Dist::Gamma { mean, .. } if self.point_mass() => mean,
            Dist::Gamma { mean, cv } => {
                let shape = 1.0 / (cv * cv);
                Gamma::new(shape, mean * cv * cv).expect("checked gamma parameters").sample(rng)
            }
        }
    }
}

/// A chain scene's masses, springs and dashpots ([`crate::chain`]) and its anchor's process
/// (drawn like a belt, from its own sub-stream).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainScene {
    /// m_i [kg]
    pub masses: Vec<f64>,
    /// k_i [N/m]
    pub stiffnesses: Vec<f64>,
    /// c_i [N·s/m]
    pub dampings: Vec<f64>,
    /// u(t): the anchor's velocity process on [0, t_a]
    pub anchor: Belt,
    /// the one mass of `[model]` under a moving anchor: its mass, stiffness and damping are
    /// each realization's (drawn) `params`, not the lists
    pub from_model: bool,
}

/// The scene every realization is drawn from: the fixed values, the random keys, the belt.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Fixed parameters (a random key holds its distribution's mean here).
    pub params: Params,
    /// The belt (a random belt key holds its distribution's mean here).
    pub belt: Belt,
    /// The random keys in [`Key::ALL`] order.
    pub random: Vec<(Key, Dist)>,
    /// μ_s is absent: it equals each realization's μ_k.
    static_follows_kinetic: bool,
    /// A chain of masses with its anchor (None: the one mass of `params`; its friction is
    /// `params`' either way).
    pub chain: Option<ChainScene>,
}

impl Scene {
    /// `static_follows_kinetic`: the scenario gives no μ_s, so each realization's μ_s is its μ_k.
    pub fn new(params: Params, belt: Belt, random: Vec<(Key, Dist)>, static_follows_kinetic: bool) -> Scene {
        Scene { params, belt, random, static_follows_kinetic, chain: None }
    }

    /// The scene with a chain in place of the one mass.
    pub fn with_chain(self, chain: ChainScene) -> Scene {
        Scene { chain: Some(chain), ..self }
    }

    /// Whether a slip's damping (the dashpot or the viscous friction) can be nonzero (the exact
    /// method then uses the damped forms).
    pub fn damped(&self) -> bool {
        self.params.damping != 0.0 || self.params.viscous != 0.0 || self.random.iter().any(|(k, _)| matches!(k, Key::Damping | Key::Viscous))
    }

    /// The column names of the drawn keys.
    pub fn columns(&self) -> Vec<&'static str> {
        self.random.iter().map(|(k, _)| k.name()).collect()
    }

    /// Draw the random keys into `params` (reset to the fixed scene first), `values` (in
    /// [`Scene::columns`] order) and the belt it returns: key j from its sub-stream of
    /// realization `index(j)` (one index for all in a plain run; a pick-freeze design mixes them).
    /// `Err(key)`: the key's law put 10,000 draws in a row outside its range (see [`Dist::sample`]).
    /// The anchor's process drawn too (a chain's) is the belt's second member.
    pub fn draw(&self, seed: u64, index: impl Fn(usize) -> u64, params: &mut Params, values: &mut Vec<f64>) -> Result<(Belt, Option<Belt>), Key> {
        *params = self.params;
        let mut belt = self.belt.clone();
        let mut anchor = self.chain.as_ref().map(|c| c.anchor.clone());
        let mut still = Process::Constant(0.0);
        values.clear();
        for (j, &(key, dist)) in self.random.iter().enumerate() {
            let x = dist.sample(&mut substream(seed, index(j), key.purpose()), key.range()).ok_or(key)?;
            values.push(x);
            (key.info().apply)(params, &mut belt.process, anchor.as_mut().map_or(&mut still, |a| &mut a.process), x);
            if key == Key::Kinetic && self.static_follows_kinetic {
                params.static_ = x;
            }
        }
        Ok((belt, anchor))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::rng::realization_rng;

    #[test]
    fn moments_of_the_distributions() {
        let n = 200_000;
        for d in [
            Dist::Uniform { low: 0.3, high: 0.7 },
            Dist::Lognormal { mean: 2.0, cv: 0.5 },
            Dist::Gamma { mean: 2.0, cv: 0.5 },
            Dist::Normal { mean: 5.0, sd: 0.5 },
        ] {
            let mut r = realization_rng(9, 1);
            let xs: Vec<f64> = (0..n).map(|_| d.sample(&mut r, (0.0, 1e9)).unwrap()).collect();
            let m = xs.iter().sum::<f64>() / n as f64;
            let sd = (xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1) as f64).sqrt();
            let (want_m, want_sd) = match d {
                Dist::Uniform { low, high } => (0.5 * (low + high), (high - low) / 12f64.sqrt()),
                Dist::Normal { mean, sd } => (mean, sd),
                Dist::Lognormal { mean, cv } | Dist::Gamma { mean, cv } => (mean, mean * cv),
            };
            // 5 standard errors of the mean; 2 % on the sd
            assert!((m - want_m).abs() < 5.0 * want_sd / (n as f64).sqrt(), "{d:?}: mean {m}");
            assert!((sd / want_sd - 1.0).abs() < 0.02, "{d:?}: sd {sd}");
        }
    }

    #[test]
    fn truncated_normal_stays_in_range() {
        let d = Dist::Normal { mean: 0.1, sd: 1.0 };
        let mut r = realization_rng(1, 2);
        assert!((0..10_000).all(|_| d.sample(&mut r, (1e-6, 1e6)).unwrap() >= 1e-6));
    }

    #[test]
    fn share_in_range_against_sampling() {
        // the exact share of each law in a range, against the fraction of 200,000 raw draws
        let n = 200_000;
        for (d, range) in [
            (Dist::Normal { mean: 0.1, sd: 1.0 }, (0.0, 1e9)),
            (Dist::Normal { mean: 1.0, sd: 2.0 }, (0.5, 3.0)),
            (Dist::Lognormal { mean: 1.0, cv: 3.0 }, (0.05, 4.0)),
            (Dist::Gamma { mean: 1.0, cv: 2.0 }, (1e-3, 2.0)),
            (Dist::Gamma { mean: 2.0, cv: 0.5 }, (1.0, 3.0)),
            (Dist::Uniform { low: -1.0, high: 3.0 }, (0.0, 1e9)),
        ] {
            let mut r = realization_rng(3, 4);
            let inside = (0..n).filter(|_| (range.0..=range.1).contains(&d.raw(&mut r))).count() as f64 / n as f64;
            let p = d.share_in(range);
            assert!((inside - p).abs() < 5.0 * (p * (1.0 - p) / n as f64).sqrt() + 1e-12, "{d:?} in {range:?}: {inside} vs {p}");
        }
        // the laws: almost nothing of them lies in the key's range
        assert!(Dist::Gamma { mean: 1.0, cv: 1e4 }.share_in(Key::Mass.range()) < 0.5);
        assert!(Dist::Lognormal { mean: 1.0, cv: 1e200 }.share_in(Key::Mass.range()) < 0.5);
        assert!(Dist::Gamma { mean: 1.0, cv: 1e5 }.share_in(Key::Speed.range()) < 0.5);
    }
}
