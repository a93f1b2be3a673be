//! The rules every value of a dataset obeys, as per-row flags for the analysis query, and the
//! message naming the first file, row and column that breaks one.

use polars::prelude::*;

use super::input::{scan, Dataset, ROW};
use crate::observables::SEVERITY_BOUND;
use crate::simulation::dataset::columns::{self as name, LISTS};
use crate::simulation::events::StickEnd;

/// The list columns of a part, with their count columns and whether they are ordered.
fn lists(switch_times: bool) -> impl Iterator<Item = (&'static str, &'static str, bool)> {
    LISTS.into_iter().filter(move |(list, _, _)| switch_times || *list != name::SWITCH_TIMES)
}

/// The largest number of belt changes a part may declare without its list (a count is its own
/// histogram bin, and bins are packed below 2^42 with the group).
const Q_LIMIT: i64 = 1 << 40;

/// One validation rule of a part file: the per-row flag of its breach (the message is made by
/// [`row_problem`] once a breach is found).
pub(crate) struct Rule {
    pub bad: Expr,
}

/// The validation rules (see [`locate`] for the messages): realization ids are the part's
/// declared consecutive range; counts are non-negative and equal their lists' lengths (Q, without
/// its list, below 2^40); event times are finite and in [0, t_a]; start instants do not
/// decrease; the stick durations add up to at most t_a; no nulls; with the tails' state
/// (`tails`), one end and one entry state per stick.
pub(crate) fn rules(first: u64, data: &Dataset) -> Vec<Rule> {
    let (horizon, switch_times, tails) = (data.scenario.run.duration, data.switch_times, data.tails_state);
    let mut out = vec![Rule { bad: col(name::REALIZATION).neq(lit(first as i64) + col(ROW).cast(DataType::Int64)).fill_null(lit(true)) }];
    if !switch_times {
        let q = col(name::N_SWITCHES).cast(DataType::Int64);
        out.push(Rule { bad: q.clone().lt(lit(0i64)).or(q.gt_eq(lit(Q_LIMIT))).fill_null(lit(true)) });
    }
    // a duration cut at t_a is t_a − start, rounded: a relative 1e-12 of slack; the durations of
    // intervals that do not overlap add up to t_a at most (with the rounding of each)
    let top = horizon * (1.0 + 1e-12);
    for (list, count, ordered) in lists(switch_times) {
        let total = (list == name::STICK_DURATION).then_some(horizon * (1.0 + 1e-9));
        out.push(Rule { bad: list_rule(list, count, top, ordered, total) });
    }
    out.push(Rule { bad: col(name::LAST_TRUNCATED).is_null() });
    for list in PER_STICK.iter().filter(|_| tails) {
        let levels = if *list == name::STICK_ENTRY_VELOCITY { data.belt_levels.clone() } else { None };
        out.push(Rule { bad: per_stick_rule(list, levels) });
    }
    if tails {
        out.push(Rule { bad: severity_outside().fill_null(lit(true)) });
        out.push(Rule { bad: tail_scalars_outside(top).fill_null(lit(true)) });
    }
    out
}

/// True where a per-realization float of schema v3 breaks its rule ([`scalar_rules`]; NaN sorts
/// above every number in polars, so it fails every upper bound), or min_velocity > max_velocity.
fn tail_scalars_outside(top: f64) -> Expr {
    let within = |c: &str, (lo, hi): (f64, f64)| col(c).gt_eq(lit(lo)).and(col(c).lt_eq(lit(hi)));
    let ok = scalar_rules(top).map(|(c, range)| within(c, range)).reduce(|a, b| a.and(b)).expect("rules");
    ok.and(col(name::MIN_VELOCITY).lt_eq(col(name::MAX_VELOCITY))).not()
}

/// The per-realization floats with a range ([`crate::simulation::schema::Bound`]; the severity's
/// rule is [`severity_outside`]) and their ranges given `top` = t_a with its rounding slack.
fn scalar_rules(top: f64) -> impl Iterator<Item = (&'static str, (f64, f64))> {
    use crate::simulation::schema::{Bound, COLUMNS};
    COLUMNS.iter().filter_map(move |c| {
        let range = match c.bound {
            Bound::Window => (0.0, top),
            Bound::Fraction => (0.0, 1.0 + 1e-9),
            Bound::Finite => (-f64::MAX, f64::MAX),
            Bound::NonNegative => (0.0, f64::MAX),
            Bound::Unchecked | Bound::Severity => return None,
        };
        Some((c.name, range))
    })
}
/// True where the severity is not a number in [0, `SEVERITY_BOUND`] (NaN sorts above every
/// number in polars, so it fails the upper bound).
fn severity_outside() -> Expr {
    let s = col(name::SEVERITY);
    // (−0.0 passes ≥ 0 but is never written: (max − min)/(2 v0) is +0 at least)
    let negative_zero = s.clone().eq(lit(0.0)).and((lit(1.0) / s.clone()).lt(lit(0.0)));
    s.clone().gt_eq(lit(0.0)).and(s.lt_eq(lit(SEVERITY_BOUND))).not().or(negative_zero)
}

