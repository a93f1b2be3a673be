//! The dataset `simulate` writes: one Parquet row per realization, ragged event lists.
//!
//! Layout: `DIR/part-IIIII-of-NNNNN.parquet`, one file per shard, rows sorted by the global
//! `realization` index. Columns (see `CONTRACT.md`): `realization` int64, `x0`, `xdot0` float64,
//! `initial_sign` int32 (belt sign at t = 0⁺: ±1, 0 for a belt at rest), `initial_velocity`
//! float64 (m/s, the belt velocity at t = 0⁺; added in v3 with the belt processes),
//! `n_switches` int64 (Q, the belt's velocity changes), `n_stick`, `n_slip` int64
//! (S_T, S_L; schema v2 — v1 had int32 counts), `stick_start`, `stick_duration`, `slip_start`, `slip_duration` list<float64>
//! (T, D, L, H; non-null lists, `[]` when empty), `last_truncated` bool; schema v3 adds the tails'
//! state: `stick_end` list<utf8> (`flip`, `breakaway`, `horizon` per stick),
//! `stick_entry_position`, `stick_entry_velocity` list<float64> (x [m] and belt velocity [m/s] at
//! each stick's start), `longest_stick`, `stick_fraction`, `min_velocity`, `max_velocity`,
//! `max_slip_speed`, `severity` float64 (s, 1, m/s, 1; [`crate::simulation::events::Record`]); then
//! `switch_times`
//! list<float64> (Y) and `switch_velocities` list<float64> (m/s, the velocity after each change)
//! only when the scenario asks for them, then one float64 column per random scene
//! key, named after the key's last component (e.g. `friction_coefficient`), with the value drawn
//! for the realization.
//!
//! Rows are sorted by `realization`, declared as the sorting column of every row group. Files are
//! written under a unique hidden temporary name and renamed when complete (see [`crate::outdir`]),
//! so a reader never sees a partial file and a failed run leaves nothing behind. Parquet settings
//! follow what polars and DuckDB both read well: zstd for the integer and boolean columns; PLAIN,
//! uncompressed, without statistics for the floats (initial conditions and event times are
//! near-incompressible: zstd saved 8 % of the size for 12 % of the run time, and
//! BYTE_STREAM_SPLIT saved 11 % of size but made polars' reads 25 % slower); no dictionaries;
//! spec-compliant list element name `element`; provenance in the file key-value metadata.

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

use super::writeback::WriteBehind;
use crate::outdir::{Created, Lock, OutDirError, TempFile};
use crate::simulation::ensemble::Outcome;
use crate::simulation::events::StickEnd;

/// Version of the column layout, recorded in every file.
pub const SCHEMA_VERSION: &str = "3";

/// The schema versions `analyze` reads (v1 had int32 counts; v3 added the tails' columns).
pub const READABLE_VERSIONS: [&str; 3] = ["1", "2", "3"];

/// Rows per Parquet row group (a row group is also flushed early past [`ROW_GROUP_BYTES`]).
const ROW_GROUP_ROWS: usize = 131_072;
const ROW_GROUP_BYTES: usize = 128 << 20;

/// The names of the columns (declared in [`super::schema`]).
pub use super::schema::columns;

/// List columns, in schema order.
pub const LIST_COLUMNS: [&str; 4] = [columns::STICK_START, columns::STICK_DURATION, columns::SLIP_START, columns::SLIP_DURATION];

/// The optional columns of a dataset: `switch_times`, and the drawn scene keys.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Layout {
    /// whether the `switch_times` and `switch_velocities` columns are written
    pub switch_times: bool,
    /// the column names of the drawn scene keys, in order
    pub drawn: Vec<&'static str>,
}

/// The Arrow schema of a dataset file: the declared columns ([`super::schema::COLUMNS`]) present
/// in this layout, then one float64 per drawn scene key.
pub fn schema(layout: &Layout) -> SchemaRef {
    use super::schema::{Presence, COLUMNS};
    let present = |c: &&super::schema::Column| c.presence == Presence::Always || layout.switch_times;
    let mut fields: Vec<Field> = COLUMNS.iter().filter(present).map(|c| Field::new(c.name, c.kind.arrow(), false)).collect();
    fields.extend(layout.drawn.iter().map(|name| Field::new(*name, DataType::Float64, false)));
    Arc::new(Schema::new(fields))
}

