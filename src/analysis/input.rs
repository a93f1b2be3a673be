//! Finding and checking a dataset before anything is computed.
//!
//! A dataset is every `part-*.parquet` file below DIR (hive-style `key=value/` subdirectories
//! included; hidden entries — temporary files of a running `simulate` — skipped; other Parquet
//! files such as analysis tables ignored). Each file's footer is read with the parquet crate and
//! must carry the stickslip schema version, the contract's columns with their types, and the
//! same resolved scenario as the other parts. Any failure names the file.

use std::fs::File;
use std::path::{Path, PathBuf};

use arrow_schema::DataType;
use parquet::arrow::parquet_to_arrow_schema;
use parquet::file::reader::{FileReader, SerializedFileReader};

use crate::metadata as meta;
use crate::scenario::Scenario;
use crate::simulation::schema::{required, Kind};

/// A checked dataset.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Part files, in realization order.
    pub files: Vec<PathBuf>,
    /// Rows of each file.
    pub file_rows: Vec<u64>,
    /// What each file looked like when checked (a file that changes later is refused).
    pub file_stamps: Vec<Stamp>,
    /// First realization index of each file.
    pub file_starts: Vec<u64>,
    /// Rows (realizations) in all the part files.
    pub rows: u64,
    /// Realizations of the whole run the parts come from (`run.realizations`).
    pub expected_rows: u64,
    /// Realization ranges of the run that no part holds (empty for a complete dataset; only
    /// with `--allow-partial`).
    pub missing: Vec<std::ops::Range<u64>>,
    /// The resolved scenario recorded in the footers (the same in every part).
    pub scenario: Scenario,
    /// Whether the parts store the `switch_times` column (`output.switch_times`).
    pub switch_times: bool,
    /// whether the parts have the tails' state of schema v3 (`stick_end` and the other columns schema v3 added)
    pub tails_state: bool,
    /// the belt's velocity levels where the scenario fixes them (a symmetric, telegraph or
    /// Markov belt whose speeds are not drawn): every stick starts at one of them
    pub belt_levels: Option<Vec<f64>>,
    /// The directory of the trajectory tables beside the dataset ([`crate::simulation::trajectory::dir_for`]),
    /// when the simulation sampled trajectories.
    pub trajectories: Option<PathBuf>,
}

/// Why a dataset cannot be analysed; every variant names the path.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// A directory could not be listed.
    #[error("cannot read dataset directory {}: {source}", path.display())]
    Dir {
        /// the directory
        path: PathBuf,
        /// the I/O error
        source: std::io::Error,
    },
    /// No part files below the directory.
    #[error("no dataset part files (part-*.parquet) under {}", path.display())]
    Empty {
        /// the directory searched
        path: PathBuf,
    },
    /// A part file failed its checks (footer, schema, scenario, realization range).
    #[error("{}: {reason}", path.display())]
    File {
        /// the part file
        path: PathBuf,
        /// what is wrong with it
        reason: String,
    },
    /// The directory holds a parameter sweep, not one dataset.
    #[error("{} is a parameter sweep of {cells} cells (key=value/ directories); `analyze` analyses each cell and writes sweep.parquet", path.display())]
    Sweep {
        /// the directory
        path: PathBuf,
        /// number of cells (directories holding part files)
        cells: usize,
    },
    /// Realization ranges of the run are missing (and `--allow-partial` was not given).
    #[error("{} is incomplete: {detail}; simulate the missing shards, or pass --allow-partial to analyse the parts present (the summary then says so)", path.display())]
    Incomplete {
        /// the dataset's directory
        path: PathBuf,
        /// the run's size and the ranges missing
        detail: String,
    },
}

impl crate::blame::Blame for InputError {
    /// Every one: the dataset given is not one that can be analysed.
    fn blame(&self) -> Option<crate::blame::Culprit> {
        Some(crate::blame::Culprit::Dataset)
    }
}