/// The per-stick lists of schema v3, one element per stick (`n_stick`).
const PER_STICK: [&str; 3] = [name::STICK_END, name::STICK_ENTRY_POSITION, name::STICK_ENTRY_VELOCITY];

/// True where the per-stick list `list` is null, its length differs from `n_stick`, or an
/// element is null or breaks the element rule: a `stick_end` is `flip`, `breakaway` or `horizon`;
/// an entry position or velocity is a finite number, and an entry velocity one of the belt's
/// `levels` where they are known.
fn per_stick_rule(list: &'static str, levels: Option<Vec<f64>>) -> Expr {
    use polars_arrow::array::{Array, ListArray, PrimitiveArray, Utf8ViewArray};
    col(list).map_many(
        move |cols: &mut [Column]| {
            let lists = cols[0].list()?.rechunk();
            let counts = cols[1].cast(&DataType::Int64)?;
            let counts = counts.i64()?.rechunk();
            let (Some(arr), Some(n)) = (lists.downcast_iter().next(), counts.downcast_iter().next()) else {
                return Ok(BooleanChunked::full_null(list.into(), 0).into_column());
            };
            // (one pass over the rows, each element checked in place)
            let o = arr.offsets().as_slice();
            let shape_bad = |arr: &ListArray<i64>, r: usize| !arr.is_valid(r) || !n.is_valid(r) || n.value(r) != o[r + 1] - o[r];
            let elements = arr.values();
            let bad: BooleanChunked = if let Some(names) = elements.as_any().downcast_ref::<Utf8ViewArray>() {
                let known = |i: usize| names.is_valid(i) && StickEnd::ALL.iter().any(|e| e.name() == names.value(i));
                flag_column((0..arr.len()).map(|r| shape_bad(arr, r) || !(o[r] as usize..o[r + 1] as usize).all(known)))
            } else if let Some(values) = elements.as_any().downcast_ref::<PrimitiveArray<f64>>() {
                let xs = values.values().as_slice();
                let known = |i: usize| values.is_valid(i) && xs[i].is_finite() && levels.as_ref().is_none_or(|l| l.contains(&xs[i]));
                flag_column((0..arr.len()).map(|r| shape_bad(arr, r) || !(o[r] as usize..o[r + 1] as usize).all(known)))
            } else {
                polars_bail!(SchemaMismatch: "column `{list}` is not a list of strings or of float64")
            };
            Ok(bad.with_name(list.into()).into_column())
        },
        &[col(name::N_STICK)],
        |_, fields| Ok(Field::new(fields[0].name().clone(), DataType::Boolean)),
    )
}

/// A non-null boolean column from per-row flags, through a bitmap (collecting the flags into a
/// `BooleanChunked` directly went through polars' type-inferring collector: 3 % of `analyze`).
fn flag_column(flags: impl Iterator<Item = bool>) -> BooleanChunked {
    use polars_arrow::array::BooleanArray;
    use polars_arrow::bitmap::MutableBitmap;
    let bits: MutableBitmap = flags.collect();
    BooleanChunked::from_chunk_iter(PlSmallStr::EMPTY, [BooleanArray::new(ArrowDataType::Boolean, bits.into(), None)])
}

