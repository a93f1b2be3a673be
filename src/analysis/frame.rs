//! The polars boundary: every polars call of the analysis lives here (its Rust API changes
//! between minor versions; polars is pinned in Cargo.toml).
//!
//! Reading: each part file is read in fixed slices of rows, projecting only the columns
//! the analysis needs; the k-th list elements are read straight from the Arrow buffers of each
//! slice. The exploded event table is never materialized and memory stays bounded by one slice
//! whatever the number of realizations. (The streaming engine's ordered batch sink was tried
//! first: it decoded ahead of the consumer and buffered, so its memory grew with the dataset.)
//! Writing: small tidy tables to Parquet.

use std::fs::File;
use std::path::Path;

use polars::prelude::*;
use polars_arrow::array::PrimitiveArray;

use super::series::{Series, Variable};

/// One batch of realizations, in dataset order: the value of each requested series (`None`
/// where a realization has no k-th event) and the columns that tell truncation.
#[derive(Debug, Default)]
pub struct Batch {
    pub values: Vec<Vec<Option<f64>>>,
    pub n_stick: Vec<i32>,
    pub n_slip: Vec<i32>,
    pub last_truncated: Vec<bool>,
}

/// The k-th elements (k in `ks`, 1-based) of every row of a list<f64> column, read straight from
/// the Arrow offsets and values buffers.
fn nth_elements(column: &Column, ks: &[u32]) -> PolarsResult<Vec<Vec<Option<f64>>>> {
    let ca = column.list()?;
    let mut out: Vec<Vec<Option<f64>>> = ks.iter().map(|_| Vec::with_capacity(ca.len())).collect();
    for arr in ca.downcast_iter() {
        let offsets = arr.offsets().as_slice();
        let values = arr
            .values()
            .as_any()
            .downcast_ref::<PrimitiveArray<f64>>()
            .ok_or_else(|| polars_err!(SchemaMismatch: "column `{}` is not a list of float64", column.name()))?
            .values()
            .as_slice();
        for r in 0..arr.len() {
            let (start, end) = (offsets[r] as usize, offsets[r + 1] as usize);
            for (slot, &k) in out.iter_mut().zip(ks) {
                let i = start + k as usize - 1;
                slot.push((i < end).then(|| values[i]));
            }
        }
    }
    Ok(out)
}

fn ints(df: &DataFrame, name: &str) -> PolarsResult<Vec<i32>> {
    Ok(df.column(name)?.i32()?.iter().map(|v| v.unwrap_or(0)).collect())
}

fn to_batch(df: &DataFrame, series: &[Series]) -> PolarsResult<Batch> {
    let mut batch = Batch {
        values: vec![Vec::new(); series.len()],
        n_stick: ints(df, "n_stick")?,
        n_slip: ints(df, "n_slip")?,
        last_truncated: df.column("last_truncated")?.bool()?.iter().map(|v| v.unwrap_or(false)).collect(),
    };
    for (i, s) in series.iter().enumerate().filter(|(_, s)| s.var == Variable::StickTime) {
        let ca = df.column(s.var.column())?.list()?;
        let mut sums = Vec::with_capacity(ca.len());
        for arr in ca.downcast_iter() {
            let offsets = arr.offsets().as_slice();
            let values = arr.values().as_any().downcast_ref::<PrimitiveArray<f64>>().map(|a| a.values().as_slice()).unwrap_or(&[]);
            sums.extend((0..arr.len()).map(|r| Some(values[offsets[r] as usize..offsets[r + 1] as usize].iter().sum::<f64>())));
        }
        batch.values[i] = sums;
    }
    let mut columns: Vec<&'static str> =
        series.iter().filter(|s| s.var != Variable::StickTime).map(|s| s.var.column()).collect();
    columns.sort_unstable();
    columns.dedup();
    for name in columns {
        let members: Vec<usize> =
            (0..series.len()).filter(|&i| series[i].var.column() == name && series[i].var != Variable::StickTime).collect();
        match series[members[0]].index {
            Some(_) => {
                let ks: Vec<u32> = members.iter().map(|&i| series[i].index.expect("indexed")).collect();
                for (i, values) in members.iter().zip(nth_elements(df.column(name)?, &ks)?) {
                    batch.values[*i] = values;
                }
            }
            None => {
                let counts = ints(df, name)?;
                for &i in &members {
                    batch.values[i] = counts.iter().map(|&c| Some(f64::from(c))).collect();
                }
            }
        }
    }
    Ok(batch)
}