/// A footer value for a message: its first line, at most 60 characters.
fn short_value(v: &str) -> String {
    let line = v.lines().next().unwrap_or("");
    if line.chars().count() > 60 || v.lines().count() > 1 {
        format!("{}…", line.chars().take(60).collect::<String>())
    } else {
        line.to_string()
    }
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

/// What a file looked like: size, modification time and (on Unix) inode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stamp {
    len: u64,
    modified: Option<std::time::SystemTime>,
    inode: u64,
}

impl Stamp {
    /// The stamp of the file at `path` now.
    pub fn of(path: &Path) -> std::io::Result<Stamp> {
        let m = std::fs::metadata(path)?;
        #[cfg(unix)]
        let inode = std::os::unix::fs::MetadataExt::ino(&m);
        #[cfg(not(unix))]
        let inode = 0;
        Ok(Stamp { len: m.len(), modified: m.modified().ok(), inode })
    }
}

fn type_name(t: &DataType) -> String {
    match t {
        DataType::Int32 => "int32".into(),
        DataType::Int64 => "int64".into(),
        DataType::Boolean => "bool".into(),
        DataType::Float64 => "float64".into(),
        DataType::Float32 => "float32".into(),
        DataType::Utf8 | DataType::LargeUtf8 | DataType::Utf8View => "utf8".into(),
        DataType::List(f) | DataType::LargeList(f) => format!("list<{}>", type_name(f.data_type())),
        other => other.to_string(),
    }
}

/// What the footer of one part file says.
struct Part {
    rows: u64,
    scenario: String,
    switch_times: bool,
    /// the schema-v3 columns of the tails' state
    tails_state: bool,
    /// `stickslip.realizations`: the whole run's size
    total: u64,
    /// `stickslip.realization_range`
    range: std::ops::Range<u64>,
    /// `stickslip.shard_block`: the block a shard with `--target-se` was given (it stops within
    /// it, at its own target); None for every other part
    block: Option<std::ops::Range<u64>>,
    stamp: Stamp,
    /// the footer's provenance that every part of one run shares (all keys but the part's own:
    /// its shard, range and block), sorted
    shared: Vec<(String, String)>,
}

/// The footer keys that differ between the parts of one run.
const PER_PART: [&str; 5] = ["stickslip.shard", meta::REALIZATION_RANGE, meta::SHARD_BLOCK, "stickslip.target_se_reached", "stickslip.target_se_met"];

