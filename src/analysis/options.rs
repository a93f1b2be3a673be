//! How to analyse: the options of `analyze` ([`Options`]), their defaults and limits, and the
//! check that refuses options that cannot work before any input is read.

use std::str::FromStr;

use super::error::AnalysisError;
use super::tails;
use crate::observables::Observable;

/// A pair of observables for a joint histogram, written `A,B` (e.g. `T_1,T_2` or `D1,D2`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pair(pub Observable, pub Observable);

impl FromStr for Pair {
    type Err = String;
    fn from_str(s: &str) -> Result<Pair, String> {
        let (a, b) = s.split_once(',').ok_or_else(|| format!("--pair {s:?}: expected A,B, e.g. D1,D2"))?;
        Ok(Pair(a.parse()?, b.parse()?))
    }
}

/// How to analyse.
#[derive(Debug, Clone)]
pub struct Options {
    /// Largest event index k analysed for T_k, L_k, D_k, H_k (and Y_k).
    pub max_index: u32,
    /// Fixed number of histogram bins (default: Scott's rule, see [`super::density`]).
    pub bins: Option<usize>,
    /// Joint histograms and independence tests.
    pub pairs: Vec<Pair>,
    /// Permutations for the mutual-information null.
    pub permutations: u32,
    /// Analyse a dataset with missing realization ranges (recorded in `summary.json`).
    pub allow_partial: bool,
    /// Compute the tails (survival curves, the conditional estimator, extremes; [`tails`]).
    pub tails: bool,
    /// Which survival-curve times and severity thresholds to evaluate (with `tails`).
    pub tail: tails::TailOptions,
}

/// Default largest event index analysed (the paper's Table 1 goes to 6).
pub const DEFAULT_MAX_INDEX: u32 = 6;
/// Largest `--max-index`: the largest index a quantity's name may carry (each index adds four
/// series with their sketches).
pub use crate::observables::MAX_INDEX;

/// The smallest share of realizations that must reach index k for T_k, L_k to enter the growth
/// regressions (and the renewal check and the sweep's slopes built on them): statistics of an
/// index few realizations reach describe those few, not the process (a λ = 1, μ = 0.1 cell gave a
/// Var T_k slope of −0.98 from a T_6 that 4 % of the realizations have).
pub const GROWTH_MIN_REACHED: f64 = 0.9;

/// Default thresholds s of P(severity > s): 1 (the mass overshoots the belt speed: its velocity
/// swings wider than the belt's ±v0) and 1.25.
pub const DEFAULT_SEVERITY: [f64; 2] = [1.0, 1.25];

/// Default number of permutations of the mutual-information null.
pub const DEFAULT_PERMUTATIONS: u32 = 199;

/// Most histogram bins (`--bins`).
pub const MAX_BINS: usize = 100_000;

impl Options {
    /// Refuse options that cannot work, before any input is read.
    pub fn check(&self) -> Result<(), AnalysisError> {
        if self.max_index == 0 || self.max_index > MAX_INDEX {
            return Err(AnalysisError::Options(format!("--max-index {}: must be between 1 and {MAX_INDEX}", self.max_index)));
        }
        if let Some(b) = self.bins.filter(|&b| b == 0 || b > MAX_BINS) {
            return Err(AnalysisError::Options(format!("--bins {b}: must be between 1 and {MAX_BINS}")));
        }
        if let Some(t) = self.tail.times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
            return Err(AnalysisError::Options(format!("--tail-times {t}: must be a finite time >= 0 s")));
        }
        if let Some(s) = self.tail.severity.iter().find(|s| !(s.is_finite() && **s >= 0.0)) {
            return Err(AnalysisError::Options(format!("--severity {s}: must be a finite number >= 0")));
        }
        if let Some(p) = self.pairs.iter().find(|p| [p.0, p.1].iter().any(|o| o.index().is_some_and(|k| k > self.max_index))) {
            return Err(AnalysisError::Options(format!(
                "--pair {},{}: an index above --max-index {} (raise --max-index to analyse it)",
                p.0, p.1, self.max_index
            )));
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_index: DEFAULT_MAX_INDEX,
            bins: None,
            pairs: vec![Pair(Observable::StickStart(1), Observable::StickStart(2)), Pair(Observable::StickDuration(1), Observable::StickDuration(2))],
            permutations: DEFAULT_PERMUTATIONS,
            allow_partial: false,
            tails: true,
            tail: tails::TailOptions { times: Vec::new(), severity: DEFAULT_SEVERITY.to_vec() },
        }
    }
}
