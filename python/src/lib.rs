//! `stickslip._stickslip`: the Python extension, a thin layer over the library's stages
//! (`stickslip::stage`) — no second implementation of anything, and no child process: each
//! function builds a stage's request, runs it in this process with the GIL released, and returns
//! its result.
//!
//! Tables cross into Python through the Arrow C stream interface (`__arrow_c_stream__`, a
//! PyCapsule named `arrow_array_stream` holding an `ArrowArrayStream`): polars, pyarrow and
//! pandas take them without copying a value. Errors are raised as the exception class of what
//! is to blame (`stickslip::stage::Culprit`: `UsageError`, `ScenarioError`, `DatasetError`,
//! `OutputError`, subclasses of `ValueError`; `RunError`, of `RuntimeError`), with the command
//! line's one-line message. Ctrl-C is noticed between chunks of work (the stages' cancel token)
//! and raises `KeyboardInterrupt`; whatever the stage had staged is removed.

use std::ffi::CString;
use std::path::PathBuf;
use std::sync::Arc;

use arrow_array::ffi_stream::FFI_ArrowArrayStream;
use arrow_array::{RecordBatch, RecordBatchIterator};
use arrow_schema::{Schema, SchemaRef};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyCapsule;

use stickslip::progress::{Control, Progress};
use stickslip::scenario::{Input, Overrides, Scenario, Source};
use stickslip::simulation::simulate;
use stickslip::stage;
use stickslip::stage::Culprit;

pyo3::create_exception!(_stickslip, UsageError, PyValueError, "An argument's value is out of range, or values that cannot go together.");
pyo3::create_exception!(_stickslip, ScenarioError, PyValueError, "The scenario: a key, a value, the scenario file, or a scene the stage cannot take.");
pyo3::create_exception!(_stickslip, DatasetError, PyValueError, "A dataset, or another stage's output read as input, that cannot be used.");
pyo3::create_exception!(_stickslip, OutputError, PyValueError, "The output directory or file was refused.");
pyo3::create_exception!(_stickslip, RunError, PyRuntimeError, "A failure while running (the input is not to blame).");

/// An Arrow table held in Rust memory: record batches sharing one schema, exported without a
/// copy through `__arrow_c_stream__`.
#[pyclass(module = "stickslip._stickslip", frozen)]
struct Table {
    schema: SchemaRef,
    batches: Vec<RecordBatch>,
}

impl Table {
    fn from_batch(batch: RecordBatch) -> Table {
        Table { schema: batch.schema(), batches: vec![batch] }
    }
}

#[pymethods]
impl Table {
    /// The Arrow PyCapsule stream interface: a fresh stream over the same buffers per call.
    #[pyo3(signature = (requested_schema=None))]
    fn __arrow_c_stream__<'py>(&self, py: Python<'py>, requested_schema: Option<Bound<'py, PyAny>>) -> PyResult<Bound<'py, PyCapsule>> {
        // (the schema is not negotiated: a consumer casts if it must)
        let _ = requested_schema;
        let reader = RecordBatchIterator::new(self.batches.clone().into_iter().map(Ok), self.schema.clone());
        let stream = FFI_ArrowArrayStream::new(Box::new(reader));
        PyCapsule::new(py, stream, Some(CString::new("arrow_array_stream").expect("no NUL")))
    }

    /// Number of rows.
    #[getter]
    fn num_rows(&self) -> usize {
        self.batches.iter().map(RecordBatch::num_rows).sum()
    }

    /// The schema's key-value metadata (a dataset's provenance).
    #[getter]
    fn metadata(&self) -> std::collections::HashMap<String, String> {
        self.schema.metadata().iter().map(|(k, v)| (k.clone(), v.clone())).collect()
    }

    fn __len__(&self) -> usize {
        self.num_rows()
    }
}

/// An error as Python sees it: the class of what is to blame, the CLI's one-line message.
fn to_py(e: anyhow::Error) -> PyErr {
    if stickslip::stage::cancelled(&e) {
        return PyKeyboardInterrupt::new_err("interrupted");
    }
    let message = stickslip::stage::message(&e);
    match stickslip::stage::culprit(&e) {
        Some(Culprit::Usage) => UsageError::new_err(message),
        Some(Culprit::Scenario) => ScenarioError::new_err(message),
        Some(Culprit::Dataset) => DatasetError::new_err(message),
        Some(Culprit::Output) => OutputError::new_err(message),
        None => RunError::new_err(message),
    }
}