/// Check one part file's footer.
fn check(path: &Path) -> Result<Part, InputError> {
    let stamp = Stamp::of(path).map_err(|e| bad(path, e.to_string()))?;
    let file = File::open(path).map_err(|e| bad(path, e.to_string()))?;
    let reader = SerializedFileReader::new(file).map_err(|e| bad(path, format!("not a readable Parquet file ({e})")))?;
    let meta = reader.metadata().file_metadata();
    let kv = meta.key_value_metadata();
    let get = |key: &str| kv.and_then(|kv| kv.iter().find(|e| e.key == key)).and_then(|e| e.value.clone());
    let (version, number) = match get(meta::SCHEMA_VERSION) {
        Some(v) => match crate::simulation::schema::readable(&v) {
            Some(number) => (v, number),
            None => {
                let readable: Vec<String> = (1..=crate::simulation::schema::VERSION).map(|v| v.to_string()).collect();
                return Err(bad(path, format!("dataset schema version {v}, this stickslip reads {readable:?}")));
            }
        },
        None => return Err(bad(path, "not a stickslip dataset (no stickslip.schema_version in its metadata)")),
    };
    let schema = parquet_to_arrow_schema(meta.schema_descr(), kv).map_err(|e| bad(path, e.to_string()))?;
    // every column of the part's version and earlier, in its type (v1 had int32 counts; schema
    // v3's tails' columns are read from a v3 part only, and a v3 part lacking one is refused,
    // never analysed as v2)
    for column in required(number) {
        let field =
            schema.field_with_name(column.name).map_err(|_| bad(path, format!("missing column `{}` (schema version {version} has it)", column.name)))?;
        let got = type_name(field.data_type());
        let v1_count = number == 1 && got == "int32" && column.kind() == Kind::Int64;
        if got != column.kind().name() && !v1_count {
            return Err(bad(path, format!("column `{}` is {got}, expected {}", column.name, column.kind().name())));
        }
    }
    let tails_state = number >= 3;
    let scenario = get(meta::SCENARIO).ok_or_else(|| bad(path, format!("no {} in its metadata", meta::SCENARIO)))?;
    let switch_times = schema.field_with_name(crate::simulation::dataset::columns::SWITCH_TIMES).is_ok();
    let number = |key: &str| -> Result<u64, InputError> {
        get(key).and_then(|v| v.trim().parse().ok()).ok_or_else(|| bad(path, format!("no valid {key} in its metadata")))
    };
    let total = number(meta::REALIZATIONS)?;
    let range = get(meta::REALIZATION_RANGE)
        .and_then(|r| {
            let (a, b) = r.split_once("..")?;
            Some(a.trim().parse::<u64>().ok()?..b.trim().parse::<u64>().ok()?)
        })
        .filter(|r| r.start <= r.end && r.end <= total)
        .ok_or_else(|| bad(path, "no valid stickslip.realization_range in its metadata"))?;
    let rows = meta.num_rows().max(0) as u64;
    if rows != range.end - range.start {
        return Err(bad(path, format!("holds {rows} rows but its metadata declares realizations {}..{}", range.start, range.end)));
    }
    let block = get(meta::SHARD_BLOCK).and_then(|r| {
        let (a, b) = r.split_once("..")?;
        Some(a.trim().parse::<u64>().ok()?..b.trim().parse::<u64>().ok()?)
    });
    if let Some(b) = &block {
        if !(b.start == range.start && range.end <= b.end && b.end <= total) {
            return Err(bad(path, "its stickslip.shard_block does not hold its realization_range"));
        }
    }
    // the shard the file is named for, its footer's shard, and the range that shard holds
    let named = path.file_name().and_then(|n| n.to_str()).and_then(|n| {
        let (i, n) = n.strip_prefix("part-")?.strip_suffix(".parquet")?.split_once("-of-")?;
        Some((i.parse::<u64>().ok()?, n.parse::<u64>().ok()?))
    });
    if let Some(declared) = get("stickslip.shard") {
        let shard: Option<crate::simulation::simulate::Shard> = declared.parse().ok();
        let Some(shard) = shard.filter(|s| named.is_none_or(|n| n == (s.index, s.count))) else {
            return Err(bad(path, format!("its footer's stickslip.shard = {declared} is not the shard its name says (part I of N: part-IIIII-of-NNNNN)")));
        };
        let own = shard.range(total);
        let held = block.clone().unwrap_or(range.clone());
        if held != own {
            return Err(bad(
                path,
                format!("holds realizations {}..{}, but shard {declared} of {total} realizations holds {}..{}", held.start, held.end, own.start, own.end),
            ));
        }
    }
    let mut shared: Vec<(String, String)> = kv
        .into_iter()
        .flatten()
        .filter(|e| e.key.starts_with("stickslip.") && !PER_PART.contains(&e.key.as_str()) && e.key != meta::SCENARIO)
        .map(|e| (e.key.clone(), e.value.clone().unwrap_or_default()))
        .collect();
    shared.sort();
    Ok(Part { rows, scenario, switch_times, tails_state, total, range, block, stamp, shared })
}

/// Find and check the dataset below `dir` (a single scenario, complete).
pub fn open(dir: &Path) -> Result<Dataset, InputError> {
    open_partial(dir, false)
}

/// Find and check the dataset below `dir` (a single scenario); `allow_partial` accepts missing
/// realization ranges.
pub fn open_partial(dir: &Path, allow_partial: bool) -> Result<Dataset, InputError> {
    let mut cells = open_cells(dir, allow_partial)?;
    if cells.len() > 1 {
        return Err(InputError::Sweep { path: dir.to_owned(), cells: cells.len() });
    }
    Ok(cells.remove(0).1)
}

