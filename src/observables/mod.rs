//! One home for the quantities the tool names — the per-realization ones here ([`Observable`]),
//! the ensemble and long-run statistics the exact law, `predict` and the tails report in
//! [`Statistic`] — and for the per-realization ones: their names (one parser for
//! what users type), units, meaning, their value on one simulated realization — the one
//! definition `simulate --target-se`, `tradeoff` and `sensitivity` use (they never write a
//! dataset) — and their polars expression over a dataset's columns ([`Observable::expr`]), the
//! same quantity under the same censoring rule for queries on written datasets
//! (`tests/it/observables.rs` checks the two paths agree on every realization).
//!
//! **Censoring (one rule, everywhere).** The interval still running at t_a is cut there and its
//! truncation recorded (`last_truncated`). A cut interval is *censored*: its length is a lower
//! bound of a duration, not a duration, so it is left out of D_k and H_k — and so out of every
//! mean duration — while the time it covers still counts toward the stick fraction (time spent
//! stuck in [0, t_a]) and its start still counts as T_k or L_k (the start is observed). A
//! realization without the k-th interval, or whose k-th duration is censored, has no value of it:
//! statistics are over the realizations that have the value, and say how many they are.

use std::fmt;
use std::str::FromStr;

mod statistic;
pub use statistic::{names, Statistic};

use polars::prelude::{col, lit, when, DataType, Expr, NULL};

use crate::simulation::dataset::columns as name;
use crate::simulation::ensemble::Outcome;
use crate::simulation::events::{Record, StickEnd};
use crate::simulation::precision::Targets;

pub use crate::simulation::schema::SEVERITY_BOUND;

/// A per-realization quantity (see the module docs for the censoring rule).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Observable {
    /// T_k [s]: start of the k-th stick, counted from the first (column `stick_start`)
    StickStart(u32),
    /// L_k [s]: start of the k-th slip, counted from the slip after the first stick (`slip_start`)
    SlipStart(u32),
    /// D_k [s]: duration of the k-th stick, censored at t_a (`stick_duration`)
    StickDuration(u32),
    /// H_k [s]: duration of the k-th slip, censored at t_a (`slip_duration`)
    SlipDuration(u32),
    /// Y_k [s]: instant of the k-th belt velocity change (`switch_times`, stored only when the
    /// scenario asks for `output.switch_times`)
    SwitchTime(u32),
    /// S_T: number of sticks (`n_stick`)
    Sticks,
    /// S_L: number of slips (`n_slip`)
    Slips,
    /// Q: number of belt velocity changes in [0, t_a] (`n_switches`)
    Switches,
    /// fraction of [0, t_a] spent stuck, the cut last stick included (Σ `stick_duration` / t_a)
    StickFraction,
    /// mean of the realization's uncensored stick durations [s]
    MeanStickDuration,
    /// mean of the realization's uncensored slip durations [s]
    MeanSlipDuration,
    /// the longest stick within [0, t_a] [s], the stick cut at t_a counted for its time in the
    /// window; 0 for a realization that never sticks
    LongestStick,
    /// severity (max ẋ − min ẋ)/(2 v0) over [0, t_a] (`severity`, schema v3)
    Severity,
    /// number of sticks that end by breakaway (`stick_end`, schema v3)
    Breakaways,
}

/// Highest index k a name may carry.
pub const MAX_INDEX: u32 = 1000;

impl Observable {
    /// The name users type and tables show: `T_3`, `S_T`, `stick_fraction`.
    pub fn name(self) -> String {
        match self {
            Observable::StickStart(k) => format!("T_{k}"),
            Observable::SlipStart(k) => format!("L_{k}"),
            Observable::StickDuration(k) => format!("D_{k}"),
            Observable::SlipDuration(k) => format!("H_{k}"),
            Observable::SwitchTime(k) => format!("Y_{k}"),
            Observable::Sticks | Observable::Slips | Observable::Switches => self.variable().into(),
            Observable::StickFraction => "stick_fraction".into(),
            Observable::MeanStickDuration => "mean_stick_duration".into(),
            Observable::MeanSlipDuration => "mean_slip_duration".into(),
            Observable::LongestStick => "longest_stick".into(),
            Observable::Severity => "severity".into(),
            Observable::Breakaways => "breakaways".into(),
        }
    }

