//! Scenario files: TOML in, a typed and validated [`Scenario`] out — every check happens here,
//! before a single realization runs.
//!
//! Resolution order: the embedded paper scenario (`pipelines/paper.toml`) ← the user's file (any
//! subset of keys) ← `--set key=value` overrides (TOML values) ← typed [`Overrides`]
//! (`--realizations`, `--seed`). The merged table is deserialized once into typed structs (serde,
//! unknown keys denied: a typo never silently keeps a default), then validated with every error
//! naming its key. Provenance is the typed value serialized back ([`Scenario::to_toml`]).
//!
//! Any numeric `[model]` or `[belt]` key is a [`Param`]: a number, a list of numbers (a sweep:
//! one cell per value, resolved by [`Scenario::resolve_sweep`]) or a distribution drawn per
//! realization ([`crate::simulation::keys`]).
//!
//! Files: this one resolves (merging, `--set`, sweeps, errors); `spec.rs` is the typed file;
//! `check.rs` validates it and builds the scene it describes.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use toml::{Table, Value};

use crate::simulation::keys::Key;
pub use crate::solver::Numerics;

mod belt;
mod check;
mod input;
mod plan;
mod spec;

pub use crate::shown::short;
pub use crate::simulation::plan::fastest_rate;
pub use input::{Input, Source};
pub use spec::{BeltSpec, InitialConditions, ModelSpec, Output, Param, ParamSlot, ProcessName, Run, Sign};

/// The paper scenario, embedded: the default of every key.
pub const PAPER_TOML: &str = include_str!("../../pipelines/paper.toml");

/// Largest accepted λ·t_a (expected belt switches per realization): their instants are held in memory.
pub const MAX_EXPECTED_SWITCHES: f64 = 1e7;

/// Largest accepted ω·t_a, the natural radians in the horizon (ω = √(k/m)), for the exact
/// solver: its events grow with it (measured at this limit: 0.12 s per realization undamped);
/// past it a run is refused at the door, or per draw naming the realization.
pub const MAX_NATURAL_RADIANS: f64 = 1e7;

/// The same for the numerical solvers, which take several steps per natural radian (rk45 at
/// rtol 1e-6 took 4.7 s per realization at ω·t_a = 1e7, 0.5 s at 1e6).
pub const MAX_NATURAL_RADIANS_NUMERICAL: f64 = 1e6;

/// The range of `run.duration` [s] the solvers are proven on (tests/it/extremes.rs).
pub const DURATION_RANGE: (f64, f64) = (1e-9, 1e6);

/// Largest |X0| [m] of the initial conditions (with ω|X0| at most the largest belt speed).
pub const MAX_POSITION: f64 = 1e9;

/// Most realizations one run may ask for.
pub const MAX_REALIZATIONS: u64 = 1_000_000_000_000;

/// Most cells one sweep may have (each is a full run and a directory).
pub const MAX_CELLS: usize = 10_000;

/// Largest scenario file read (a scenario is a few hundred bytes).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// Most trajectory samples in all (`output.trajectories` × duration / step): about 0.6 GB of CSV.
pub const MAX_TRAJECTORY_SAMPLES: f64 = 1e7;

/// A scenario: the typed file. Fields may be set directly; [`Scenario::check`] validates again.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// `[model]`: the oscillator and its friction
    pub model: ModelSpec,
    /// `[belt]`: the belt process
    pub belt: BeltSpec,
    /// `[initial_conditions]`: the ranges X0, Ẋ0 are drawn from
    pub initial_conditions: InitialConditions,
    /// `[run]`: window, realizations, seed, solver
    pub run: Run,
    /// `[numerics]`: the solvers' tolerances, steps and budgets
    pub numerics: Numerics,
    /// `[output]`: what is stored beside the events
    pub output: Output,
}

/// Typed overrides applied after `--set` (`--realizations`, `--seed`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Overrides {
    /// `--realizations`: replaces `run.realizations`
    pub realizations: Option<u64>,
    /// `--seed`: replaces `run.seed`
    pub seed: Option<u64>,
}