/// Rows per slice (the dataset's row-group size): bounds the memory of a pass (about 70 MB of
/// list data on the paper scenario).
const SLICE_ROWS: u64 = 131_072;

/// Reader threads per file: each decodes every `READERS`-th slice (polars decodes one slice on
/// one thread), while the caller consumes the slices in order.
const READERS: usize = 2;

/// Stream `series` of one part file (`rows` rows) through `sink`, in row order, one bounded
/// slice at a time: polars' Parquet reader decodes only the projected columns of the row groups
/// overlapping a slice; [`READERS`] threads each stay one slice ahead of `sink`.
pub fn stream_file(path: &Path, rows: u64, series: &[Series], sink: &mut dyn FnMut(&Batch)) -> PolarsResult<()> {
    let mut names: Vec<String> = series.iter().map(|s| s.var.column().to_string()).collect();
    names.extend(["n_stick", "n_slip", "last_truncated"].map(String::from));
    names.sort_unstable();
    names.dedup();
    let read = |offset: u64| -> PolarsResult<Batch> {
        let file = File::open(path).map_err(|e| polars_err!(ComputeError: "{e}"))?;
        let df = ParquetReader::new(file)
            .with_columns(Some(names.clone()))
            .with_slice(Some((offset as usize, SLICE_ROWS as usize)))
            .finish()?;
        to_batch(&df, series)
    };
    let offsets: Vec<u64> = (0..rows).step_by(SLICE_ROWS as usize).collect();
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

/// A small tidy table, column by column.
#[derive(Debug, Clone, Default)]
pub struct Table {
    pub columns: Vec<(String, Col)>,
}

#[derive(Debug, Clone)]
pub enum Col {
    Str(Vec<String>),
    Int(Vec<Option<i64>>),
    Float(Vec<Option<f64>>),
}

impl Table {
    /// Read a table written by [`Table::write_parquet`] (string, integer and float columns).
    pub fn read_parquet(path: &Path) -> PolarsResult<Table> {
        let file = File::open(path).map_err(|e| polars_err!(ComputeError: "{}: {e}", path.display()))?;
        let df = ParquetReader::new(file).finish()?;
        let mut t = Table::default();
        for c in df.columns() {
            let name = c.name().to_string();
            let col = match c.dtype() {
                DataType::String => Col::Str(c.str()?.iter().map(|v| v.unwrap_or_default().to_string()).collect()),
                DataType::Int64 | DataType::Int32 => Col::Int(c.cast(&DataType::Int64)?.i64()?.iter().collect()),
                DataType::Float64 => Col::Float(c.f64()?.iter().collect()),
                other => polars_bail!(SchemaMismatch: "{}: column `{name}` has unsupported type {other}", path.display()),
            };
            t.columns.push((name, col));
        }
        Ok(t)
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.columns.first().map_or(0, |(_, c)| match c {
            Col::Str(v) => v.len(),
            Col::Int(v) => v.len(),
            Col::Float(v) => v.len(),
        })
    }

    fn col(&self, name: &str) -> Option<&Col> {
        self.columns.iter().find(|(n, _)| n == name).map(|(_, c)| c)
    }

    pub fn strings(&self, name: &str) -> Option<&[String]> {
        match self.col(name)? {
            Col::Str(v) => Some(v),
            _ => None,
        }
    }

    pub fn ints(&self, name: &str) -> Option<&[Option<i64>]> {
        match self.col(name)? {
            Col::Int(v) => Some(v),
            _ => None,
        }
    }

    pub fn floats(&self, name: &str) -> Option<&[Option<f64>]> {
        match self.col(name)? {
            Col::Float(v) => Some(v),
            _ => None,
        }
    }

    pub fn push(&mut self, name: &str, col: Col) -> &mut Self {
        self.columns.push((name.to_string(), col));
        self
    }

    /// Write as Parquet (zstd) to `path`.
    pub fn write_parquet(&self, path: &Path) -> PolarsResult<()> {
        let columns: Vec<Column> = self
            .columns
            .iter()
            .map(|(name, c)| match c {
                Col::Str(v) => Column::new(name.as_str().into(), v),
                Col::Int(v) => Column::new(name.as_str().into(), v),
                Col::Float(v) => Column::new(name.as_str().into(), v),
            })
            .collect();
        let mut df = DataFrame::new_infer_height(columns)?;
        let file = File::create(path).map_err(|e| polars_err!(ComputeError: "{}: {e}", path.display()))?;
        ParquetWriter::new(file).with_compression(ParquetCompression::Zstd(None)).finish(&mut df)?;
        Ok(())
    }
}
