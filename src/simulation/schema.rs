//! The dataset's columns, declared once: name, type, the schema version that introduced it,
//! when it is present, the rule its values obey, its unit and meaning. The writer's Arrow schema
//! ([`crate::simulation::dataset::schema`]), the reader's type checks and per-value ranges
//! (`analysis::input`, `analysis::rules`) and the README's dataset table (checked by
//! `tests/it/readme.rs`) are read off [`COLUMNS`].

use arrow_schema::DataType;

use columns as name;

/// The names of the columns the readers use (the contract's), in one place.
pub mod columns {
    /// `int64`: the global realization index 0..N−1
    pub const REALIZATION: &str = "realization";
    /// `int64`: Q, the belt velocity changes in [0, t_a]
    pub const N_SWITCHES: &str = "n_switches";
    /// `int64`: S_T, the number of sticks
    pub const N_STICK: &str = "n_stick";
    /// `int64`: S_L, the number of slips
    pub const N_SLIP: &str = "n_slip";
    /// `bool`: the last interval was cut at t_a (its duration is censored)
    pub const LAST_TRUNCATED: &str = "last_truncated";
    /// `list<float64>`: T_1..T_{S_T}, the stick start instants [s]
    pub const STICK_START: &str = "stick_start";
    /// `list<float64>`: D_1..D_{S_T}, the stick durations [s]
    pub const STICK_DURATION: &str = "stick_duration";
    /// `list<float64>`: L_1..L_{S_L}, the slip start instants [s] (from the slip after the first
    /// stick)
    pub const SLIP_START: &str = "slip_start";
    /// `list<float64>`: H_1..H_{S_L}, the slip durations [s]
    pub const SLIP_DURATION: &str = "slip_duration";
    /// `list<float64>`: Y_1..Y_Q, the belt velocity change instants [s] (only with
    /// `output.switch_times`)
    pub const SWITCH_TIMES: &str = "switch_times";
    /// `list<float64>`: the belt velocity after each change [m/s] (with `switch_times`)
    pub const SWITCH_VELOCITIES: &str = "switch_velocities";
    /// `float64`: the belt velocity at t = 0⁺ [m/s] (schema v3)
    pub const INITIAL_VELOCITY: &str = "initial_velocity";
    /// `list<utf8>`: how each stick ended, `flip`, `breakaway` or `horizon` (schema v3)
    pub const STICK_END: &str = "stick_end";
    /// `list<float64>`: x at each stick's start [m] (schema v3)
    pub const STICK_ENTRY_POSITION: &str = "stick_entry_position";
    /// `list<float64>`: the belt velocity at each stick's start [m/s] (schema v3)
    pub const STICK_ENTRY_VELOCITY: &str = "stick_entry_velocity";
    /// `float64`: the longest stick within [0, t_a] [s], the cut one counted for its time in the
    /// window (schema v3)
    pub const LONGEST_STICK: &str = "longest_stick";
    /// `float64`: the fraction of [0, t_a] spent stuck (schema v3)
    pub const STICK_FRACTION: &str = "stick_fraction";
    /// `float64`: the least mass velocity ẋ over [0, t_a] [m/s] (schema v3)
    pub const MIN_VELOCITY: &str = "min_velocity";
    /// `float64`: the greatest mass velocity ẋ over [0, t_a] [m/s] (schema v3)
    pub const MAX_VELOCITY: &str = "max_velocity";
    /// `float64`: the largest slip speed |v − ẋ| over [0, t_a] [m/s] (schema v3)
    pub const MAX_SLIP_SPEED: &str = "max_slip_speed";
    /// `float64`: (max_velocity − min_velocity)/(2 v0), v0 the forward belt speed: the stick-slip
    /// severity (schema v3)
    pub const SEVERITY: &str = "severity";

    /// The per-stick float lists of schema v3, one value per stick.
    pub const STICK_LISTS: [&str; 2] = [STICK_ENTRY_POSITION, STICK_ENTRY_VELOCITY];
    /// The columns the tails' analysis needs beyond schema v2 (`analysis::tails`).
    pub const TAILS_STATE: [&str; 5] = [STICK_END, STICK_ENTRY_POSITION, STICK_ENTRY_VELOCITY, LONGEST_STICK, SEVERITY];
    /// The per-realization floats of schema v3.
    pub const TAIL_SCALARS: [&str; 6] = [LONGEST_STICK, STICK_FRACTION, MIN_VELOCITY, MAX_VELOCITY, MAX_SLIP_SPEED, SEVERITY];

    /// Each list column with the count column of its length, and whether its values are start
    /// instants (in increasing order); `switch_times` is present only when the scenario asks.
    pub const LISTS: [(&str, &str, bool); 5] = [
        (STICK_START, N_STICK, true),
        (STICK_DURATION, N_STICK, false),
        (SLIP_START, N_SLIP, true),
        (SLIP_DURATION, N_SLIP, false),
        (SWITCH_TIMES, N_SWITCHES, true),
    ];
}

/// The largest severity a dataset may hold, 2^24 ≈ 1.7e7 (a rule of the dataset: `simulate`
/// refuses at the door a scene whose initial state implies more, and its writers refuse a
/// realization past it; `analyze` checks it). The analysis' dyadic histograms start at width
/// 2^(24 − 40) = 2^−16 and pack bin indices below 2^42, which holds every value up to 2^26; the
/// paper scene's severities (1 to 1.26) are binned at 2^−13, as under the earlier bound 1024.
pub const SEVERITY_BOUND: f64 = 16_777_216.0;

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
    /// in [0, [`SEVERITY_BOUND`]], never −0
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
