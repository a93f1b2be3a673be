//! The `[belt]` keys → the belt process ([`crate::simulation::belt::Process`]): which process
//! (`belt.process`, or inferred from the `reverse_*` keys when absent), the keys each uses, and
//! the recorded velocity log read from its file.
//!
//! | process | its keys |
//! |---|---|
//! | `symmetric` (default) | `speed`, `switch_rate`, `initial_sign` |
//! | `telegraph` | those and `reverse_speed`, `reverse_switch_rate` |
//! | `markov` | `velocities` [m/s], `rates` [1/s] (n×n, diagonal ignored) |
//! | `recorded` | `file` (CSV or Parquet with columns `time` [s], `velocity` [m/s]) |
//!
//! A key another process uses is refused with the process that uses it; `speed`, `switch_rate`
//! and `initial_sign` have defaults (the paper's), so for a chain or a record only a value other
//! than the default is refused.

use std::path::Path;
use std::sync::Arc;

use super::spec::{Param, ProcessName};
use super::types::{invalid, Scenario, ScenarioError, MAX_EXPECTED_SWITCHES};
use crate::shown::short;
use crate::simulation::belt::{Markov, Process, Recorded, Symmetric, Telegraph, MAX_SPEED, MIN_SPEED};
use crate::simulation::keys::Key;

impl Scenario {
    /// The belt's process, inferred when `belt.process` is absent: symmetric, or telegraph when
    /// both `reverse_*` keys are given.
    pub fn process_name(&self) -> ProcessName {
        let b = &self.belt;
        match (b.process, &b.reverse_speed, &b.reverse_switch_rate) {
            (Some(p), _, _) => p,
            (None, Some(_), Some(_)) => ProcessName::Telegraph,
            (None, _, _) => ProcessName::Symmetric,
        }
    }

