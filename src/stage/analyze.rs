//! `analyze`: a dataset (every cell of a sweep) in, the analysis tables out
//! ([`crate::analysis`]).

use std::path::PathBuf;

use anyhow::Context;

use crate::analysis::{self, Analysis};
use crate::blame::usage;
use crate::progress::Control;
use crate::table::Table;

/// What to analyse, how, and where the tables go.
#[derive(Debug, Clone)]
pub struct Request {
    /// the dataset directory
    pub dataset: PathBuf,
    /// the analysis directory (replaced when complete; none: the tables are only returned)
    pub out: Option<PathBuf>,
    /// what to compute
    pub options: analysis::Options,
}

/// What `analyze` computed: each cell's analysis (the empty path for a plain dataset).
#[derive(Debug)]
pub struct Outcome {
    /// (cell path, analysis), in cell order
    pub cells: Vec<(String, Analysis)>,
    /// the analysis directory, if one was written
    pub out: Option<PathBuf>,
    /// the stage's wall-clock time [s]
    pub seconds: f64,
}

impl Outcome {
    /// Realizations analysed, over every cell.
    pub fn realizations(&self) -> u64 {
        self.cells.iter().map(|(_, a)| a.dataset.rows).sum()
    }

    /// Whether the dataset is a sweep (cells below hive paths).
    pub fn is_sweep(&self) -> bool {
        self.cells.len() > 1 || self.cells.iter().any(|(p, _)| !p.is_empty())
    }

    /// A sweep's table of cells (`sweep.parquet`); none for a plain dataset.
    pub fn sweep_table(&self) -> Option<Table> {
        self.is_sweep().then(|| analysis::sweep::table(&self.cells.iter().map(|(p, a)| analysis::sweep::summarize(p, a)).collect::<Vec<_>>()))
    }
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    if crate::outdir::is_marked(&req.dataset, crate::outdir::Kind::Reproduce) {
        let d = req.dataset.join("dataset");
        return Err(usage(format!("{} is a `reproduce` output, not a dataset: did you mean {}?", req.dataset.display(), d.display())));
    }
    let start = std::time::Instant::now();
    let cells = analysis::sweep::analyze_all(&req.dataset, &req.options, req.out.as_deref(), ctl).context("analyze")?;
    Ok(Outcome { cells, out: req.out.clone(), seconds: start.elapsed().as_secs_f64() })
}
