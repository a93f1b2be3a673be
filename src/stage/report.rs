//! `report`: a dataset, its analysis and figures (and optionally an exact law) in, one
//! self-contained HTML page and its Markdown twin out ([`crate::report`]).

use std::path::PathBuf;

use anyhow::Context;

use crate::progress::Control;

/// What to report on, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the dataset directory
    pub dataset: PathBuf,
    /// its analysis directory
    pub analysis: PathBuf,
    /// its figures directory
    pub figures: PathBuf,
    /// an `exact-law` directory of the same scene, compared beside the sampled values
    pub exact: Option<PathBuf>,
    /// the HTML file (the Markdown twin beside it)
    pub out: PathBuf,
}

/// What `report` wrote.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// the HTML page
    pub html: PathBuf,
    /// its Markdown twin
    pub markdown: PathBuf,
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    ctl.check()?;
    let [html, markdown] = crate::report::run(&req.dataset, &req.analysis, &req.figures, req.exact.as_deref(), &req.out).context("report")?;
    Ok(Outcome { html, markdown })
}
