//! `figures`: an analysis in, the paper's figures out (PNG and SVG; [`crate::figures`]).

use std::path::PathBuf;

use anyhow::Context;

use crate::progress::Control;

/// Which analysis to draw, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the analysis directory
    pub analysis: PathBuf,
    /// the figures directory (replaced when complete)
    pub out: PathBuf,
}

/// What `figures` drew.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// the figures' names (each NAME.png and NAME.svg in the directory)
    pub names: Vec<String>,
    /// the figures directory
    pub out: PathBuf,
    /// the stage's wall-clock time [s]
    pub seconds: f64,
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    ctl.check()?;
    let start = std::time::Instant::now();
    let names = crate::figures::run(&req.analysis, &req.out).context("figures")?;
    Ok(Outcome { names, out: req.out.clone(), seconds: start.elapsed().as_secs_f64() })
}