    /// The belt process with its parameters (`value` gives a key's fixed value: the number, a
    /// distribution's mean, a sweep's first value).
    pub(super) fn process(&self, value: impl Fn(&Param) -> f64) -> Result<Process, ScenarioError> {
        let b = &self.belt;
        let name = self.process_name();
        let used = |key: &str, by: &[ProcessName]| -> Result<(), ScenarioError> {
            if by.contains(&name) {
                Ok(())
            } else {
                let by = by.iter().map(|p| format!("\"{}\"", p.as_str())).collect::<Vec<_>>().join(" or ");
                Err(invalid(key, "(set)", &format!("only belt.process = {by} uses it (this belt is \"{}\")", name.as_str())))
            }
        };
        if b.process.is_none() && b.reverse_speed.is_some() != b.reverse_switch_rate.is_some() {
            let (k, other) =
                if b.reverse_speed.is_some() { ("belt.reverse_speed", "belt.reverse_switch_rate") } else { ("belt.reverse_switch_rate", "belt.reverse_speed") };
            return Err(invalid(k, "(set)", &format!("the asymmetric belt needs {other} too (give both, or neither for the paper's symmetric belt)")));
        }
        let (two_state, chain, record) = ([ProcessName::Symmetric, ProcessName::Telegraph], [ProcessName::Markov], [ProcessName::Recorded]);
        // (typed, not checked: checking builds this very process)
        let paper = &super::types::paper_typed().belt;
        for (key, set) in [
            ("belt.speed", b.speed != paper.speed),
            ("belt.switch_rate", b.switch_rate != paper.switch_rate),
            ("belt.initial_sign", b.initial_sign != paper.initial_sign),
        ] {
            if set {
                used(key, &two_state)?;
            }
        }
        for (key, set) in [("belt.reverse_speed", b.reverse_speed.is_some()), ("belt.reverse_switch_rate", b.reverse_switch_rate.is_some())] {
            if set {
                used(key, &[ProcessName::Telegraph])?;
            }
        }
        for (key, set, by) in [
            ("belt.velocities", b.velocities.is_some(), &chain),
            ("belt.rates", b.rates.is_some(), &chain),
            ("belt.file", b.file.is_some(), &record),
            ("belt.velocity", b.velocity.is_some(), &[ProcessName::Constant]),
        ] {
            if set {
                used(key, by)?;
            }
        }
        let (speed, rate) = (value(&b.speed), value(&b.switch_rate));
        Ok(match name {
            ProcessName::Symmetric => Process::Symmetric(Symmetric { speed, switch_rate: rate }),
            ProcessName::Telegraph => {
                let (Some(rs), Some(rr)) = (&b.reverse_speed, &b.reverse_switch_rate) else {
                    let missing = if b.reverse_speed.is_none() { "belt.reverse_speed" } else { "belt.reverse_switch_rate" };
                    return Err(invalid(
                        missing,
                        "(absent)",
                        "the telegraph belt needs belt.reverse_speed and belt.reverse_switch_rate (give both, or neither for the paper's symmetric belt)",
                    ));
                };
                // equal fixed values of an inferred telegraph belt are the paper's belt, drawn by
                // the paper's steps; `process = "telegraph"` asks for the telegraph's draws
                if b.process.is_none() && b.speed == *rs && b.switch_rate == *rr && matches!(rs, Param::Value(_)) && matches!(rr, Param::Value(_)) {
                    Process::Symmetric(Symmetric { speed, switch_rate: rate })
                } else {
                    Process::Telegraph(Telegraph { forward_speed: speed, forward_rate: rate, reverse_speed: value(rs), reverse_rate: value(rr) })
                }
            }
            ProcessName::Markov => {
                let (Some(velocities), Some(rates)) = (&b.velocities, &b.rates) else {
                    let missing = if b.velocities.is_none() { "belt.velocities" } else { "belt.rates" };
                    return Err(invalid(missing, "(absent)", "the markov belt needs belt.velocities (m/s) and belt.rates (1/s, an n×n matrix)"));
                };
                let shown_v = format!("[{}]", velocities.iter().map(|v| short(*v)).collect::<Vec<_>>().join(", "));
                check_velocities("belt.velocities", &shown_v, velocities)?;
                let (_, max_rate) = Key::SwitchRate.range();
                // (the diagonal is ignored, whatever it holds)
                let off_diagonal = rates.iter().enumerate().flat_map(|(i, row)| row.iter().enumerate().filter(move |(j, _)| *j != i).map(|(_, r)| r));
                if let Some(r) = off_diagonal.into_iter().find(|r| r.is_finite() && **r > max_rate) {
                    return Err(invalid("belt.rates", &short(*r), &format!("a rate must be at most {max_rate:e} (1/s), the range the solvers are proven on")));
                }
                let m = Process::Markov(Arc::new(Markov::new(velocities.clone(), rates.clone()).map_err(|e| invalid("belt.rates", "(the matrix)", &e))?));
                self.check_scale(&m, "belt.velocities", &shown_v)?;
                m
            }
            ProcessName::Constant => {
                let Some(v) = b.velocity else {
                    return Err(invalid("belt.velocity", "(absent)", "the constant belt needs belt.velocity (m/s; 0 is a belt at rest)"));
                };
                if !(v == 0.0 || (MIN_SPEED..=MAX_SPEED).contains(&v.abs())) {
                    return Err(invalid(
                        "belt.velocity",
                        &short(v),
                        &format!("must be 0 or between {MIN_SPEED:e} and {MAX_SPEED:e} m/s in size, the range the solvers are proven on"),
                    ));
                }
                Process::Constant(v)
            }
            ProcessName::Recorded => {
                let Some(file) = &b.file else {
                    return Err(invalid(
                        "belt.file",
                        "(absent)",
                        "the recorded belt needs belt.file, a CSV or Parquet file with columns time (s) and velocity (m/s)",
                    ));
                };
                let (times, velocities) = read_log(Path::new(file)).map_err(|e| invalid("belt.file", &format!("{file:?}"), &e))?;
                let r = Recorded::new(times, velocities).map_err(|e| invalid("belt.file", &format!("{file:?}"), &e))?;
                let within: Vec<f64> = r.rows().take_while(|(t, _)| *t < self.run.duration).map(|(_, v)| v).collect();
                check_velocities("belt.file", &format!("{file:?}"), &within)?;
                let r = Process::Recorded(Arc::new(r));
                self.check_scale(&r, "belt.file", &format!("{file:?}"))?;
                r
            }
        })
    }

