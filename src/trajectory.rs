//! Sampled trajectories for the paper's Fig. 4: mass and belt velocity on a time grid, evaluated
//! from the exact closed-form pieces of the motion (no integrator), plus the event marks.
//!
//! Only the first `output.trajectories` realizations are sampled, and only when asked: the file
//! `DIR/trajectories.csv` (not Parquet, so `DIR/**/*.parquet` stays the event table) has columns
//! `realization,kind,t,x,xdot,belt_velocity` with `kind` one of `sample`, `switch`,
//! `stick_start`, `stick_end` (event rows carry only `t`).

use std::fmt::Write as _;

use crate::events::{Observer, Record, Segment};
use crate::model::Accel;

/// Records grid samples of every segment it is shown.
#[derive(Debug, Clone)]
pub struct Sampler {
    accel: Accel,
    step: f64,
    /// (t, x, ẋ, belt velocity)
    pub samples: Vec<[f64; 4]>,
}

impl Sampler {
    pub fn new(accel: Accel, step: f64) -> Sampler {
        Sampler { accel, step, samples: Vec::new() }
    }
}

impl Observer for Sampler {
    fn stick(&mut self, _t: f64, _x: f64) {}
    fn slip(&mut self, _t: f64, _x: f64, _xdot: f64) {}
    fn segment(&mut self, s: &Segment) {
        let mut j = (s.t0 / self.step).ceil() as u64;
        loop {
            let t = j as f64 * self.step;
            if t >= s.t1 {
                break;
            }
            let tau = t - s.t0;
            let (x, xdot) = if s.stick { (s.x0 + s.v * tau, s.v) } else { self.accel.slip_state(s.x0, s.xdot0, s.a0, tau) };
            self.samples.push([t, x, xdot, s.v]);
            j += 1;
        }
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
    fn segment(&mut self, s: &Segment) {
        self.0.segment(s);
        self.1.segment(s);
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
