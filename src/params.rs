//! Random parameters: any numeric `[model]` or `[belt]` key may be a distribution, drawn per
//! realization.
//!
//! Each random key draws from its own sub-stream of the realization's generator
//! ([`crate::rng::substream`], purpose = the key), never from the stream of the initial
//! conditions and the belt: making a key random does not shift the belt's draws (the same seed
//! keeps the same belt), and making a second key random does not shift the first one's.
//!
//! Distributions (rand_distr 0.6, pinned):
//! - `uniform (low, high)`: `low + (high − low) U`, U a 53-bit uniform on [0, 1);
//! - `normal (mean, sd)`: truncated to the key's valid range by rejection (the mean must lie in
//!   the range, so at most half the draws are rejected on average);
//! - `lognormal (mean, cv)`: `exp(μ + σ Z)` with `σ² = ln(1 + cv²)`, `μ = ln mean − σ²/2`;
//! - `gamma (mean, cv)`: shape `1/cv²`, scale `mean·cv²`.

use rand::Rng;
use rand_distr::{Distribution, Gamma, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::belt::{Belt, Process};
use crate::physics::Params;
use crate::rng::{substream, unit_f64};

/// The numeric scene keys (the ones that may be swept or random).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    Mass,
    Stiffness,
    Damping,
    NormalForce,
    Kinetic,
    Static,
    Speed,
    SwitchRate,
    ReverseSpeed,
    ReverseSwitchRate,
    StribeckVelocity,
    StribeckExponent,
}

impl Key {
    pub const ALL: [Key; 12] = [
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
    ];

    /// The key as written, e.g. `model.friction_coefficient`.
    pub fn dotted(self) -> &'static str {
        match self {
            Key::Mass => "model.mass",
            Key::Stiffness => "model.stiffness",
            Key::Damping => "model.damping",
            Key::NormalForce => "model.normal_force",
            Key::Kinetic => "model.friction_coefficient",
            Key::Static => "model.static_friction_coefficient",
            Key::Speed => "belt.speed",
            Key::SwitchRate => "belt.switch_rate",
            Key::ReverseSpeed => "belt.reverse_speed",
            Key::ReverseSwitchRate => "belt.reverse_switch_rate",
            Key::StribeckVelocity => "model.stribeck_velocity",
            Key::StribeckExponent => "model.stribeck_exponent",
        }
    }

    /// Its last component: the hive name of a swept key, the column of a random one.
    pub fn name(self) -> &'static str {
        let d = self.dotted();
        &d[d.find('.').map_or(0, |i| i + 1)..]
    }

    /// The valid range's lower end and whether it is excluded (every key is unbounded above).
    pub fn lower_bound(self) -> (f64, bool) {
        match self {
            Key::Mass | Key::Speed | Key::ReverseSpeed | Key::StribeckVelocity | Key::StribeckExponent => (0.0, true),
            _ => (0.0, false),
        }
    }

    /// The unit, for messages.
    pub fn unit(self) -> &'static str {
        match self {
            Key::Mass => " (kg)",
            Key::Stiffness => " (N/m)",
            Key::Damping => " (N·s/m)",
            Key::NormalForce => " (N)",
            Key::Kinetic | Key::Static | Key::StribeckExponent => "",
            Key::StribeckVelocity => " (m/s)",
            Key::Speed | Key::ReverseSpeed => " (m/s)",
            Key::SwitchRate | Key::ReverseSwitchRate => " (1/s)",
        }
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
    Uniform { low: f64, high: f64 },
    Normal { mean: f64, sd: f64 },
    Lognormal { mean: f64, cv: f64 },
    Gamma { mean: f64, cv: f64 },
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

    /// Whether the support's lower end is never drawn (lognormal and gamma draw > 0).
    pub fn open_at_low(&self) -> bool {
        matches!(self, Dist::Lognormal { .. } | Dist::Gamma { .. })
    }

    /// Whether it is truncated to the key's range (normal).
    pub fn truncated(&self) -> bool {
        matches!(self, Dist::Normal { .. })
    }

    /// The mean (of the untruncated law).
    pub fn mean(&self) -> f64 {
        match *self {
            Dist::Uniform { low, high } => low + 0.5 * (high - low),
            Dist::Normal { mean, .. } | Dist::Lognormal { mean, .. } | Dist::Gamma { mean, .. } => mean,
        }
    }

    /// One draw, inside the valid range `(lo, ∞)` (open) or `[lo, ∞)`: a draw outside it (the
    /// normal's truncation, or a lognormal or gamma draw that underflows to 0 at a huge cv) is
    /// drawn again.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R, (lo, open): (f64, bool)) -> f64 {
        let ok = |x: f64| x.is_finite() && if open { x > lo } else { x >= lo };
        for _ in 0..10_000 {
            let x = self.raw(rng);
            if ok(x) {
                return x;
            }
        }
        self.mean() // unreachable in practice: the mean lies in the range (checked)
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
            Dist::Gamma { mean, cv } => {
                let shape = 1.0 / (cv * cv);
                Gamma::new(shape, mean * cv * cv).expect("checked gamma parameters").sample(rng)
            }
        }
    }
}