    /// The `variable` column of the analysis tables: the family letter of an indexed quantity
    /// (`T`, `L`, `D`, `H`, `Y`) or the whole name of a scalar one (`S_T`, `stick_fraction`).
    pub const fn variable(self) -> &'static str {
        match self {
            Observable::StickStart(_) => "T",
            Observable::SlipStart(_) => "L",
            Observable::StickDuration(_) => "D",
            Observable::SlipDuration(_) => "H",
            Observable::SwitchTime(_) => "Y",
            Observable::Sticks => "S_T",
            Observable::Slips => "S_L",
            Observable::Switches => "Q",
            Observable::StickFraction => "stick_fraction",
            Observable::MeanStickDuration => "mean_stick_duration",
            Observable::MeanSlipDuration => "mean_slip_duration",
            Observable::LongestStick => "longest_stick",
            Observable::Severity => "severity",
            Observable::Breakaways => "breakaways",
        }
    }

    /// The `index` column: k of an indexed quantity, None for a scalar one.
    pub fn index(self) -> Option<u32> {
        match self {
            Observable::StickStart(k) | Observable::SlipStart(k) | Observable::StickDuration(k) | Observable::SlipDuration(k) | Observable::SwitchTime(k) => {
                Some(k)
            }
            _ => None,
        }
    }

    /// The same family at index `k` (None for a scalar quantity).
    pub fn at(self, k: u32) -> Option<Observable> {
        match self {
            Observable::StickStart(_) => Some(Observable::StickStart(k)),
            Observable::SlipStart(_) => Some(Observable::SlipStart(k)),
            Observable::StickDuration(_) => Some(Observable::StickDuration(k)),
            Observable::SlipDuration(_) => Some(Observable::SlipDuration(k)),
            Observable::SwitchTime(_) => Some(Observable::SwitchTime(k)),
            _ => None,
        }
    }

    /// The indexed families, at k = 1.
    pub const FAMILIES: [Observable; 5] =
        [Observable::StickStart(1), Observable::SlipStart(1), Observable::StickDuration(1), Observable::SlipDuration(1), Observable::SwitchTime(1)];

    /// The counts S_T, S_L, Q and the breakaways.
    pub const COUNTS: [Observable; 4] = [Observable::Sticks, Observable::Slips, Observable::Switches, Observable::Breakaways];

    /// The quantities without an index.
    pub const SCALARS: [Observable; 9] = [
        Observable::Sticks,
        Observable::Slips,
        Observable::Switches,
        Observable::StickFraction,
        Observable::MeanStickDuration,
        Observable::MeanSlipDuration,
        Observable::LongestStick,
        Observable::Severity,
        Observable::Breakaways,
    ];

    /// The scalar quantities `analyze` reports beside the indexed families (its moments table has
    /// a row for each; a new scalar listed here is analysed with no other change; those that
    /// [`Observable::needs_tails_state`] only for datasets that have it).
    pub const ANALYSED_SCALARS: [Observable; 7] = [
        Observable::Sticks,
        Observable::Slips,
        Observable::Switches,
        Observable::StickFraction,
        Observable::LongestStick,
        Observable::Severity,
        Observable::Breakaways,
    ];

    /// Every quantity, the indexed families for k ≤ `max_index` (what the consistency test runs
    /// through: a new quantity is covered once it is listed here).
    pub fn every(max_index: u32) -> Vec<Observable> {
        let indexed = Observable::FAMILIES.into_iter().flat_map(|f| (1..=max_index).filter_map(move |k| f.at(k)));
        indexed.chain(Observable::SCALARS).collect()
    }

    /// Whether it is a count (integer values: exact distributions, unit histogram bins).
    pub fn is_count(self) -> bool {
        Observable::COUNTS.contains(&self)
    }

    /// Whether it needs the `switch_times` column.
    pub fn needs_switch_times(self) -> bool {
        matches!(self, Observable::SwitchTime(_))
    }

    /// Whether it needs the per-stick and per-realization state of schema v3.
    pub fn needs_tails_state(self) -> bool {
        matches!(self, Observable::Severity | Observable::Breakaways)
    }

    /// The bound of its values in a window t_a [s]: every time and duration lies in [0, t_a], the
    /// fraction in [0, 1], the severity in [0, [`SEVERITY_BOUND`]] (a rule of the dataset). For a
    /// count, which has none, t_a (the analysis bins counts by value).
    pub fn scale(self, t_a: f64) -> f64 {
        match self {
            Observable::StickFraction => 1.0,
            Observable::Severity => SEVERITY_BOUND,
            _ => t_a,
        }
    }

    /// Its unit: `s`, or `1` for counts and fractions.
    pub fn unit(self) -> &'static str {
        match self {
            Observable::Sticks | Observable::Slips | Observable::Switches | Observable::StickFraction | Observable::Severity | Observable::Breakaways => "1",
            _ => "s",
        }
    }

    /// What it is, in a sentence.
    pub fn about(self) -> &'static str {
        match self {
            Observable::StickStart(_) => "start of the k-th stick, counting from the first stick",
            Observable::SlipStart(_) => "start of the k-th slip, counting from the slip after the first stick",
            Observable::StickDuration(_) => "duration of the k-th stick; none when it is the stick cut at t_a (censored)",
            Observable::SlipDuration(_) => "duration of the k-th slip; none when it is the slip cut at t_a (censored)",
            Observable::SwitchTime(_) => "instant of the k-th change of the belt velocity",
            Observable::Sticks => "number of sticks in [0, t_a]",
            Observable::Slips => "number of slips in [0, t_a], counted from the slip after the first stick",
            Observable::Switches => "number of changes of the belt velocity in [0, t_a]",
            Observable::StickFraction => "fraction of [0, t_a] spent stuck, the stick cut at t_a included",
            Observable::MeanStickDuration => "mean duration of the realization's sticks, the censored one left out; none without one",
            Observable::MeanSlipDuration => "mean duration of the realization's slips, the censored one left out; none without one",
            Observable::LongestStick => "the longest stick within [0, t_a], the stick cut at t_a counted for its time in the window; 0 without a stick",
            Observable::Severity => {
                "(max − min of the mass velocity over [0, t_a]) / (2 v0), v0 the forward belt speed: 1 for a mass that only follows a symmetric belt"
            }
            Observable::Breakaways => "number of sticks that end by breakaway (the spring overcoming static friction), not by a belt change or the horizon",
        }
    }

    /// Its value on one realization — its record, its belt's change instants and the window t_a
    /// — `None` when the realization does not have it (no k-th interval, a censored duration, no
    /// uncensored interval to average).
    pub fn value(self, o: &Outcome) -> Option<f64> {
        let (r, switch_times, duration) = (&o.record, o.belt.switch_times.as_slice(), o.t_a);
        let at = |v: &[f64], k: u32| v.get(k as usize - 1).copied();
        let mean = |v: &[f64], stick: bool| {
            let kept: Vec<f64> = (1..=v.len() as u32).filter(|&k| !censored(r, stick, k)).map(|k| v[k as usize - 1]).collect();
            (!kept.is_empty()).then(|| kept.iter().sum::<f64>() / kept.len() as f64)
        };
        match self {
            Observable::StickStart(k) => at(&r.stick_start, k),
            Observable::SlipStart(k) => at(&r.slip_start, k),
            Observable::StickDuration(k) => at(&r.stick_duration, k).filter(|_| !censored(r, true, k)),
            Observable::SlipDuration(k) => at(&r.slip_duration, k).filter(|_| !censored(r, false, k)),
            Observable::SwitchTime(k) => at(switch_times, k),
            Observable::Sticks => Some(r.n_stick() as f64),
            Observable::Slips => Some(r.n_slip() as f64),
            Observable::Switches => Some(switch_times.len() as f64),
            Observable::StickFraction => Some(r.stick_fraction(duration)),
            Observable::MeanStickDuration => mean(&r.stick_duration, true),
            Observable::MeanSlipDuration => mean(&r.slip_duration, false),
            Observable::LongestStick => Some(r.longest_stick()),
            Observable::Severity => Some(r.severity(o.speed_scale)),
            Observable::Breakaways => Some(r.stick_end.iter().filter(|e| **e == StickEnd::Breakaway).count() as f64),
        }
    }

    /// Its polars expression over the dataset columns (schema v2: `stick_start`, `stick_duration`,
    /// `slip_start`, `slip_duration` lists, `n_stick`, `n_slip`, `last_truncated`; `n_switches`,
    /// and `switch_times` for Y_k), one float64 value per realization, null where
    /// [`Observable::value`] is None; `duration` is t_a [s].
    pub fn expr(self, duration: f64) -> Expr {
        let (n_stick, n_slip) = (count_column(name::N_STICK), count_column(name::N_SLIP));
        let at = |c: &str, k: u32| col(c).list().get(lit(i64::from(k) - 1), true);
        let unless = |censored: Expr, value: Expr| when(censored).then(lit(NULL)).otherwise(value).cast(DataType::Float64);
        let uncensored_mean = |c: &str, count: Expr, last_cut: Expr| col(c).list().slice(lit(0i64), count - last_cut.cast(DataType::Int64)).list().mean();
        let named = match self {
            Observable::StickStart(k) => at(name::STICK_START, k),
            Observable::SlipStart(k) => at(name::SLIP_START, k),
            Observable::StickDuration(k) | Observable::SlipDuration(k) => {
                let column = if matches!(self, Observable::StickDuration(_)) { name::STICK_DURATION } else { name::SLIP_DURATION };
                unless(self.censored_expr().expect("a duration"), at(column, k))
            }
            Observable::SwitchTime(k) => at(name::SWITCH_TIMES, k),
            Observable::Sticks => n_stick,
            Observable::Slips => n_slip,
            Observable::Switches => count_column(name::N_SWITCHES),
            Observable::StickFraction => col(name::STICK_DURATION).list().sum() / lit(duration),
            Observable::MeanStickDuration => uncensored_mean(name::STICK_DURATION, n_stick, last_cut(true)),
            Observable::MeanSlipDuration => uncensored_mean(name::SLIP_DURATION, n_slip, last_cut(false)),
            Observable::LongestStick => col(name::STICK_DURATION).list().max().fill_null(lit(0.0)),
            Observable::Severity => col(name::SEVERITY),
            Observable::Breakaways => breakaways(),
        };
        named.cast(DataType::Float64).alias(self.name())
    }

    /// For D_k and H_k, the expression that is true where the realization's k-th duration is the
    /// interval cut at t_a (censored, so its value is null); None for every other quantity.
    pub fn censored_expr(self) -> Option<Expr> {
        match self {
            Observable::StickDuration(k) => Some(last_cut(true).and(count_column(name::N_STICK).eq(lit(i64::from(k))))),
            Observable::SlipDuration(k) => Some(last_cut(false).and(count_column(name::N_SLIP).eq(lit(i64::from(k))))),
            _ => None,
        }
    }

    /// The paper's Table 1 quantities: T_k, D_k, L_k, H_k for k ≤ 6, then S_T and S_L.
    pub fn table1() -> Vec<Observable> {
        let mut out = Vec::new();
        for k in 1..=6 {
            out.extend([Observable::StickStart(k), Observable::StickDuration(k), Observable::SlipStart(k), Observable::SlipDuration(k)]);
        }
        out.extend([Observable::Sticks, Observable::Slips]);
        out
    }
}