/// One cell of a parameter sweep: the swept keys' values, its hive path and its scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// (dotted key, value) of each swept key, in the order of their names
    pub values: Vec<(String, f64)>,
    /// `name=value/...` with the last component of each key (empty without a sweep)
    pub path: String,
    /// the cell's scenario (every swept key at its value, `run.seed` derived for the cell)
    pub scenario: Scenario,
}

/// Everything that can be wrong with a scenario, each naming its culprit.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The scenario file could not be read.
    #[error("cannot read scenario file {}: {source}", path.display())]
    Read {
        /// the file
        path: PathBuf,
        /// the I/O error
        source: std::io::Error,
    },
    /// The scenario file is not valid TOML.
    #[error("scenario file {} is not valid TOML: {message}", path.display())]
    Syntax {
        /// the file (`<scenario>` for text without one)
        path: PathBuf,
        /// the parser's error, on one line with its line and column
        message: String,
    },
    /// A key the scenario does not have (a typo is never ignored).
    #[error("unknown scenario key `{key}`{hint}")]
    UnknownKey {
        /// the dotted key
        key: String,
        /// the keys known at that place
        hint: Hint,
    },
    /// A key's value is of the wrong type or out of range.
    #[error("scenario key `{key}` = {value}: {reason}")]
    Invalid {
        /// the dotted key
        key: String,
        /// the value as written (`(missing)` when absent)
        value: String,
        /// what is wrong with it
        reason: String,
    },
    /// A `--set` argument that is not `KEY=VALUE`.
    #[error("--set {arg:?}: expected KEY=VALUE with a dotted key, e.g. --set belt.switch_rate=1.0")]
    BadSet {
        /// the argument as given
        arg: String,
    },
    /// A `--set` value that cannot be used.
    #[error("--set {arg:?}: {reason}")]
    BadSetValue {
        /// the argument as given
        arg: String,
        /// what is wrong with it
        reason: String,
    },
    /// The scenario file is not a small regular UTF-8 file.
    #[error("scenario file {}: {reason}", path.display())]
    Unreadable {
        /// the file
        path: PathBuf,
        /// why it is refused
        reason: String,
    },
}

impl crate::blame::Blame for ScenarioError {
    /// Every one: a scenario error names the key, value or file at fault.
    fn blame(&self) -> Option<crate::blame::Culprit> {
        Some(crate::blame::Culprit::Scenario)
    }
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
    /// A relative `belt.file` in the file is a path from the file's directory (as a scenario
    /// and its log are shipped side by side), recorded as an absolute path; one given by `--set`
    /// is a path from the working directory.
    pub fn resolve(file: Option<&Path>, sets: &[String]) -> Result<Scenario, ScenarioError> {
        let sc = typed(merged(read(file)?.as_deref(), file.unwrap_or(Path::new("<scenario>")), file.map(belt::base_dir), sets)?)?;
        sc.check()?;
        Ok(sc)
    }

    /// Resolve a scenario from TOML text (`origin` names it in errors) and overrides (a relative
    /// `belt.file` is a path from the working directory).
    pub fn from_text(text: Option<&str>, origin: &Path, sets: &[String]) -> Result<Scenario, ScenarioError> {
        let sc = typed(merged(text, origin, None, sets)?)?;
        sc.check()?;
        Ok(sc)
    }

    /// A scenario recorded in a dataset or an analysis, read as provenance: typed (its keys
    /// must exist), but not checked against today's ranges, so that data written before a range
    /// tightened stays readable. The stages that read one guard the values they compute with
    /// themselves (e.g. `analyze` bounds every event time by the recorded t_a).
    pub fn recorded(text: &str, origin: &Path) -> Result<Scenario, ScenarioError> {
        typed(merged(Some(text), origin, None, &[])?)
    }

    /// Refuse a swept key (a list) for `stage`, which runs one scene: the first swept key named.
    pub fn refuse_sweep(&self, stage: &str) -> Result<(), ScenarioError> {
        match Key::ALL.into_iter().find_map(|k| match self.param(k) {
            Some(Param::Sweep(list)) => Some((k, list)),
            _ => None,
        }) {
            Some((key, list)) => {
                Err(invalid(key.dotted(), &shown_list(list), &format!("{stage} runs one scene, not a sweep: give one value (run {stage} once per value)")))
            }
            None => Ok(()),
        }
    }

