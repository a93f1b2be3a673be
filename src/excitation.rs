//! The stochastic belt: a bang-bang velocity ±v0 whose sign flips at random instants.
//!
//! Lima & Sampaio, section 3, "three-step procedure" on the analysis window [0, t_a]:
//! 1. draw the number of sign changes Q ~ Poisson(λ t_a);
//! 2. draw Q iid instants P_1..P_Q ~ Uniform(0, t_a);
//! 3. sort them into Y_1 ≤ … ≤ Y_Q.
//!
//! λ = 0 gives a constant belt. Two flips at the same instant cancel, and a flip at t = 0 only
//! changes the initial sign: [`BeltPath::effective_switches`] folds both so that no solver ever
//! sees a zero-length belt segment. The raw draw (`Y`, `Q`) is kept for the dataset.

use rand::Rng;
use rand_distr::{Distribution, Poisson};

use crate::rng::unit_f64;

/// Initial belt direction of a scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitialSign {
    Positive,
    Negative,
    /// ±1 with probability ½ each, drawn per realization.
    Random,
}

/// The belt law of a scenario: speed v0 [m/s], switch rate λ [1/s], window t_a [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Belt {
    pub speed: f64,
    pub switch_rate: f64,
    pub initial_sign: InitialSign,
    pub duration: f64,
}

/// One realization of the belt velocity on [0, t_a].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BeltPath {
    /// Sign of the belt velocity at t = 0⁺ (before any flip at t = 0 is applied), ±1.
    pub initial_sign: f64,
    /// Y_1 ≤ … ≤ Y_Q, the sorted flip instants as drawn (Q = `switch_times.len()`).
    pub switch_times: Vec<f64>,
}

impl Belt {
    /// Draw a belt path with the paper's three-step procedure, reusing `path`'s buffer.
    ///
    /// Draw order (fixed, part of the reproducibility contract): initial sign (only when
    /// `Random`: one 64-bit word), Q (rand_distr's Poisson), then the Q instants.
    pub fn sample_into<R: Rng + ?Sized>(&self, rng: &mut R, path: &mut BeltPath) {
        path.initial_sign = match self.initial_sign {
            InitialSign::Positive => 1.0,
            InitialSign::Negative => -1.0,
            InitialSign::Random => {
                if rng.next_u64() >> 63 == 0 {
                    1.0
                } else {
                    -1.0
                }
            }
        };
        path.switch_times.clear();
        let mean = self.switch_rate * self.duration;
        if mean > 0.0 {
            // The scenario validation bounds λ t_a, so the cast is exact.
            let q = Poisson::new(mean).expect("validated λ t_a").sample(rng) as usize;
            path.switch_times.extend((0..q).map(|_| unit_f64(rng) * self.duration));
            // The instants are ≥ 0, and non-negative doubles order like their bit patterns.
            path.switch_times.sort_unstable_by_key(|t| t.to_bits());
        }
    }
}

impl BeltPath {
    /// Sign at t = 0⁺ after folding flips at exactly t = 0, and the flip instants in (0, t_a)
    /// with coincident pairs removed (they cancel), written into `out`.
    pub fn effective_switches(&self, out: &mut Vec<f64>) -> f64 {
        out.clear();
        let mut sign = self.initial_sign;
        for &t in &self.switch_times {
            if t <= 0.0 {
                sign = -sign;
            } else if out.last() == Some(&t) {
                out.pop();
            } else {
                out.push(t);
            }
        }
        sign
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coincident_and_initial_flips_are_folded() {
        let p = BeltPath { initial_sign: 1.0, switch_times: vec![0.0, 1.0, 2.0, 2.0, 2.0, 3.0] };
        let mut out = Vec::new();
        assert_eq!(p.effective_switches(&mut out), -1.0);
        assert_eq!(out, vec![1.0, 2.0, 3.0]);
    }
}