/// The number of `breakaway` ends in each row's `stick_end` list (an int64 count).
pub(crate) fn breakaways() -> Expr {
    use polars::prelude::{polars_err, Column, Field, Int64Chunked, IntoColumn, NewChunkedArray};
    use polars_arrow::array::{Array, Utf8ViewArray};
    col(name::STICK_END).map(
        |c: Column| {
            let ca = c.list()?.rechunk();
            let mut out: Vec<Option<i64>> = Vec::with_capacity(ca.len());
            for arr in ca.downcast_iter() {
                let values = arr
                    .values()
                    .as_any()
                    .downcast_ref::<Utf8ViewArray>()
                    .ok_or_else(|| polars_err!(SchemaMismatch: "column `stick_end` is not a list of strings"))?;
                let o = arr.offsets().as_slice();
                out.extend((0..arr.len()).map(|r| {
                    arr.is_valid(r).then(|| (o[r] as usize..o[r + 1] as usize).filter(|&i| values.value(i) == StickEnd::Breakaway.name()).count() as i64)
                }));
            }
            Ok(Int64Chunked::from_iter_options(c.name().clone(), out.into_iter()).into_column())
        },
        |_, f| Ok(Field::new(f.name().clone(), DataType::Int64)),
    )
}

/// A count column as int64 (int32 in schema v1).
fn count_column(name: &str) -> Expr {
    col(name).cast(DataType::Int64)
}

