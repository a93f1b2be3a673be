//! Scenario files: TOML in, a validated [`Scenario`] out — every check happens here, before a
//! single realization runs.
//!
//! Resolution order: the embedded paper scenario (`pipelines/paper.toml`, which lists every key)
//! ← the user's file (any subset of keys) ← `--set key=value` overrides ← `--realizations` /
//! `--seed`. A key that the paper scenario does not have is an error, so a typo never silently
//! keeps a default. The resolved table is what datasets record as provenance.

use std::fmt;
use std::path::{Path, PathBuf};

use toml::{Table, Value};

use crate::excitation::{Belt, InitialSign};
use crate::model::Model;

/// The paper scenario, embedded: the default and the list of known keys.
pub const PAPER_TOML: &str = include_str!("../pipelines/paper.toml");

/// Largest accepted λ·t_a (expected belt flips per realization): their instants are held in memory.
pub const MAX_EXPECTED_SWITCHES: f64 = 1e7;

/// Most realizations one run may ask for.
pub const MAX_REALIZATIONS: u64 = 1_000_000_000_000;

/// Most cells one sweep may have (each is a full run and a directory).
pub const MAX_CELLS: usize = 10_000;

/// Largest scenario file read (a scenario is a few hundred bytes).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// Most trajectory samples in all (`output.trajectories` × duration / step): about 0.6 GB of CSV.
pub const MAX_TRAJECTORY_SAMPLES: f64 = 1e7;

/// The solvers `run.solver` may name.
pub const SOLVERS: &[&str] = &["exact", "rk45", "rk4", "moreau", "smooth"];

/// Settings of the numerical solvers (see `pipelines/paper.toml`, table `[numerics]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Numerics {
    pub rtol: f64,
    pub atol: f64,
    pub max_step: f64,
    pub step: f64,
    pub epsilon: f64,
    pub stick_velocity: f64,
    pub step_budget: u64,
}

/// A fully resolved and validated scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    pub model: Model,
    pub belt: Belt,
    /// Uniform ranges [lo, hi] of X0 [m] and Ẋ0 [m/s].
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub realizations: u64,
    pub seed: u64,
    pub solver: String,
    /// Settings of the numerical solvers (`[numerics]`).
    pub numerics: Numerics,
    pub store_switch_times: bool,
    /// Realizations 0..N sampled for trajectories (0: none), every `trajectory_step` seconds.
    pub trajectories: u64,
    pub trajectory_step: f64,
    /// The resolved table, for provenance.
    pub table: Table,
}

/// One cell of a parameter sweep: the swept keys' values, its hive path and its scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// (dotted key, value) of each swept key, in file order
    pub values: Vec<(String, f64)>,
    /// `name=value/...` with the last component of each key (empty without a sweep)
    pub path: String,
    pub scenario: Scenario,
}

/// Everything that can be wrong with a scenario, each naming its culprit.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error("cannot read scenario file {}: {source}", path.display())]
    Read { path: PathBuf, source: std::io::Error },
    #[error("scenario file {} is not valid TOML: {message}", path.display())]
    Syntax { path: PathBuf, message: String },
    #[error("unknown scenario key `{key}`{hint}")]
    UnknownKey { key: String, hint: Hint },
    #[error("scenario key `{key}` = {value}: {reason}")]
    Invalid { key: String, value: String, reason: String },
    #[error("--set {arg:?}: expected KEY=VALUE with a dotted key, e.g. --set belt.switch_rate=1.0")]
    BadSet { arg: String },
    #[error("--set {arg:?}: {reason}")]
    BadSetValue { arg: String, reason: String },
    #[error("scenario file {}: {reason}", path.display())]
    TooBig { path: PathBuf, reason: String },
}

/// The known keys next to an unknown one, for the error message.
#[derive(Debug)]
pub struct Hint(Vec<String>);

impl fmt::Display for Hint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            Ok(())
        } else {
            write!(f, " (known here: {})", self.0.join(", "))
        }
    }
}

