//! Stop at a target precision: `simulate --target-se VAR=SE` (repeatable).
//!
//! VAR is the mean of one per-realization quantity of the observables home (`crate::observables`,
//! which parses `VAR=SE` and reads the values: this file only tracks them) — `S_T`, `S_L`,
//! `T_k`, `D_k`, `L_k`, `H_k` (k ≥ 1), `stick_fraction`, `mean_stick_duration`,
//! `mean_slip_duration` — and SE the standard error of that mean the run should reach,
//! `se = √(s²/n)` over the realizations that have the quantity (its censoring rule is the
//! observables' one, as everywhere). Realizations are simulated in index order; after every
//! chunk of [`crate::simulation::ensemble::Ensemble::chunk_len`] realizations (a boundary that depends on the
//! scenario only) the standard errors are updated and the run stops at the first boundary where
//! every target is met. The dataset is therefore exactly the first N rows of a fixed-N run with
//! the same seed, for any thread count; `run.realizations` is the cap, and reaching it before the
//! targets is reported (stderr and the dataset's metadata), not hidden.

use crate::simulation::ensemble::Outcome;
use crate::stats::Moments;

/// The targets of a run: a name, the standard error to reach and how to read the value off a
/// realization, for each (the observables home builds them from `--target-se`).
pub struct Targets<'a> {
    /// VAR of each target, for progress and messages
    pub names: Vec<String>,
    /// SE of each, the standard error of the mean to reach (> 0)
    pub se: Vec<f64>,
    /// the value of target `i` on a realization (None: the realization has none)
    pub value: Box<dyn Fn(usize, &Outcome) -> Option<f64> + Sync + 'a>,
}

impl Targets<'_> {
    /// No target: the run goes to its size.
    pub fn none() -> Targets<'static> {
        Targets { names: Vec::new(), se: Vec::new(), value: Box::new(|_, _| None) }
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.se.is_empty()
    }
}

/// The running moments of each target's quantity.
#[derive(Debug, Clone)]
pub struct Tracker {
    /// the running moments of each target's quantity, in the targets' order
    pub moments: Vec<Moments>,
}

impl Tracker {
    /// A tracker of `targets` with no realization added.
    pub fn new(targets: &Targets) -> Tracker {
        Tracker { moments: vec![Moments::default(); targets.se.len()] }
    }

    /// Add one realization.
    pub fn add(&mut self, targets: &Targets, o: &Outcome) {
        for (i, m) in self.moments.iter_mut().enumerate() {
            if let Some(x) = (targets.value)(i, o) {
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
    pub fn met(&self, targets: &Targets) -> bool {
        self.errors().iter().zip(&targets.se).all(|(se, t)| se.is_some_and(|se| se <= *t))
    }

    /// `VAR se=… (target …)` for each target, for progress and messages.
    pub fn describe(&self, targets: &Targets) -> String {
        targets
            .names
            .iter()
            .zip(&targets.se)
            .zip(self.errors())
            .map(|((name, t), se)| format!("{name} se {} (target {})", se.map_or("–".into(), |x| format!("{x:.3e}")), crate::shown::short(*t)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
