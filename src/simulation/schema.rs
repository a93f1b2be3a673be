//! The dataset's columns, declared once: name, the value a realization writes there (which fixes
//! the Arrow type), the schema version that introduced it, when it is present, how it is stored,
//! the rule its values obey, its unit and meaning. The writer's Arrow schema, its rows and its
//! Parquet settings ([`crate::simulation::dataset`]), the reader's type checks and per-value
//! ranges (`analysis::input`, `analysis::rules`) and the README's dataset table (checked by
//! `tests/it/readme.rs`) are read off [`COLUMNS`]: a new column is one entry here.

use arrow_schema::DataType;

use super::ensemble::Outcome;
use super::events::StickEnd;

use columns as name;

pub use super::columns::{self, SEVERITY_BOUND};

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

/// One realization as the writer sees it: its global index and what it produced.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// the global realization index
    pub index: u64,
    /// the realization
    pub out: &'a Outcome,
}

/// What a realization writes in a column; the variant is the column's [`Kind`]. A list's
/// function appends the row's values.
#[derive(Clone, Copy)]
pub enum Value {
    /// one int64
    Int64(fn(Row) -> i64),
    /// one int32
    Int32(fn(Row) -> i32),
    /// one float64
    Float64(fn(Row) -> f64),
    /// one bool
    Bool(fn(Row) -> bool),
    /// a list of float64
    Floats(fn(Row, &mut Vec<f64>)),
    /// a list of strings, each one of a few words: the words, and the function appending the
    /// row's words as their positions in it (a byte each while the rows are gathered)
    Strings(&'static [&'static str], fn(Row, &mut Vec<u8>)),
}

impl Value {
    /// The Arrow type it makes.
    pub fn kind(self) -> Kind {
        match self {
            Value::Int64(_) => Kind::Int64,
            Value::Int32(_) => Kind::Int32,
            Value::Float64(_) => Kind::Float64,
            Value::Bool(_) => Kind::Bool,
            Value::Floats(_) => Kind::Floats,
            Value::Strings(..) => Kind::Strings,
        }
    }
}

impl std::fmt::Debug for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Value({})", self.kind().name())
    }
}

/// How a column is stored in Parquet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Store {
    /// zstd, with min/max statistics per row group (integers, booleans, few distinct floats)
    Packed,
    /// PLAIN, uncompressed, no statistics: near-incompressible floats (random initial
    /// conditions, event times; zstd saved 8 % of the size and cost 12 % of the run)
    Plain,
    /// a dictionary, then zstd, no statistics: a few values repeated per stick (no reader skips
    /// row groups on them, and a string's min/max cost 4 % of a run's instructions)
    Dictionary,
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
    /// what a realization writes there
    pub value: Value,
    /// the schema version that introduced it
    pub since: u8,
    /// when it is present
    pub presence: Presence,
    /// how it is stored
    pub store: Store,
    /// the rule of its values, for a per-realization float
    pub bound: Bound,
    /// its unit (`s`, `m/s`, `1`, …)
    pub unit: &'static str,
    /// what it holds, in a line
    pub meaning: &'static str,
}

impl Column {
    /// Its Arrow type.
    pub fn kind(&self) -> Kind {
        self.value.kind()
    }
}

const fn col(name: &'static str, value: Value, since: u8, store: Store, bound: Bound, unit: &'static str, meaning: &'static str) -> Column {
    Column { name, value, since, presence: Presence::Always, store, bound, unit, meaning }
}

/// The words of `stick_end`, in the order of [`StickEnd`]'s codes.
const STICK_END_WORDS: [&str; 3] = [StickEnd::ALL[0].name(), StickEnd::ALL[1].name(), StickEnd::ALL[2].name()];

/// A count as the int64 the dataset holds.
fn count(n: usize) -> i64 {
    n as i64
}

