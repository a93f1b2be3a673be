//! Monte Carlo over realizations: each realization is a pure function of (scenario, index).
//!
//! Realization `i` draws, from its own stream `realization_rng(seed, i)` and in this order:
//! X0 ~ U[lo, hi], Ẋ0 ~ U[lo, hi] (one 53-bit uniform each), then the belt path
//! ([`Belt::sample_into`]). Chunks of consecutive indices are the unit of parallel work; the
//! chunk length depends only on the scenario, so the rows — and the bytes written — are the same
//! for any number of threads or shards.

use std::ops::Range;

use crate::dataset::Rows;
use crate::events::{Observer, Record};
use crate::excitation::{Belt, BeltPath};
use crate::model::Accel;
use crate::rng::{realization_rng, unit_f64};
use crate::scenario::Scenario;
use crate::solver::{AnySolver, Drive, SolveError, Solver};
use crate::trajectory::{Sampler, Tee};

/// A realization that could not be solved.
#[derive(Debug, thiserror::Error)]
#[error("realization {realization}: {source}")]
pub struct RunError {
    pub realization: u64,
    pub source: SolveError,
}

/// One simulated realization.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    pub x0: f64,
    pub xdot0: f64,
    pub belt: BeltPath,
    pub record: Record,
    switches: Vec<f64>,
}

impl Outcome {
    /// The effective belt flips (see `BeltPath::effective_switches`).
    pub fn switches(&self) -> &[f64] {
        &self.switches
    }
}

/// A scenario ready to run.
#[derive(Debug, Clone)]
pub struct Ensemble {
    belt: Belt,
    position: [f64; 2],
    velocity: [f64; 2],
    seed: u64,
    store_switch_times: bool,
    accel: Accel,
    solver: AnySolver,
}

impl Ensemble {
    pub fn new(scenario: &Scenario) -> Ensemble {
        Ensemble {
            belt: scenario.belt,
            position: scenario.position,
            velocity: scenario.velocity,
            seed: scenario.seed,
            store_switch_times: scenario.store_switch_times,
            accel: scenario.model.per_unit_mass(),
            solver: AnySolver::new(&scenario.solver, &scenario.model, scenario.numerics),
        }
    }

    /// Simulate realization `index` into `out` (its buffers are reused).
    pub fn realization(&self, index: u64, out: &mut Outcome) -> Result<(), RunError> {
        self.run(index, out, &mut ())
    }

    /// Simulate realization `index` and sample its trajectory every `step` seconds.
    pub fn trajectory(&self, index: u64, step: f64, out: &mut Outcome) -> Result<Sampler, RunError> {
        let mut sampler = Sampler::new(self.accel, step);
        self.run(index, out, &mut sampler)?;
        Ok(sampler)
    }

    /// Simulate realization `index`, counting into `out.record` and also showing `extra` the motion.
    fn run<O: Observer>(&self, index: u64, out: &mut Outcome, extra: &mut O) -> Result<(), RunError> {
        let mut rng = realization_rng(self.seed, index);
        let uniform = |r: [f64; 2], u: f64| r[0] + (r[1] - r[0]) * u;
        out.x0 = uniform(self.position, unit_f64(&mut rng));
        out.xdot0 = uniform(self.velocity, unit_f64(&mut rng));
        self.belt.sample_into(&mut rng, &mut out.belt);
        let sign0 = out.belt.effective_switches(&mut out.switches);
        let drive = Drive { sign0, switches: &out.switches, speed: self.belt.speed, t_end: self.belt.duration };
        out.record.clear();
        self.solver
            .solve(&drive, out.x0, out.xdot0, &mut Tee(&mut out.record, extra))
            .map_err(|source| RunError { realization: index, source })?;
        out.record.finish(self.belt.duration);
        Ok(())
    }

    /// Simulate a contiguous range of realizations into dataset rows.
    pub fn rows(&self, range: Range<u64>) -> Result<Rows, RunError> {
        let mut rows = Rows::new(self.store_switch_times);
        let mut out = Outcome::default();
        for index in range {
            self.realization(index, &mut out)?;
            rows.push(index, out.x0, out.xdot0, &out.belt, &out.record);
        }
        Ok(rows)
    }

    /// Realizations per chunk: about 2^18 list values per chunk (≈ 1,000 paper realizations:
    /// few, large batches for the Parquet encoder), at most 8192 rows.
    pub fn chunk_len(&self) -> u64 {
        let per_realization = 4.0 * self.belt.switch_rate * self.belt.duration + 64.0;
        (262_144.0 / per_realization).clamp(1.0, 8192.0) as u64
    }
}
