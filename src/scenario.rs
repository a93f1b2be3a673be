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
//! realization ([`crate::params`]).

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use toml::{Table, Value};

use crate::belt::{Belt, InitialSign, Process, Symmetric, Telegraph};
use crate::params::{Dist, Key, Scene};
use crate::physics::{FrictionLaw, Params, Stribeck};
pub use crate::solver::Numerics;
use crate::solver::SolverKind;

/// The paper scenario, embedded: the default of every key.
pub const PAPER_TOML: &str = include_str!("../pipelines/paper.toml");

/// Largest accepted λ·t_a (expected belt switches per realization): their instants are held in memory.
pub const MAX_EXPECTED_SWITCHES: f64 = 1e7;

/// Most realizations one run may ask for.
pub const MAX_REALIZATIONS: u64 = 1_000_000_000_000;

/// Most cells one sweep may have (each is a full run and a directory).
pub const MAX_CELLS: usize = 10_000;

/// Largest scenario file read (a scenario is a few hundred bytes).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// Most trajectory samples in all (`output.trajectories` × duration / step): about 0.6 GB of CSV.
pub const MAX_TRAJECTORY_SAMPLES: f64 = 1e7;

/// A numeric scene key as written: a number, a sweep or a distribution.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Param {
    Value(f64),
    Sweep(Vec<f64>),
    Random(Dist),
}

impl<'de> Deserialize<'de> for Param {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Param, D::Error> {
        use serde::de::Error;
        let number = |v: &Value| match *v {
            Value::Float(x) => Some(x),
            Value::Integer(i) => Some(i as f64),
            _ => None,
        };
        let v = Value::deserialize(d)?;
        match &v {
            Value::Array(list) => list.iter().map(number).collect::<Option<Vec<f64>>>().map(Param::Sweep).ok_or_else(|| {
                D::Error::custom("a list is a sweep and lists numbers only (a key cannot be both swept and random)")
            }),
            Value::Table(t) => Dist::deserialize(t.clone()).map(Param::Random).map_err(|e| D::Error::custom(e.message())),
            other => number(other).map(Param::Value).ok_or_else(|| {
                D::Error::custom("must be a number, a list of numbers (a sweep) or a distribution such as { dist = \"uniform\", low = 0.3, high = 0.7 }")
            }),
        }
    }
}

/// `[model]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// m, kg, > 0
    pub mass: Param,
    /// k, N/m, ≥ 0
    pub stiffness: Param,
    /// n, N, ≥ 0
    pub normal_force: Param,
    /// μ_k, ≥ 0
    pub friction_coefficient: Param,
    /// c, N·s/m, ≥ 0 (absent: 0)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<Param>,
    /// μ_s ≥ μ_k (absent: = μ_k)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_friction_coefficient: Option<Param>,
    /// absent: coulomb
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_law: Option<FrictionLaw>,
    /// v_s, m/s, > 0 (required by the Stribeck law)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_velocity: Option<Param>,
    /// δ, > 0 (absent: 2)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_exponent: Option<Param>,
}

/// `belt.initial_sign`: 1, −1 or "random".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sign(pub InitialSign);

impl Serialize for Sign {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0 {
            InitialSign::Positive => s.serialize_i64(1),
            InitialSign::Negative => s.serialize_i64(-1),
            InitialSign::Random => s.serialize_str("random"),
        }
    }
}

impl<'de> Deserialize<'de> for Sign {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Sign, D::Error> {
        match Value::deserialize(d)? {
            Value::Integer(1) => Ok(Sign(InitialSign::Positive)),
            Value::Integer(-1) => Ok(Sign(InitialSign::Negative)),
            Value::String(s) if s == "random" => Ok(Sign(InitialSign::Random)),
            _ => Err(serde::de::Error::custom("must be 1, -1 or \"random\"")),
        }
    }
}

