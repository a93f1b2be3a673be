//! The scenario file as typed values: each section a serde struct with unknown keys denied, and
//! every numeric scene key a [`Param`] (a number, a sweep or a distribution).

use serde::{Deserialize, Serialize};
use toml::Value;

use crate::physics::FrictionLaw;
use crate::simulation::belt::InitialSign;
use crate::simulation::keys::Dist;
use crate::solver::SolverKind;

/// A numeric scene key as written: a number, a sweep or a distribution.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Param {
    /// A number: the key's value in every realization.
    Value(f64),
    /// A list of numbers: a sweep, one cell per value.
    Sweep(Vec<f64>),
    /// A distribution: the value drawn per realization.
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
            Value::Array(list) => list
                .iter()
                .map(number)
                .collect::<Option<Vec<f64>>>()
                .map(Param::Sweep)
                .ok_or_else(|| D::Error::custom("a list is a sweep and lists numbers only (a key cannot be both swept and random)")),
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
    /// σ_v, N·s/m, ≥ 0 (absent: 0): the viscous term of the slip friction, any law
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscous_friction: Option<Param>,
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

/// `belt.process`: which belt process (absent: inferred, symmetric unless the `reverse_*`
/// keys make it a telegraph belt).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProcessName {
    /// The paper's belt: ±v0, sign changes at the instants of a Poisson process of rate λ.
    Symmetric,
    /// Two-state Markov chain: +v_f left at rate λ_f, −v_r left at rate λ_r.
    Telegraph,
    /// Continuous-time Markov chain on the levels `velocities` with the transition `rates`.
    Markov,
    /// A measured velocity log (`file`); nothing is drawn.
    Recorded,
    /// One velocity throughout (`velocity`, 0 included: the rock); nothing is drawn.
    Constant,
}

/// `[belt]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeltSpec {
    /// absent: symmetric, or telegraph when both `reverse_*` keys are given
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub process: Option<ProcessName>,
    /// v0 = v_f, m/s, > 0
    pub speed: Param,
    /// λ = λ_f, 1/s, ≥ 0
    pub switch_rate: Param,
    /// 1, −1 or "random" (±1 with probability ½ each, per realization)
    pub initial_sign: Sign,
    /// v_r, m/s, > 0 (with `reverse_switch_rate`: the asymmetric telegraph belt)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reverse_speed: Option<Param>,
    /// λ_r, 1/s, ≥ 0
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reverse_switch_rate: Option<Param>,
    /// the levels of a Markov belt, m/s
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocities: Option<Vec<f64>>,
    /// the transition rates of a Markov belt, 1/s (n×n, diagonal ignored)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rates: Option<Vec<Vec<f64>>>,
    /// the velocity log of a recorded belt: CSV or Parquet with columns `time`, `velocity`
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// the velocity of a constant belt, m/s (any value, 0 included)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
}

/// `[chain]`: the masses between the anchor and the contact ([`crate::chain`]); the last mass
/// rubs on the belt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSpec {
    /// m_1 … m_N, kg, > 0
    pub masses: Vec<f64>,
    /// k_1 … k_N, N/m, ≥ 0 (k_1 ties m_1 to the anchor)
    pub stiffnesses: Vec<f64>,
    /// c_1 … c_N, N·s/m, ≥ 0 (absent: zeros)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dampings: Option<Vec<f64>>,
}

/// `anchor.process`: how the anchor (the top drive) moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AnchorProcess {
    /// At `speed` throughout (the default; 0: the paper's fixed wall).
    Constant,
    /// A continuous-time Markov chain on `velocities` with the transition `rates` (the belt's
    /// Markov semantics: the initial level from the stationary law).
    Markov,
    /// A measured velocity log (`file`, the belt's log format).
    Recorded,
}

/// `[anchor]`: the anchor's motion u(t) [m/s], piecewise constant, a(0) = 0.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnchorSpec {
    /// absent: constant
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub process: Option<AnchorProcess>,
    /// U, m/s, any sign (absent: 0)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<Param>,
    /// the levels of a Markov anchor, m/s
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocities: Option<Vec<f64>>,
    /// the transition rates of a Markov anchor, 1/s (n×n, diagonal ignored)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rates: Option<Vec<Vec<f64>>>,
    /// the velocity log of a recorded anchor: CSV or Parquet with columns `time`, `velocity`
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
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
    /// N, the number of realizations, 1 ..= `MAX_REALIZATIONS`
    pub realizations: u64,
    /// the random seed, ≤ i64::MAX (realization i draws from its own stream of the seed)
    pub seed: u64,
    /// the solver that integrates each realization
    pub solver: SolverKind,
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// store the instants of the belt velocity changes (column `switch_times`; Y_k)
    pub switch_times: bool,
    /// realizations 0..N sampled for trajectories (0: none)
    pub trajectories: u64,
    /// s
    pub trajectory_step: f64,
}

/// A [`Param`] slot: required keys always hold one, optional ones may be absent.
pub enum ParamSlot<'a> {
    /// A required key: always holds a value.
    Required(&'a mut Param),
    /// An optional key: may be absent.
    Optional(&'a mut Option<Param>),
}

impl ParamSlot<'_> {
    /// Set the key.
    pub fn set(self, p: Param) {
        match self {
            ParamSlot::Required(slot) => *slot = p,
            ParamSlot::Optional(slot) => *slot = Some(p),
        }
    }
}
