//! The belt: a random process that yields piecewise-constant velocity segments `(t, v)`.
//!
//! Every process has one output, [`BeltPath`]: the velocity at t = 0⁺ and the instants of the
//! velocity changes with the velocity after each; no solver knows which process made the
//! segments ([`BeltPath::segments`]). A new process is a new variant of [`Process`] here, its
//! draws and its answers ([`Process::scale`], [`Process::max_rate`]), and its keys in the
//! scenario (`belt.process`).
//!
//! - [`Symmetric`] (`"symmetric"`, the paper's belt; Lima & Sampaio, section 3, "three-step
//!   procedure" on [0, t_a]): Q ~ Poisson(λ t_a) sign changes at Q iid Uniform(0, t_a) instants,
//!   sorted; the velocity is ±v0.
//! - [`Telegraph`] (`"telegraph"`), a two-state Markov chain: +v_f in the forward state, left at
//!   rate λ_f; −v_r in the reverse state, left at rate λ_r; exponential holding times
//!   `−ln(1 − U)/λ` drawn in order until t_a (a rate of 0 holds the state to the end).
//! - [`Markov`] (`"markov"`), a continuous-time Markov chain on n velocity levels v_1 … v_n
//!   (any signs, 0 allowed: a rotary table that stops) with transition rates r_ij [1/s]: the
//!   initial level drawn from the chain's stationary law π (π Q = 0, Σ π = 1, unique: the
//!   scenario refuses a chain with more than one closed class), then in level i an exponential
//!   holding time of rate q_i = Σ_{j≠i} r_ij and the next level j with probability r_ij/q_i. A
//!   jump between two levels of equal velocity is not a velocity change and is not recorded.
//! - [`Recorded`] (`"recorded"`): a measured velocity log, `(time, velocity)` rows held until
//!   the next time, the last to t_a; nothing is drawn.
//!
//! The symmetric and telegraph belts start per `belt.initial_sign` (±1, or ±1 with probability
//! ½ each, one 64-bit word). With v_r = v_f and λ_r = λ_f the scenario builds the symmetric belt,
//! drawn by the paper's three steps, so its realizations are the paper's.

use std::sync::Arc;

use rand::Rng;
use rand_distr::{Distribution, Poisson};

use crate::simulation::rng::unit_f64;

mod markov;

/// Initial belt direction of a symmetric or telegraph belt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitialSign {
    /// +1: the belt starts forward.
    Positive,
    /// −1: the belt starts in reverse.
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
    /// v0, m/s (> 0): the belt moves at ±v0
    pub speed: f64,
    /// λ, 1/s (≥ 0): the rate of the sign changes
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

pub use markov::{Markov, MAX_LEVELS};

/// A recorded belt: the velocity `velocities[i]` [m/s] from `times[i]` [s] to the next time
/// (`times[0] = 0`, increasing), the last to the end of the window.
#[derive(Debug, Clone, PartialEq)]
pub struct Recorded {
    times: Vec<f64>,
    velocities: Vec<f64>,
}

impl Recorded {
    /// `Err` names the first bad row (1-based, as a user counts the data rows).
    pub fn new(times: Vec<f64>, velocities: Vec<f64>) -> Result<Recorded, String> {
        if times.is_empty() || times.len() != velocities.len() {
            return Err("needs at least one (time, velocity) row".into());
        }
        if times[0] != 0.0 {
            return Err(format!("the first time must be 0 (s), is {}", times[0]));
        }
        for (i, (t, v)) in times.iter().zip(&velocities).enumerate() {
            if !t.is_finite() || (i > 0 && !(*t > times[i - 1])) {
                return Err(format!("row {}: time {t} must be finite and greater than the previous time", i + 1));
            }
            if !(v.is_finite() && v.abs() <= MAX_SPEED) {
                return Err(format!("row {}: velocity {v} must be finite and at most {MAX_SPEED:e} m/s in size", i + 1));
            }
        }
        Ok(Recorded { times, velocities })
    }

