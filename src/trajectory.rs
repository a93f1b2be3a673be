//! Sampled trajectories for the paper's Fig. 4: mass and belt velocity on a time grid, evaluated
//! by the solver's driver on each method's own pieces of motion (closed forms for `exact`, dense
//! output for the integrators), plus the event marks.
//!
//! Only the first `output.trajectories` realizations are sampled, and only when asked: the file
//! `DIR/trajectories.csv` (not Parquet, so `DIR/**/*.parquet` stays the event table) has columns
//! `realization,kind,t,x,xdot,belt_velocity` with `kind` one of `sample`, `switch`,
//! `stick_start`, `stick_end` (event rows carry only `t`).

use std::fmt::Write as _;

use crate::events::{Observer, Record};

/// Records the grid samples the driver hands it.
#[derive(Debug, Clone)]
pub struct Sampler {
    step: f64,
    /// (t, x, ẋ, belt velocity)
    pub samples: Vec<[f64; 4]>,
}

impl Sampler {
    pub fn new(step: f64) -> Sampler {
        Sampler { step, samples: Vec::new() }
    }
}

impl Observer for Sampler {
    fn stick(&mut self, _t: f64, _x: f64) {}
    fn slip(&mut self, _t: f64, _x: f64, _xdot: f64) {}
    fn sample_step(&self) -> Option<f64> {
        Some(self.step)
    }
    fn sample(&mut self, t: f64, x: f64, xdot: f64, v: f64) {
        self.samples.push([t, x, xdot, v]);
    }
}

/// Feeds one realization's events to two observers.
pub struct Tee<'a, A, B>(pub &'a mut A, pub &'a mut B);

impl<A: Observer, B: Observer> Observer for Tee<'_, A, B> {
    fn stick(&mut self, t: f64, x: f64) {
        self.0.stick(t, x);
        self.1.stick(t, x);
    }
    fn slip(&mut self, t: f64, x: f64, xdot: f64) {
        self.0.slip(t, x, xdot);
        self.1.slip(t, x, xdot);
    }
    fn sample_step(&self) -> Option<f64> {
        self.0.sample_step().or(self.1.sample_step())
    }
    fn sample(&mut self, t: f64, x: f64, xdot: f64, v: f64) {
        self.0.sample(t, x, xdot, v);
        self.1.sample(t, x, xdot, v);
    }
}

/// CSV header of `trajectories.csv`.
pub const CSV_HEADER: &str = "realization,kind,t,x,xdot,belt_velocity\n";

/// Append the CSV rows of one sampled realization.
pub fn csv_rows(out: &mut String, realization: u64, samples: &[[f64; 4]], switches: &[f64], record: &Record) {
    for [t, x, xdot, v] in samples {
        let _ = writeln!(out, "{realization},sample,{t},{x},{xdot},{v}");
    }
    for t in switches {
        let _ = writeln!(out, "{realization},switch,{t},,,");
    }
    for (t, d) in record.stick_start.iter().zip(&record.stick_duration) {
        let _ = writeln!(out, "{realization},stick_start,{t},,,");
        let _ = writeln!(out, "{realization},stick_end,{},,,", t + d);
    }
}
