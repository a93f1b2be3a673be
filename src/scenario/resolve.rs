//! Resolution: the embedded paper scenario ← the file ← `--set` overrides, merged as TOML,
//! typed once (unknown keys denied) and checked; a sweep resolved into its cells.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::{Table, Value};

use super::belt;
use super::spec::Param;
use super::types::{cell_seed, invalid, shown, shown_list, Cell, Hint, Overrides, Scenario, ScenarioError, MAX_CELLS, MAX_FILE_BYTES, PAPER_TOML};
use crate::shown::short;
use crate::simulation::keys::Key;

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
    pub(super) fn sweep_cells(mut base: Scenario, over: Overrides) -> Result<Vec<Cell>, ScenarioError> {
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

/// The typed scenario of a merged table; errors name the key.
pub(super) fn typed(table: Table) -> Result<Scenario, ScenarioError> {
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
pub(super) fn merged(text: Option<&str>, origin: &Path, base: Option<PathBuf>, sets: &[String]) -> Result<Table, ScenarioError> {
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
        return Err(ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(sections(table)) });
    };
    if OPTIONAL_SECTIONS.contains(&section) && !table.contains_key(section) {
        table.insert(section.to_owned(), Value::Table(Table::new()));
    }
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
        _ => Err(ScenarioError::UnknownKey { key: key.to_owned(), hint: Hint(sections(table)) }),
    }
}

/// The sections the paper scenario leaves out (a `--set` may open them).
const OPTIONAL_SECTIONS: [&str; 2] = ["anchor", "chain"];

/// The sections a key may start with.
fn sections(table: &Table) -> Vec<String> {
    let mut s: Vec<String> = table.keys().cloned().chain(OPTIONAL_SECTIONS.iter().map(|s| s.to_string())).collect();
    s.sort();
    s.dedup();
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Params;
    use crate::scenario::*;
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