/// Whether the last interval was a stick (`stick`) or a slip cut at t_a: the rule of
/// [`censored`], as columns.
pub(crate) fn last_cut(stick: bool) -> Expr {
    let (n_stick, n_slip) = (count_column(name::N_STICK), count_column(name::N_SLIP));
    col(name::LAST_TRUNCATED).and(if stick { n_stick.gt(n_slip) } else { n_stick.eq(n_slip) })
}

/// Whether the k-th stick (`stick`) or slip duration is the interval cut at t_a: the last
/// interval was cut, it is the k-th of its kind, and it is the last one (a final stick when
/// S_T > S_L, a final slip when S_T = S_L). The one censoring rule (module docs).
pub fn censored(r: &Record, stick: bool, k: u32) -> bool {
    let (n_stick, n_slip, k) = (r.n_stick(), r.n_slip(), k as usize);
    r.last_truncated && if stick { n_stick == k && n_stick > n_slip } else { n_slip == k && n_stick == n_slip }
}

impl fmt::Display for Observable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl FromStr for Observable {
    type Err = String;
    /// The one parser of the names users type: `S_T`, `S_L`, `stick_fraction`,
    /// `mean_stick_duration`, `mean_slip_duration`, and `T_k`, `L_k`, `D_k`, `H_k` with k ≥ 1 in
    /// digits (`T_3`; `T3` too). Anything else is refused, naming what is accepted.
    fn from_str(s: &str) -> Result<Observable, String> {
        let s = s.trim();
        let scalars: Vec<String> = Observable::SCALARS.iter().map(|o| o.name()).collect();
        let known = format!("{}, or T_k, L_k, D_k, H_k, Y_k with k >= 1", scalars.join(", "));
        if let Some(o) = Observable::SCALARS.into_iter().find(|o| o.name() == s) {
            return Ok(o);
        }
        let family: Option<fn(u32) -> Observable> = match s.chars().next() {
            Some('T') => Some(Observable::StickStart),
            Some('L') => Some(Observable::SlipStart),
            Some('D') => Some(Observable::StickDuration),
            Some('H') => Some(Observable::SlipDuration),
            Some('Y') => Some(Observable::SwitchTime),
            _ => None,
        };
        let family = family.ok_or_else(|| format!("{s:?}: unknown quantity; expected {known}"))?;
        let digits = s[1..].strip_prefix('_').unwrap_or(&s[1..]);
        // digits only: `parse` would also take `+1`
        let k = Some(digits)
            .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|d| d.parse::<u32>().ok())
            .filter(|k| (1..=MAX_INDEX).contains(k))
            .ok_or_else(|| format!("{s:?}: k must be an integer from 1 to {MAX_INDEX}, written in digits; expected {known}"))?;
        Ok(family(k))
    }
}