    /// The speed scale of a chain or a record ([`Process::scale`]) at least [`MIN_SPEED`]: the
    /// severity's unit (a chain that sits at 0 but for a level it enters once in 1e12 s).
    fn check_scale(&self, process: &Process, key: &str, shown: &str) -> Result<(), ScenarioError> {
        let scale = process.scale(self.run.duration);
        if !(scale >= MIN_SPEED) {
            return Err(invalid(
                key,
                shown,
                &format!(
                    "the belt's speed scale (its mean |v| over [0, run.duration], the severity's unit) is {}; it must be at least {MIN_SPEED:e} m/s",
                    short(scale)
                ),
            ));
        }
        Ok(())
    }

    /// The expected velocity changes per realization of a chain or a record, against
    /// [`MAX_EXPECTED_SWITCHES`] (the symmetric and telegraph rates are checked per key).
    pub(super) fn check_belt_changes(&self, process: &Process) -> Result<(), ScenarioError> {
        let (key, shown) = match process {
            Process::Markov(_) => ("belt.rates", "(the matrix)".to_string()),
            Process::Recorded(_) => ("belt.file", format!("{:?}", self.belt.file.as_deref().unwrap_or(""))),
            _ => return Ok(()),
        };
        let expected = process.max_rate(self.run.duration) * self.run.duration;
        if !(expected <= MAX_EXPECTED_SWITCHES) {
            return Err(invalid(
                key,
                &shown,
                &format!("{expected:e} velocity changes per realization at the fastest rate; at most {MAX_EXPECTED_SWITCHES:e} are supported"),
            ));
        }
        Ok(())
    }
}

/// The directory of a scenario file, absolute (a relative `belt.file` in it starts there).
pub(super) fn base_dir(file: &Path) -> std::path::PathBuf {
    let dir = file.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::path::absolute(dir).unwrap_or_else(|_| dir.to_owned())
}

/// A relative `belt.file` or `anchor.file` of a scenario file's table joined to the file's
/// directory `base` (a scenario and its logs are shipped side by side; the joined path is what
/// provenance records).
pub(super) fn anchor_log(user: &mut toml::Table, base: Option<std::path::PathBuf>) {
    let Some(base) = base else { return };
    for section in ["belt", "anchor"] {
        if let Some(toml::Value::Table(t)) = user.get_mut(section) {
            if let Some(toml::Value::String(file)) = t.get_mut("file") {
                if Path::new(file.as_str()).is_relative() {
                    *file = base.join(file.as_str()).to_string_lossy().into_owned();
                }
            }
        }
    }
}

impl ProcessName {
    /// Its name in a scenario.
    pub fn as_str(self) -> &'static str {
        match self {
            ProcessName::Symmetric => "symmetric",
            ProcessName::Telegraph => "telegraph",
            ProcessName::Markov => "markov",
            ProcessName::Recorded => "recorded",
            ProcessName::Constant => "constant",
        }
    }
}

/// The levels of a chain or a record: finite, 0 or between [`MIN_SPEED`] and [`MAX_SPEED`] in
/// size, not all 0 (a belt that never moves has no speed scale for the severity).
fn check_velocities(key: &str, shown: &str, v: &[f64]) -> Result<(), ScenarioError> {
    if let Some(x) = v.iter().find(|x| !(x.is_finite() && x.abs() <= MAX_SPEED && (**x == 0.0 || x.abs() >= MIN_SPEED))) {
        return Err(invalid(key, shown, &format!("the velocity {} must be 0 or between {MIN_SPEED:e} and {MAX_SPEED:e} m/s in size (finite)", short(*x))));
    }
    if !v.iter().any(|x| *x != 0.0) {
        return Err(invalid(key, shown, "at least one velocity must be nonzero (a belt at rest throughout moves nothing)"));
    }
    Ok(())
}

/// Most rows of a velocity log (the changes a realization may hold, plus the first row).
const MAX_LOG_ROWS: usize = MAX_EXPECTED_SWITCHES as usize + 1;

/// Largest velocity log read, in bytes (a CSV of [`MAX_LOG_ROWS`] rows of two 20-digit numbers
/// fits; it is read whole).
const MAX_LOG_BYTES: u64 = 1 << 30;