impl Scenario {
    /// The paper scenario.
    pub fn paper() -> Scenario {
        Scenario::resolve(None, &[]).expect("the embedded paper scenario is valid")
    }

    /// Resolve a scenario from an optional file and `KEY=VALUE` overrides.
    pub fn resolve(file: Option<&Path>, sets: &[String]) -> Result<Scenario, ScenarioError> {
        Scenario::from_text(read(file)?.as_deref(), file.unwrap_or(Path::new("<scenario>")), sets)
    }

    /// Resolve a scenario from TOML text (`origin` names it in errors) and overrides.
    pub fn from_text(text: Option<&str>, origin: &Path, sets: &[String]) -> Result<Scenario, ScenarioError> {
        Scenario::from_table(merged(text, origin, sets)?)
    }

    /// Resolve a scenario that may give lists for numeric keys (a sweep) into its cells: the
    /// Cartesian product of the lists, in file order. Each cell's `run.seed` is derived from the
    /// base seed and the cell's path (SplitMix64 of seed ⊕ FNV-1a(path)), so cells draw
    /// independent streams, and re-running one cell's recorded scenario reproduces it.
    pub fn resolve_sweep(file: Option<&Path>, sets: &[String]) -> Result<Vec<Cell>, ScenarioError> {
        let table = merged(read(file)?.as_deref(), file.unwrap_or(Path::new("<scenario>")), sets)?;
        let defaults: Table = PAPER_TOML.parse().expect("embedded scenario parses");
        let mut axes: Vec<(String, Vec<Value>)> = Vec::new();
        for (section, entries) in &table {
            let Value::Table(entries) = entries else { continue };
            for (key, value) in entries {
                let numeric_default = matches!(defaults[section][key], Value::Float(_) | Value::Integer(_));
                if let (true, Value::Array(list)) = (numeric_default, value) {
                    let dotted = format!("{section}.{key}");
                    if !SWEEPABLE_SECTIONS.contains(&section.as_str()) {
                        return Err(invalid(&dotted, value, &format!(
                            "a list is a sweep, and only keys of {SWEEPABLE_SECTIONS:?} can be swept (run two simulations for two seeds)"
                        )));
                    }
                    if list.is_empty() {
                        return Err(invalid(&dotted, value, "a swept key needs at least one value"));
                    }
                    let mut seen: Vec<f64> = Vec::new();
                    for v in list {
                        let x = Getter(&table).number(&dotted, v)?;
                        if seen.contains(&x) {
                            return Err(invalid(&dotted, value, &format!("the value {} is listed twice", short(x))));
                        }
                        seen.push(x);
                    }
                    axes.push((dotted, list.clone()));
                }
            }
        }
        let base_seed = Getter(&table).count("run.seed", 0)?;
        let mut cells = Vec::new();
        let total = axes.iter().try_fold(1usize, |n, a| n.checked_mul(a.1.len()).filter(|&n| n <= MAX_CELLS));
        let Some(total) = total else {
            let sizes: Vec<String> = axes.iter().map(|(k, l)| format!("{k}: {}", l.len())).collect();
            return Err(ScenarioError::Invalid {
                key: axes.iter().map(|a| a.0.as_str()).collect::<Vec<_>>().join(", "),
                value: sizes.join(" × "),
                reason: format!("the sweep has more than {MAX_CELLS} cells"),
            });
        };
        for n in 0..total {
            let (mut t, mut values, mut parts, mut rest) = (table.clone(), Vec::new(), Vec::new(), n);
            for (key, list) in axes.iter().rev() {
                let v = &list[rest % list.len()];
                rest /= list.len();
                let x = Getter(&t).number(key, v)?;
                set(&mut t, key, v.clone())?;
                values.push((key.clone(), x));
                parts.push(format!("{}={}", key.rsplit('.').next().unwrap_or(key), hive_value(v)));
            }
            values.reverse();
            parts.reverse();
            let path = parts.join("/");
            if !axes.is_empty() {
                let seed = cell_seed(base_seed, &path);
                set(&mut t, "run.seed", Value::Integer(seed as i64))?;
            }
            cells.push(Cell { values, path, scenario: Scenario::from_table(t)? });
        }
        Ok(cells)
    }
}

