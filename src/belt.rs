//! The belt: a random process that yields piecewise-constant velocity segments `(t, v)`.
//!
//! Two processes, one output ([`BeltPath`]: the initial sign and the switch instants); no solver
//! knows which one made the segments ([`BeltPath::segments`]).
//!
//! - [`Symmetric`], the paper's belt (Lima & Sampaio, section 3, "three-step procedure" on
//!   [0, t_a]): Q ~ Poisson(λ t_a) sign changes at Q iid Uniform(0, t_a) instants, sorted; the
//!   velocity is ±v0.
//! - [`Telegraph`], a two-state Markov chain: +v_f in the forward state, left at rate λ_f;
//!   −v_r in the reverse state, left at rate λ_r; exponential holding times
//!   `−ln(1 − U)/λ` drawn in order until t_a (a rate of 0 holds the state to the end).
//!
//! Both start per `belt.initial_sign` (±1, or ±1 with probability ½ each, one 64-bit word). With
//! v_r = v_f and λ_r = λ_f the scenario builds the symmetric belt, drawn by the paper's three
//! steps, so its realizations are the paper's.

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

impl InitialSign {
    fn draw<R: Rng + ?Sized>(self, rng: &mut R) -> f64 {
        match self {
            InitialSign::Positive => 1.0,
            InitialSign::Negative => -1.0,
            InitialSign::Random => {
                if rng.next_u64() >> 63 == 0 {
                    1.0
                } else {
                    -1.0
                }
            }
        }
    }
}

/// The paper's symmetric belt: ±`speed` [m/s], `switch_rate` λ [1/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Symmetric {
    pub speed: f64,
    pub switch_rate: f64,
}

/// The asymmetric two-state telegraph belt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Telegraph {
    /// v_f, m/s (> 0)
    pub forward_speed: f64,
    /// λ_f, 1/s (≥ 0): rate of leaving the forward state
    pub forward_rate: f64,
    /// v_r, m/s (> 0)
    pub reverse_speed: f64,
    /// λ_r, 1/s (≥ 0): rate of leaving the reverse state
    pub reverse_rate: f64,
}

/// A belt process.
pub trait BeltProcess {
    /// Draw the switch instants on [0, `duration`] into `path.switch_times` (the initial sign is
    /// already in `path`).
    fn switches_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath);
    /// The belt velocities in the forward and the reverse state, `(v_f, v_r)` (both > 0).
    fn speeds(&self) -> (f64, f64);
    /// The largest expected number of switches per unit time.
    fn max_rate(&self) -> f64;
}

impl BeltProcess for Symmetric {
    /// The paper's steps 1–3 (rand_distr's Poisson, then Q 53-bit uniforms, sorted).
    fn switches_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath) {
        let mean = self.switch_rate * duration;
        if mean > 0.0 {
            // The scenario validation bounds λ t_a, so the cast is exact.
            let q = Poisson::new(mean).expect("validated λ t_a").sample(rng) as usize;
            path.switch_times.extend((0..q).map(|_| unit_f64(rng) * duration));
            // The instants are ≥ 0, and non-negative doubles order like their bit patterns.
            path.switch_times.sort_unstable_by_key(|t| t.to_bits());
        }
    }

    fn speeds(&self) -> (f64, f64) {
        (self.speed, self.speed)
    }

    fn max_rate(&self) -> f64 {
        self.switch_rate
    }
}

impl BeltProcess for Telegraph {
    fn switches_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath) {
        let (mut sign, mut t) = (path.initial_sign, 0.0);
        loop {
            let rate = if sign > 0.0 { self.forward_rate } else { self.reverse_rate };
            if !(rate > 0.0) {
                return;
            }
            t += -(-unit_f64(rng)).ln_1p() / rate;
            if !(t < duration) {
                return;
            }
            path.switch_times.push(t);
            sign = -sign;
        }
    }

    fn speeds(&self) -> (f64, f64) {
        (self.forward_speed, self.reverse_speed)
    }

    fn max_rate(&self) -> f64 {
        self.forward_rate.max(self.reverse_rate)
    }
}

/// The belt of a scenario: its process, its initial sign and the window t_a [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Belt {
    pub process: Process,
    pub initial_sign: InitialSign,
    pub duration: f64,
}