/// `[belt]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeltSpec {
    /// v0 = v_f, m/s, > 0
    pub speed: Param,
    /// λ = λ_f, 1/s, ≥ 0
    pub switch_rate: Param,
    pub initial_sign: Sign,
    /// v_r, m/s, > 0 (with `reverse_switch_rate`: the asymmetric telegraph belt)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reverse_speed: Option<Param>,
    /// λ_r, 1/s, ≥ 0
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reverse_switch_rate: Option<Param>,
}

/// `[initial_conditions]`: uniform ranges [lo, hi].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialConditions {
    /// X0, m
    pub position: [f64; 2],
    /// Ẋ0, m/s
    pub velocity: [f64; 2],
}

/// `[run]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Run {
    /// t_a, s, > 0
    pub duration: f64,
    pub realizations: u64,
    pub seed: u64,
    pub solver: SolverKind,
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    pub switch_times: bool,
    /// realizations 0..N sampled for trajectories (0: none)
    pub trajectories: u64,
    /// s
    pub trajectory_step: f64,
}

/// A scenario: the typed file. Fields may be set directly; [`Scenario::check`] validates again.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub model: ModelSpec,
    pub belt: BeltSpec,
    pub initial_conditions: InitialConditions,
    pub run: Run,
    pub numerics: Numerics,
    pub output: Output,
}

/// Typed overrides applied after `--set` (`--realizations`, `--seed`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Overrides {
    pub realizations: Option<u64>,
    pub seed: Option<u64>,
}