/// The progress sink of a Python call: each event handed to a Python callable
/// (`("start", what, total)`, `("advance", n)`, `("message", text)`, `("finish",)`,
/// `("status", line)`, `("note", line)`); an exception it raises is printed and ignored.
struct Sink(Option<Py<PyAny>>);

impl Sink {
    fn send(&self, call: impl FnOnce(Python<'_>, &Py<PyAny>) -> PyResult<Py<PyAny>>) {
        if let Some(f) = &self.0 {
            Python::attach(|py| {
                if let Err(e) = call(py, f) {
                    e.print(py);
                }
            });
        }
    }
}

impl Progress for Sink {
    fn start(&self, what: &str, total: u64) {
        self.send(|py, f| f.call1(py, ("start", what, total)));
    }
    fn advance(&self, n: u64) {
        self.send(|py, f| f.call1(py, ("advance", n)));
    }
    fn message(&self, text: &str) {
        self.send(|py, f| f.call1(py, ("message", text)));
    }
    fn finish(&self) {
        self.send(|py, f| f.call1(py, ("finish",)));
    }
    fn status(&self, line: &str) {
        self.send(|py, f| f.call1(py, ("status", line)));
    }
    fn note(&self, line: &str) {
        self.send(|py, f| f.call1(py, ("note", line)));
    }
}

/// Ctrl-C: Python's handler only sets a flag; the stage asks here between chunks of work.
fn interrupted() -> bool {
    Python::attach(|py| py.check_signals().is_err())
}

/// Run `f` (a stage) with the GIL released, `progress` as its sink and Ctrl-C as its cancel.
/// The token stays cancelled once it is (Python's check consumes the signal, and a stage may
/// ask again to tell a stop from a failure).
fn staged<T: Send>(py: Python<'_>, progress: Option<Py<PyAny>>, f: impl FnOnce(Control) -> anyhow::Result<T> + Send) -> PyResult<T> {
    let sink = Sink(progress);
    let stopped = std::sync::atomic::AtomicBool::new(false);
    let cancel = || {
        use std::sync::atomic::Ordering::Relaxed;
        stopped.load(Relaxed) || {
            let now = interrupted();
            stopped.fetch_or(now, Relaxed);
            now
        }
    };
    py.detach(|| f(Control { progress: &sink, cancel: &cancel })).map_err(to_py)
}

/// A scenario as the package passes it: `("paper", None)`, `("file", path)` or `("text", toml)`,
/// and the `--set` overrides.
fn input(kind: &str, value: Option<String>, sets: Vec<String>) -> PyResult<Input> {
    let source = match (kind, value) {
        ("paper", _) => Source::Paper,
        ("file", Some(p)) => Source::File(PathBuf::from(p)),
        ("text", Some(t)) => Source::Text(t),
        _ => return Err(UsageError::new_err(format!("scenario: unknown kind {kind:?}"))),
    };
    Ok(Input { source, sets })
}

/// Most realizations `simulate` holds in memory (about 7.5 GB of rows on the paper scene).
const MAX_IN_MEMORY: u64 = 10_000_000;

/// Simulate one scene into memory: the dataset's rows as one table (provenance in its metadata).
#[pyfunction]
#[pyo3(signature = (kind, value, sets, realizations=None, seed=None, threads=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn simulate_table(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    realizations: Option<u64>,
    seed: Option<u64>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Table> {
    let input = input(kind, value, sets)?;
    let batches = staged(py, progress, |ctl| {
        let mut sc = input.resolve()?;
        Overrides { realizations, seed }.apply(&mut sc);
        sc.check()?;
        sc.refuse_sweep("simulate (from Python, into memory)")?;
        if sc.run.realizations > MAX_IN_MEMORY {
            return Err(stickslip::stage::Usage(format!(
                "realizations = {}: at most {MAX_IN_MEMORY} are held in memory (about 750 bytes each on the paper scene); write them with out=DIR and scan the Parquet files",
                sc.run.realizations
            ))
            .into());
        }
        Ok(simulate::batches(&sc.plan()?, threads, ctl)?)
    })?;
    let schema = batches.first().map_or_else(|| Arc::new(Schema::empty()), RecordBatch::schema);
    Ok(Table { schema, batches })
}

/// A cell `simulate_to` wrote: (part file, realizations, seconds, Σ S_T, targets met or None).
type Written = (String, u64, f64, u64, Option<bool>);

/// The `simulate` stage into a directory; returns each cell's (part file, realizations, seconds,
/// Σ S_T, targets met or None).
#[pyfunction]
#[pyo3(signature = (kind, value, sets, out, realizations=None, seed=None, threads=None, target_se=Vec::new(), progress=None))]
#[allow(clippy::too_many_arguments)]
fn simulate_to(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    out: PathBuf,
    realizations: Option<u64>,
    seed: Option<u64>,
    threads: Option<usize>,
    target_se: Vec<String>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<Written>> {
    let target_se = target_se.iter().map(|t| t.parse().map_err(|e: String| UsageError::new_err(format!("target_se: {e}")))).collect::<PyResult<Vec<_>>>()?;
    let request = stage::simulate::Request { input: input(kind, value, sets)?, out, shard: simulate::Shard::WHOLE, realizations, seed, target_se, threads };
    let done = staged(py, progress, |ctl| stage::simulate::run(&request, ctl))?;
    Ok(done.summaries.into_iter().map(|s| (s.path.display().to_string(), s.realizations, s.seconds, s.total_sticks, s.targets.map(|t| t.0))).collect())
}

/// One cell of an analysis: (cell path, the tables by name, `summary.json` as text).
type Cell = (String, Vec<(String, Table)>, String);

/// The `analyze` stage: every cell's tables and summary, and a sweep's table of cells; `out`
/// (if given) gets the files too.
#[pyfunction]
#[pyo3(signature = (dataset, out=None, max_index=None, bins=None, pairs=None, permutations=None, allow_partial=false, tails=true, tail_times=None, severity=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn analyze(
    py: Python<'_>,
    dataset: PathBuf,
    out: Option<PathBuf>,
    max_index: Option<u32>,
    bins: Option<usize>,
    pairs: Option<Vec<String>>,
    permutations: Option<u32>,
    allow_partial: bool,
    tails: bool,
    tail_times: Option<Vec<f64>>,
    severity: Option<Vec<f64>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Vec<Cell>, Option<Table>)> {
    let mut options = stickslip::analysis::Options { bins, allow_partial, tails, ..Default::default() };
    options.max_index = max_index.unwrap_or(options.max_index);
    options.permutations = permutations.unwrap_or(options.permutations);
    if let Some(p) = pairs {
        options.pairs = p.iter().map(|p| p.parse().map_err(|e: String| UsageError::new_err(format!("pairs: {e}")))).collect::<PyResult<_>>()?;
    }
    options.tail.times = tail_times.unwrap_or(options.tail.times);
    options.tail.severity = severity.unwrap_or(options.tail.severity);
    let request = stage::analyze::Request { dataset, out, options };
    staged(py, progress, |ctl| {
        let done = stage::analyze::run(&request, ctl)?;
        let mut cells = Vec::with_capacity(done.cells.len());
        for (path, a) in &done.cells {
            cells.push((path.clone(), tables(stickslip::analysis::output::tables(a)?)?, stickslip::analysis::output::summary(a).to_json()));
        }
        let sweep = done.sweep_table().map(|t| Table::from_batch(t.to_arrow()));
        Ok((cells, sweep))
    })
}

/// The `tradeoff` stage into `out`; its tables by name.
#[pyfunction]
#[pyo3(signature = (kind, value, sets, out, realizations=None, bias_fraction=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn tradeoff(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    out: PathBuf,
    realizations: Option<u64>,
    bias_fraction: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<(String, Table)>> {
    let request = stage::tradeoff::Request {
        input: input(kind, value, sets)?,
        out,
        realizations: realizations.unwrap_or(stage::tradeoff::DEFAULT_REALIZATIONS),
        bias_fraction: bias_fraction.unwrap_or(stickslip::tradeoff::BIAS_FRACTION),
    };
    staged(py, progress, |ctl| tables(stage::tradeoff::run(&request, ctl)?.tables()))
}

/// The `sensitivity` stage into `out`; its tables by name.
#[pyfunction]
#[pyo3(signature = (kind, value, sets, out, realizations=None, seed=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn sensitivity(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    out: PathBuf,
    realizations: Option<u64>,
    seed: Option<u64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<(String, Table)>> {
    let request = stage::sensitivity::Request {
        input: input(kind, value, sets)?,
        out,
        realizations: realizations.unwrap_or(stage::sensitivity::DEFAULT_REALIZATIONS),
        seed,
    };
    staged(py, progress, |ctl| tables(stage::sensitivity::run(&request, ctl)?.tables()))
}

/// The `exact-law` stage into `out`; its tables by name.
#[pyfunction]
#[pyo3(signature = (kind, value, sets, out, resolution=None, tail_times=None, counts=None, densities=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn exact_law(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    out: PathBuf,
    resolution: Option<u32>,
    tail_times: Option<Vec<f64>>,
    counts: Option<u32>,
    densities: Option<u32>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<(String, Table)>> {
    let mut request = stage::exact_law::Request::new(input(kind, value, sets)?, out);
    request.resolution = resolution.unwrap_or(request.resolution);
    request.tail_times = tail_times.unwrap_or(request.tail_times);
    (request.counts, request.densities) = (counts, densities);
    staged(py, progress, |ctl| tables(stage::exact_law::run(&request, ctl)?.tables))
}

/// The `predict` stage (its tables also written into `out`, if given); its tables by name.
#[pyfunction]
#[pyo3(signature = (kind, value, sets, state, out=None, stuck=false, futures=None, horizon=None, resolution=None, seed=None, densities=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn predict(
    py: Python<'_>,
    kind: &str,
    value: Option<String>,
    sets: Vec<String>,
    state: (f64, f64, f64),
    out: Option<PathBuf>,
    stuck: bool,
    futures: Option<u64>,
    horizon: Option<f64>,
    resolution: Option<u32>,
    seed: Option<u64>,
    densities: Option<u32>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<(String, Table)>> {
    let mut request = stage::predict::Request::new(input(kind, value, sets)?, state);
    request.resolution = resolution.unwrap_or(request.resolution);
    (request.stuck, request.futures, request.horizon, request.seed, request.out, request.densities) = (stuck, futures, horizon, seed, out, densities);
    staged(py, progress, |ctl| tables(stage::predict::run(&request, ctl)?.tables()))
}

/// A stage's tables by name (`moments`, `sobol`, …), for Python, each checked against its
/// definition and for impossible values first (as a written table is).
fn tables(tables: Vec<(&'static stickslip::table::Def, stickslip::table::Table)>) -> anyhow::Result<Vec<(String, Table)>> {
    tables
        .into_iter()
        .map(|(def, t)| def.check_all(&t).map(|()| (def.name().to_string(), Table::from_batch(t.to_arrow()))).map_err(anyhow::Error::msg))
        .collect()
}

/// Run the command line with `argv` (the program name first), as the `stickslip` binary does;
/// returns the exit code (0, 1 or 2), the error printed on stderr as the binary prints it.
/// Like the binary, it takes over SIGINT and SIGTERM (temporaries removed, exit 130/143): it is
/// meant for a process of its own (the console script).
#[pyfunction]
fn run_cli(py: Python<'_>, argv: Vec<String>) -> i32 {
    stickslip::interrupt::install();
    py.detach(|| match stickslip::cli::main_from(argv) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("stickslip: error: {}", stickslip::stage::message(&e));
            i32::from(stickslip::stage::exit_code(&e))
        }
    })
}

