//! `stickslip._stickslip`: the Python extension, a thin layer over the library — no second
//! implementation of anything. Scenarios are resolved by `stickslip::scenario`, realizations
//! simulated by `stickslip::simulation::simulate::batches` (the rows the CLI writes); the stages
//! that write files run the command line's own code (`stickslip::cli::main_from`, in a child
//! process started by the package, so that Ctrl-C ends them as it ends the CLI).
//!
//! Tables cross into Python through the Arrow C stream interface (`__arrow_c_stream__`, a
//! PyCapsule named `arrow_array_stream` holding an `ArrowArrayStream`): polars, pyarrow and
//! pandas take them without copying a value. Errors: `ValueError` when the input is to blame
//! (the same one-line message as the CLI), `RuntimeError` otherwise. Long work runs with the
//! GIL released; Ctrl-C is noticed between windows of chunks and ends the run with
//! `KeyboardInterrupt`.

use std::ffi::CString;
use std::path::Path;
use std::sync::Arc;

use arrow_array::ffi_stream::FFI_ArrowArrayStream;
use arrow_array::{RecordBatch, RecordBatchIterator};
use arrow_schema::{Schema, SchemaRef};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyCapsule;

use stickslip::scenario::{Overrides, Scenario};
use stickslip::simulation::simulate::{self, SimulateError};

/// An Arrow table held in Rust memory: record batches sharing one schema, exported without a
/// copy through `__arrow_c_stream__`.
#[pyclass(module = "stickslip._stickslip", frozen)]
struct Table {
    schema: SchemaRef,
    batches: Vec<RecordBatch>,
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

    /// The column names.
    #[getter]
    fn column_names(&self) -> Vec<String> {
        self.schema.fields().iter().map(|f| f.name().clone()).collect()
    }

    /// The schema's key-value metadata (a dataset's provenance).
    #[getter]
    fn metadata(&self) -> std::collections::HashMap<String, String> {
        self.schema.metadata().iter().map(|(k, v)| (k.clone(), v.clone())).collect()
    }

    fn __len__(&self) -> usize {
        self.num_rows()
    }

    fn __repr__(&self) -> String {
        format!("stickslip.Table({} rows; columns {})", self.num_rows(), self.column_names().join(", "))
    }
}

/// An error as Python sees it: `ValueError` when the input is to blame, else `RuntimeError`;
/// the message is the CLI's one line.
fn to_py(e: anyhow::Error) -> PyErr {
    if e.chain().any(|c| c.is::<Interrupted>()) {
        return PyKeyboardInterrupt::new_err("interrupted");
    }
    let message = stickslip::cli::message(&e);
    if stickslip::cli::exit_code(&e) == 2 {
        PyValueError::new_err(message)
    } else {
        PyRuntimeError::new_err(message)
    }
}

/// Ctrl-C reached a run.
#[derive(Debug)]
struct Interrupted;

impl std::error::Error for Interrupted {}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("interrupted")
    }
}

/// Resolve a scenario as the CLI does: the embedded paper scenario ← the file or TOML text (the
/// package writes a dict as TOML) ← `sets` (`--set KEY=VALUE`) ← `realizations`, `seed`.
fn resolve(path: Option<&str>, toml_text: Option<&str>, sets: &[String], over: Overrides) -> anyhow::Result<Scenario> {
    let mut sc = match path {
        Some(p) => Scenario::resolve(Some(Path::new(p)), sets)?,
        None => Scenario::from_text(toml_text, Path::new("<scenario>"), sets)?,
    };
    over.apply(&mut sc);
    sc.check()?;
    sc.refuse_sweep("simulate (from Python, into memory)")?;
    Ok(sc)
}

/// Most realizations `simulate` holds in memory (about 7.5 GB of rows on the paper scene).
const MAX_IN_MEMORY: u64 = 10_000_000;