/// One `--target-se VAR=SE`: stop the run once the mean of VAR has this standard error
/// ([`crate::simulation::precision`] tracks it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// VAR, the quantity whose mean is tracked
    pub quantity: Observable,
    /// SE, the standard error of the mean to reach (> 0)
    pub se: f64,
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.quantity)
    }
}

impl FromStr for Target {
    type Err = String;
    fn from_str(s: &str) -> Result<Target, String> {
        let bad = |why: &str| format!("--target-se {s:?}: {why}; expected VAR=SE, e.g. S_T=0.05");
        let (var, se) = s.split_once('=').ok_or_else(|| bad("no '='"))?;
        let se: f64 = se.trim().parse().map_err(|_| bad("SE is not a number"))?;
        if !(se.is_finite() && se > 0.0) {
            return Err(bad("SE must be a positive number"));
        }
        let quantity = var.parse::<Observable>().map_err(|e| bad(&e))?;
        Ok(Target { quantity, se })
    }
}

impl Target {
    /// The targets as the simulate path tracks them.
    pub fn tracked(targets: &[Target]) -> Targets<'_> {
        Targets {
            names: targets.iter().map(Target::to_string).collect(),
            se: targets.iter().map(|t| t.se).collect(),
            value: Box::new(|i, o| targets[i].quantity.value(o)),
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn targets_parse_and_bad_ones_are_named() {
        let t: Target = "D_3=0.01".parse().unwrap();
        assert_eq!((t.quantity, t.se, t.to_string()), (Observable::StickDuration(3), 0.01, "D_3".to_string()));
        assert_eq!("stick_fraction=1e-3".parse::<Target>().unwrap().quantity, Observable::StickFraction);
        for bad in ["S_T", "S_T=0", "S_T=-1", "X_1=0.1", "T_0=0.1", "T_x=0.1", "S_T=nan", "T_+1=0.1"] {
            let e = bad.parse::<Target>().unwrap_err();
            assert!(e.contains("--target-se"), "{e}");
        }
    }

    use super::*;
    use crate::simulation::events::{Observer, Release};

    /// A record built by hand: first stick at 1 s for 0.5 s, a slip of 2 s, a stick at 3.5 s
    /// still running at t_a = 4 s (cut: censored).
    fn record() -> Record {
        let mut r = Record::default();
        r.stick(1.0, 0.0, 1.0);
        r.slip(1.5, 0.0, 1.0, Release::Breakaway);
        r.stick(3.5, 0.0, 1.0);
        r.finish(4.0);
        r
    }

    fn outcome(record: Record, switch_times: &[f64], t_a: f64) -> Outcome {
        let mut o = Outcome::default();
        (o.record, o.t_a, o.speed_scale) = (record, t_a, 1.0);
        o.belt.switch_times = switch_times.to_vec();
        o
    }

    #[test]
    fn values_follow_the_one_censoring_rule() {
        let r = record();
        let o = outcome(r, &[0.7, 2.9], 4.0);
        let v = |q: &str| q.parse::<Observable>().unwrap().value(&o);
        assert_eq!((v("S_T"), v("S_L")), (Some(2.0), Some(1.0)));
        assert_eq!((v("T_1"), v("T_2"), v("T_3")), (Some(1.0), Some(3.5), None));
        assert_eq!((v("D_1"), v("D_2")), (Some(0.5), None), "the stick cut at t_a is censored");
        assert_eq!((v("L_1"), v("H_1")), (Some(1.5), Some(2.0)));
        assert_eq!((v("Q"), v("Y_2"), v("Y_3")), (Some(2.0), Some(2.9), None));
        assert_eq!(v("stick_fraction"), Some((0.5 + 0.5) / 4.0), "the cut stick's time is time stuck");
        assert_eq!((v("mean_stick_duration"), v("mean_slip_duration")), (Some(0.5), Some(2.0)));
        assert_eq!(v("breakaways"), Some(1.0), "the first stick ended by breakaway");
        // a realization that never sticks has no durations to average
        let mut none = Record::default();
        none.finish(4.0);
        assert_eq!(Observable::MeanStickDuration.value(&outcome(none, &[], 4.0)), None);
    }

    #[test]
    fn names_round_trip_and_bad_ones_are_refused() {
        for o in Observable::every(12) {
            assert_eq!(o.name().parse::<Observable>(), Ok(o));
        }
        assert_eq!("D3".parse::<Observable>(), Ok(Observable::StickDuration(3)));
        for bad in ["T_+1", "T_0", "T_", "X_1", "T_1001", "s_t", "T_1.5"] {
            let e = bad.parse::<Observable>().unwrap_err();
            assert!(e.contains(bad) && e.contains("expected"), "{bad}: {e}");
        }
    }
}
