//! The scenario as typed data: the limits every check uses, the [`Scenario`] and its sections,
//! the overrides and sweep cells, and the errors, each naming its key.

use std::fmt;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use toml::Value;

use super::spec::{AnchorSpec, BeltSpec, ChainSpec, InitialConditions, ModelSpec, Output, Param, ParamSlot, Run};
use crate::shown::short;
use crate::simulation::keys::Key;
use crate::solver::Numerics;

/// The paper scenario, embedded: the default of every key.
pub const PAPER_TOML: &str = include_str!("../../pipelines/paper.toml");

/// The embedded paper scenario, typed but not checked (checking builds the scene this serves),
/// parsed once: the defaults a key set by the user is compared with.
pub(super) fn paper_typed() -> &'static Scenario {
    static PAPER: std::sync::OnceLock<Scenario> = std::sync::OnceLock::new();
    PAPER.get_or_init(|| Scenario::recorded(PAPER_TOML, std::path::Path::new("pipelines/paper.toml")).expect("the embedded paper scenario is valid"))
}

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
    /// `[initial_conditions]`: the ranges X0, Ẋ0 are drawn from (each mass of a chain draws
    /// its own)
    pub initial_conditions: InitialConditions,
    /// `[chain]`: a chain of masses in place of `model.mass`, `model.stiffness` and
    /// `model.damping` ([`crate::chain`]; absent: the one mass of `[model]`)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain: Option<ChainSpec>,
    /// `[anchor]`: how the anchor moves (absent: a fixed wall)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anchor: Option<AnchorSpec>,
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
pub struct Hint(pub(super) Vec<String>);

impl fmt::Display for Hint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            Ok(())
        } else {
            write!(f, " (known here: {})", self.0.join(", "))
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

pub(super) fn invalid(key: &str, value: &str, reason: &str) -> ScenarioError {
    ScenarioError::Invalid { key: key.to_owned(), value: value.to_owned(), reason: reason.to_owned() }
}

pub(super) fn shown_list(l: &[f64]) -> String {
    format!("[{}]", l.iter().map(|x| short(*x)).collect::<Vec<_>>().join(", "))
}

pub(super) fn shown_param(p: &Param) -> String {
    shown(&Value::try_from(p).unwrap_or(Value::String("?".into())))
}

/// A value as an error message shows it: numbers in their short form ([`short`]).
pub(super) fn shown(v: &Value) -> String {
    match v {
        Value::Float(x) => short(*x),
        Value::Array(a) => format!("[{}]", a.iter().map(shown).collect::<Vec<_>>().join(", ")),
        Value::Table(t) => format!("{{ {} }}", t.iter().map(|(k, v)| format!("{k} = {}", shown(v))).collect::<Vec<_>>().join(", ")),
        other => other.to_string(),
    }
}

impl Scenario {
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
            Key::Viscous => m.viscous_friction.as_ref(),
            Key::AnchorSpeed => self.anchor.as_ref().and_then(|a| a.speed.as_ref()),
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
            Key::Viscous => ParamSlot::Optional(&mut m.viscous_friction),
            Key::AnchorSpeed => ParamSlot::Optional(&mut self.anchor.get_or_insert_with(AnchorSpec::default).speed),
        }
    }
}