/// A ragged float column being filled realization by realization.
#[derive(Debug, Clone)]
struct ListColumn {
    offsets: Vec<i32>,
    values: Vec<f64>,
}

impl ListColumn {
    /// Room for `rows` lists of `values` values in all.
    fn with_capacity(rows: usize, values: usize) -> Self {
        ListColumn { offsets: offsets_for(rows), values: Vec::with_capacity(values) }
    }

    fn push(&mut self, row: &[f64]) {
        self.extend(row.iter().copied());
    }

    fn extend(&mut self, row: impl Iterator<Item = f64>) {
        self.values.extend(row);
        self.offsets.push(i32::try_from(self.values.len()).expect("a chunk holds < 2^31 list values"));
    }

    /// The column as an Arrow list array, its unused reserve given back first (the Python
    /// package holds every batch of a run).
    fn into_array(mut self) -> ArrayRef {
        self.values.shrink_to_fit();
        let field = Arc::new(Field::new("element", DataType::Float64, false));
        let offsets = OffsetBuffer::new(ScalarBuffer::from(self.offsets));
        Arc::new(ListArray::new(field, offsets, Arc::new(Float64Array::from(self.values)), None))
    }
}

/// A list column's offsets before its first row (`[0]`), with room for `rows` rows.
fn offsets_for(rows: usize) -> Vec<i32> {
    let mut offsets = Vec::with_capacity(rows + 1);
    offsets.push(0);
    offsets
}

/// The most values a list column reserves up front (512 KiB of f64; [`Rows::new`]).
const LIST_RESERVE: usize = 1 << 16;

/// The rows of a contiguous run of realizations, column by column.
#[derive(Debug, Clone)]
pub struct Rows {
    realization: Vec<i64>,
    x0: Vec<f64>,
    xdot0: Vec<f64>,
    initial_sign: Vec<i32>,
    initial_velocity: Vec<f64>,
    n_switches: Vec<i64>,
    n_stick: Vec<i64>,
    n_slip: Vec<i64>,
    lists: [ListColumn; 4],
    last_truncated: Vec<bool>,
    /// `stick_end` as codes ([`StickEnd::ALL`]) with its offsets
    stick_end: (Vec<i32>, Vec<u8>),
    stick_lists: [ListColumn; 2],
    tail_scalars: [Vec<f64>; 6],
    /// `switch_times` and `switch_velocities`
    switch_times: Option<[ListColumn; 2]>,
    drawn: Vec<Vec<f64>>,
}

impl Rows {
    /// Rows with the switch times column (or not) and `drawn` columns of drawn scene keys, with
    /// room for `rows` rows of about `per_list` values in each list (a hint: the columns grow
    /// past it; sized right, no column is copied while the rows are gathered). A list reserves at
    /// most [`LIST_RESERVE`] values: a chunk holds about 2^18 list values in all
    /// ([`crate::simulation::ensemble::Ensemble::chunk_len`]), and a scene with far more events per
    /// realization than that (one row per chunk) grows its lists as it goes rather than reserving
    /// its whole hint up front.
    pub fn new(with_switch_times: bool, drawn: usize, rows: usize, per_list: usize) -> Rows {
        let values = rows.saturating_mul(per_list).min(LIST_RESERVE);
        let list = || ListColumn::with_capacity(rows, values);
        Rows {
            realization: Vec::with_capacity(rows),
            x0: Vec::with_capacity(rows),
            xdot0: Vec::with_capacity(rows),
            initial_sign: Vec::with_capacity(rows),
            initial_velocity: Vec::with_capacity(rows),
            n_switches: Vec::with_capacity(rows),
            n_stick: Vec::with_capacity(rows),
            n_slip: Vec::with_capacity(rows),
            lists: std::array::from_fn(|_| list()),
            last_truncated: Vec::with_capacity(rows),
            stick_end: (offsets_for(rows), Vec::with_capacity(values)),
            stick_lists: std::array::from_fn(|_| list()),
            tail_scalars: std::array::from_fn(|_| Vec::with_capacity(rows)),
            switch_times: with_switch_times.then(|| [list(), list()]),
            // (not `vec![…; drawn]`: a clone of an empty Vec has no capacity)
            drawn: (0..drawn).map(|_| Vec::with_capacity(rows)).collect(),
        }
    }