/// Find and check the datasets below `dir`, one per directory holding part files (the cells of a
/// sweep, `key=value/…` paths relative to `dir`; the empty path for a plain dataset).
pub fn open_cells(dir: &Path, allow_partial: bool) -> Result<Vec<(String, Dataset)>, InputError> {
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
    let cells: Vec<(String, Dataset)> = groups
        .into_iter()
        .map(|(cell_dir, files)| {
            let rel = cell_dir.strip_prefix(dir).unwrap_or(&cell_dir).to_string_lossy().replace('\\', "/");
            Ok((rel, checked(&cell_dir, files, allow_partial)?))
        })
        .collect::<Result<_, InputError>>()?;
    // the cells of one sweep sweep the same keys in the same order: two sweeps (or a plain run
    // and a sweep) written into one directory would otherwise be summarised as one, their cells
    // labelled by the first one's keys
    let keys = |rel: &str| rel.split('/').map(|c| c.split_once('=').map_or("", |(k, _)| k).to_string()).collect::<Vec<_>>();
    let first = keys(&cells[0].0);
    if let Some((rel, _)) = cells.iter().find(|(rel, _)| keys(rel) != first) {
        let name = |r: &str| if r.is_empty() { "a plain dataset at the top".to_string() } else { r.to_string() };
        return Err(bad(
            dir,
            format!("holds two different runs: {} and {} sweep different keys; analyse each in a directory of its own", name(&cells[0].0), name(rel)),
        ));
    }
    Ok(cells)
}

/// The parts of one run share their whole provenance, not only the scenario: a part of another
/// seed, solver, schema or tool version is another run's. The message names a part that differs
/// from most of the others (the odd one), and one of those.
fn disagreement(parts: &[(PathBuf, Part)]) -> Result<(), InputError> {
    let value = |q: &Part, k: &str| q.shared.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone());
    let mut keys: Vec<&str> = parts.iter().flat_map(|(_, p)| p.shared.iter().map(|(k, _)| k.as_str())).collect();
    keys.sort_unstable();
    keys.dedup();
    for k in keys {
        let values: Vec<Option<String>> = parts.iter().map(|(_, p)| value(p, k)).collect();
        let most =
            values.iter().max_by_key(|v| (values.iter().filter(|w| w == v).count(), std::cmp::Reverse(values.iter().position(|w| w == *v)))).expect("parts");
        if let Some(odd) = values.iter().position(|v| v != most) {
            let usual = values.iter().position(|v| v == most).expect("the most common value is held");
            let shown = |v: &Option<String>| v.as_deref().map_or("(absent)".to_string(), short_value);
            return Err(bad(
                &parts[odd].0,
                format!(
                    "its footer's {k} = {} differs from {}'s {} (the parts of one run share their provenance: is it from another run?)",
                    shown(&values[odd]),
                    parts[usual].0.display(),
                    shown(most)
                ),
            ));
        }
    }
    Ok(())
}