/// Write a table made by `simulate_table` as a dataset directory, as `simulate --out` writes it
/// (the scene from the table's own provenance); returns the part file's path.
#[pyfunction]
fn write_table(py: Python<'_>, table: &Table, out: PathBuf) -> PyResult<String> {
    let text =
        table.schema.metadata().get("stickslip.scenario").cloned().ok_or_else(|| {
            DatasetError::new_err("the table has no stickslip.scenario metadata: only tables from stickslip.simulate can be written or analysed")
        })?;
    py.detach(|| -> anyhow::Result<String> {
        let sc = Scenario::recorded(&text, std::path::Path::new("<table>"))?;
        Ok(simulate::write_batches(&table.batches, &sc.plan()?, &out)?.display().to_string())
    })
    .map_err(to_py)
}

/// The shipped scenarios: (name, text) pairs, the paper's first.
#[pyfunction]
fn scenes() -> Vec<(String, String)> {
    stickslip::scenes::SHIPPED.iter().map(|s| (s.name.to_owned(), s.text.to_owned())).collect()
}

/// The extension module.
#[pymodule]
fn _stickslip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // (at import, before the extension's polars starts a thread)
    stickslip::analysis::decode_on_every_core().map_err(UsageError::new_err)?;
    m.add_class::<Table>()?;
    for (name, class) in [
        ("UsageError", py.get_type::<UsageError>()),
        ("ScenarioError", py.get_type::<ScenarioError>()),
        ("DatasetError", py.get_type::<DatasetError>()),
        ("OutputError", py.get_type::<OutputError>()),
        ("RunError", py.get_type::<RunError>()),
    ] {
        m.add(name, class)?;
    }
    m.add_function(wrap_pyfunction!(simulate_table, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_to, m)?)?;
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    m.add_function(wrap_pyfunction!(tradeoff, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(exact_law, m)?)?;
    m.add_function(wrap_pyfunction!(predict, m)?)?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(write_table, m)?)?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