    /// Rows held.
    pub fn len(&self) -> usize {
        self.realization.len()
    }

    /// Whether no row is held.
    pub fn is_empty(&self) -> bool {
        self.realization.is_empty()
    }

    /// Σ S_T over the rows.
    pub fn total_sticks(&self) -> u64 {
        self.n_stick.iter().map(|&n| n as u64).sum()
    }

    /// Append realization `index`.
    pub fn push(&mut self, index: u64, out: &Outcome) {
        let (x0, xdot0, belt, rec) = (out.x0, out.xdot0, &out.belt, &out.record);
        let count = |n: usize| n as i64;
        self.realization.push(index as i64);
        self.x0.push(x0);
        self.xdot0.push(xdot0);
        self.initial_sign.push(belt.initial_sign());
        self.initial_velocity.push(belt.initial_velocity);
        self.n_switches.push(count(belt.switch_times.len()));
        self.n_stick.push(count(rec.n_stick()));
        self.n_slip.push(count(rec.n_slip()));
        for (col, values) in self.lists.iter_mut().zip([&rec.stick_start, &rec.stick_duration, &rec.slip_start, &rec.slip_duration]) {
            col.push(values);
        }
        self.last_truncated.push(rec.last_truncated);
        self.stick_end.1.extend(rec.stick_end.iter().map(|&e| e as u8));
        self.stick_end.0.push(i32::try_from(self.stick_end.1.len()).expect("a chunk holds < 2^31 list values"));
        self.stick_lists[0].push(&rec.stick_entry_position);
        self.stick_lists[1].push(&rec.stick_entry_velocity);
        let t_a = out.t_a;
        let tails = [rec.longest_stick(), rec.stick_fraction(t_a), rec.min_velocity, rec.max_velocity, rec.max_slip_speed, rec.severity(out.speed_scale)];
        for (col, x) in self.tail_scalars.iter_mut().zip(tails) {
            col.push(x);
        }
        if let Some([times, velocities]) = &mut self.switch_times {
            times.push(&belt.switch_times);
            velocities.extend((0..belt.switch_times.len()).map(|k| belt.velocity_after(k)));
        }
        for (col, &x) in self.drawn.iter_mut().zip(&out.drawn) {
            col.push(x);
        }
    }