    /// The rows `(time, velocity)`.
    pub fn rows(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.times.iter().copied().zip(self.velocities.iter().copied())
    }

    fn draw_into(&self, duration: f64, path: &mut BeltPath) {
        path.initial_velocity = self.velocities[0];
        for (t, v) in self.rows().skip(1).take_while(|(t, _)| *t < duration) {
            path.switch_times.push(t);
            path.velocities.push(v);
        }
    }
}

/// The largest belt speed a process may have, m/s (the range of `belt.speed`).
pub const MAX_SPEED: f64 = 1e6;

/// The smallest nonzero belt speed, and the smallest speed scale ([`Process::scale`]), m/s (the
/// lower end of `belt.speed`): a level of 1e-320 m/s would put the severity's unit in the
/// subnormals and the severity at ∞.
pub const MIN_SPEED: f64 = 1e-9;

/// The belt of a scenario: its process, its initial sign (symmetric and telegraph belts) and the
/// window t_a [s].
#[derive(Debug, Clone, PartialEq)]
pub struct Belt {
    /// the random process of the belt velocity
    pub process: Process,
    /// the initial direction (symmetric and telegraph belts only)
    pub initial_sign: InitialSign,
    /// t_a, the observation window [s]
    pub duration: f64,
}

/// Which process (see the module docs). The chains' tables are shared, not copied, per
/// realization.
#[derive(Debug, Clone, PartialEq)]
pub enum Process {
    /// The paper's belt ([`Symmetric`]).
    Symmetric(Symmetric),
    /// The asymmetric two-state belt ([`Telegraph`]).
    Telegraph(Telegraph),
    /// The multi-level Markov belt ([`Markov`]).
    Markov(Arc<Markov>),
    /// A measured velocity log ([`Recorded`]).
    Recorded(Arc<Recorded>),
    /// One velocity throughout (`"constant"`; 0: the rock under a drill bit); nothing is drawn.
    Constant(f64),
}

/// A two-state flip belt (the symmetric and the telegraph belt): each state's velocity and
/// the rate at which the belt leaves it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoState {
    /// the forward state's speed v_f [m/s] (velocity +v_f)
    pub forward_speed: f64,
    /// the reverse state's speed v_r [m/s] (velocity −v_r)
    pub reverse_speed: f64,
    /// the rate of leaving the forward state λ_f [1/s]
    pub forward_rate: f64,
    /// the rate of leaving the reverse state λ_r [1/s]
    pub reverse_rate: f64,
}

impl Process {
    /// The two states of a two-state flip belt — the symmetric belt is the telegraph with equal
    /// states — or None for a belt of another kind (Markov, recorded). The one answer every
    /// caller asks (the exact law, the conditional estimator of the tails, predict).
    pub fn two_state(&self) -> Option<TwoState> {
        match self {
            Process::Symmetric(s) => {
                Some(TwoState { forward_speed: s.speed, reverse_speed: s.speed, forward_rate: s.switch_rate, reverse_rate: s.switch_rate })
            }
            Process::Telegraph(t) => {
                Some(TwoState { forward_speed: t.forward_speed, reverse_speed: t.reverse_speed, forward_rate: t.forward_rate, reverse_rate: t.reverse_rate })
            }
            Process::Markov(_) | Process::Recorded(_) | Process::Constant(_) => None,
        }
    }

