//! Sampled trajectories for the paper's Fig. 4: mass and belt velocity on a time grid, evaluated
//! by the solver's driver on each method's own pieces of motion (closed forms for `exact`, dense
//! output for the integrators), plus the event instants.
//!
//! Only the first `output.trajectories` realizations are sampled, and only when asked. They go
//! beside the dataset, never into it (the dataset directory holds part files only, so that
//! `polars.read_parquet(DIR)` and `pyarrow.dataset(DIR)` read it as one table): for a dataset
//! `DIR` (a sweep cell `DIR/CELL`) the directory `DIR.trajectories/` (`DIR.trajectories/CELL/`,
//! [`dir_for`]) holds two tidy Parquet tables:
//! - `samples.parquet`: `realization` (int64), `t`, `x`, `xdot`, `belt_velocity` (float64, s, m,
//!   m/s, m/s), one row per grid instant;
//! - `events.parquet`: `realization` (int64), `event` (`belt_switch`, `stick_start`,
//!   `stick_end`), `t` (float64, s), `belt_velocity` (float64, m/s: the belt's velocity from
//!   this instant on), one row per event.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use parquet::arrow::ArrowWriter;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use crate::outdir::{is_marked, resolved, Kind, Lock, OutDirError, TempFile};
use crate::simulation::events::{Observer, Record, Release};

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
    fn stick(&mut self, _t: f64, _x: f64, _v: f64) {}
    fn slip(&mut self, _t: f64, _x: f64, _xdot: f64, _by: Release) {}
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
    fn stick(&mut self, t: f64, x: f64, v: f64) {
        self.0.stick(t, x, v);
        self.1.stick(t, x, v);
    }
    fn slip(&mut self, t: f64, x: f64, xdot: f64, by: Release) {
        self.0.slip(t, x, xdot, by);
        self.1.slip(t, x, xdot, by);
    }
    fn wants_motion(&self) -> bool {
        self.0.wants_motion() || self.1.wants_motion()
    }
    fn motion(&mut self, lo: f64, hi: f64, v: f64) {
        self.0.motion(lo, hi, v);
        self.1.motion(lo, hi, v);
    }
    fn sample_step(&self) -> Option<f64> {
        self.0.sample_step().or(self.1.sample_step())
    }
    fn sample(&mut self, t: f64, x: f64, xdot: f64, v: f64) {
        self.0.sample(t, x, xdot, v);
        self.1.sample(t, x, xdot, v);
    }
}

crate::table::table! {
    /// `samples.parquet`: the sampled paths.
    samples = "samples.parquet", "the first realizations' paths, sampled every output.trajectory_step" {
        REALIZATION: "realization", Int, "the realization's global index";
        T: "t", Float, "the instant [s]";
        X: "x", Float, "the mass' position [m]";
        XDOT: "xdot", Float, "the mass' velocity [m/s]";
        BELT_VELOCITY: "belt_velocity", Float, "the belt's velocity [m/s]";
    }
}

crate::table::table! {
    /// `events.parquet`: the sampled realizations' events.
    events = "events.parquet", "the sampled realizations' belt switches, stick starts and stick ends, in time order" {
        REALIZATION: "realization", Int, "the realization's global index";
        EVENT: "event", Str, "belt_switch, stick_start or stick_end";
        T: "t", Float, "its instant [s]";
        BELT_VELOCITY: "belt_velocity", Float, "the belt's velocity from that instant on [m/s]";
    }
}

/// The two table files, in [`dir_for`].
pub const SAMPLES: &str = samples::DEF.file;
pub const EVENTS: &str = events::DEF.file;
/// The `event` values of [`EVENTS`].
pub const EVENT_NAMES: [&str; 3] = ["belt_switch", "stick_start", "stick_end"];

/// The footer key that marks a trajectory table as the tool's (a file without it is never
/// replaced).
const MARK: &str = "stickslip.trajectories";

/// Where the trajectories of the dataset (or sweep cell) directory `dir` go: `TOP.trajectories/`
/// beside the dataset's top directory (the nearest ancestor marked as a dataset), plus the
/// cell's path below it. `None` for a top without a name (the file system root).
pub fn dir_for(dir: &Path) -> Option<PathBuf> {
    let top = dir.ancestors().find(|a| !a.as_os_str().is_empty() && is_marked(a, Kind::Dataset)).unwrap_or(dir);
    let cell = dir.strip_prefix(top).unwrap_or(Path::new(""));
    let top = resolved(top);
    let name = top.file_name()?.to_string_lossy().into_owned();
    Some(top.parent()?.join(format!("{name}.trajectories")).join(cell))
}

/// The sampled realizations, as the two tables.
#[derive(Debug, Default)]
pub struct Tables {
    sample_realization: Vec<i64>,
    samples: Vec<[f64; 4]>,
    event_realization: Vec<i64>,
    event: Vec<&'static str>,
    event_t: Vec<f64>,
    event_belt: Vec<f64>,
}