/// A velocity log: Parquet (by its magic bytes) or CSV with a header naming `time` and
/// `velocity` (other columns ignored; blank lines and lines starting with `#` skipped).
pub(super) fn read_log(path: &Path) -> Result<(Vec<f64>, Vec<f64>), String> {
    // a regular file of bounded size only: a FIFO would block in open(), a device never end
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read it: {e}"))?;
    if !meta.is_file() {
        return Err("is not a regular file (a velocity log is a CSV or Parquet file)".into());
    }
    if meta.len() > MAX_LOG_BYTES {
        return Err(format!("is {} bytes, larger than the {MAX_LOG_BYTES} bytes a velocity log may have", meta.len()));
    }
    let mut head = [0u8; 4];
    let is_parquet = std::fs::File::open(path).and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head)).is_ok() && &head == b"PAR1";
    if is_parquet {
        read_parquet_log(path)
    } else {
        read_csv_log(path)
    }
}

fn read_csv_log(path: &Path) -> Result<(Vec<f64>, Vec<f64>), String> {
    use std::io::Read as _;
    let mut bytes = Vec::new();
    std::fs::File::open(path).and_then(|f| f.take(MAX_LOG_BYTES + 1).read_to_end(&mut bytes)).map_err(|e| format!("cannot read it: {e}"))?;
    if bytes.len() as u64 > MAX_LOG_BYTES {
        return Err(format!("larger than the {MAX_LOG_BYTES} bytes a velocity log may have"));
    }
    let text = String::from_utf8(bytes).map_err(|_| "is not UTF-8 text (a CSV log) nor a Parquet file".to_string())?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines.next().ok_or("it is empty (expected a header line: time,velocity)")?;
    let names: Vec<&str> = header.split(',').map(|c| c.trim().trim_matches('"')).collect();
    let column = |name: &str| names.iter().position(|c| *c == name).ok_or(format!("its header {header:?} has no column `{name}`"));
    let (ti, vi) = (column("time")?, column("velocity")?);
    let (mut times, mut velocities) = (Vec::new(), Vec::new());
    for (line, l) in lines {
        let cells: Vec<&str> = l.split(',').map(str::trim).collect();
        let number = |i: usize| cells.get(i).and_then(|c| c.parse::<f64>().ok()).ok_or(format!("line {}: {l:?} has no number in column {}", line + 1, i + 1));
        times.push(number(ti)?);
        velocities.push(number(vi)?);
        if times.len() > MAX_LOG_ROWS {
            return Err(format!("more than {MAX_LOG_ROWS} rows"));
        }
    }
    Ok((times, velocities))
}

/// A Parquet log, read with polars (whose Parquet reader has every codec pyarrow and pandas write:
/// snappy, gzip, lz4, brotli, zstd). The columns `time` and `velocity` may be float64 or int64.
fn read_parquet_log(path: &Path) -> Result<(Vec<f64>, Vec<f64>), String> {
    use polars::prelude::{DataType, ParquetReader, SerReader};
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read it: {e}"))?;
    let mut reader = ParquetReader::new(file);
    let schema = reader.schema().map_err(|e| format!("not a readable Parquet file ({e})"))?;
    if reader.num_rows().map_err(|e| format!("not a readable Parquet file ({e})"))? > MAX_LOG_ROWS {
        return Err(format!("more than {MAX_LOG_ROWS} rows"));
    }
    for name in ["time", "velocity"] {
        if !schema.contains(name) {
            return Err(format!("it has no column `{name}`"));
        }
    }
    let frame = reader.with_columns(Some(vec!["time".into(), "velocity".into()])).finish().map_err(|e| format!("reading it: {e}"))?;
    let column = |name: &str| -> Result<Vec<f64>, String> {
        let c = frame.column(name).map_err(|e| e.to_string())?.as_materialized_series();
        if c.null_count() > 0 {
            return Err(format!("column `{name}` holds nulls"));
        }
        match c.dtype() {
            DataType::Float64 => Ok(c.f64().map_err(|e| e.to_string())?.into_no_null_iter().collect()),
            DataType::Int64 => Ok(c.i64().map_err(|e| e.to_string())?.into_no_null_iter().map(|x| x as f64).collect()),
            other => Err(format!("column `{name}` is {other}, expected float64 or int64")),
        }
    };
    Ok((column("time")?, column("velocity")?))
}