/// One cell of a parameter sweep: the swept keys' values, its hive path and its scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// (dotted key, value) of each swept key, in the order of their names
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
        let sc = typed(merged(text, origin, sets)?)?;
        sc.check()?;
        Ok(sc)
    }

    /// Resolve a scenario whose `[model]`/`[belt]` keys may be lists (a sweep) into its cells: the
    /// Cartesian product of the lists, keys in the order of their dotted names (`belt.*` before
    /// `model.*`; the hive path nests them in that order). Each cell's `run.seed` is derived from the
    /// base seed and the cell's path (SplitMix64 of seed ⊕ FNV-1a(path)), so cells draw
    /// independent streams, and re-running one cell's recorded scenario reproduces it.
    pub fn resolve_sweep(file: Option<&Path>, sets: &[String], over: Overrides) -> Result<Vec<Cell>, ScenarioError> {
        let mut base = typed(merged(read(file)?.as_deref(), file.unwrap_or(Path::new("<scenario>")), sets)?)?;
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
                sc.param_mut(*key).set(Some(Param::Value(x)));
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

    /// Whether the scene's slips have closed forms: Coulomb friction, or a Stribeck law whose
    /// μ_s is μ_k (no `static_friction_coefficient`), which is Coulomb.
    pub fn has_closed_forms(&self) -> bool {
        self.model.friction_law != Some(FrictionLaw::Stribeck) || self.model.static_friction_coefficient.is_none()
    }

    /// The solver that actually runs: `auto` is `exact` where the scene has closed forms, else
    /// `rk45` at the `[numerics]` tolerances.
    pub fn solver(&self) -> SolverKind {
        match self.run.solver {
            SolverKind::Auto if self.has_closed_forms() => SolverKind::Exact,
            SolverKind::Auto => SolverKind::Rk45,
            other => other,
        }
    }

    /// The scene every realization is drawn from: fixed parameters, random keys, the belt.
    pub fn scene(&self) -> Result<Scene, ScenarioError> {
        let m = &self.model;
        let fixed = |p: &Option<Param>| match p {
            Some(Param::Value(x)) => Some(*x),
            _ => None,
        };
        let value = |p: &Param| match p {
            Param::Value(x) => *x,
            Param::Random(d) => d.mean(),
            Param::Sweep(l) => l[0],
        };
        let kinetic = value(&m.friction_coefficient);
        let params = Params {
            mass: value(&m.mass),
            stiffness: value(&m.stiffness),
            damping: m.damping.as_ref().map_or(0.0, value),
            normal_force: value(&m.normal_force),
            kinetic,
            static_: m.static_friction_coefficient.as_ref().map_or(kinetic, value),
            law: m.friction_law.unwrap_or(FrictionLaw::Coulomb),
            stribeck: Stribeck {
                velocity: m.stribeck_velocity.as_ref().map_or(Params::PAPER.stribeck.velocity, value),
                exponent: m.stribeck_exponent.as_ref().map_or(2.0, value),
            },
        };
        let b = &self.belt;
        let (speed, rate) = (value(&b.speed), value(&b.switch_rate));
        let symmetric = match (&b.reverse_speed, &b.reverse_switch_rate) {
            (None, None) => true,
            (Some(rs), Some(rr)) => fixed(&Some(rs.clone())) == Some(speed) && fixed(&Some(rr.clone())) == Some(rate) && !matches!(b.speed, Param::Random(_)) && !matches!(b.switch_rate, Param::Random(_)),
            (Some(_), None) | (None, Some(_)) => {
                let (k, other) = if b.reverse_speed.is_some() { ("belt.reverse_speed", "belt.reverse_switch_rate") } else { ("belt.reverse_switch_rate", "belt.reverse_speed") };
                return Err(invalid(k, "(set)", &format!("the asymmetric belt needs {other} too (give both, or neither for the paper's symmetric belt)")));
            }
        };
        let process = if symmetric {
            Process::Symmetric(Symmetric { speed, switch_rate: rate })
        } else {
            Process::Telegraph(Telegraph {
                forward_speed: speed,
                forward_rate: rate,
                reverse_speed: b.reverse_speed.as_ref().map_or(speed, value),
                reverse_rate: b.reverse_switch_rate.as_ref().map_or(rate, value),
            })
        };
        let belt = Belt { process, initial_sign: b.initial_sign.0, duration: self.run.duration };
        let random = Key::ALL
            .into_iter()
            .filter_map(|k| match self.param(k) {
                Some(Param::Random(d)) => Some((k, *d)),
                _ => None,
            })
            .collect();
        Ok(Scene::new(params, belt, random))
    }

    /// The mean λ t_a of the Poisson number of belt switches: the paper's symmetric belt at a
    /// fixed rate only (None otherwise).
    pub fn poisson_mean(&self) -> Option<f64> {
        let scene = self.scene().ok()?;
        let random_rate = scene.random.iter().any(|(k, _)| *k == Key::SwitchRate);
        match scene.belt.process {
            Process::Symmetric(p) if !random_rate => Some(p.switch_rate * self.run.duration),
            _ => None,
        }
    }

    /// The [`Param`] of a scene key (None: absent).
    pub fn param(&self, key: Key) -> Option<&Param> {
        let (m, b) = (&self.model, &self.belt);
        match key {
            Key::Mass => Some(&m.mass),
            Key::Stiffness => Some(&m.stiffness),
            Key::Damping => m.damping.as_ref(),
            Key::NormalForce => Some(&m.normal_force),
            Key::Kinetic => Some(&m.friction_coefficient),
            Key::Static => m.static_friction_coefficient.as_ref(),
            Key::Speed => Some(&b.speed),
            Key::SwitchRate => Some(&b.switch_rate),
            Key::ReverseSpeed => b.reverse_speed.as_ref(),
            Key::ReverseSwitchRate => b.reverse_switch_rate.as_ref(),
            Key::StribeckVelocity => m.stribeck_velocity.as_ref(),
            Key::StribeckExponent => m.stribeck_exponent.as_ref(),
        }
    }

    /// The slot of a scene key, to set it.
    pub fn param_mut(&mut self, key: Key) -> ParamSlot<'_> {
        let (m, b) = (&mut self.model, &mut self.belt);
        match key {
            Key::Mass => ParamSlot::Required(&mut m.mass),
            Key::Stiffness => ParamSlot::Required(&mut m.stiffness),
            Key::Damping => ParamSlot::Optional(&mut m.damping),
            Key::NormalForce => ParamSlot::Required(&mut m.normal_force),
            Key::Kinetic => ParamSlot::Required(&mut m.friction_coefficient),
            Key::Static => ParamSlot::Optional(&mut m.static_friction_coefficient),
            Key::Speed => ParamSlot::Required(&mut b.speed),
            Key::SwitchRate => ParamSlot::Required(&mut b.switch_rate),
            Key::ReverseSpeed => ParamSlot::Optional(&mut b.reverse_speed),
            Key::ReverseSwitchRate => ParamSlot::Optional(&mut b.reverse_switch_rate),
            Key::StribeckVelocity => ParamSlot::Optional(&mut m.stribeck_velocity),
            Key::StribeckExponent => ParamSlot::Optional(&mut m.stribeck_exponent),
        }
    }

    /// Every check: each key in its range, each distribution's support inside its key's range,
    /// and the combinations (μ_s ≥ μ_k for every draw, finite ratios, budgets).
    pub fn check(&self) -> Result<(), ScenarioError> {
        for key in Key::ALL {
            if let Some(p) = self.param(key) {
                check_param(key, p)?;
            }
        }
        let (lo_s, _) = self.model.static_friction_coefficient.as_ref().map_or((f64::INFINITY, 0.0), support);
        let (_, hi_k) = support(&self.model.friction_coefficient);
        if self.model.static_friction_coefficient.is_some() && lo_s < hi_k {
            return Err(invalid(
                "model.static_friction_coefficient",
                &shown_param(self.model.static_friction_coefficient.as_ref().unwrap()),
                &format!("must be >= model.friction_coefficient for every draw (the smallest possible is {}, the largest friction_coefficient {})", short(lo_s), short(hi_k)),
            ));
        }
        let law = self.model.friction_law.unwrap_or(FrictionLaw::Coulomb);
        if law == FrictionLaw::Stribeck && self.model.stribeck_velocity.is_none() {
            return Err(invalid("model.stribeck_velocity", "(absent)", "the Stribeck law needs v_s > 0 (m/s)"));
        }
        if law != FrictionLaw::Stribeck {
            if let Some(key) = [(Key::StribeckVelocity), (Key::StribeckExponent)].into_iter().find(|&k| self.param(k).is_some()) {
                return Err(invalid(key.dotted(), "(set)", "only the Stribeck law uses it: set model.friction_law = \"stribeck\" too"));
            }
        }
        if self.run.solver == SolverKind::Exact && !self.has_closed_forms() {
            return Err(invalid(
                "model.friction_law",
                "\"stribeck\"",
                "has no closed-form slip, so run.solver = \"exact\" cannot run it: use \"auto\" (rk45) or a numerical solver",
            ));
        }
        let r = &self.run;
        if !(r.duration.is_finite() && r.duration > 0.0) {
            return Err(invalid("run.duration", &short(r.duration), "must be > 0 (s) and finite"));
        }
        if r.realizations == 0 || r.realizations > MAX_REALIZATIONS {
            return Err(invalid("run.realizations", &r.realizations.to_string(), &format!("must be between 1 and {MAX_REALIZATIONS}")));
        }
        if r.seed > i64::MAX as u64 {
            return Err(invalid("run.seed", &r.seed.to_string(), &format!("must be at most {}", i64::MAX)));
        }
        for (key, [lo, hi]) in [("initial_conditions.position", self.initial_conditions.position), ("initial_conditions.velocity", self.initial_conditions.velocity)] {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi && (hi - lo).is_finite()) {
                return Err(invalid(key, &format!("[{}, {}]", short(lo), short(hi)), "must be [lo, hi] with finite lo <= hi and a finite width hi - lo"));
            }
        }
        let n = &self.numerics;
        for (key, x, unit) in [
            ("numerics.rtol", n.rtol, ""),
            ("numerics.atol", n.atol, ""),
            ("numerics.max_step", n.max_step, " (s)"),
            ("numerics.step", n.step, " (s)"),
            ("numerics.epsilon", n.epsilon, " (m/s)"),
            ("numerics.stick_velocity", n.stick_velocity, " (m/s)"),
            ("output.trajectory_step", self.output.trajectory_step, " (s)"),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(invalid(key, &short(x), &format!("must be > 0{unit} and finite")));
            }
        }
        if n.step_budget == 0 {
            return Err(invalid("numerics.step_budget", "0", "must be an integer >= 1"));
        }
        self.check_derived()
    }

    /// Checks on combinations of keys, at the extremes of every random key's support where
    /// they are finite (a draw of an unbounded law that still overflows a ratio is refused per
    /// realization, naming it).
    fn check_derived(&self) -> Result<(), ScenarioError> {
        self.scene()?;
        let bounded = |p: &Param| {
            let (lo, hi) = support(p);
            let mean = match p {
                Param::Random(d) => d.mean(),
                _ => lo,
            };
            (if lo > 0.0 && lo.is_finite() { lo } else { mean }, if hi.is_finite() { hi } else { mean })
        };
        let (m_lo, m_hi) = self.param(Key::Mass).map_or((1.0, 1.0), bounded);
        let hi = |k: Key| self.param(k).map_or(0.0, |p| bounded(p).1);
        let ratios = [hi(Key::Stiffness) / m_lo, hi(Key::Damping) / m_lo, hi(Key::NormalForce) * hi(Key::Static).max(hi(Key::Kinetic)) / m_lo];
        if ratios.iter().any(|r| !r.is_finite()) || !(m_hi > 0.0) {
            return Err(ScenarioError::Invalid {
                key: "model".into(),
                value: format!("k/m up to {:e} 1/s², c/m up to {:e} 1/s, mu n/m up to {:e} m/s²", ratios[0], ratios[1], ratios[2]),
                reason: "these ratios must be finite".into(),
            });
        }
        let o = &self.output;
        if o.trajectories > 1000 || o.trajectories as f64 * self.run.duration / o.trajectory_step > MAX_TRAJECTORY_SAMPLES {
            return Err(ScenarioError::Invalid {
                key: "output.trajectories".into(),
                value: o.trajectories.to_string(),
                reason: format!(
                    "at most 1000 trajectories and {MAX_TRAJECTORY_SAMPLES:e} samples in all (run.duration / output.trajectory_step = {:e} each)",
                    self.run.duration / o.trajectory_step
                ),
            });
        }
        // Numerical solvers: refuse settings that cannot work, before any realization runs.
        let num = &self.numerics;
        let solver = self.solver();
        let fixed = matches!(solver, SolverKind::Rk4 | SolverKind::Moreau);
        let omega = ratios[0].sqrt();
        if solver == SolverKind::Rk4 && omega * num.step > 1.0 {
            return Err(invalid(
                "numerics.step",
                &short(num.step),
                &format!(
                    "too coarse for rk4 with ω = √(k/m) up to {omega:e} rad/s: ω·step = {:e} must be at most 1 (RK4 loses accuracy, and is unstable past 2.8)",
                    omega * num.step
                ),
            ));
        }
        let least_steps = self.run.duration / if fixed { num.step } else { num.max_step };
        if matches!(solver, SolverKind::Rk45 | SolverKind::Rk4 | SolverKind::Moreau) && least_steps > num.step_budget as f64 {
            let key = if fixed { "numerics.step" } else { "numerics.max_step" };
            return Err(invalid(
                key,
                &short(if fixed { num.step } else { num.max_step }),
                &format!("run.duration needs at least {least_steps:e} steps, over numerics.step_budget = {}", num.step_budget),
            ));
        }
        let rate = hi(Key::SwitchRate).max(hi(Key::ReverseSwitchRate));
        let expected = rate * self.run.duration;
        if !(expected <= MAX_EXPECTED_SWITCHES) {
            return Err(invalid(
                "belt.switch_rate",
                &short(rate),
                &format!("switch rate × run.duration = {expected:e} expected belt switches per realization; at most {MAX_EXPECTED_SWITCHES:e} are supported"),
            ));
        }
        Ok(())
    }
}