/// A hive partition value: an integer as written (5), a float in its shortest round-trip form,
/// positional while that takes at most 16 characters (0.51, 0.00001, 2.5), otherwise with an
/// exponent (1e300, 1.5e-20).
fn hive_value(v: &Value) -> String {
    match v {
        Value::Integer(i) => i.to_string(),
        Value::Float(f) => short(*f),
        other => other.to_string(),
    }
}

/// A number in its shortest round-trip form, never as hundreds of digits (see [`hive_value`]).
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 16 {
        plain
    } else {
        format!("{x:e}")
    }
}

/// The sections whose numeric keys may be swept (lists).
pub const SWEEPABLE_SECTIONS: [&str; 3] = ["model", "belt", "initial_conditions"];

/// The seed of a sweep cell: SplitMix64(seed ⊕ FNV-1a 64(path)), kept below 2^63.
pub fn cell_seed(seed: u64, path: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in path.bytes() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    let mut z = (seed ^ h).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) >> 1
}

/// The text of an optional scenario file (at most [`MAX_FILE_BYTES`], UTF-8).
fn read(file: Option<&Path>) -> Result<Option<String>, ScenarioError> {
    use std::io::Read as _;
    let Some(path) = file else { return Ok(None) };
    let err = |source| ScenarioError::Read { path: path.to_owned(), source };
    let mut bytes = Vec::new();
    std::fs::File::open(path).and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)).map_err(err)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ScenarioError::TooBig { path: path.to_owned(), reason: format!("larger than {MAX_FILE_BYTES} bytes; a scenario is a small TOML file") });
    }
    String::from_utf8(bytes).map(Some).map_err(|_| ScenarioError::TooBig { path: path.to_owned(), reason: "is not UTF-8 text".into() })
}

/// Signed zeros become +0 everywhere (a `-0.0` passes `>= 0` but divides to −∞).
fn positive_zeros(table: &mut Table) {
    fn fix(v: &mut Value) {
        match v {
            Value::Float(x) if *x == 0.0 => *x = 0.0,
            Value::Array(a) => a.iter_mut().for_each(fix),
            Value::Table(t) => t.iter_mut().for_each(|(_, v)| fix(v)),
            _ => {}
        }
    }
    table.iter_mut().for_each(|(_, v)| fix(v));
}

/// The paper scenario ← the user's text ← `--set` overrides, as a table (not yet validated).
fn merged(text: Option<&str>, origin: &Path, sets: &[String]) -> Result<Table, ScenarioError> {
    let mut table: Table = PAPER_TOML.parse().expect("embedded scenario parses");
    if let Some(text) = text {
        let user: Table = text.parse().map_err(|e: toml::de::Error| ScenarioError::Syntax {
            path: origin.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })?;
        merge(&mut table, user, "")?;
    }
    for arg in sets {
        if arg.chars().any(char::is_control) {
            return Err(ScenarioError::BadSetValue { arg: arg.clone(), reason: "contains a newline or control character; give one KEY=VALUE per --set".into() });
        }
        let (key, value) = arg.split_once('=').ok_or_else(|| ScenarioError::BadSet { arg: arg.clone() })?;
        set(&mut table, key.trim(), parse_value(value.trim()))?;
    }
    Ok(table)
}

impl Scenario {
    /// Override one key by its dotted name (the value as TOML, or a bare string).
    pub fn with(self, key: &str, value: &str) -> Result<Scenario, ScenarioError> {
        let mut table = self.table;
        set(&mut table, key, parse_value(value))?;
        Scenario::from_table(table)
    }