/// Check the part files of one directory as one dataset: one scenario, and realization ranges
/// that neither overlap nor (unless `allow_partial`) leave gaps.
fn checked(dir: &Path, files: Vec<PathBuf>, allow_partial: bool) -> Result<Dataset, InputError> {
    let mut parts: Vec<(PathBuf, Part)> = files.into_iter().map(|f| check(&f).map(|p| (f, p))).collect::<Result<_, _>>()?;
    disagreement(&parts)?;
    let (first, p0) = (&parts[0].0, &parts[0].1);
    for (f, p) in &parts[1..] {
        if p.scenario != p0.scenario {
            return Err(bad(f, format!("was simulated with a different scenario than {}", first.display())));
        }
        if p.switch_times != p0.switch_times {
            return Err(bad(f, format!("switch_times column differs from {}", first.display())));
        }
        if p.tails_state != p0.tails_state {
            return Err(bad(f, format!("has {} the tails' columns (schema v3) of {}", if p.tails_state { "" } else { "not" }, first.display())));
        }
    }
    let (toml, switch_times, tails_state, total, first) = (p0.scenario.clone(), p0.switch_times, p0.tails_state, p0.total, first.clone());
    parts.sort_by_key(|(f, p)| (p.range.start, p.range.end, f.clone()));
    let mut missing = Vec::new();
    // `next`: the end of the parts so far; `intended`: where the previous part's block ends (a
    // shard that met its own --target-se stopped inside its block: the rest of the block was
    // never meant to be simulated, and only what lies past it is missing)
    let (mut next, mut intended) = (0u64, 0u64);
    for (i, (f, p)) in parts.iter().enumerate() {
        if p.range.start < next {
            let (g, q) = &parts[i - 1];
            return Err(bad(
                f,
                format!(
                    "realizations {}..{} overlap {} ({}..{}): a duplicated or copied part, or shards of different splits; remove one",
                    p.range.start,
                    p.range.end,
                    g.display(),
                    q.range.start,
                    q.range.end
                ),
            ));
        }
        let from = next.max(intended);
        if p.range.start > from {
            missing.push(from..p.range.start);
        }
        next = p.range.end;
        intended = p.block.as_ref().map_or(next, |b| b.end);
    }
    let from = next.max(intended);
    if total > from {
        missing.push(from..total);
    }
    if !missing.is_empty() && !allow_partial {
        let gaps: Vec<String> = missing.iter().map(|r| format!("{}..{}", r.start, r.end)).collect();
        return Err(InputError::Incomplete {
            path: dir.to_owned(),
            detail: format!("the run has {total} realizations, the parts present lack {}", gaps.join(", ")),
        });
    }
    let scenario = Scenario::recorded(&toml, &first).map_err(|e| bad(&first, format!("its recorded scenario: {e}")))?;
    // the one recorded value the analysis computes with: every event time lies in [0, t_a]
    let t_a = scenario.run.duration;
    if !(t_a.is_finite() && t_a > 0.0 && t_a <= crate::scenario::DURATION_RANGE.1) {
        return Err(bad(
            &first,
            format!("its recorded run.duration = {t_a:e} s lies outside (0, {:e}] s, the window the analysis is proven on", crate::scenario::DURATION_RANGE.1),
        ));
    }
    // the trajectory tables beside the dataset, only if this run sampled them (tables another run
    // left there record another scenario, and are not taken for these realizations)
    let trajectories = crate::simulation::trajectory::dir_for(dir).filter(|d| {
        use crate::simulation::trajectory::{recorded_scenario, EVENTS, SAMPLES};
        [SAMPLES, EVENTS].iter().all(|f| recorded_scenario(&d.join(f)).as_deref() == Some(toml.as_str()))
    });
    if let Some(d) = &trajectories {
        check_trajectories(d, t_a)?;
    }
    let rows: u64 = parts.iter().map(|(_, p)| p.rows).sum();
    // shards that stopped at their own targets: the run is what they simulated
    let expected_rows = if parts.iter().any(|(_, p)| p.block.is_some()) { rows + missing.iter().map(|r| r.end - r.start).sum::<u64>() } else { total };
    Ok(Dataset {
        rows,
        file_rows: parts.iter().map(|(_, p)| p.rows).collect(),
        file_stamps: parts.iter().map(|(_, p)| p.stamp).collect(),
        file_starts: parts.iter().map(|(_, p)| p.range.start).collect(),
        files: parts.into_iter().map(|(f, _)| f).collect(),
        expected_rows,
        missing,
        switch_times,
        tails_state,
        belt_levels: belt_levels(&scenario),
        trajectories,
        scenario,
    })
}

/// The velocity levels of a recorded scenario's belt where they are fixed (module docs of
/// [`Dataset::belt_levels`]); None for a record (its file may be gone) or a drawn speed.
fn belt_levels(scenario: &Scenario) -> Option<Vec<f64>> {
    use crate::scenario::{Param, ProcessName};
    use crate::simulation::belt::Process;
    let fixed = |p: &Option<Param>| !matches!(p, Some(Param::Random(_)) | Some(Param::Sweep(_)));
    if scenario.process_name() == ProcessName::Recorded || !fixed(&Some(scenario.belt.speed.clone())) || !fixed(&scenario.belt.reverse_speed) {
        return None;
    }
    match scenario.scene().ok()?.belt.process {
        Process::Symmetric(s) => Some(vec![s.speed, -s.speed]),
        Process::Telegraph(t) => Some(vec![t.forward_speed, -t.reverse_speed]),
        Process::Markov(m) => Some(m.velocities().to_vec()),
        Process::Recorded(_) => None,
        Process::Constant(v) => Some(vec![v]),
    }
}

