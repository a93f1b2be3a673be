//! The dataset `simulate` writes: one Parquet row per realization, ragged event lists.
//!
//! Layout: `DIR/part-IIIII-of-NNNNN.parquet`, one file per shard, rows sorted by the global
//! `realization` index. The columns are declared once, in [`schema::COLUMNS`] (name, the value a
//! realization writes, type, schema version, presence, storage, rule, unit, meaning): the
//! schema, the rows ([`Rows`]) and the Parquet settings here are read off it. After them, one
//! float64 column per random scene key, named after the key's last component (e.g.
//! `friction_coefficient`), with the value drawn for the realization.
//!
//! Rows are sorted by `realization`, declared as the sorting column of every row group. Files are
//! written under a unique hidden temporary name and renamed when complete (see [`crate::outdir`]),
//! so a reader never sees a partial file and a failed run leaves nothing behind. Parquet settings
//! follow what polars and DuckDB both read well ([`schema::Store`]: zstd for the integer and boolean
//! columns; PLAIN, uncompressed, without statistics for the floats — BYTE_STREAM_SPLIT saved 11 %
//! of size but made polars' reads 25 % slower; dictionaries only for the per-stick words and belt
//! velocities); spec-compliant list element name `element`; provenance in the file key-value
//! metadata.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{ArrayRef, BooleanArray, Float64Array, Int32Array, Int64Array, ListArray, RecordBatch, StringArray};
use arrow_buffer::{OffsetBuffer, ScalarBuffer};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use parquet::arrow::ArrowWriter;
use parquet::basic::{Compression, Encoding, ZstdLevel};
use parquet::file::metadata::{KeyValue, SortingColumn};
use parquet::file::properties::{EnabledStatistics, WriterProperties};
use parquet::schema::types::ColumnPath;

use super::schema::{self, Kind, Row, Store, Value};
use super::writeback::WriteBehind;
use crate::outdir::{Created, Lock, OutDirError, TempFile};
use crate::simulation::ensemble::Outcome;

/// Version of the column layout, recorded in every file ([`schema::VERSION`]).
pub use super::schema::VERSION as SCHEMA_VERSION;

/// Rows per Parquet row group (a row group is also flushed early past [`ROW_GROUP_BYTES`]).
const ROW_GROUP_ROWS: usize = 131_072;
const ROW_GROUP_BYTES: usize = 128 << 20;

/// The names of the columns (declared in [`super::schema`]).
pub use super::schema::columns;

/// The optional columns of a dataset: `switch_times`, and the drawn scene keys.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Layout {
    /// whether the `switch_times` and `switch_velocities` columns are written
    pub switch_times: bool,
    /// the column names of the drawn scene keys, in order
    pub drawn: Vec<&'static str>,
    /// whether a chain's columns are written
    pub chain: bool,
}

/// The Arrow schema of a dataset file: the declared columns ([`schema::COLUMNS`]) present
/// in this layout, then one float64 per drawn scene key.
pub fn schema(layout: &Layout) -> SchemaRef {
    let mut fields: Vec<Field> = schema::present(layout.switch_times, layout.chain).map(|c| Field::new(c.name, c.kind().arrow(), false)).collect();
    fields.extend(layout.drawn.iter().map(|name| Field::new(*name, DataType::Float64, false)));
    Arc::new(Schema::new(fields))
}

/// A ragged column being filled realization by realization: its values and the offsets after
/// each row.
#[derive(Debug, Clone)]
struct Ragged<T> {
    offsets: Vec<i32>,
    values: Vec<T>,
}

impl<T> Ragged<T> {
    /// Room for `rows` lists of `values` values in all.
    fn with_capacity(rows: usize, values: usize) -> Self {
        let mut offsets = Vec::with_capacity(rows + 1);
        offsets.push(0);
        Ragged { offsets, values: Vec::with_capacity(values) }
    }

    /// Append a row, its values added by `fill`.
    fn push_with(&mut self, fill: impl FnOnce(&mut Vec<T>)) {
        fill(&mut self.values);
        self.offsets.push(i32::try_from(self.values.len()).expect("a chunk holds < 2^31 list values"));
    }

    /// The column as an Arrow list of `values` (made of the values, their unused reserve given
    /// back first: the Python package holds every batch of a run).
    fn into_list(mut self, values: impl FnOnce(Vec<T>) -> ArrayRef) -> ArrayRef {
        self.values.shrink_to_fit();
        let values = values(self.values);
        let field = Arc::new(Field::new("element", values.data_type().clone(), false));
        Arc::new(ListArray::new(field, OffsetBuffer::new(ScalarBuffer::from(self.offsets)), values, None))
    }
}

/// The most values a list column reserves up front (512 KiB of f64; [`Rows::new`]).
const LIST_RESERVE: usize = 1 << 16;