    /// Its name in a scenario (`belt.process`).
    pub fn name(&self) -> &'static str {
        match self {
            Process::Symmetric(_) => "symmetric",
            Process::Telegraph(_) => "telegraph",
            Process::Markov(_) => "markov",
            Process::Recorded(_) => "recorded",
            Process::Constant(_) => "constant",
        }
    }

    /// The belt's speed scale v0 [m/s] over the window [0, t_a] (`duration`), the unit of the
    /// severity: what the belt does in the window, whatever levels it could have but never takes.
    ///
    /// - symmetric belt: its speed (|v| = v0 throughout);
    /// - telegraph belt: its forward speed v_f (the nominal speed; the reverse is a perturbation);
    /// - Markov belt: the expected time average of |v| over the window, Σ_i π_i |v_i| — exact,
    ///   as the chain starts in its stationary law π and stays in it (a level π gives 0, one the
    ///   chain never enters, does not count);
    /// - recorded belt: the time average of |v| over [0, t_a], (1/t_a) Σ_i |v_i| (t_{i+1} ∧ t_a − t_i)
    ///   over the rows before t_a (a row after t_a does not count).
    ///
    /// Where every level that counts has the same |v| that |v| is the scale exactly (an average
    /// of a constant, with no rounding).
    pub fn scale(&self, duration: f64) -> f64 {
        // (weight, |v|) pairs → their weighted mean, exactly |v| when all |v| agree
        let mean = |pairs: &mut dyn Iterator<Item = (f64, f64)>| {
            let (mut total, mut weight, mut first, mut same) = (0.0, 0.0, None, true);
            for (w, v) in pairs.filter(|(w, _)| *w > 0.0) {
                same &= first.is_none_or(|f| f == v.abs());
                first.get_or_insert(v.abs());
                total += w * v.abs();
                weight += w;
            }
            match first {
                Some(f) if same => f,
                _ if weight > 0.0 => total / weight,
                _ => 0.0,
            }
        };
        match self {
            Process::Symmetric(p) => p.speed,
            Process::Telegraph(p) => p.forward_speed,
            Process::Markov(m) => mean(&mut m.stationary.iter().copied().zip(m.velocities.iter().copied())),
            Process::Constant(v) => v.abs(),
            Process::Recorded(r) => {
                let n = r.times.len();
                mean(
                    &mut (0..n)
                        .filter(|&i| r.times[i] < duration)
                        .map(|i| (r.times.get(i + 1).map_or(duration, |t| t.min(duration)) - r.times[i], r.velocities[i])),
                )
            }
        }
    }

    /// The largest |v| the belt can take in the window [0, t_a] (`duration`), m/s.
    pub fn top_speed(&self, duration: f64) -> f64 {
        let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
        match self {
            Process::Symmetric(p) => p.speed,
            Process::Telegraph(p) => p.forward_speed.max(p.reverse_speed),
            Process::Markov(m) => largest(&mut m.stationary.iter().zip(&m.velocities).filter(|(p, _)| **p > 0.0).map(|(_, v)| *v)),
            Process::Recorded(r) => largest(&mut r.rows().take_while(|(t, _)| *t < duration).map(|(_, v)| v)),
            Process::Constant(v) => v.abs(),
        }
    }

    /// The largest expected number of velocity changes per unit time (a record: its changes
    /// per unit time over the window, from `duration`).
    pub fn max_rate(&self, duration: f64) -> f64 {
        match self {
            Process::Symmetric(p) => p.switch_rate,
            Process::Telegraph(p) => p.forward_rate.max(p.reverse_rate),
            Process::Markov(m) => m.leave.iter().fold(0.0, |a: f64, &b| a.max(b)),
            Process::Recorded(r) => r.times.iter().filter(|t| **t < duration).count() as f64 / duration,
            Process::Constant(_) => 0.0,
        }
    }
}

impl Symmetric {
    /// The paper's steps 1–3 (rand_distr's Poisson, then Q 53-bit uniforms, sorted).
    fn draw_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath) {
        let mean = self.switch_rate * duration;
        if mean > 0.0 {
            // The scenario validation bounds λ t_a, so the cast is exact.
            let q = Poisson::new(mean).expect("validated λ t_a").sample(rng) as usize;
            path.switch_times.extend((0..q).map(|_| unit_f64(rng) * duration));
            // The instants are ≥ 0, and non-negative doubles order like their bit patterns.
            path.switch_times.sort_unstable_by_key(|t| t.to_bits());
        }
    }
}