/// The sampled trajectories beside a dataset, checked before `analyze` copies them into its
/// output: every value finite ([`crate::table::Table::read_parquet`]), the instants in [0, t_a],
/// each realization's in order, and every event one the simulation writes.
fn check_trajectories(dir: &Path, t_a: f64) -> Result<(), InputError> {
    use crate::simulation::trajectory::{events, samples, EVENT_NAMES};
    // (by the columns checked here, not the whole shape: an older simulate's tables are copied as
    // they are, and the figures say what they lack)
    for (file, realization, instant) in [(samples::DEF.file, samples::REALIZATION, samples::T), (events::DEF.file, events::REALIZATION, events::T)] {
        let path = dir.join(file);
        let t = crate::table::Table::read_parquet(&path).map_err(|e| bad(&path, e.to_string()))?;
        let (Some(ids), Some(times)) = (t.ints(realization.name), t.floats(instant.name)) else {
            return Err(bad(&path, format!("lacks the int64 column `{}` or the float64 column `{}`", realization.name, instant.name)));
        };
        for r in 0..t.height() {
            let (id, at) = (ids[r], times[r]);
            if !at.is_some_and(|x| (0.0..=t_a * (1.0 + 1e-12)).contains(&x)) {
                return Err(bad(
                    &path,
                    format!("row {r}, column `{}`: {} (an instant in [0, t_a = {t_a}] s)", instant.name, at.map_or("null".into(), crate::scenario::short)),
                ));
            }
            if r > 0 && id == ids[r - 1] && at < times[r - 1] {
                return Err(bad(&path, format!("row {r}, column `{}`: the instants of realization {} decrease", instant.name, id.unwrap_or(-1))));
            }
        }
        if let Some(kinds) = t.strings(events::EVENT.name) {
            if let Some((r, e)) = kinds.iter().enumerate().find(|(_, e)| !EVENT_NAMES.contains(&e.as_str())) {
                return Err(bad(&path, format!("row {r}, column `{}`: {e:?} (one of {})", events::EVENT.name, EVENT_NAMES.join(", "))));
            }
        }
    }
    Ok(())
}

/// The name of the row number column of [`scan`].
pub(crate) const ROW: &str = "__row";

/// The scan of one part file, its rows numbered from 0 (hive partitioning off: a sweep's
/// `key=value/` directories are cells, not columns).
pub(crate) fn scan(path: &Path, n_rows: Option<usize>, row_index: bool) -> polars::prelude::PolarsResult<polars::prelude::LazyFrame> {
    use polars::prelude::*;
    let args = ScanArgsParquet {
        n_rows,
        row_index: row_index.then(|| RowIndex { name: ROW.into(), offset: 0 }),
        hive_options: HiveOptions { enabled: Some(false), ..Default::default() },
        ..Default::default()
    };
    LazyFrame::scan_parquet(PlRefPath::new(path.to_string_lossy().as_ref()), args)
}

/// One lazy frame of every part file of `data`, in realization order if `ordered`.
pub(crate) fn scan_all(data: &Dataset, ordered: bool) -> polars::prelude::PolarsResult<polars::prelude::LazyFrame> {
    use polars::prelude::*;
    let files = data.files.iter().map(|f| scan(f, None, false)).collect::<PolarsResult<Vec<_>>>()?;
    concat(files, UnionArgs { maintain_order: ordered, ..Default::default() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_writers_schema_has_every_column_the_reader_requires() {
        let schema = crate::simulation::dataset::schema(&crate::simulation::dataset::Layout::default());
        for column in required(3) {
            let field = schema.field_with_name(column.name).unwrap_or_else(|_| panic!("the writer has no {}", column.name));
            assert_eq!(type_name(field.data_type()), column.kind().name(), "{}", column.name);
        }
    }
}
