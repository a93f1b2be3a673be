//! Reading a dataset's part files with polars, for the analysis (its Rust API changes between
//! minor versions; polars is pinned in Cargo.toml; the small tables' I/O is `crate::table`, the
//! observables' expressions `crate::observables`).
//!
//! Reading: each part file is read in fixed slices of rows, projecting only the columns
//! the analysis needs; the k-th list elements are read straight from the Arrow buffers of each
//! slice. The exploded event table is never materialized and memory stays bounded by one slice
//! whatever the number of realizations. (The streaming engine's ordered batch sink was tried
//! first: it decoded ahead of the consumer and buffered, so its memory grew with the dataset.)

use std::fs::File;
use std::path::Path;

use polars::prelude::*;
use polars_arrow::array::{Array, PrimitiveArray};

use super::input::Stamp;
use super::series::{Series, Variable};

/// One batch of realizations, in dataset order: the value of each requested series (`None`
/// where a realization has no k-th event) and the columns that tell truncation.
#[derive(Debug, Default)]
pub struct Batch {
    /// the realization index of row 0 (rows are consecutive realizations)
    pub first: u64,
    pub values: Vec<Vec<Option<f64>>>,
    pub n_stick: Vec<i64>,
    pub n_slip: Vec<i64>,
    pub last_truncated: Vec<bool>,
}

/// One part file to stream: where, how many rows, its first realization index, and what it
/// looked like when checked.
#[derive(Debug, Clone)]
pub struct FilePart<'a> {
    pub path: &'a Path,
    pub rows: u64,
    pub first: u64,
    pub stamp: Stamp,
    /// the recorded t_a [s]: no event time or duration exceeds it
    pub horizon: f64,
}

/// The offsets and values of a list<f64> column, chunk by chunk, refusing nulls (`first`: the
/// dataset row of the column's first row, for the message).
fn list_chunks(column: &Column, first: u64) -> PolarsResult<Vec<(&[i64], &[f64])>> {
    let ca = column.list()?;
    let mut out = Vec::new();
    let mut row0 = first;
    for arr in ca.downcast_iter() {
        let values = arr
            .values()
            .as_any()
            .downcast_ref::<PrimitiveArray<f64>>()
            .ok_or_else(|| polars_err!(SchemaMismatch: "column `{}` is not a list of float64", column.name()))?;
        if arr.null_count() > 0 {
            polars_bail!(ComputeError: "column `{}` has a null list (lists are never null; an empty list is [])", column.name());
        }
        if let Some(j) = values.validity().and_then(|v| v.iter().position(|valid| !valid)) {
            let row = arr.offsets().as_slice().partition_point(|&o| o as usize <= j).saturating_sub(1);
            polars_bail!(ComputeError: "row {}, column `{}`: a null element inside a list", row0 + row as u64, column.name());
        }
        row0 += arr.len() as u64;
        out.push((arr.offsets().as_slice(), values.values().as_slice()));
    }
    Ok(out)
}

/// The rows of a list<f64> column as slices (`first`: see [`list_chunks`]).
fn list_rows(column: &Column, first: u64) -> PolarsResult<Vec<&[f64]>> {
    let mut rows = Vec::with_capacity(column.len());
    for (offsets, values) in list_chunks(column, first)? {
        rows.extend(offsets.windows(2).map(|w| &values[w[0] as usize..w[1] as usize]));
    }
    Ok(rows)
}

/// A count column (int32 in schema v1, int64 in v2), refusing nulls.
fn ints(df: &DataFrame, name: &str) -> PolarsResult<Vec<i64>> {
    let c = df.column(name)?;
    if c.null_count() > 0 {
        polars_bail!(ComputeError: "column `{name}` has null values");
    }
    Ok(c.cast(&DataType::Int64)?.i64()?.iter().map(|v| v.unwrap_or(0)).collect())
}

/// Check every value of a slice before anything is folded: realization ids are the declared
/// consecutive range, counts are non-negative and equal their lists' lengths, event times are
/// finite, non-negative and at most the horizon t_a, starts do not decrease. The error names row,
/// realization and column. Returns the rows of the list columns it checked, for [`to_batch`].
fn validate(df: &DataFrame, first: u64, switch_times: bool, horizon: f64) -> PolarsResult<Lists<'_>> {
    let ids = ints(df, "realization")?;
    let at = |r: usize, col: &str, why: String| polars_err!(ComputeError: "row {} (realization {}), column `{col}`: {why}", first + r as u64, ids[r]);
    for (r, &id) in ids.iter().enumerate() {
        if id != (first + r as u64) as i64 {
            return Err(at(r, "realization", format!("expected realization {} (the part's declared range), found {id}", first + r as u64)));
        }
    }
    let mut checked = Lists::new();
    let mut counted = vec![("n_stick", ["stick_start", "stick_duration"].as_slice()), ("n_slip", ["slip_start", "slip_duration"].as_slice())];
    if switch_times {
        counted.push(("n_switches", ["switch_times"].as_slice()));
    }
    for (count, cols) in counted {
        let n = ints(df, count)?;
        for &col in cols {
            let rows = list_rows(df.column(col)?, first)?;
            for (r, row) in rows.iter().enumerate() {
                if n[r] < 0 || row.len() as i64 != n[r] {
                    return Err(at(r, col, format!("{} values, but `{count}` = {}", row.len(), n[r])));
                }
                // (a duration cut at t_a is t_a − start, rounded: a relative 1e-12 of slack)
                if let Some(x) = row.iter().find(|x| !(**x >= 0.0 && **x <= horizon * (1.0 + 1e-12))) {
                    return Err(at(r, col, format!("value {} (event times and durations lie in [0, t_a = {horizon}] s)", crate::scenario::short(*x))));
                }
                let is_start = col.ends_with("_start") || col == "switch_times";
                if is_start && row.windows(2).any(|w| w[1] < w[0]) {
                    return Err(at(r, col, "values decrease (start instants are in increasing order)".into()));
                }
            }
            checked.insert(col, rows);
        }
    }
    if df.column("last_truncated")?.null_count() > 0 {
        polars_bail!(ComputeError: "column `last_truncated` has null values");
    }
    Ok(checked)
}