    /// Resolve a scenario whose `[model]`/`[belt]` keys may be lists (a sweep) into its cells: the
    /// Cartesian product of the lists, keys in the order of their dotted names (`belt.*` before
    /// `model.*`; the hive path nests them in that order). Each cell's `run.seed` is derived from the
    /// base seed and the cell's path (SplitMix64 of seed ⊕ FNV-1a(path)), so cells draw
    /// independent streams, and re-running one cell's recorded scenario reproduces it.
    pub fn resolve_sweep(file: Option<&Path>, sets: &[String], over: Overrides) -> Result<Vec<Cell>, ScenarioError> {
        Scenario::sweep_cells(typed(merged(read(file)?.as_deref(), file.unwrap_or(Path::new("<scenario>")), file.map(belt::base_dir), sets)?)?, over)
    }

    /// The cells of the sweep `base` (typed, not yet checked) with `over` applied.
    fn sweep_cells(mut base: Scenario, over: Overrides) -> Result<Vec<Cell>, ScenarioError> {
        over.apply(&mut base);
        let mut axes: Vec<(Key, Vec<f64>)> = Vec::new();
        for key in Key::ALL {
            if let Some(Param::Sweep(list)) = base.param(key) {
                if list.is_empty() {
                    return Err(invalid(key.dotted(), "[]", "a swept key needs at least one value"));
                }
                let mut seen: Vec<f64> = Vec::new();
                for &x in list {
                    if seen.contains(&x) {
                        return Err(invalid(key.dotted(), &shown_list(list), &format!("the value {} is listed twice", short(x))));
                    }
                    seen.push(x);
                }
                axes.push((key, list.clone()));
            }
        }
        axes.sort_by_key(|a| a.0.dotted());
        let total = axes.iter().try_fold(1usize, |n, a| n.checked_mul(a.1.len()).filter(|&n| n <= MAX_CELLS));
        let Some(total) = total else {
            let sizes: Vec<String> = axes.iter().map(|(k, l)| format!("{}: {}", k.dotted(), l.len())).collect();
            return Err(ScenarioError::Invalid {
                key: axes.iter().map(|a| a.0.dotted()).collect::<Vec<_>>().join(", "),
                value: sizes.join(" × "),
                reason: format!("the sweep has more than {MAX_CELLS} cells"),
            });
        };
        let mut cells = Vec::with_capacity(total);
        for n in 0..total {
            let (mut sc, mut values, mut parts, mut rest) = (base.clone(), Vec::new(), Vec::new(), n);
            for (key, list) in axes.iter().rev() {
                let x = list[rest % list.len()];
                rest /= list.len();
                sc.param_mut(*key).set(Param::Value(x));
                values.push((key.dotted().to_string(), x));
                parts.push(format!("{}={}", key.name(), short(x)));
            }
            values.reverse();
            parts.reverse();
            let path = parts.join("/");
            if !axes.is_empty() {
                sc.run.seed = cell_seed(base.run.seed, &path);
            }
            sc.check()?;
            cells.push(Cell { values, path, scenario: sc });
        }
        Ok(cells)
    }

    /// The resolved scenario as TOML text (the provenance datasets record).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a scenario serializes")
    }
}

impl Overrides {
    /// Set the typed fields.
    pub fn apply(&self, sc: &mut Scenario) {
        if let Some(n) = self.realizations {
            sc.run.realizations = n;
        }
        if let Some(s) = self.seed {
            sc.run.seed = s;
        }
    }
}

/// The typed scenario of a merged table; errors name the key.
fn typed(table: Table) -> Result<Scenario, ScenarioError> {
    let mut table = table;
    positive_zeros(&mut table);
    Scenario::deserialize(table.clone()).map_err(|e| schema_error(&e, &table))
}