/// One column being filled: the declared value ([`Value`]) with what it has gathered.
#[derive(Debug, Clone)]
enum Builder {
    Int64(fn(Row) -> i64, Vec<i64>),
    Int32(fn(Row) -> i32, Vec<i32>),
    Float64(fn(Row) -> f64, Vec<f64>),
    Bool(fn(Row) -> bool, Vec<bool>),
    Floats(fn(Row, &mut Vec<f64>), Ragged<f64>),
    Strings(&'static [&'static str], fn(Row, &mut Vec<u8>), Ragged<u8>),
}

impl Builder {
    fn new(value: Value, rows: usize, values: usize) -> Builder {
        match value {
            Value::Int64(f) => Builder::Int64(f, Vec::with_capacity(rows)),
            Value::Int32(f) => Builder::Int32(f, Vec::with_capacity(rows)),
            Value::Float64(f) => Builder::Float64(f, Vec::with_capacity(rows)),
            Value::Bool(f) => Builder::Bool(f, Vec::with_capacity(rows)),
            Value::Floats(f) => Builder::Floats(f, Ragged::with_capacity(rows, values)),
            Value::Strings(words, f) => Builder::Strings(words, f, Ragged::with_capacity(rows, values)),
        }
    }

    fn push(&mut self, row: Row) {
        match self {
            Builder::Int64(f, v) => v.push(f(row)),
            Builder::Int32(f, v) => v.push(f(row)),
            Builder::Float64(f, v) => v.push(f(row)),
            Builder::Bool(f, v) => v.push(f(row)),
            Builder::Floats(f, v) => v.push_with(|values| f(row, values)),
            Builder::Strings(_, f, v) => v.push_with(|values| f(row, values)),
        }
    }

    fn into_array(self) -> ArrayRef {
        match self {
            Builder::Int64(_, v) => Arc::new(Int64Array::from(v)),
            Builder::Int32(_, v) => Arc::new(Int32Array::from(v)),
            Builder::Float64(_, v) => Arc::new(Float64Array::from(v)),
            Builder::Bool(_, v) => Arc::new(BooleanArray::from(v)),
            Builder::Floats(_, v) => v.into_list(|values| Arc::new(Float64Array::from(values))),
            Builder::Strings(words, _, v) => v.into_list(|codes| Arc::new(StringArray::from_iter_values(codes.iter().map(|&c| words[usize::from(c)])))),
        }
    }
}

/// The rows of a contiguous run of realizations, column by column: one builder per declared
/// column present ([`schema::present`]), then the drawn scene keys.
#[derive(Debug, Clone)]
pub struct Rows {
    columns: Vec<Builder>,
    drawn: Vec<Vec<f64>>,
    /// rows held
    len: usize,
    /// Σ S_T over the rows
    sticks: u64,
}

impl Rows {
    /// Rows with the switch times column (or not) and `drawn` columns of drawn scene keys, with
    /// room for `rows` rows of about `per_list` values in each list (a hint: the columns grow
    /// past it; sized right, no column is copied while the rows are gathered). A list reserves at
    /// most [`LIST_RESERVE`] values: a chunk holds about 2^18 list values in all
    /// ([`crate::simulation::ensemble::Ensemble::chunk_len`]), and a scene with far more events per
    /// realization than that (one row per chunk) grows its lists as it goes rather than reserving
    /// its whole hint up front.
    pub fn new((with_switch_times, with_chain): (bool, bool), drawn: usize, rows: usize, per_list: usize) -> Rows {
        let values = rows.saturating_mul(per_list).min(LIST_RESERVE);
        Rows {
            columns: schema::present(with_switch_times, with_chain).map(|c| Builder::new(c.value, rows, values)).collect(),
            // (not `vec![…; drawn]`: a clone of an empty Vec has no capacity)
            drawn: (0..drawn).map(|_| Vec::with_capacity(rows)).collect(),
            len: 0,
            sticks: 0,
        }
    }

    /// Rows held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no row is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Σ S_T over the rows.
    pub fn total_sticks(&self) -> u64 {
        self.sticks
    }

    /// Append realization `index`.
    pub fn push(&mut self, index: u64, out: &Outcome) {
        let row = Row { index, out };
        for column in &mut self.columns {
            column.push(row);
        }
        for (col, &x) in self.drawn.iter_mut().zip(&out.drawn) {
            col.push(x);
        }
        self.len += 1;
        self.sticks += out.record.n_stick() as u64;
    }

    /// The rows as an Arrow record batch with [`schema`].
    pub fn into_batch(self, layout: &Layout) -> RecordBatch {
        let mut columns: Vec<ArrayRef> = self.columns.into_iter().map(Builder::into_array).collect();
        columns.extend(self.drawn.into_iter().map(|v| Arc::new(Float64Array::from(v)) as ArrayRef));
        RecordBatch::try_new(schema(layout), columns).expect("columns match the schema")
    }
}