/// The rows of list columns, by column name.
type Lists<'a> = std::collections::HashMap<&'static str, Vec<&'a [f64]>>;

/// The batch of `series` from a validated slice and the list rows [`validate`] returned.
fn to_batch<'a>(df: &'a DataFrame, series: &[Series], mut rows_of: Lists<'a>) -> PolarsResult<Batch> {
    let mut batch = Batch {
        first: 0,
        values: vec![Vec::new(); series.len()],
        n_stick: ints(df, "n_stick")?,
        n_slip: ints(df, "n_slip")?,
        last_truncated: df.column("last_truncated")?.bool()?.iter().map(|v| v.unwrap_or(false)).collect(),
    };
    for (i, s) in series.iter().enumerate() {
        let name = s.var.column();
        if s.var == Variable::StickTime || s.index.is_some() {
            if !rows_of.contains_key(name) {
                rows_of.insert(name, list_rows(df.column(name)?, 0)?);
            }
        }
        batch.values[i] = match (s.var, s.index) {
            (Variable::StickTime, _) => rows_of[name].iter().map(|row| Some(row.iter().sum::<f64>())).collect(),
            (_, Some(k)) => rows_of[name].iter().map(|row| row.get(k as usize - 1).copied()).collect(),
            (_, None) => ints(df, name)?.iter().map(|&c| Some(c as f64)).collect(),
        };
    }
    Ok(batch)
}

/// Rows per slice (the dataset's row-group size): bounds the memory of a pass (about 70 MB of
/// list data on the paper scenario).
const SLICE_ROWS: u64 = 131_072;

/// Reader threads per file: each decodes every `READERS`-th slice (polars decodes one slice on
/// one thread), while the caller consumes the slices in order.
const READERS: usize = 2;

/// Stream `series` of one part file through `sink`, in row order, one bounded slice at a time:
/// polars' Parquet reader decodes only the projected columns of the row groups overlapping a
/// slice; [`READERS`] threads each stay one slice ahead of `sink`. Every slice is validated
/// ([`validate`]) before `sink` sees it, and the file must keep the stamp it had when checked.
pub fn stream_file(part: &FilePart, series: &[Series], switch_times: bool, sink: &mut dyn FnMut(&Batch)) -> PolarsResult<()> {
    let with_switches = switch_times && series.iter().any(|s| s.var == Variable::Y);
    let mut names: Vec<String> = series.iter().map(|s| s.var.column().to_string()).collect();
    names.extend(["realization", "n_stick", "n_slip", "last_truncated", "stick_start", "stick_duration", "slip_start", "slip_duration"].map(String::from));
    if with_switches {
        names.extend(["n_switches", "switch_times"].map(String::from));
    }
    names.sort_unstable();
    names.dedup();
    let unchanged = || -> PolarsResult<()> {
        match Stamp::of(part.path) {
            Ok(now) if now == part.stamp => Ok(()),
            _ => Err(polars_err!(ComputeError: "the file changed while it was being analysed (is a simulate still writing here?); run analyze again when it is done")),
        }
    };
    let read = |offset: u64| -> PolarsResult<Batch> {
        unchanged()?;
        let file = File::open(part.path).map_err(|e| polars_err!(ComputeError: "{e}"))?;
        let df = ParquetReader::new(file)
            .with_columns(Some(names.clone()))
            .with_slice(Some((offset as usize, SLICE_ROWS as usize)))
            .finish()?;
        if df.height() as u64 != SLICE_ROWS.min(part.rows - offset) {
            polars_bail!(ComputeError: "rows {offset}.. could not be read in full");
        }
        let lists = validate(&df, part.first + offset, with_switches, part.horizon)?;
        let mut batch = to_batch(&df, series, lists)?;
        batch.first = part.first + offset;
        unchanged()?;
        Ok(batch)
    };
    let offsets: Vec<u64> = (0..part.rows).step_by(SLICE_ROWS as usize).collect();
    std::thread::scope(|scope| {
        let receivers: Vec<_> = (0..READERS)
            .map(|r| {
                let (tx, rx) = std::sync::mpsc::sync_channel::<PolarsResult<Batch>>(1);
                let (read, mine) = (&read, offsets.iter().skip(r).step_by(READERS).copied().collect::<Vec<_>>());
                scope.spawn(move || {
                    for offset in mine {
                        let batch = read(offset);
                        let failed = batch.is_err();
                        if tx.send(batch).is_err() || failed {
                            return;
                        }
                    }
                });
                rx
            })
            .collect();
        for i in 0..offsets.len() {
            let batch = receivers[i % READERS].recv().map_err(|_| polars_err!(ComputeError: "reader stopped"))??;
            sink(&batch);
        }
        Ok(())
    })
}