/// A serde error as a scenario error naming the key (toml records the key path).
fn schema_error(e: &toml::de::Error, table: &Table) -> ScenarioError {
    let text = e.to_string();
    let path = text.lines().find_map(|l| l.strip_prefix("in `").and_then(|s| s.strip_suffix('`'))).unwrap_or("").to_string();
    let msg = e.message();
    if let Some(rest) = msg.strip_prefix("unknown field `") {
        let field = rest.split('`').next().unwrap_or("");
        let known = msg.split_once("expected").map_or(vec![], |(_, k)| k.split('`').skip(1).step_by(2).map(str::to_string).collect());
        let key = if path.is_empty() { field.to_string() } else { format!("{path}.{field}") };
        return ScenarioError::UnknownKey { key, hint: Hint(known) };
    }
    let mut v = Some(&Value::Table(table.clone()));
    for part in path.split('.').filter(|p| !p.is_empty()) {
        v = v.and_then(|v| v.get(part));
    }
    let owned = v.map_or_else(|| "(missing)".to_string(), shown);
    ScenarioError::Invalid { key: path, value: owned, reason: msg.trim_end().to_string() }
}

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
    // a regular file only: a FIFO or a device would block or never end
    let meta = std::fs::metadata(path).map_err(err)?;
    if !meta.is_file() {
        return Err(ScenarioError::Unreadable { path: path.to_owned(), reason: "is not a regular file (a scenario is a TOML file)".into() });
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path).and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)).map_err(err)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ScenarioError::Unreadable {
            path: path.to_owned(),
            reason: format!("larger than {MAX_FILE_BYTES} bytes; a scenario is a small TOML file"),
        });
    }
    String::from_utf8(bytes).map(Some).map_err(|_| ScenarioError::Unreadable { path: path.to_owned(), reason: "is not UTF-8 text".into() })
}

/// A TOML error on one line: `line L, column C: what` (the parser's own text spans several
/// lines and quotes the offending line, control bytes included).
fn syntax_message(text: &str, e: &toml::de::Error) -> String {
    let what = e.message().split_whitespace().collect::<Vec<_>>().join(" ");
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {column}: {what}")
        }
        None => what,
    }
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

/// The paper scenario ← the user's text ← `--set` overrides, as a table (not yet typed); a
/// relative `belt.file` of the text is joined to `base` when given.
fn merged(text: Option<&str>, origin: &Path, base: Option<PathBuf>, sets: &[String]) -> Result<Table, ScenarioError> {
    let mut table: Table = PAPER_TOML.parse().expect("embedded scenario parses");
    if let Some(text) = text {
        let mut user: Table =
            text.parse().map_err(|e: toml::de::Error| ScenarioError::Syntax { path: origin.to_owned(), message: syntax_message(text, &e) })?;
        belt::anchor_log(&mut user, base);
        fold_friction_table(&mut user)?;
        merge(&mut table, user, "")?;
    }
    for arg in sets {
        if arg.chars().any(char::is_control) {
            return Err(ScenarioError::BadSetValue {
                arg: arg.clone(),
                reason: "contains a newline or control character; give one KEY=VALUE per --set".into(),
            });
        }
        let (key, value) = arg.split_once('=').ok_or_else(|| ScenarioError::BadSet { arg: arg.clone() })?;
        let key = key.trim();
        let flat = match key.strip_prefix("model.friction.") {
            Some(leaf) => format!("model.{}", friction_key(leaf)?),
            None => key.to_owned(),
        };
        set(&mut table, &flat, parse_value(value.trim()))?;
    }
    Ok(table)
}

/// The `[model.friction]` table: the law and its parameters under the law, each the same value
/// as a flat `[model]` key (the canonical form, and the one provenance records).
const FRICTION_TABLE: [(&str, &str); 6] = [
    ("law", "friction_law"),
    ("kinetic", "friction_coefficient"),
    ("static", "static_friction_coefficient"),
    ("velocity", "stribeck_velocity"),
    ("exponent", "stribeck_exponent"),
    ("viscous", "viscous_friction"),
];