/// Errors writing a dataset, each naming the path.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// The output directory could not be prepared or locked.
    #[error(transparent)]
    Out(#[from] OutDirError),
    /// The directory holds a part of a run split into a different number of shards.
    #[error("output directory {} already holds {}, a part of a run split into a different number of shards; remove it or choose another --out", dir.display(), other.display())]
    Layout {
        /// the output directory
        dir: PathBuf,
        /// the part of the other split found there
        other: PathBuf,
    },
    /// Writing a part file failed.
    #[error("writing {}: {source}", path.display())]
    Write {
        /// the file
        path: PathBuf,
        /// the Arrow, Parquet or I/O error
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

impl crate::blame::Blame for DatasetError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            DatasetError::Layout { .. } => Some(crate::blame::Culprit::Output),
            DatasetError::Out(o) => o.blame(),
            DatasetError::Write { .. } => None,
        }
    }
}

/// File name of shard `index` of `count`.
pub fn part_name(index: u64, count: u64) -> String {
    format!("part-{index:05}-of-{count:05}.parquet")
}

/// Whether the file at `path` is a stickslip dataset part (its footer says so).
fn is_stickslip_part(path: &Path) -> bool {
    crate::metadata::footer(path).is_some_and(|kv| kv.iter().any(|(k, _)| k == crate::metadata::SCHEMA_VERSION))
}

/// Writes one part file: created under a unique temporary name while holding the part's lock,
/// renamed by [`PartWriter::commit`], removed if dropped before that.
pub struct PartWriter {
    writer: Option<ArrowWriter<WriteBehind>>,
    layout: Layout,
    tmp: Option<TempFile>,
    _lock: Lock,
    /// a sweep cell's directories this part created, kept on commit
    created: Created,
}

impl PartWriter {
    /// Open `dir/part-index-of-count.parquet` for writing, with key-value `metadata`; `dir`
    /// exists and is a dataset directory ([`crate::outdir::DatasetDir`]).
    pub fn create(dir: &Path, index: u64, count: u64, layout: Layout, metadata: Vec<(String, String)>) -> Result<PartWriter, DatasetError> {
        let out_err = |e: std::io::Error| DatasetError::Write { path: dir.to_owned(), source: Box::new(e) };
        let created = Created::dir_all(dir)?;
        let name = part_name(index, count);
        let path = dir.join(&name);
        let lock = Lock::acquire(&path)?;
        let suffix = format!("-of-{count:05}.parquet");
        for entry in std::fs::read_dir(dir).map_err(out_err)? {
            let file = entry.map_err(out_err)?.file_name().to_string_lossy().into_owned();
            if file.starts_with("part-") && file.ends_with(".parquet") && !file.ends_with(&suffix) {
                return Err(DatasetError::Layout { dir: dir.to_owned(), other: dir.join(file) });
            }
        }
        if std::fs::symlink_metadata(&path).is_ok() && !is_stickslip_part(&path) {
            return Err(OutDirError {
                path,
                message: "exists and is not a stickslip part file; refusing to replace it: choose another --out".into(),
                refused: true,
            }
            .into());
        }
        let (tmp, file) = TempFile::create(&path)?;
        let writer = ArrowWriter::try_new(WriteBehind::new(file), schema(&layout), Some(properties(&layout, metadata)))
            .map_err(|e| DatasetError::Write { path: path.clone(), source: Box::new(e) })?;
        Ok(PartWriter { writer: Some(writer), layout, tmp: Some(tmp), _lock: lock, created })
    }

    fn write_err(&self, e: impl std::error::Error + Send + Sync + 'static) -> DatasetError {
        let path = self.tmp.as_ref().map_or_else(PathBuf::new, |t| t.path().to_owned());
        DatasetError::Write { path, source: Box::new(e) }
    }

    /// Append rows; row groups are cut at a fixed row count (or size), never by timing.
    pub fn write(&mut self, rows: Rows) -> Result<(), DatasetError> {
        let batch = rows.into_batch(&self.layout);
        self.write_batch(&batch)
    }

    /// Append a record batch of this file's schema (rows already made, as
    /// [`crate::simulation::simulate::batches`] makes them).
    pub fn write_batch(&mut self, batch: &RecordBatch) -> Result<(), DatasetError> {
        let writer = self.writer.as_mut().expect("open until finished");
        let result = writer.write(batch).and_then(|()| if writer.in_progress_size() > ROW_GROUP_BYTES { writer.flush() } else { Ok(()) });
        result.map_err(|e| self.write_err(e))
    }

    /// Add a key-value pair to the file's metadata (written when it is finished).
    pub fn append_metadata(&mut self, key: &str, value: &str) {
        self.writer.as_mut().expect("open until finished").append_key_value_metadata(KeyValue::new(key.to_string(), value.to_string()));
    }