/// The scene every realization is drawn from: the fixed values, the random keys, the belt.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Fixed parameters (a random key holds its distribution's mean here).
    pub params: Params,
    pub belt: Belt,
    /// The random keys in [`Key::ALL`] order.
    pub random: Vec<(Key, Dist)>,
    /// μ_s is absent: it equals each realization's μ_k.
    static_follows_kinetic: bool,
}

impl Scene {
    /// `static_follows_kinetic`: the scenario gives no μ_s, so each realization's μ_s is its μ_k.
    pub fn new(params: Params, belt: Belt, random: Vec<(Key, Dist)>, static_follows_kinetic: bool) -> Scene {
        Scene { params, belt, random, static_follows_kinetic }
    }

    /// Whether the damping can be nonzero (the exact method then uses the damped forms).
    pub fn damped(&self) -> bool {
        self.params.damping != 0.0 || self.random.iter().any(|(k, _)| *k == Key::Damping)
    }

    /// The column names of the drawn keys.
    pub fn columns(&self) -> Vec<&'static str> {
        self.random.iter().map(|(k, _)| k.name()).collect()
    }

    /// Draw the random keys into `params`, `belt` (reset to the fixed scene first) and `values`
    /// (in [`Scene::columns`] order): key j from its sub-stream of realization `index(j)` (one
    /// index for all in a plain run; a pick-freeze design mixes them).
    pub fn draw(&self, seed: u64, index: impl Fn(usize) -> u64, params: &mut Params, belt: &mut Belt, values: &mut Vec<f64>) {
        *params = self.params;
        *belt = self.belt;
        values.clear();
        for (j, &(key, dist)) in self.random.iter().enumerate() {
            let x = dist.sample(&mut substream(seed, index(j), key.purpose()), key.lower_bound());
            values.push(x);
            match (key, &mut belt.process) {
                (Key::Mass, _) => params.mass = x,
                (Key::Stiffness, _) => params.stiffness = x,
                (Key::Damping, _) => params.damping = x,
                (Key::NormalForce, _) => params.normal_force = x,
                (Key::Kinetic, _) => {
                    params.kinetic = x;
                    if self.static_follows_kinetic {
                        params.static_ = x;
                    }
                }
                (Key::Static, _) => params.static_ = x,
                (Key::StribeckVelocity, _) => params.stribeck.velocity = x,
                (Key::StribeckExponent, _) => params.stribeck.exponent = x,
                (Key::Speed, Process::Symmetric(p)) => p.speed = x,
                (Key::Speed, Process::Telegraph(p)) => p.forward_speed = x,
                (Key::SwitchRate, Process::Symmetric(p)) => p.switch_rate = x,
                (Key::SwitchRate, Process::Telegraph(p)) => p.forward_rate = x,
                (Key::ReverseSpeed, Process::Telegraph(p)) => p.reverse_speed = x,
                (Key::ReverseSwitchRate, Process::Telegraph(p)) => p.reverse_rate = x,
                (Key::ReverseSpeed | Key::ReverseSwitchRate, Process::Symmetric(_)) => {}
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::realization_rng;

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
            let xs: Vec<f64> = (0..n).map(|_| d.sample(&mut r, (0.0, false))).collect();
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
        assert!((0..10_000).all(|_| d.sample(&mut r, (0.0, true)) > 0.0));
    }
}