impl Telegraph {
    fn draw_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath) {
        let mut t = 0.0;
        let mut forward = path.initial_velocity > 0.0;
        loop {
            let rate = if forward { self.forward_rate } else { self.reverse_rate };
            if !(rate > 0.0) {
                return;
            }
            t += -(-unit_f64(rng)).ln_1p() / rate;
            if !(t < duration) {
                return;
            }
            forward = !forward;
            path.switch_times.push(t);
        }
    }
}

impl Belt {
    /// Draw a belt path, reusing `path`'s buffers. Draw order (fixed, part of the reproducibility
    /// contract): for the symmetric and telegraph belts the initial sign (only when `Random`:
    /// one 64-bit word), then the process's draws.
    pub fn sample_into<R: Rng + ?Sized>(&self, rng: &mut R, path: &mut BeltPath) {
        path.switch_times.clear();
        path.velocities.clear();
        path.alternate = f64::NAN;
        match &self.process {
            Process::Symmetric(p) => {
                path.initial_velocity = self.initial_sign.draw(rng) * p.speed;
                path.alternate = -path.initial_velocity;
                p.draw_into(rng, self.duration, path)
            }
            Process::Telegraph(p) => {
                let sign = self.initial_sign.draw(rng);
                (path.initial_velocity, path.alternate) = if sign > 0.0 { (p.forward_speed, -p.reverse_speed) } else { (-p.reverse_speed, p.forward_speed) };
                p.draw_into(rng, self.duration, path)
            }
            Process::Markov(m) => m.draw_into(rng, self.duration, path),
            Process::Recorded(r) => r.draw_into(self.duration, path),
            Process::Constant(v) => path.initial_velocity = *v,
        }
    }

    /// The belt's speed scale over the window, m/s ([`Process::scale`]).
    pub fn scale(&self) -> f64 {
        self.process.scale(self.duration)
    }

    /// Expected velocity changes per realization at the fastest rate.
    pub fn expected_switches(&self) -> f64 {
        self.process.max_rate(self.duration) * self.duration
    }
}

/// One realization of the belt on [0, t_a], as drawn.
///
/// A two-state belt alternates between `initial_velocity` and `alternate` and lists nothing
/// (the symmetric belt's paper rows cost what they cost before belts with more levels existed);
/// any other lists the velocity after each change in `velocities`.
#[derive(Debug, Clone, PartialEq)]
pub struct BeltPath {
    /// The belt velocity at t = 0⁺ before any change at exactly t = 0, m/s.
    pub initial_velocity: f64,
    /// Y_1 ≤ … ≤ Y_Q, the instants of the velocity changes as drawn (Q = `switch_times.len()`).
    pub switch_times: Vec<f64>,
    /// The velocity after each change, m/s (Q values; empty for a two-state belt).
    pub velocities: Vec<f64>,
    /// The other velocity of a two-state belt, m/s (NaN otherwise).
    pub alternate: f64,
}

impl Default for BeltPath {
    fn default() -> BeltPath {
        BeltPath { initial_velocity: 0.0, switch_times: Vec::new(), velocities: Vec::new(), alternate: f64::NAN }
    }
}

impl BeltPath {
    /// A two-state belt starting at `initial`, flipping to `alternate` and back at `switch_times`.
    pub fn alternating(initial: f64, alternate: f64, switch_times: Vec<f64>) -> BeltPath {
        BeltPath { initial_velocity: initial, switch_times, velocities: Vec::new(), alternate }
    }

    /// A belt listing the velocity after each change.
    pub fn listed(initial: f64, switch_times: Vec<f64>, velocities: Vec<f64>) -> BeltPath {
        BeltPath { initial_velocity: initial, switch_times, velocities, alternate: f64::NAN }
    }

