//! Stop at a target precision: `simulate --target-se VAR=SE` (repeatable).
//!
//! VAR is the mean of one per-realization quantity of [`crate::observables`] — `S_T`, `S_L`,
//! `T_k`, `D_k`, `L_k`, `H_k` (k ≥ 1), `stick_fraction`, `mean_stick_duration`,
//! `mean_slip_duration` — and SE the standard error of that mean the run should reach,
//! `se = √(s²/n)` over the realizations that have the quantity (its censoring rule is the
//! observables' one, as everywhere). Realizations are simulated in index order; after every
//! chunk of [`crate::simulation::ensemble::Ensemble::chunk_len`] realizations (a boundary that depends on the
//! scenario only) the standard errors are updated and the run stops at the first boundary where
//! every target is met. The dataset is therefore exactly the first N rows of a fixed-N run with
//! the same seed, for any thread count; `run.realizations` is the cap, and reaching it before the
//! targets is reported (stderr and the dataset's metadata), not hidden.

use std::str::FromStr;

use crate::observables::Observable;
use crate::simulation::ensemble::Outcome;
use crate::stats::Moments;

/// One `--target-se VAR=SE`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// VAR, the quantity whose mean is tracked
    pub quantity: Observable,
    /// SE, the standard error of the mean to reach (> 0)
    pub se: f64,
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.quantity)
    }
}

impl FromStr for Target {
    type Err = String;
    fn from_str(s: &str) -> Result<Target, String> {
        let bad = |why: &str| format!("--target-se {s:?}: {why}; expected VAR=SE, e.g. S_T=0.05");
        let (var, se) = s.split_once('=').ok_or_else(|| bad("no '='"))?;
        let se: f64 = se.trim().parse().map_err(|_| bad("SE is not a number"))?;
        if !(se.is_finite() && se > 0.0) {
            return Err(bad("SE must be a positive number"));
        }
        let quantity = var.parse::<Observable>().map_err(|e| bad(&e))?;
        Ok(Target { quantity, se })
    }
}

/// The running moments of each target's quantity.
#[derive(Debug, Clone)]
pub struct Tracker {
    /// the targets, in the order given
    pub targets: Vec<Target>,
    /// the running moments of each target's quantity, in the same order
    pub moments: Vec<Moments>,
}

impl Tracker {
    /// A tracker of `targets` with no realization added.
    pub fn new(targets: &[Target]) -> Tracker {
        Tracker { targets: targets.to_vec(), moments: vec![Moments::default(); targets.len()] }
    }

    /// Add one realization.
    pub fn add(&mut self, o: &Outcome) {
        for (t, m) in self.targets.iter().zip(&mut self.moments) {
            if let Some(x) = t.quantity.value(o) {
                m.add(x);
            }
        }
    }

    /// Merge a later chunk's tracker (same targets).
    pub fn merge(&mut self, later: &Tracker) {
        for (m, l) in self.moments.iter_mut().zip(&later.moments) {
            *m = m.merge(l);
        }
    }

    /// The current standard errors of the means (None below two values).
    pub fn errors(&self) -> Vec<Option<f64>> {
        self.moments.iter().map(Moments::mean_se).collect()
    }

    /// Every target met.
    pub fn met(&self) -> bool {
        self.errors().iter().zip(&self.targets).all(|(se, t)| se.is_some_and(|se| se <= t.se))
    }

    /// `VAR se=… (target …)` for each target, for progress and messages.
    pub fn describe(&self) -> String {
        self.targets
            .iter()
            .zip(self.errors())
            .map(|(t, se)| format!("{t} se {} (target {})", se.map_or("–".into(), |x| format!("{x:.3e}")), crate::scenario::short(t.se)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_parse_and_bad_ones_are_named() {
        let t: Target = "D_3=0.01".parse().unwrap();
        assert_eq!((t.quantity, t.se, t.to_string()), (Observable::StickDuration(3), 0.01, "D_3".to_string()));
        assert_eq!("stick_fraction=1e-3".parse::<Target>().unwrap().quantity, Observable::StickFraction);
        for bad in ["S_T", "S_T=0", "S_T=-1", "X_1=0.1", "T_0=0.1", "T_x=0.1", "S_T=nan", "T_+1=0.1"] {
            let e = bad.parse::<Target>().unwrap_err();
            assert!(e.contains("--target-se"), "{e}");
        }
    }
}