/// The rule of a list column and its count as one pass over the values (polars' list kernels
/// took a fifth of the analysis): true where the list is null, its length differs from the
/// count, an element is null, not finite or outside [0, `top`], or (`ordered`) an element is
/// below the one before it, or the elements add up to more than `total`. (A null element is
/// looked for whatever the schema declares.)
fn list_rule(list: &'static str, count: &'static str, top: f64, ordered: bool, total: Option<f64>) -> Expr {
    use polars_arrow::array::{Array, PrimitiveArray};
    col(list).map_many(
        move |cols: &mut [Column]| {
            let lists = cols[0].list()?.rechunk();
            let counts = cols[1].cast(&DataType::Int64)?;
            let counts = counts.i64()?.rechunk();
            let (arr, n) = (lists.downcast_iter().next(), counts.downcast_iter().next());
            let bad: BooleanChunked = match (arr, n) {
                (Some(arr), Some(n)) => {
                    let values = arr
                        .values()
                        .as_any()
                        .downcast_ref::<PrimitiveArray<f64>>()
                        .ok_or_else(|| polars_err!(SchemaMismatch: "column `{list}` is not a list of float64"))?;
                    let offsets = arr.offsets().as_slice();
                    flag_column((0..arr.len()).map(|r| {
                        let (a, b) = (offsets[r] as usize, offsets[r + 1] as usize);
                        if !arr.is_valid(r) || !n.is_valid(r) || n.value(r) != (b - a) as i64 {
                            return true;
                        }
                        if values.validity().is_some_and(|v| (a..b).any(|i| !v.get_bit(i))) {
                            return true;
                        }
                        let xs = &values.values()[a..b];
                        xs.iter().any(|x| !(*x >= 0.0 && *x <= top))
                            || (ordered && xs.windows(2).any(|w| w[1] < w[0]))
                            || total.is_some_and(|t| xs.iter().sum::<f64>() > t)
                    }))
                }
                _ => BooleanChunked::full_null("".into(), 0),
            };
            Ok(bad.with_name(list.into()).into_column())
        },
        &[col(count)],
        |_, fields| Ok(Field::new(fields[0].name().clone(), DataType::Boolean)),
    )
}

/// The error naming the first file, row and column that break a rule (the main query found one):
/// each file is scanned again for its first offending row, which is checked in Rust for the
/// message ([`row_problem`]).
pub(crate) fn locate(cells: &[&Dataset]) -> PolarsError {
    for data in cells {
        for f in 0..data.files.len() {
            let rules = rules(data.file_starts[f], data);
            let any = rules.iter().map(|r| r.bad.clone()).reduce(|a, b| a.or(b)).expect("rules");
            let found = scan(&data.files[f], None, true).and_then(|lf| lf.filter(any).limit(1).collect());
            let df = match found {
                Ok(df) if df.height() == 0 => continue,
                Ok(df) => df,
                Err(e) => return polars_err!(ComputeError: "{}: {e}", data.files[f].display()),
            };
            let why = row_problem(&df, data.file_starts[f], data).unwrap_or_else(|| "a value breaks the dataset's rules".into());
            return polars_err!(ComputeError: "{}: {why}", data.files[f].display());
        }
    }
    polars_err!(ComputeError: "a value breaks the dataset's rules, but no file shows it when read again (did a file change?)")
}

