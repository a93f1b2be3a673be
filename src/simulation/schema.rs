//! The dataset's columns, declared once: name, type, the schema version that introduced it,
//! when it is present, the rule its values obey, its unit and meaning. The writer's Arrow schema
//! ([`crate::simulation::dataset::schema`]), the reader's type checks and per-value ranges
//! (`analysis::input`, `analysis::rules`) and the README's dataset table (checked by
//! `tests/it/readme.rs`) are read off [`COLUMNS`].

use arrow_schema::DataType;

use super::dataset::columns as name;

/// A column's Arrow type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// int64
    Int64,
    /// int32
    Int32,
    /// float64
    Float64,
    /// bool
    Bool,
    /// list<float64>, non-null elements
    Floats,
    /// list<utf8>, non-null elements
    Strings,
}

impl Kind {
    /// The Arrow type the writer uses.
    pub fn arrow(self) -> DataType {
        let list = |t: DataType| DataType::List(std::sync::Arc::new(arrow_schema::Field::new("element", t, false)));
        match self {
            Kind::Int64 => DataType::Int64,
            Kind::Int32 => DataType::Int32,
            Kind::Float64 => DataType::Float64,
            Kind::Bool => DataType::Boolean,
            Kind::Floats => list(DataType::Float64),
            Kind::Strings => list(DataType::Utf8),
        }
    }

    /// Its name in messages and in the README (`int64`, `list<float64>`, …).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Int64 => "int64",
            Kind::Int32 => "int32",
            Kind::Float64 => "float64",
            Kind::Bool => "bool",
            Kind::Floats => "list<float64>",
            Kind::Strings => "list<utf8>",
        }
    }
}

/// When a column is in a part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presence {
    /// in every part of its schema version and later
    Always,
    /// only with `output.switch_times = true`
    SwitchTimes,
}

/// The range of a per-realization float, checked on read (the lists' rules, which tie each list
/// to its count, are `analysis::rules`'s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// not read by the analysis
    Unchecked,
    /// a time in [0, t_a]
    Window,
    /// in [0, 1]
    Fraction,
    /// any finite number
    Finite,
    /// a finite number ≥ 0
    NonNegative,
    /// in [0, [`crate::observables::SEVERITY_BOUND`]], never −0
    Severity,
}

/// One column of a part file.
#[derive(Debug, Clone, Copy)]
pub struct Column {
    /// its name (`columns::…`)
    pub name: &'static str,
    /// its Arrow type
    pub kind: Kind,
    /// the schema version that introduced it
    pub since: u8,
    /// when it is present
    pub presence: Presence,
    /// the rule of its values, for a per-realization float
    pub bound: Bound,
    /// its unit (`s`, `m/s`, `1`, …)
    pub unit: &'static str,
    /// what it holds, in a line
    pub meaning: &'static str,
}

const fn col(name: &'static str, kind: Kind, since: u8, bound: Bound, unit: &'static str, meaning: &'static str) -> Column {
    Column { name, kind, since, presence: Presence::Always, bound, unit, meaning }
}

/// Every column, in the writer's order (the drawn scene keys, one float64 each, follow them).
pub const COLUMNS: [Column; 24] = {
    use Bound::*;
    use Kind::*;
    [
        col(name::REALIZATION, Int64, 1, Unchecked, "1", "global index 0..N−1"),
        col("x0", Float64, 1, Unchecked, "m", "initial position"),
        col("xdot0", Float64, 1, Unchecked, "m/s", "initial velocity"),
        col("initial_sign", Int32, 1, Unchecked, "1", "belt direction at t = 0 (0: a belt at rest)"),
        col(name::INITIAL_VELOCITY, Float64, 3, Unchecked, "m/s", "belt velocity at t = 0"),
        col(name::N_SWITCHES, Int64, 1, Unchecked, "1", "Q, belt velocity changes in [0, t_a]"),
        col(name::N_STICK, Int64, 1, Unchecked, "1", "S_T, the number of sticks"),
        col(name::N_SLIP, Int64, 1, Unchecked, "1", "S_L, the number of slips"),
        col(name::STICK_START, Floats, 1, Unchecked, "s", "T_1..T_{S_T}, the stick start instants"),
        col(name::STICK_DURATION, Floats, 1, Unchecked, "s", "D_1..D_{S_T}, the stick durations"),
        col(name::SLIP_START, Floats, 1, Unchecked, "s", "L_1..L_{S_L}, the slip start instants (from the slip after the first stick)"),
        col(name::SLIP_DURATION, Floats, 1, Unchecked, "s", "H_1..H_{S_L}, the slip durations"),
        col(name::LAST_TRUNCATED, Bool, 1, Unchecked, "1", "the last interval was cut at t_a (its duration is censored)"),
        col(name::STICK_END, Strings, 3, Unchecked, "1", "how each stick ended: flip, breakaway or horizon"),
        col(name::STICK_ENTRY_POSITION, Floats, 3, Unchecked, "m", "x at each stick's start"),
        col(name::STICK_ENTRY_VELOCITY, Floats, 3, Unchecked, "m/s", "the belt velocity at each stick's start"),
        col(name::LONGEST_STICK, Float64, 3, Window, "s", "the longest stick within [0, t_a], the cut one counted for its time in the window"),
        col(name::STICK_FRACTION, Float64, 3, Fraction, "1", "fraction of [0, t_a] spent stuck"),
        col(name::MIN_VELOCITY, Float64, 3, Finite, "m/s", "least mass velocity over [0, t_a]"),
        col(name::MAX_VELOCITY, Float64, 3, Finite, "m/s", "greatest mass velocity over [0, t_a]"),
        col(name::MAX_SLIP_SPEED, Float64, 3, NonNegative, "m/s", "largest slip speed |v − ẋ| over [0, t_a]"),
        col(name::SEVERITY, Float64, 3, Severity, "1", "(max_velocity − min_velocity)/(2 v0), v0 the belt's speed scale over [0, t_a]"),
        Column { presence: Presence::SwitchTimes, ..col(name::SWITCH_TIMES, Floats, 1, Unchecked, "s", "Y_1..Y_Q, the belt velocity change instants") },
        Column { presence: Presence::SwitchTimes, ..col(name::SWITCH_VELOCITIES, Floats, 3, Unchecked, "m/s", "the belt velocity after each change") },
    ]
};

/// The columns every part of schema `version` has (the switch times aside).
pub fn required(version: u8) -> impl Iterator<Item = &'static Column> {
    COLUMNS.iter().filter(move |c| c.presence == Presence::Always && c.since <= version)
}