/// A [`Param`] slot: required keys always hold one, optional ones may be absent.
pub enum ParamSlot<'a> {
    Required(&'a mut Param),
    Optional(&'a mut Option<Param>),
}

impl ParamSlot<'_> {
    /// Set the key (None: remove an optional key; a required key keeps its value).
    pub fn set(self, p: Option<Param>) {
        match (self, p) {
            (ParamSlot::Required(slot), Some(p)) => *slot = p,
            (ParamSlot::Required(_), None) => {}
            (ParamSlot::Optional(slot), p) => *slot = p,
        }
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

/// The smallest and largest value a key can take: the number, or the distribution's support
/// (a sweep's extremes).
fn support(p: &Param) -> (f64, f64) {
    match p {
        Param::Value(x) => (*x, *x),
        Param::Sweep(l) => l.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x))),
        Param::Random(d) => d.support(),
    }
}

/// One key's value or distribution against the key's valid range.
fn check_param(key: Key, p: &Param) -> Result<(), ScenarioError> {
    let (lo, open) = key.lower_bound();
    let unit = key.unit();
    let rel = if open { ">" } else { ">=" };
    let ok = |x: f64| x.is_finite() && if open { x > lo } else { x >= lo };
    match p {
        Param::Value(x) => {
            if !ok(*x) {
                return Err(invalid(key.dotted(), &short(*x), &if x.is_finite() { format!("must be {rel} {lo}{unit}") } else { "must be finite".into() }));
            }
        }
        Param::Sweep(list) => {
            if let Some(x) = list.iter().find(|x| !ok(**x)) {
                return Err(invalid(key.dotted(), &shown_list(list), &format!("the value {} must be {rel} {lo}{unit} and finite", short(*x))));
            }
        }
        Param::Random(d) => {
            d.check().map_err(|reason| invalid(key.dotted(), &shown_param(p), &reason))?;
            let (s_lo, _) = d.support();
            let inside = if open { s_lo > lo || (s_lo == lo && d.open_at_low()) } else { s_lo >= lo };
            if !inside && !d.truncated() {
                return Err(invalid(key.dotted(), &shown_param(p), &format!("the distribution can draw {}, but the key must be {rel} {lo}{unit}", short(s_lo))));
            }
            if d.truncated() && !ok(d.mean()) {
                return Err(invalid(key.dotted(), &shown_param(p), &format!("a normal is truncated to the key's range ({rel} {lo}{unit}); its mean must lie in it")));
            }
        }
    }
    Ok(())
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
    let owned;
    for part in path.split('.').filter(|p| !p.is_empty()) {
        v = v.and_then(|v| v.get(part));
    }
    owned = v.map_or_else(|| "(missing)".to_string(), shown);
    ScenarioError::Invalid { key: path, value: owned, reason: msg.trim_end().to_string() }
}