/// Which process (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Process {
    Symmetric(Symmetric),
    Telegraph(Telegraph),
}

impl Belt {
    /// Draw a belt path, reusing `path`'s buffer. Draw order (fixed, part of the reproducibility
    /// contract): the initial sign (only when `Random`: one 64-bit word), then the process's draws.
    pub fn sample_into<R: Rng + ?Sized>(&self, rng: &mut R, path: &mut BeltPath) {
        path.initial_sign = self.initial_sign.draw(rng);
        path.switch_times.clear();
        match &self.process {
            Process::Symmetric(p) => p.switches_into(rng, self.duration, path),
            Process::Telegraph(p) => p.switches_into(rng, self.duration, path),
        }
    }

    /// `(v_f, v_r)`.
    pub fn speeds(&self) -> (f64, f64) {
        match &self.process {
            Process::Symmetric(p) => p.speeds(),
            Process::Telegraph(p) => p.speeds(),
        }
    }

    /// Expected switches per realization at the faster rate.
    pub fn expected_switches(&self) -> f64 {
        let rate = match &self.process {
            Process::Symmetric(p) => p.max_rate(),
            Process::Telegraph(p) => p.max_rate(),
        };
        rate * self.duration
    }
}

/// One realization of the belt on [0, t_a], as drawn.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BeltPath {
    /// Sign of the belt velocity at t = 0⁺ (before any switch at t = 0 is applied), ±1.
    pub initial_sign: f64,
    /// Y_1 ≤ … ≤ Y_Q, the sorted switch instants as drawn (Q = `switch_times.len()`).
    pub switch_times: Vec<f64>,
}

impl BeltPath {
    /// The velocity segments a solver sees: the switch instants in (0, t_a) with a switch at
    /// exactly t = 0 folded into the initial state and coincident pairs removed (they cancel),
    /// into `switches`; the velocity of each of the `switches.len() + 1` segments into
    /// `velocities` (+v_f in the forward state, −v_r in the reverse one).
    pub fn segments(&self, (forward, reverse): (f64, f64), switches: &mut Vec<f64>, velocities: &mut Vec<f64>) {
        switches.clear();
        velocities.clear();
        let mut sign = self.initial_sign;
        for &t in &self.switch_times {
            if t <= 0.0 {
                sign = -sign;
            } else if switches.last() == Some(&t) {
                switches.pop();
            } else {
                switches.push(t);
            }
        }
        let (v0, v1) = if sign > 0.0 { (forward, -reverse) } else { (-reverse, forward) };
        velocities.extend((0..=switches.len()).map(|k| if k % 2 == 0 { v0 } else { v1 }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::realization_rng;

    #[test]
    fn coincident_and_initial_switches_are_folded() {
        let p = BeltPath { initial_sign: 1.0, switch_times: vec![0.0, 1.0, 2.0, 2.0, 2.0, 3.0] };
        let (mut sw, mut v) = (Vec::new(), Vec::new());
        p.segments((1.0, 0.5), &mut sw, &mut v);
        assert_eq!(sw, vec![1.0, 2.0, 3.0]);
        assert_eq!(v, vec![-0.5, 1.0, -0.5, 1.0]);
    }

    #[test]
    fn telegraph_time_fractions_match_the_stationary_law() {
        // Long window: the fraction of time forward tends to λ_r/(λ_f + λ_r).
        let belt = Belt {
            process: Process::Telegraph(Telegraph { forward_speed: 1.0, forward_rate: 1.0, reverse_speed: 0.5, reverse_rate: 3.0 }),
            initial_sign: InitialSign::Positive,
            duration: 20_000.0,
        };
        let mut path = BeltPath::default();
        belt.sample_into(&mut realization_rng(3, 0), &mut path);
        let mut edges = vec![0.0];
        edges.extend(&path.switch_times);
        edges.push(belt.duration);
        let forward: f64 = edges.windows(2).step_by(2).map(|w| w[1] - w[0]).sum();
        let frac = forward / belt.duration;
        // ~7,500 cycles: the standard error of the fraction is below 0.005
        assert!((frac - 0.75).abs() < 0.02, "forward fraction {frac}");
    }
}