/// The message for the first broken rule of a one-row frame (row `__row` of a part whose first
/// realization is `first`): row, realization, column, and what is wrong.
fn row_problem(df: &DataFrame, first: u64, data: &Dataset) -> Option<String> {
    let (horizon, switch_times, tails) = (data.scenario.run.duration, data.switch_times, data.tails_state);
    let int = |name: &str| df.column(name).ok()?.cast(&DataType::Int64).ok()?.i64().ok()?.get(0);
    let row = int(ROW)? as u64;
    let id = int(name::REALIZATION);
    let at = |c: &str, why: String| Some(format!("row {} (realization {}), column `{c}`: {why}", first + row, id.map_or("null".into(), |i| i.to_string())));
    if id != Some((first + row) as i64) {
        return at(
            name::REALIZATION,
            format!("expected realization {} (the part's declared range), found {}", first + row, id.map_or("null".into(), |i| i.to_string())),
        );
    }
    for (c, count, ordered) in lists(switch_times) {
        let n = int(count);
        let list = df.column(c).ok()?.list().ok()?.get_as_series(0);
        let Some(list) = list else { return at(c, "a null list (lists are never null; an empty list is [])".into()) };
        let values: Vec<Option<f64>> = list.cast(&DataType::Float64).ok()?.f64().ok()?.iter().collect();
        match n {
            Some(n) if n >= 0 && values.len() as i64 == n => {}
            Some(n) => return at(c, format!("{} values, but `{count}` = {n}", values.len())),
            None => return at(count, "a null count".into()),
        }
        if values.iter().any(Option::is_none) {
            return at(c, "a null element inside a list".into());
        }
        let values: Vec<f64> = values.into_iter().flatten().collect();
        if let Some(x) = values.iter().find(|x| !(**x >= 0.0 && **x <= horizon * (1.0 + 1e-12))) {
            return at(c, format!("value {} (event times and durations lie in [0, t_a = {horizon}] s)", crate::scenario::short(*x)));
        }
        if ordered && values.windows(2).any(|w| w[1] < w[0]) {
            return at(c, "values decrease (start instants are in increasing order)".into());
        }
        let sum: f64 = values.iter().sum();
        if c == name::STICK_DURATION && sum > horizon * (1.0 + 1e-9) {
            return at(c, format!("the sticks last {} s in all, more than t_a = {horizon} s", crate::scenario::short(sum)));
        }
    }
    if !switch_times {
        match int(name::N_SWITCHES) {
            Some(q) if (0..Q_LIMIT).contains(&q) => {}
            q => return at(name::N_SWITCHES, format!("{} (a count of belt changes, from 0 to 2^40)", q.map_or("null".into(), |q| q.to_string()))),
        }
    }
    if let Some(why) = df.column(name::LAST_TRUNCATED).ok().filter(|col| col.null_count() > 0).and_then(|_| at(name::LAST_TRUNCATED, "a null value".into())) {
        return Some(why);
    }
    if tails {
        let float = |c: &str| df.column(c).ok()?.f64().ok()?.get(0);
        let shown = |x: Option<f64>| x.map_or("null".into(), crate::scenario::short);
        let severity = float(name::SEVERITY);
        if !severity.is_some_and(|x| (0.0..=SEVERITY_BOUND).contains(&x) && !(x == 0.0 && x.is_sign_negative())) {
            return at(name::SEVERITY, format!("{} (a severity lies in [0, {SEVERITY_BOUND:e}])", shown(severity)));
        }
        let top = horizon * (1.0 + 1e-12);
        for (c, (lo, hi)) in scalar_rules(top) {
            let x = float(c);
            if !x.is_some_and(|x| x >= lo && x <= hi) {
                let rule = if hi == f64::MAX {
                    format!("a finite number{}", if lo == 0.0 { " >= 0" } else { "" })
                } else if hi == top {
                    format!("a time in [0, t_a = {}] s", shown(Some(horizon)))
                } else {
                    format!("a number in [{}, {}]", shown(Some(lo)), shown(Some(hi)))
                };
                return at(c, format!("{} (it is {rule})", shown(x)));
            }
        }
        let (lo, hi) = (float(name::MIN_VELOCITY), float(name::MAX_VELOCITY));
        if !(lo <= hi) {
            return at(name::MIN_VELOCITY, format!("{} is above max_velocity = {}", shown(lo), shown(hi)));
        }
    }
    let n = int(name::N_STICK)?;
    for c in PER_STICK.iter().filter(|_| tails) {
        match df.column(c).ok()?.list().ok()?.get_as_series(0) {
            None => return at(c, "a null list (lists are never null; an empty list is [])".into()),
            Some(l) if l.len() as i64 != n => return at(c, format!("{} values, but `{}` = {n} (one per stick)", l.len(), name::N_STICK)),
            Some(l) if l.dtype() == &DataType::String => {
                let ends = l.str().ok()?;
                if let Some(v) = ends.iter().find(|v| !v.is_some_and(|v| StickEnd::ALL.iter().any(|e| e.name() == v))) {
                    return at(c, format!("{:?} (a stick ends by flip, breakaway or horizon)", v.unwrap_or("null")));
                }
            }
            Some(l) => {
                let values = l.cast(&DataType::Float64).ok()?;
                let bad = values.f64().ok()?.iter().find(|v| !v.is_some_and(f64::is_finite));
                if let Some(v) = bad {
                    return at(c, format!("{} (an entry state is a finite number)", shown_opt(v)));
                }
                let levels = data.belt_levels.as_ref().filter(|_| *c == name::STICK_ENTRY_VELOCITY);
                let off = levels.and_then(|l| values.f64().ok()?.iter().flatten().find(|v| !l.contains(v)));
                if let (Some(v), Some(l)) = (off, levels) {
                    let shown: Vec<String> = l.iter().map(|x| crate::scenario::short(*x)).collect();
                    return at(c, format!("{} (a stick starts at a belt velocity, one of {})", crate::scenario::short(v), shown.join(", ")));
                }
            }
        }
    }
    None
}

fn shown_opt(x: Option<f64>) -> String {
    x.map_or("null".into(), crate::scenario::short)
}