    /// The rows as an Arrow record batch with [`schema`].
    pub fn into_batch(self, layout: &Layout) -> RecordBatch {
        let schema = schema(layout);
        let mut columns: Vec<ArrayRef> = vec![
            Arc::new(Int64Array::from(self.realization)),
            Arc::new(Float64Array::from(self.x0)),
            Arc::new(Float64Array::from(self.xdot0)),
            Arc::new(Int32Array::from(self.initial_sign)),
            Arc::new(Float64Array::from(self.initial_velocity)),
            Arc::new(Int64Array::from(self.n_switches)),
            Arc::new(Int64Array::from(self.n_stick)),
            Arc::new(Int64Array::from(self.n_slip)),
        ];
        columns.extend(self.lists.into_iter().map(ListColumn::into_array));
        columns.push(Arc::new(BooleanArray::from(self.last_truncated)));
        let (offsets, codes) = self.stick_end;
        let names = StringArray::from_iter_values(codes.iter().map(|&c| StickEnd::ALL[c as usize].name()));
        let field = Arc::new(Field::new("element", DataType::Utf8, false));
        columns.push(Arc::new(ListArray::new(field, OffsetBuffer::new(ScalarBuffer::from(offsets)), Arc::new(names), None)));
        columns.extend(self.stick_lists.into_iter().map(ListColumn::into_array));
        columns.extend(self.tail_scalars.into_iter().map(|v| Arc::new(Float64Array::from(v)) as ArrayRef));
        columns.extend(self.switch_times.into_iter().flatten().map(ListColumn::into_array));
        columns.extend(self.drawn.into_iter().map(|v| Arc::new(Float64Array::from(v)) as ArrayRef));
        RecordBatch::try_new(schema, columns).expect("columns match the schema")
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
    let mut floats = vec![ColumnPath::from("x0"), ColumnPath::from("xdot0")];
    floats.extend(layout.drawn.iter().chain(&columns::TAIL_SCALARS).map(|c| ColumnPath::from(*c)));
    let lists = LIST_COLUMNS.iter().copied().chain([columns::STICK_ENTRY_POSITION]).chain(layout.switch_times.then_some("switch_times"));
    floats.extend(lists.map(|c| ColumnPath::new(vec![c.into(), "list".into(), "element".into()])));
    // No dictionaries (the counts are small integers zstd packs anyway; interning cost 2 % of a
    // run); min/max statistics per row group for the integer columns (realization ranges let
    // readers skip row groups), none for the floats.
    let mut builder = WriterProperties::builder()
        .set_compression(Compression::ZSTD(ZstdLevel::try_new(1).expect("valid level")))
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::Chunk)
        .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
        .set_coerce_types(true)
        // rows are in realization order (column 0): declared, so readers can rely on it
        .set_sorting_columns(Some(vec![SortingColumn { column_idx: 0, descending: false, nulls_first: false }]))
        .set_key_value_metadata(Some(metadata.into_iter().map(|(k, v)| KeyValue::new(k, v)).collect()))
        // three words, or the few belt velocities, repeated per stick: a dictionary, then zstd
        .set_column_dictionary_enabled(ColumnPath::new(vec![columns::STICK_END.into(), "list".into(), "element".into()]), true)
        .set_column_dictionary_enabled(ColumnPath::new(vec![columns::STICK_ENTRY_VELOCITY.into(), "list".into(), "element".into()]), true);
    // nor statistics for them: no reader skips row groups on a stick's end word or belt velocity,
    // and the strings' min/max cost 4 % of a run's instructions
    for c in [columns::STICK_END, columns::STICK_ENTRY_VELOCITY] {
        builder = builder.set_column_statistics_enabled(ColumnPath::new(vec![c.into(), "list".into(), "element".into()]), EnabledStatistics::None);
    }
    // Floats are near-incompressible (random initial conditions, event times): stored PLAIN and
    // uncompressed (zstd saved 8 % of the size and cost 12 % of the run), without statistics.
    for col in floats {
        builder = builder
            .set_column_encoding(col.clone(), Encoding::PLAIN)
            .set_column_statistics_enabled(col.clone(), EnabledStatistics::None)
            .set_column_compression(col, Compression::UNCOMPRESSED);
    }
    builder.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_reserve_what_the_chunk_needs_and_no_more_than_the_cap() {
        // a chunk of 1,000 rows of 30 values per list, two drawn keys, switch times kept
        let rows = Rows::new(true, 2, 1000, 30);
        let lists = rows.lists.iter().chain(&rows.stick_lists).chain(rows.switch_times.iter().flatten());
        for col in lists {
            assert!(col.values.capacity() >= 30_000 && col.offsets.capacity() >= 1001);
        }
        assert!(rows.stick_end.1.capacity() >= 30_000);
        // every drawn column, not only the last (a clone of an empty Vec has no capacity)
        assert!(rows.drawn.iter().all(|c| c.capacity() >= 1000), "{:?}", rows.drawn.iter().map(Vec::capacity).collect::<Vec<_>>());
        // a scene with 10^7 expected events per realization (one row per chunk) grows its lists
        // instead of reserving 80 MB each up front
        let huge = Rows::new(true, 0, 1, 10_000_000);
        for col in huge.lists.iter().chain(&huge.stick_lists).chain(huge.switch_times.iter().flatten()) {
            assert!(col.values.capacity() <= LIST_RESERVE);
        }
        assert!(huge.stick_end.1.capacity() <= LIST_RESERVE);
    }
}