/// Every column, in the writer's order (the drawn scene keys, one float64 each, stored
/// [`Store::Plain`], follow them).
pub const COLUMNS: [Column; 24] = {
    use Bound::*;
    use Store::*;
    use Value as V;
    [
        col(name::REALIZATION, V::Int64(|r| r.index as i64), 1, Packed, Unchecked, "1", "global index 0..N−1"),
        col("x0", V::Float64(|r| r.out.x0), 1, Plain, Unchecked, "m", "initial position"),
        col("xdot0", V::Float64(|r| r.out.xdot0), 1, Plain, Unchecked, "m/s", "initial velocity"),
        col("initial_sign", V::Int32(|r| r.out.belt.initial_sign()), 1, Packed, Unchecked, "1", "belt direction at t = 0 (0: a belt at rest)"),
        col(name::INITIAL_VELOCITY, V::Float64(|r| r.out.belt.initial_velocity), 3, Packed, Unchecked, "m/s", "belt velocity at t = 0"),
        col(name::N_SWITCHES, V::Int64(|r| count(r.out.belt.switch_times.len())), 1, Packed, Unchecked, "1", "Q, belt velocity changes in [0, t_a]"),
        col(name::N_STICK, V::Int64(|r| count(r.out.record.n_stick())), 1, Packed, Unchecked, "1", "S_T, the number of sticks"),
        col(name::N_SLIP, V::Int64(|r| count(r.out.record.n_slip())), 1, Packed, Unchecked, "1", "S_L, the number of slips"),
        col(name::STICK_START, V::Floats(|r, v| v.extend(&r.out.record.stick_start)), 1, Plain, Unchecked, "s", "T_1..T_{S_T}, the stick start instants"),
        col(name::STICK_DURATION, V::Floats(|r, v| v.extend(&r.out.record.stick_duration)), 1, Plain, Unchecked, "s", "D_1..D_{S_T}, the stick durations"),
        col(
            name::SLIP_START,
            V::Floats(|r, v| v.extend(&r.out.record.slip_start)),
            1,
            Plain,
            Unchecked,
            "s",
            "L_1..L_{S_L}, the slip start instants (from the slip after the first stick)",
        ),
        col(name::SLIP_DURATION, V::Floats(|r, v| v.extend(&r.out.record.slip_duration)), 1, Plain, Unchecked, "s", "H_1..H_{S_L}, the slip durations"),
        col(
            name::LAST_TRUNCATED,
            V::Bool(|r| r.out.record.last_truncated),
            1,
            Packed,
            Unchecked,
            "1",
            "the last interval was cut at t_a (its duration is censored)",
        ),
        col(
            name::STICK_END,
            V::Strings(&STICK_END_WORDS, |r, v| v.extend(r.out.record.stick_end.iter().map(|&e| e as u8))),
            3,
            Dictionary,
            Unchecked,
            "1",
            "how each stick ended: flip, breakaway or horizon",
        ),
        col(name::STICK_ENTRY_POSITION, V::Floats(|r, v| v.extend(&r.out.record.stick_entry_position)), 3, Plain, Unchecked, "m", "x at each stick's start"),
        col(
            name::STICK_ENTRY_VELOCITY,
            V::Floats(|r, v| v.extend(&r.out.record.stick_entry_velocity)),
            3,
            Dictionary,
            Unchecked,
            "m/s",
            "the belt velocity at each stick's start",
        ),
        col(
            name::LONGEST_STICK,
            V::Float64(|r| r.out.record.longest_stick()),
            3,
            Plain,
            Window,
            "s",
            "the longest stick within [0, t_a], the cut one counted for its time in the window",
        ),
        col(name::STICK_FRACTION, V::Float64(|r| r.out.record.stick_fraction(r.out.t_a)), 3, Plain, Fraction, "1", "fraction of [0, t_a] spent stuck"),
        col(name::MIN_VELOCITY, V::Float64(|r| r.out.record.min_velocity), 3, Plain, Finite, "m/s", "least mass velocity over [0, t_a]"),
        col(name::MAX_VELOCITY, V::Float64(|r| r.out.record.max_velocity), 3, Plain, Finite, "m/s", "greatest mass velocity over [0, t_a]"),
        col(name::MAX_SLIP_SPEED, V::Float64(|r| r.out.record.max_slip_speed), 3, Plain, NonNegative, "m/s", "largest slip speed |v − ẋ| over [0, t_a]"),
        col(
            name::SEVERITY,
            V::Float64(|r| r.out.record.severity(r.out.speed_scale)),
            3,
            Plain,
            Severity,
            "1",
            "(max_velocity − min_velocity)/(2 v0), v0 the belt's speed scale over [0, t_a]",
        ),
        Column {
            presence: Presence::SwitchTimes,
            ..col(
                name::SWITCH_TIMES,
                V::Floats(|r, v| v.extend(&r.out.belt.switch_times)),
                1,
                Plain,
                Unchecked,
                "s",
                "Y_1..Y_Q, the belt velocity change instants",
            )
        },
        Column {
            presence: Presence::SwitchTimes,
            ..col(
                name::SWITCH_VELOCITIES,
                V::Floats(|r, v| v.extend((0..r.out.belt.switch_times.len()).map(|k| r.out.belt.velocity_after(k)))),
                3,
                Packed,
                Unchecked,
                "m/s",
                "the belt velocity after each change",
            )
        },
    ]
};

/// The dataset's schema version, recorded in every part: the latest `since` of [`COLUMNS`]
/// (v1 had int32 counts, v2 int64 ones; v3 added the tails' columns). `analyze` reads every
/// version from 1 to this one.
pub const VERSION: u8 = {
    let mut latest = 0;
    let mut i = 0;
    while i < COLUMNS.len() {
        if COLUMNS[i].since > latest {
            latest = COLUMNS[i].since;
        }
        i += 1;
    }
    latest
};

/// Whether `analyze` reads parts of schema `version` (written as in their metadata).
pub fn readable(version: &str) -> Option<u8> {
    (1..=VERSION).find(|v| v.to_string() == version)
}

/// The columns every part of schema `version` has (the switch times aside).
pub fn required(version: u8) -> impl Iterator<Item = &'static Column> {
    COLUMNS.iter().filter(move |c| c.presence == Presence::Always && c.since <= version)
}

/// The columns a part of this schema version has, with or without the switch times.
pub fn present(switch_times: bool) -> impl Iterator<Item = &'static Column> {
    COLUMNS.iter().filter(move |c| c.presence == Presence::Always || switch_times)
}