    /// The velocity after change k (0-based), m/s.
    pub fn velocity_after(&self, k: usize) -> f64 {
        if self.alternate.is_nan() {
            self.velocities[k]
        } else if k.is_multiple_of(2) {
            self.alternate
        } else {
            self.initial_velocity
        }
    }

    /// The sign of the initial velocity (the dataset's `initial_sign`: ±1, 0 for a belt at rest).
    pub fn initial_sign(&self) -> i32 {
        if self.initial_velocity > 0.0 {
            1
        } else if self.initial_velocity < 0.0 {
            -1
        } else {
            0
        }
    }

    /// The velocity segments a solver sees: the changes in (0, t_a), with changes at exactly
    /// t = 0 folded into the initial velocity and changes at one instant composed (the last
    /// velocity holds; none at all if it is the velocity before them, as two flips of the
    /// symmetric belt cancel), into `switches`; the velocity of each of the `switches.len() + 1`
    /// segments into `velocities`. Consecutive segments always differ in velocity.
    pub fn segments(&self, switches: &mut Vec<f64>, velocities: &mut Vec<f64>) {
        switches.clear();
        velocities.clear();
        if !self.alternate.is_nan() {
            // two states: every change flips, so coincident pairs cancel
            let (mut current, mut other) = (self.initial_velocity, self.alternate);
            for &t in &self.switch_times {
                if t <= 0.0 {
                    (current, other) = (other, current);
                } else if switches.last() == Some(&t) {
                    switches.pop();
                } else {
                    switches.push(t);
                }
            }
            velocities.extend((0..=switches.len()).map(|k| if k % 2 == 0 { current } else { other }));
            return;
        }
        velocities.push(self.initial_velocity);
        for (&t, &v) in self.switch_times.iter().zip(&self.velocities) {
            let n = velocities.len();
            if t <= 0.0 {
                velocities[0] = v;
            } else if switches.last() == Some(&t) {
                // a second change at the same instant: it replaces the first
                if velocities[n - 2] == v {
                    switches.pop();
                    velocities.pop();
                } else {
                    velocities[n - 1] = v;
                }
            } else if velocities[n - 1] != v {
                switches.push(t);
                velocities.push(v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::rng::realization_rng;

    #[test]
    fn coincident_and_initial_switches_are_folded() {
        // a telegraph belt (+1, −0.5) starting forward, flipped at 0, 1, three times at 2, and 3
        let times = vec![0.0, 1.0, 2.0, 2.0, 2.0, 3.0];
        let (mut sw, mut v) = (Vec::new(), Vec::new());
        // the two-state fold and the general one (the same changes listed) agree
        for p in [BeltPath::alternating(1.0, -0.5, times.clone()), BeltPath::listed(1.0, times.clone(), vec![-0.5, 1.0, -0.5, 1.0, -0.5, 1.0])] {
            p.segments(&mut sw, &mut v);
            assert_eq!(sw, vec![1.0, 2.0, 3.0]);
            assert_eq!(v, vec![-0.5, 1.0, -0.5, 1.0]);
        }
        // three levels: changes at one instant compose; a change back to the same velocity is none
        let p = BeltPath::listed(1.0, vec![1.0, 1.0, 2.0, 2.0], vec![0.0, -1.0, 0.0, -1.0]);
        p.segments(&mut sw, &mut v);
        assert_eq!((sw.as_slice(), v.as_slice()), (&[1.0][..], &[1.0, -1.0][..]));
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

    /// A chain stopping between the two directions: +1 → 0 at 2/s, 0 → ±1 at 1/s each, −1 → 0
    /// at 4/s. Balance (π Q = 0) by hand: 2 π₊ = π₀ = 4 π₋ → π = (2, 4, 1)/7.
    fn stopping_table() -> Markov {
        Markov::new(vec![1.0, 0.0, -1.0], vec![vec![0.0, 2.0, 0.0], vec![1.0, 0.0, 1.0], vec![0.0, 4.0, 0.0]]).unwrap()
    }

    #[test]
    fn markov_stationary_law_and_time_fractions() {
        let m = stopping_table();
        for (got, want) in m.stationary().iter().zip([2.0 / 7.0, 4.0 / 7.0, 1.0 / 7.0]) {
            assert!((got - want).abs() < 1e-15, "{:?}", m.stationary());
        }
        // one long path: the time at each level tends to π (about 14,000 holding times: the
        // standard errors of the fractions are below 0.006)
        let belt = Belt { process: Process::Markov(Arc::new(m)), initial_sign: InitialSign::Positive, duration: 20_000.0 };
        let mut path = BeltPath::default();
        belt.sample_into(&mut realization_rng(4, 0), &mut path);
        let (mut sw, mut v) = (Vec::new(), Vec::new());
        path.segments(&mut sw, &mut v);
        let mut edges = vec![0.0];
        edges.extend(&sw);
        edges.push(belt.duration);
        for (level, want) in [(1.0, 2.0 / 7.0), (0.0, 4.0 / 7.0), (-1.0, 1.0 / 7.0)] {
            let time: f64 = edges.windows(2).zip(&v).filter(|(_, x)| **x == level).map(|(w, _)| w[1] - w[0]).sum();
            assert!((time / belt.duration - want).abs() < 0.03, "level {level}: {} vs {want}", time / belt.duration);
        }
        // every change is a change of velocity, and the chain only steps through 0
        assert!(v.windows(2).all(|w| w[0] != w[1] && (w[0] == 0.0 || w[1] == 0.0)));
    }

    #[test]
    fn markov_chains_without_a_unique_stationary_law_are_refused() {
        // two absorbing levels
        let e = Markov::new(vec![1.0, 0.0, -1.0], vec![vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 1.0], vec![0.0, 0.0, 0.0]]).unwrap_err();
        assert!(e.contains("two closed classes"), "{e}");
        assert!(Markov::new(vec![1.0, 2.0], vec![vec![0.0, -1.0], vec![1.0, 0.0]]).unwrap_err().contains(">= 0"));
        assert!(Markov::new(vec![1.0, 2.0], vec![vec![0.0, 1.0]]).unwrap_err().contains("2×2"));
        // a transient level gets π = 0; one absorbing level has π = 1; one level is a constant belt
        let m = Markov::new(vec![1.0, -1.0], vec![vec![0.0, 3.0], vec![0.0, 0.0]]).unwrap();
        assert_eq!(m.stationary(), &[0.0, 1.0]);
        assert_eq!(Markov::new(vec![0.5], vec![vec![7.0]]).unwrap().stationary(), &[1.0]);
    }

    #[test]
    fn a_recorded_belt_holds_each_velocity_until_the_next_time() {
        let r = Recorded::new(vec![0.0, 1.0, 2.5, 20.0], vec![1.0, 0.0, -0.5, 2.0]).unwrap();
        let belt = Belt { process: Process::Recorded(Arc::new(r)), initial_sign: InitialSign::Positive, duration: 10.0 };
        let mut path = BeltPath::default();
        belt.sample_into(&mut realization_rng(1, 0), &mut path);
        assert_eq!((path.initial_velocity, path.switch_times.as_slice(), path.velocities.as_slice()), (1.0, &[1.0, 2.5][..], &[0.0, -0.5][..]));
        assert!(Recorded::new(vec![0.5], vec![1.0]).unwrap_err().contains("first time must be 0"));
        assert!(Recorded::new(vec![0.0, 1.0, 1.0], vec![1.0, 2.0, 3.0]).unwrap_err().contains("row 3"));
        assert!(Recorded::new(vec![0.0, 1.0], vec![1.0, f64::NAN]).unwrap_err().contains("row 2"));
    }
}