/// A number in its shortest round-trip form, never as hundreds of digits (hive values, errors):
/// positional while that takes at most 16 characters (0.51, 0.00001, 2.5), else with an exponent.
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 16 {
        plain
    } else {
        format!("{x:e}")
    }
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

/// The paper scenario ← the user's text ← `--set` overrides, as a table (not yet typed).
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

/// A `--set` value: TOML if it parses as TOML (`1.0`, `[-1, 1]`, `{ dist = … }`, `"x"`), else a
/// bare string.
fn parse_value(text: &str) -> Value {
    format!("v = {text}")
        .parse::<Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(text.to_owned()))
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
        assert!(e.contains("model.mass") && e.contains("> 0"), "{e}");
        let e = Scenario::resolve(None, &["model.mass=nan".into()]).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        let e = Scenario::resolve(None, &["run.realizations=0".into()]).unwrap_err().to_string();
        assert!(e.contains("run.realizations"), "{e}");
        let e = Scenario::resolve(None, &["run.solver=rk5".into()]).unwrap_err().to_string();
        assert!(e.contains("run.solver") && e.contains("rk45"), "{e}");
    }

    #[test]
    fn provenance_round_trips() {
        let s = Scenario::resolve(None, &["model.damping=0.5".into(), "model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}".into()]).unwrap();
        let again = Scenario::from_text(Some(&s.to_toml()), Path::new("x"), &[]).unwrap();
        assert_eq!(s, again);
    }
}