/// The flat `[model]` key of a `[model.friction]` key.
fn friction_key(leaf: &str) -> Result<&'static str, ScenarioError> {
    FRICTION_TABLE.iter().find(|(k, _)| *k == leaf).map(|(_, flat)| *flat).ok_or_else(|| ScenarioError::UnknownKey {
        key: format!("model.friction.{leaf}"),
        hint: Hint(FRICTION_TABLE.iter().map(|(k, _)| k.to_string()).collect()),
    })
}

/// Fold a user's `[model.friction]` table (`law = "stribeck"`, `kinetic`, `static`, `velocity`,
/// `exponent`, `viscous`) into the flat `[model]` keys; a key given both ways is refused.
fn fold_friction_table(user: &mut Table) -> Result<(), ScenarioError> {
    let Some(Value::Table(model)) = user.get_mut("model") else { return Ok(()) };
    let Some(friction) = model.remove("friction") else { return Ok(()) };
    let Value::Table(friction) = friction else {
        return Err(invalid("model.friction", &shown(&friction), "must be a table, e.g. [model.friction] with law = \"stribeck\""));
    };
    for (leaf, value) in friction {
        let flat = friction_key(&leaf)?;
        if model.contains_key(flat) {
            return Err(invalid(&format!("model.friction.{leaf}"), &shown(&value), &format!("model.{flat} is given too: give one of the two")));
        }
        model.insert(flat.to_owned(), value);
    }
    Ok(())
}

/// A `--set` value: TOML if it parses as TOML (`1.0`, `[-1, 1]`, `{ dist = … }`, `"x"`), else a
/// bare string.
fn parse_value(text: &str) -> Value {
    format!("v = {text}").parse::<Table>().ok().and_then(|mut t| t.remove("v")).unwrap_or_else(|| Value::String(text.to_owned()))
}

/// Merge `user` into `base` (tables merge, values replace; unknown keys are left for the typed
/// step to name).
fn merge(base: &mut Table, user: Table, prefix: &str) -> Result<(), ScenarioError> {
    for (key, value) in user {
        let dotted = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
        match (base.get_mut(&key), value) {
            (Some(Value::Table(b)), Value::Table(u)) if !is_dist(&u) => merge(b, u, &dotted)?,
            (Some(Value::Table(_)), v) => return Err(invalid(&dotted, &shown(&v), "must be a table")),
            (None, Value::Table(u)) if prefix.is_empty() => {
                base.insert(key, Value::Table(u));
            }
            (_, v) => {
                base.insert(key, v);
            }
        }
    }
    Ok(())
}

fn is_dist(t: &Table) -> bool {
    t.contains_key("dist")
}

/// Set one dotted key (its section must exist; the typed step refuses unknown leaves).
fn set(table: &mut Table, key: &str, value: Value) -> Result<(), ScenarioError> {
    let Some((section, leaf)) = key.split_once('.') else {
        return Err(ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(table.keys().cloned().collect()) });
    };
    match table.get_mut(section) {
        Some(Value::Table(t)) if !leaf.contains('.') && !leaf.is_empty() => {
            t.insert(leaf.to_owned(), value);
            Ok(())
        }
        // a key below a leaf (`model.mass.sub`): the keys of its section are the ones to show
        Some(Value::Table(t)) => {
            let known = Key::ALL.into_iter().map(|k| k.dotted().to_string()).filter(|k| k.starts_with(&format!("{section}.")));
            let mut keys: Vec<String> = t.keys().map(|k| format!("{section}.{k}")).chain(known).collect();
            keys.sort();
            keys.dedup();
            Err(ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(keys) })
        }
        _ => Err(ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(table.keys().cloned().collect()) }),
    }
}

fn invalid(key: &str, value: &str, reason: &str) -> ScenarioError {
    ScenarioError::Invalid { key: key.to_owned(), value: value.to_owned(), reason: reason.to_owned() }
}

fn shown_list(l: &[f64]) -> String {
    format!("[{}]", l.iter().map(|x| short(*x)).collect::<Vec<_>>().join(", "))
}

fn shown_param(p: &Param) -> String {
    shown(&Value::try_from(p).unwrap_or(Value::String("?".into())))
}