    fn from_table(mut table: Table) -> Result<Scenario, ScenarioError> {
        positive_zeros(&mut table);
        let g = Getter(&table);
        let model = Model {
            mass: g.f64("model.mass", |x| x > 0.0, "must be > 0 (kg)")?,
            stiffness: g.f64("model.stiffness", |x| x >= 0.0, "must be >= 0 (N/m)")?,
            normal_force: g.f64("model.normal_force", |x| x >= 0.0, "must be >= 0 (N)")?,
            friction_coefficient: g.f64("model.friction_coefficient", |x| x >= 0.0, "must be >= 0")?,
        };
        let sign = match g.get("belt.initial_sign") {
            Value::Integer(1) => InitialSign::Positive,
            Value::Integer(-1) => InitialSign::Negative,
            Value::String(s) if s == "random" => InitialSign::Random,
            other => return Err(invalid("belt.initial_sign", other, "must be 1, -1 or \"random\"")),
        };
        let belt = Belt {
            speed: g.f64("belt.speed", |x| x > 0.0, "must be > 0 (m/s)")?,
            switch_rate: g.f64("belt.switch_rate", |x| x >= 0.0, "must be >= 0 (1/s)")?,
            initial_sign: sign,
            duration: g.f64("run.duration", |x| x > 0.0, "must be > 0 (s)")?,
        };
        let solver = match g.get("run.solver") {
            Value::String(s) if SOLVERS.contains(&s.as_str()) => s.clone(),
            other => return Err(invalid("run.solver", other, &format!("must be one of {SOLVERS:?}"))),
        };
        let scenario = Scenario {
            model,
            belt,
            position: g.range("initial_conditions.position")?,
            velocity: g.range("initial_conditions.velocity")?,
            realizations: g.bounded_count("run.realizations", 1, MAX_REALIZATIONS)?,
            seed: g.count("run.seed", 0)?,
            solver,
            numerics: Numerics {
                rtol: g.f64("numerics.rtol", |x| x > 0.0, "must be > 0")?,
                atol: g.f64("numerics.atol", |x| x > 0.0, "must be > 0")?,
                max_step: g.f64("numerics.max_step", |x| x > 0.0, "must be > 0 (s)")?,
                step: g.f64("numerics.step", |x| x > 0.0, "must be > 0 (s)")?,
                epsilon: g.f64("numerics.epsilon", |x| x > 0.0, "must be > 0 (m/s)")?,
                stick_velocity: g.f64("numerics.stick_velocity", |x| x > 0.0, "must be > 0 (m/s)")?,
                step_budget: g.count("numerics.step_budget", 1)?,
            },
            store_switch_times: match g.get("output.switch_times") {
                Value::Boolean(b) => *b,
                other => return Err(invalid("output.switch_times", other, "must be true or false")),
            },
            trajectories: g.count("output.trajectories", 0)?,
            trajectory_step: g.f64("output.trajectory_step", |x| x > 0.0, "must be > 0 (s)")?,
            table,
        };
        scenario.check_derived()?;
        Ok(scenario)
    }