/// Simulate one scene into memory (module docs). Arguments as `stickslip.simulate`.
#[pyfunction]
#[pyo3(signature = (path=None, toml_text=None, sets=Vec::new(), realizations=None, seed=None, threads=None))]
fn simulate_table(
    py: Python<'_>,
    path: Option<&str>,
    toml_text: Option<&str>,
    sets: Vec<String>,
    realizations: Option<u64>,
    seed: Option<u64>,
    threads: Option<usize>,
) -> PyResult<Table> {
    let sc = resolve(path, toml_text, &sets, Overrides { realizations, seed }).map_err(to_py)?;
    if sc.run.realizations > MAX_IN_MEMORY {
        return Err(PyValueError::new_err(format!(
            "realizations = {}: at most {MAX_IN_MEMORY} are held in memory (about 750 bytes each on the paper scene); write them with out=DIR and scan the Parquet files",
            sc.run.realizations
        )));
    }
    // Ctrl-C: Python's handler only sets a flag; the run asks for it between windows of chunks
    let stop = || Python::attach(|py| py.check_signals().is_err());
    let batches = py
        .detach(|| simulate::batches(&sc, threads, &stop))
        .map_err(|e| match e {
            SimulateError::Interrupted => anyhow::Error::new(Interrupted),
            e => anyhow::Error::new(e),
        })
        .map_err(to_py)?;
    let schema = match batches.first() {
        Some(b) => b.schema(),
        None => Arc::new(Schema::empty()),
    };
    Ok(Table { schema, batches })
}

/// Run the command line with `argv` (the program name first), as the `stickslip` binary does;
/// returns the exit code (0, 1 or 2), the error printed on stderr as the binary prints it.
/// Like the binary, it takes over SIGINT and SIGTERM (temporaries removed, exit 130/143): it is
/// meant for a process of its own (the console script, or the package's stage runner).
#[pyfunction]
fn run_cli(py: Python<'_>, argv: Vec<String>) -> i32 {
    stickslip::interrupt::install();
    py.detach(|| match stickslip::cli::main_from(argv) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("stickslip: error: {}", stickslip::cli::message(&e));
            i32::from(stickslip::cli::exit_code(&e))
        }
    })
}

/// Write a table made by `simulate_table` as a dataset directory, as `simulate --out` writes it
/// (the scene from the table's own provenance); returns the part file's path.
#[pyfunction]
fn write_table(py: Python<'_>, table: &Table, out: &str) -> PyResult<String> {
    let text =
        table.schema.metadata().get("stickslip.scenario").cloned().ok_or_else(|| {
            PyValueError::new_err("the table has no stickslip.scenario metadata: only tables from stickslip.simulate can be written or analysed")
        })?;
    py.detach(|| -> anyhow::Result<String> {
        let sc = Scenario::recorded(&text, Path::new("<table>"))?;
        Ok(simulate::write_batches(&table.batches, &sc, Path::new(out))?.display().to_string())
    })
    .map_err(to_py)
}

/// Read a Parquet file into a table (an analysis table or a dataset part).
#[pyfunction]
fn read_parquet(py: Python<'_>, path: &str) -> PyResult<Table> {
    py.detach(|| -> anyhow::Result<Table> {
        let file = std::fs::File::open(path).map_err(|e| anyhow::anyhow!("reading {path}: {e}"))?;
        let builder = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file)?;
        let schema = builder.schema().clone();
        let batches = builder.build()?.collect::<Result<Vec<_>, _>>()?;
        Ok(Table { schema, batches })
    })
    .map_err(|e| PyRuntimeError::new_err(stickslip::cli::message(&e)))
}

/// The shipped scenarios: (name, text) pairs, the paper's first.
#[pyfunction]
fn scenes() -> Vec<(String, String)> {
    stickslip::scenes::SHIPPED.iter().map(|s| (s.name.to_owned(), s.text.to_owned())).collect()
}

/// The extension module.
#[pymodule]
fn _stickslip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Table>()?;
    m.add_function(wrap_pyfunction!(simulate_table, m)?)?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(read_parquet, m)?)?;
    m.add_function(wrap_pyfunction!(write_table, m)?)?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
