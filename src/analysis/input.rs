//! Finding and checking a dataset before anything is computed.
//!
//! A dataset is every `part-*.parquet` file below DIR (hive-style `key=value/` subdirectories
//! included; hidden entries — temporary files of a running `simulate` — skipped; other Parquet
//! files such as analysis tables ignored). Each file's footer is read with the parquet crate and
//! must carry the stickslip schema version, the contract's columns with their types, and the
//! same resolved scenario as the other parts. Any failure names the file.

use std::fs::File;
use std::path::{Path, PathBuf};

use arrow::datatypes::DataType;
use parquet::arrow::parquet_to_arrow_schema;
use parquet::file::reader::{FileReader, SerializedFileReader};

use crate::dataset::SCHEMA_VERSION;
use crate::scenario::Scenario;

/// A checked dataset.
#[derive(Debug, Clone)]
pub struct Dataset {
    pub files: Vec<PathBuf>,
    /// Rows of each file.
    pub file_rows: Vec<u64>,
    pub rows: u64,
    pub scenario: Scenario,
    pub switch_times: bool,
    /// `DIR/trajectories.csv`, when the simulation sampled trajectories.
    pub trajectories: Option<PathBuf>,
}

#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("cannot read dataset directory {}: {source}", path.display())]
    Dir { path: PathBuf, source: std::io::Error },
    #[error("no dataset part files (part-*.parquet) under {}", path.display())]
    Empty { path: PathBuf },
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{} is a parameter sweep of {cells} cells (key=value/ directories); `analyze` analyses each cell and writes sweep.parquet", path.display())]
    Sweep { path: PathBuf, cells: usize },
}

fn bad(path: &Path, reason: impl Into<String>) -> InputError {
    InputError::File { path: path.to_owned(), reason: reason.into() }
}

/// All part files below `dir`, sorted by path.
fn discover(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), InputError> {
    let entries = std::fs::read_dir(dir).map_err(|source| InputError::Dir { path: dir.to_owned(), source })?;
    for entry in entries {
        let entry = entry.map_err(|source| InputError::Dir { path: dir.to_owned(), source })?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        if name.starts_with('.') {
            continue;
        }
        if path.is_dir() {
            discover(&path, out)?;
        } else if name.starts_with("part-") && name.ends_with(".parquet") {
            out.push(path);
        }
    }
    Ok(())
}

const COLUMNS: &[(&str, &str)] = &[
    ("realization", "int64"),
    ("n_switches", "int32"),
    ("n_stick", "int32"),
    ("n_slip", "int32"),
    ("last_truncated", "bool"),
    ("stick_start", "list<float64>"),
    ("stick_duration", "list<float64>"),
    ("slip_start", "list<float64>"),
    ("slip_duration", "list<float64>"),
];

fn type_name(t: &DataType) -> String {
    match t {
        DataType::Int32 => "int32".into(),
        DataType::Int64 => "int64".into(),
        DataType::Boolean => "bool".into(),
        DataType::Float64 => "float64".into(),
        DataType::List(f) | DataType::LargeList(f) => format!("list<{}>", type_name(f.data_type())),
        other => other.to_string(),
    }
}

/// Check one part file; returns (rows, scenario TOML, has switch_times).
fn check(path: &Path) -> Result<(u64, String, bool), InputError> {
    let file = File::open(path).map_err(|e| bad(path, e.to_string()))?;
    let reader = SerializedFileReader::new(file).map_err(|e| bad(path, format!("not a readable Parquet file ({e})")))?;
    let meta = reader.metadata().file_metadata();
    let kv = meta.key_value_metadata();
    let get = |key: &str| kv.and_then(|kv| kv.iter().find(|e| e.key == key)).and_then(|e| e.value.clone());
    match get("stickslip.schema_version") {
        Some(v) if v == SCHEMA_VERSION => {}
        Some(v) => return Err(bad(path, format!("dataset schema version {v}, this stickslip reads {SCHEMA_VERSION}"))),
        None => return Err(bad(path, "not a stickslip dataset (no stickslip.schema_version in its metadata)")),
    }
    let schema = parquet_to_arrow_schema(meta.schema_descr(), kv).map_err(|e| bad(path, e.to_string()))?;
    for (name, want) in COLUMNS {
        let field = schema.field_with_name(name).map_err(|_| bad(path, format!("missing column `{name}`")))?;
        let got = type_name(field.data_type());
        if got != *want {
            return Err(bad(path, format!("column `{name}` is {got}, expected {want}")));
        }
    }
    let scenario = get("stickslip.scenario").ok_or_else(|| bad(path, "no stickslip.scenario in its metadata"))?;
    let switch_times = schema.field_with_name("switch_times").is_ok();
    Ok((meta.num_rows() as u64, scenario, switch_times))
}

/// Find and check the dataset below `dir` (a single scenario).
pub fn open(dir: &Path) -> Result<Dataset, InputError> {
    let mut cells = open_cells(dir)?;
    if cells.len() > 1 {
        return Err(InputError::Sweep { path: dir.to_owned(), cells: cells.len() });
    }
    Ok(cells.remove(0).1)
}

/// Find and check the datasets below `dir`, one per directory holding part files (the cells of a
/// sweep, `key=value/…` paths relative to `dir`; the empty path for a plain dataset).
pub fn open_cells(dir: &Path) -> Result<Vec<(String, Dataset)>, InputError> {
    let mut files = Vec::new();
    discover(dir, &mut files)?;
    if files.is_empty() {
        return Err(InputError::Empty { path: dir.to_owned() });
    }
    files.sort();
    let mut groups: std::collections::BTreeMap<PathBuf, Vec<PathBuf>> = Default::default();
    for f in files {
        groups.entry(f.parent().unwrap_or(dir).to_owned()).or_default().push(f);
    }
    groups
        .into_iter()
        .map(|(cell_dir, files)| {
            let rel = cell_dir.strip_prefix(dir).unwrap_or(&cell_dir).to_string_lossy().replace('\\', "/");
            Ok((rel, checked(&cell_dir, files)?))
        })
        .collect()
}

/// Check the part files of one directory as one dataset.
fn checked(dir: &Path, files: Vec<PathBuf>) -> Result<Dataset, InputError> {
    let first = files[0].clone();
    let (rows, toml, switch_times) = check(&first)?;
    let mut file_rows = vec![rows];
    for f in &files[1..] {
        let (n, other, st) = check(f)?;
        if other != toml {
            return Err(bad(f, format!("was simulated with a different scenario than {}", first.display())));
        }
        if st != switch_times {
            return Err(bad(f, format!("switch_times column differs from {}", first.display())));
        }
        file_rows.push(n);
    }
    let rows = file_rows.iter().sum();
    let scenario = Scenario::from_text(Some(&toml), &first, &[]).map_err(|e| bad(&first, format!("its recorded scenario: {e}")))?;
    let trajectories = Some(dir.join("trajectories.csv")).filter(|p| p.is_file());
    Ok(Dataset { files, file_rows, rows, scenario, switch_times, trajectories })
}