    /// Checks on combinations of keys.
    fn check_derived(&self) -> Result<(), ScenarioError> {
        let m = &self.model;
        let a = m.per_unit_mass();
        if !a.omega2.is_finite() || !a.friction.is_finite() || !m.max_friction().is_finite() {
            return Err(ScenarioError::Invalid {
                key: "model".into(),
                value: format!("k/m = {:e} 1/s², mu n/m = {:e} m/s²", a.omega2, a.friction),
                reason: "these ratios must be finite".into(),
            });
        }
        if self.trajectories > 1000 || self.trajectories as f64 * self.belt.duration / self.trajectory_step > MAX_TRAJECTORY_SAMPLES {
            return Err(ScenarioError::Invalid {
                key: "output.trajectories".into(),
                value: self.trajectories.to_string(),
                reason: format!(
                    "at most 1000 trajectories and {MAX_TRAJECTORY_SAMPLES:e} samples in all (run.duration / output.trajectory_step = {:e} each)",
                    self.belt.duration / self.trajectory_step
                ),
            });
        }
        // Numerical solvers: refuse settings that cannot work, before any realization runs.
        let num = &self.numerics;
        let fixed = matches!(self.solver.as_str(), "rk4" | "moreau");
        if self.solver == "rk4" && a.omega * num.step > 1.0 {
            return Err(ScenarioError::Invalid {
                key: "numerics.step".into(),
                value: num.step.to_string(),
                reason: format!(
                    "too coarse for rk4 with ω = √(k/m) = {:e} rad/s: ω·step = {:e} must be at most 1 (RK4 loses accuracy, and is unstable past 2.8)",
                    a.omega,
                    a.omega * num.step
                ),
            });
        }
        let least_steps = self.belt.duration / if fixed { num.step } else { num.max_step };
        if self.solver != "exact" && self.solver != "smooth" && least_steps > num.step_budget as f64 {
            let key = if fixed { "numerics.step" } else { "numerics.max_step" };
            return Err(ScenarioError::Invalid {
                key: key.into(),
                value: (if fixed { num.step } else { num.max_step }).to_string(),
                reason: format!(
                    "run.duration needs at least {least_steps:e} steps, over numerics.step_budget = {}",
                    num.step_budget
                ),
            });
        }
        let expected = self.belt.switch_rate * self.belt.duration;
        if !(expected <= MAX_EXPECTED_SWITCHES) {
            return Err(ScenarioError::Invalid {
                key: "belt.switch_rate".into(),
                value: self.belt.switch_rate.to_string(),
                reason: format!(
                    "belt.switch_rate × run.duration = {expected:e} expected belt flips per realization; at most {MAX_EXPECTED_SWITCHES:e} are supported"
                ),
            });
        }
        Ok(())
    }

    /// The resolved scenario as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string(&self.table).expect("a TOML table serializes")
    }
}

/// A `--set` value: TOML if it parses as TOML (`1.0`, `[-1, 1]`, `"x"`, `true`), else a bare string.
fn parse_value(text: &str) -> Value {
    format!("v = {text}")
        .parse::<Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(text.to_owned()))
}

/// Merge `user` into `base`, refusing keys `base` does not have.
fn merge(base: &mut Table, user: Table, prefix: &str) -> Result<(), ScenarioError> {
    for (key, value) in user {
        let dotted = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
        match (base.get_mut(&key), value) {
            (None, _) => return Err(unknown(&dotted, base)),
            (Some(Value::Table(b)), Value::Table(u)) => merge(b, u, &dotted)?,
            (Some(Value::Table(_)), v) => return Err(invalid(&dotted, &v, "must be a table")),
            (Some(_), Value::Table(_)) => return Err(ScenarioError::UnknownKey { key: dotted, hint: Hint(vec![]) }),
            (Some(slot), v) => *slot = v,
        }
    }
    Ok(())
}

fn set(table: &mut Table, key: &str, value: Value) -> Result<(), ScenarioError> {
    set_in(table, key, key, value)
}

fn set_in(table: &mut Table, full: &str, rest: &str, value: Value) -> Result<(), ScenarioError> {
    let (head, tail) = match rest.split_once('.') {
        Some((head, tail)) => (head, Some(tail)),
        None => (rest, None),
    };
    match (table.get_mut(head), tail) {
        (Some(Value::Table(t)), Some(tail)) => set_in(t, full, tail, value),
        (Some(slot), None) if !slot.is_table() => {
            *slot = value;
            Ok(())
        }
        _ => Err(unknown(full, table)),
    }
}

fn unknown(key: &str, siblings: &Table) -> ScenarioError {
    ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(siblings.keys().cloned().collect()) }
}

fn invalid(key: &str, value: &Value, reason: &str) -> ScenarioError {
    ScenarioError::Invalid { key: key.to_owned(), value: shown(value), reason: reason.to_owned() }
}