    /// Finish the file, still under its temporary name: [`Finished::commit`] moves it.
    pub fn finish(mut self) -> Result<Finished, DatasetError> {
        let writer = self.writer.take().expect("open until finished");
        writer.close().map_err(|e| self.write_err(e))?;
        Ok(Finished { tmp: self.tmp.take().expect("present until finished"), _lock: self._lock, created: std::mem::take(&mut self.created) })
    }

    /// Finish the file and move it to its final name.
    pub fn commit(self) -> Result<PathBuf, DatasetError> {
        self.finish()?.commit()
    }
}

/// A complete part file under its temporary name (the part stays locked).
#[derive(Debug)]
pub struct Finished {
    tmp: TempFile,
    _lock: Lock,
    created: Created,
}

impl Finished {
    /// The final path.
    pub fn path(&self) -> &Path {
        self.tmp.path()
    }

    /// Rename into place.
    pub fn commit(self) -> Result<PathBuf, DatasetError> {
        let path = self.tmp.commit()?;
        self.created.keep();
        Ok(path)
    }
}

fn properties(layout: &Layout, metadata: Vec<(String, String)>) -> WriterProperties {
    // zstd, no dictionaries (the counts are small integers zstd packs anyway; interning cost 2 %
    // of a run), min/max statistics per row group (realization ranges let readers skip row
    // groups): [`Store::Packed`], the default; the other columns as their declarations say.
    let mut builder = WriterProperties::builder()
        .set_compression(Compression::ZSTD(ZstdLevel::try_new(1).expect("valid level")))
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::Chunk)
        .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
        .set_coerce_types(true)
        // rows are in realization order (column 0): declared, so readers can rely on it
        .set_sorting_columns(Some(vec![SortingColumn { column_idx: 0, descending: false, nulls_first: false }]))
        .set_key_value_metadata(Some(metadata.into_iter().map(|(k, v)| KeyValue::new(k, v)).collect()));
    let declared = schema::present(layout.switch_times, layout.chain).map(|c| (c.name, c.kind(), c.store));
    let drawn = layout.drawn.iter().map(|name| (*name, Kind::Float64, Store::Plain));
    for (name, kind, store) in declared.chain(drawn) {
        let path = match kind {
            Kind::Floats | Kind::Strings => ColumnPath::new(vec![name.into(), "list".into(), "element".into()]),
            _ => ColumnPath::from(name),
        };
        builder = match store {
            Store::Packed => builder,
            Store::Plain => builder
                .set_column_encoding(path.clone(), Encoding::PLAIN)
                .set_column_statistics_enabled(path.clone(), EnabledStatistics::None)
                .set_column_compression(path, Compression::UNCOMPRESSED),
            Store::Dictionary => builder.set_column_dictionary_enabled(path.clone(), true).set_column_statistics_enabled(path, EnabledStatistics::None),
        };
    }
    builder.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The capacity of each list column's values.
    fn list_capacities(rows: &Rows) -> Vec<usize> {
        let lists = rows.columns.iter().filter_map(|c| match c {
            Builder::Floats(_, v) => Some((v.values.capacity(), v.offsets.capacity())),
            Builder::Strings(_, _, v) => Some((v.values.capacity(), v.offsets.capacity())),
            _ => None,
        });
        lists.map(|(values, offsets)| values.min(offsets.saturating_mul(1 << 20))).collect()
    }

    #[test]
    fn rows_reserve_what_the_chunk_needs_and_no_more_than_the_cap() {
        // a chunk of 1,000 rows of 30 values per list, two drawn keys, switch times kept: the
        // four interval lists, stick_end, the two entry lists and the two switch lists
        let rows = Rows::new((true, false), 2, 1000, 30);
        assert_eq!(list_capacities(&rows).len(), 9);
        for c in &rows.columns {
            let (values, offsets) = match c {
                Builder::Floats(_, v) => (v.values.capacity(), v.offsets.capacity()),
                Builder::Strings(_, _, v) => (v.values.capacity(), v.offsets.capacity()),
                _ => continue,
            };
            assert!(values >= 30_000 && offsets >= 1001, "{values} {offsets}");
        }
        // every drawn column, not only the last (a clone of an empty Vec has no capacity)
        assert!(rows.drawn.iter().all(|c| c.capacity() >= 1000), "{:?}", rows.drawn.iter().map(Vec::capacity).collect::<Vec<_>>());
        // a scene with 10^7 expected events per realization (one row per chunk) grows its lists
        // instead of reserving 80 MB each up front
        let huge = Rows::new((true, false), 0, 1, 10_000_000);
        assert!(list_capacities(&huge).iter().all(|&c| c <= LIST_RESERVE));
    }
}