/// A value as an error message shows it: numbers in their short form ([`short`]).
fn shown(v: &Value) -> String {
    match v {
        Value::Float(x) => short(*x),
        Value::Array(a) => format!("[{}]", a.iter().map(shown).collect::<Vec<_>>().join(", ")),
        Value::Table(t) => format!("{{ {} }}", t.iter().map(|(k, v)| format!("{k} = {}", shown(v))).collect::<Vec<_>>().join(", ")),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Params;
    use crate::simulation::belt::InitialSign;
    use crate::solver::SolverKind;

    #[test]
    fn paper_defaults() {
        let s = Scenario::paper();
        assert_eq!(s.scene().unwrap().params, Params::PAPER);
        assert_eq!(s.run.realizations, 18_000);
        assert_eq!(s.initial_conditions.position, [-1.0, 1.0]);
        assert_eq!(s.solver(), SolverKind::Exact);
    }

    #[test]
    fn set_overrides_and_names_unknown_keys() {
        let s = Scenario::resolve(None, &["belt.switch_rate=1".into(), "belt.initial_sign=random".into()]).unwrap();
        assert_eq!(s.belt.switch_rate, Param::Value(1.0));
        assert_eq!(s.belt.initial_sign, Sign(InitialSign::Random));
        let e = Scenario::resolve(None, &["belt.swich_rate=1".into()]).unwrap_err().to_string();
        assert!(e.contains("belt.swich_rate") && e.contains("switch_rate"), "{e}");
        let e = Scenario::resolve(None, &["model.mass=-1".into()]).unwrap_err().to_string();
        assert!(e.contains("model.mass") && e.contains("between 1e-9 and 1e6 (kg)"), "{e}");
        let e = Scenario::resolve(None, &["model.mass=nan".into()]).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        let e = Scenario::resolve(None, &["run.realizations=0".into()]).unwrap_err().to_string();
        assert!(e.contains("run.realizations"), "{e}");
        let e = Scenario::resolve(None, &["run.solver=rk5".into()]).unwrap_err().to_string();
        assert!(e.contains("run.solver") && e.contains("rk45"), "{e}");
    }

    #[test]
    fn provenance_round_trips() {
        let s =
            Scenario::resolve(None, &["model.damping=0.5".into(), "model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}".into()]).unwrap();
        let again = Scenario::from_text(Some(&s.to_toml()), Path::new("x"), &[]).unwrap();
        assert_eq!(s, again);
    }

    #[test]
    fn the_friction_table_is_the_flat_keys() {
        let table = "[model.friction]\nlaw = \"stribeck\"\nkinetic = 0.4\nstatic = 0.7\nvelocity = 0.05\nexponent = 1.0\nviscous = 0.3\n";
        let flat = "[model]\nfriction_law = \"stribeck\"\nfriction_coefficient = 0.4\nstatic_friction_coefficient = 0.7\nstribeck_velocity = 0.05\nstribeck_exponent = 1.0\nviscous_friction = 0.3\n";
        let (a, b) = (Scenario::from_text(Some(table), Path::new("t"), &[]).unwrap(), Scenario::from_text(Some(flat), Path::new("f"), &[]).unwrap());
        assert_eq!(a, b);
        // --set reaches the table's keys too, a sweep included
        let c = Scenario::resolve(None, &["model.friction.static=[0.6, 0.7]".into()]).unwrap();
        assert_eq!(c.model.static_friction_coefficient, Some(Param::Sweep(vec![0.6, 0.7])));
        let e =
            Scenario::from_text(Some("[model]\nfriction_coefficient = 0.4\n[model.friction]\nkinetic = 0.5\n"), Path::new("x"), &[]).unwrap_err().to_string();
        assert!(e.contains("model.friction.kinetic") && e.contains("model.friction_coefficient is given too"), "{e}");
        let e = Scenario::resolve(None, &["model.friction.stribek=1".into()]).unwrap_err().to_string();
        assert!(e.contains("model.friction.stribek") && e.contains("velocity"), "{e}");
    }
}