/// A value as an error message shows it: numbers in their short form ([`short`]), never as
/// hundreds of digits.
fn shown(v: &Value) -> String {
    match v {
        Value::Float(x) => short(*x),
        Value::Array(a) => format!("[{}]", a.iter().map(shown).collect::<Vec<_>>().join(", ")),
        Value::Table(t) => format!("{{ {} }}", t.iter().map(|(k, v)| format!("{k} = {}", shown(v))).collect::<Vec<_>>().join(", ")),
        other => other.to_string(),
    }
}

/// Typed access to the merged table by dotted key.
struct Getter<'a>(&'a Table);

impl Getter<'_> {
    fn get(&self, key: &str) -> &Value {
        let mut parts = key.split('.');
        let mut v = &self.0[parts.next().unwrap()];
        for p in parts {
            v = &v[p];
        }
        v
    }

    fn number(&self, key: &str, v: &Value) -> Result<f64, ScenarioError> {
        match *v {
            Value::Float(x) => Ok(x),
            Value::Integer(i) => Ok(i as f64),
            ref other => Err(invalid(key, other, "must be a number")),
        }
    }

    fn f64(&self, key: &str, ok: impl Fn(f64) -> bool, reason: &str) -> Result<f64, ScenarioError> {
        let v = self.get(key);
        let x = self.number(key, v)?;
        if x.is_finite() && ok(x) {
            Ok(x)
        } else {
            Err(invalid(key, v, if x.is_finite() { reason } else { "must be finite" }))
        }
    }

    fn range(&self, key: &str) -> Result<[f64; 2], ScenarioError> {
        let v = self.get(key);
        let bad = || invalid(key, v, "must be [lo, hi] with finite lo <= hi and a finite width hi - lo");
        match v {
            Value::Array(a) if a.len() == 2 => {
                let (lo, hi) = (self.number(key, &a[0])?, self.number(key, &a[1])?);
                if lo.is_finite() && hi.is_finite() && lo <= hi && (hi - lo).is_finite() {
                    Ok([lo, hi])
                } else {
                    Err(bad())
                }
            }
            _ => Err(bad()),
        }
    }

    fn count(&self, key: &str, min: i64) -> Result<u64, ScenarioError> {
        match *self.get(key) {
            Value::Integer(i) if i >= min => Ok(i as u64),
            ref other => Err(invalid(key, other, &format!("must be an integer >= {min}"))),
        }
    }

    fn bounded_count(&self, key: &str, min: i64, max: u64) -> Result<u64, ScenarioError> {
        let n = self.count(key, min)?;
        if n > max {
            return Err(invalid(key, self.get(key), &format!("must be at most {max}")));
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_defaults() {
        let s = Scenario::paper();
        assert_eq!(s.model, Model::PAPER);
        assert_eq!(s.belt.switch_rate, 5.0);
        assert_eq!(s.realizations, 18_000);
        assert_eq!(s.position, [-1.0, 1.0]);
    }

    #[test]
    fn set_overrides_and_names_unknown_keys() {
        let s = Scenario::resolve(None, &["belt.switch_rate=1".into(), "belt.initial_sign=random".into()]).unwrap();
        assert_eq!(s.belt.switch_rate, 1.0);
        assert_eq!(s.belt.initial_sign, InitialSign::Random);
        let e = Scenario::resolve(None, &["belt.swich_rate=1".into()]).unwrap_err().to_string();
        assert!(e.contains("belt.swich_rate") && e.contains("switch_rate"), "{e}");
        let e = Scenario::resolve(None, &["model.mass=-1".into()]).unwrap_err().to_string();
        assert!(e.contains("model.mass") && e.contains("> 0"), "{e}");
        let e = Scenario::resolve(None, &["model.mass=nan".into()]).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        let e = Scenario::resolve(None, &["run.realizations=0".into()]).unwrap_err().to_string();
        assert!(e.contains("run.realizations"), "{e}");
    }
}