impl Tables {
    /// Add one sampled realization: its grid samples, its effective belt switches with the
    /// velocity of each segment (`switches.len() + 1` of them) and its sticks.
    pub fn push(&mut self, realization: u64, samples: &[[f64; 4]], switches: &[f64], velocities: &[f64], record: &Record) {
        let r = realization as i64;
        self.sample_realization.extend(std::iter::repeat_n(r, samples.len()));
        self.samples.extend_from_slice(samples);
        let [switch, start, end] = EVENT_NAMES;
        let mut events: Vec<(f64, &'static str)> = switches.iter().map(|&t| (t, switch)).collect();
        for (t, d) in record.stick_start.iter().zip(&record.stick_duration) {
            events.extend([(*t, start), (t + d, end)]);
        }
        // (stable: a belt switch stays before the stick end it causes)
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        // the belt from an instant on: the segment that starts at or before it
        let belt = |t: f64| velocities[switches.partition_point(|&s| s <= t)];
        for (t, e) in events {
            self.event_realization.push(r);
            self.event.push(e);
            self.event_t.push(t);
            self.event_belt.push(belt(t));
        }
    }

    fn samples_batch(&self) -> RecordBatch {
        let f = |i: usize| Arc::new(Float64Array::from(self.samples.iter().map(|s| s[i]).collect::<Vec<_>>())) as ArrayRef;
        let cols: Vec<ArrayRef> = vec![Arc::new(Int64Array::from(self.sample_realization.clone())), f(0), f(1), f(2), f(3)];
        RecordBatch::try_new(Arc::new(samples::DEF.arrow_schema()), cols).expect("columns of equal length")
    }

    fn events_batch(&self) -> RecordBatch {
        let schema = events::DEF.arrow_schema();
        let cols: Vec<ArrayRef> = vec![
            Arc::new(Int64Array::from(self.event_realization.clone())),
            Arc::new(StringArray::from(self.event.clone())),
            Arc::new(Float64Array::from(self.event_t.clone())),
            Arc::new(Float64Array::from(self.event_belt.clone())),
        ];
        RecordBatch::try_new(Arc::new(schema), cols).expect("columns of equal length")
    }

    /// Write both tables into `dir` under temporary names (each under its lock), to be
    /// committed with the part: an existing table is replaced only if it is the tool's. `scenario`
    /// (the resolved scenario, as the parts record it) goes into their footers, so that tables
    /// left beside a dataset by another run are never taken for this one's ([`recorded_scenario`]).
    pub fn write(&self, dir: &Path, scenario: &str) -> Result<Vec<(TempFile, Lock)>, OutDirError> {
        let mut out = Vec::new();
        for (name, batch) in [(SAMPLES, self.samples_batch()), (EVENTS, self.events_batch())] {
            let path = dir.join(name);
            let lock = Lock::acquire(&path)?;
            if std::fs::symlink_metadata(&path).is_ok() && !is_ours(&path) {
                return Err(OutDirError {
                    path,
                    message: "exists and is not a stickslip trajectory table; refusing to replace it: move it away or choose another --out".into(),
                    refused: true,
                });
            }
            let (tmp, file) = TempFile::create(&path)?;
            let fail = |e: &dyn std::fmt::Display| OutDirError { path: path.clone(), message: e.to_string(), refused: false };
            let kv = vec![
                KeyValue::new(MARK.into(), name.trim_end_matches(".parquet").to_string()),
                KeyValue::new(crate::metadata::VERSION.into(), env!("CARGO_PKG_VERSION").to_string()),
                KeyValue::new(SCENARIO.into(), scenario.to_string()),
            ];
            let props = WriterProperties::builder().set_key_value_metadata(Some(kv)).build();
            let mut w = ArrowWriter::try_new(file, batch.schema(), Some(props)).map_err(|e| fail(&e))?;
            w.write(&batch).map_err(|e| fail(&e))?;
            w.close().map_err(|e| fail(&e))?;
            out.push((tmp, lock));
        }
        Ok(out)
    }
}

/// The footer key holding the scenario of the run that sampled the trajectories (the parts' key).
const SCENARIO: &str = crate::metadata::SCENARIO;

/// Whether the file at `path` is one of the tool's trajectory tables (its footer says so).
fn is_ours(path: &Path) -> bool {
    crate::metadata::footer(path).is_some_and(|kv| kv.iter().any(|(k, _)| k == MARK))
}

/// The scenario recorded in the trajectory table at `path`, if it is the tool's.
pub fn recorded_scenario(path: &Path) -> Option<String> {
    crate::metadata::footer(path)?.into_iter().find(|(k, _)| k == SCENARIO).and_then(|(_, v)| v)
}
