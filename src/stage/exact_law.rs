//! `exact-law`: a scenario in; the long-run law and Table 1 computed without sampling, with an
//! error estimate from refinement, out ([`crate::law`]).

use std::path::PathBuf;

use anyhow::Context;

use super::request::{check_resolution, inputs};
use crate::blame::usage;
use crate::law::{counts::CountRow, densities::DensityRow, sticks, LawError, Level, SCENARIO_FILE};
use crate::outdir::{check_separate, Kind, StagedDir};
use crate::progress::Control;
use crate::scenario::Input;
use crate::table::{Def, Table};

/// The finest resolution by default.
pub const DEFAULT_RESOLUTION: u32 = 80;

/// What to compute, and where.
#[derive(Debug, Clone)]
pub struct Request {
    /// the scenario (one scene the exact method holds for)
    pub input: Input,
    /// the output directory
    pub out: PathBuf,
    /// the finest resolution N (8 to 320; solved at N/4, N/2, N)
    pub resolution: u32,
    /// times t [s] (finite, ≥ 0) at which P(D_k > t) is also evaluated
    pub tail_times: Vec<f64>,
    /// also the laws of S_T and S_L, at this finest resolution (8 to 320)
    pub counts: Option<u32>,
    /// also the densities of T_k, L_k, H_k, at this finest resolution (8 to 320)
    pub densities: Option<u32>,
}

impl Request {
    /// The defaults for `input` into `out`: resolution 80, reproduce's tail times.
    pub fn new(input: Input, out: PathBuf) -> Request {
        Request { input, out, resolution: DEFAULT_RESOLUTION, tail_times: crate::analysis::tails::PAPER_TAIL_TIMES.to_vec(), counts: None, densities: None }
    }
}

/// What `exact-law` computed.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// the long run at each resolution
    pub levels: Vec<Level>,
    /// Table 1's rows (with S_T and S_L when counted)
    pub rows: Vec<sticks::Row>,
    /// the counts' laws (empty unless asked for)
    pub counts: Vec<CountRow>,
    /// the densities (empty unless asked for)
    pub densities: Vec<DensityRow>,
    /// a warning on the window t_a, if the sticks reach past it
    pub warning: Option<String>,
    /// every table written, with its definition ([`crate::law::tables::all`])
    pub tables: Vec<(&'static Def, Table)>,
}

/// Run the stage.
pub fn run(req: &Request, ctl: Control) -> anyhow::Result<Outcome> {
    check_resolution("--resolution", req.resolution)?;
    if let Some(t) = req.tail_times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
        return Err(usage(format!("--tail-times {t}: must be a finite time >= 0 s")));
    }
    if let Some(n) = req.counts {
        check_resolution("--counts", n)?;
    }
    if let Some(n) = req.densities {
        check_resolution("--densities", n)?;
    }
    check_separate(&req.out, "--out", &inputs(&req.input))?;
    // (resolved and checked)
    let scenario = req.input.resolve()?;
    scenario.refuse_sweep("exact-law")?;
    if let Some(note) = scenario.scene().ok().as_ref().and_then(crate::law::cost_note) {
        ctl.progress.note(&note);
    }
    let opts = crate::law::Options { finest: req.resolution, tail_times: req.tail_times.clone(), counts: req.counts, densities: req.densities };
    let (solved, tables) = solve_into(&scenario, &opts, &req.out, ctl).context("exact-law")?;
    Ok(Outcome { levels: solved.levels, rows: solved.rows, counts: solved.counts, densities: solved.densities, warning: solved.warning, tables })
}

/// Check, solve and write `out` (replaced when complete): the scenario the law is of
/// (`scenario.toml`: the report refuses a law of another scene beside a dataset), every table of
/// the law ([`crate::law::tables::all`], returned with it) and its figures.
pub fn solve_into(
    scenario: &crate::scenario::Scenario,
    opts: &crate::law::Options,
    out: &std::path::Path,
    ctl: Control,
) -> Result<(crate::law::Solved, Vec<(&'static Def, Table)>), LawError> {
    let plan = crate::law::plan(scenario, opts)?;
    let staged = StagedDir::new(out, Kind::ExactLaw, "--out", &[])?;
    let solved = crate::law::solve(scenario, &plan, ctl)?;
    let werr = |name: &str, e: &dyn std::fmt::Display| LawError::Write { path: out.join(name), message: e.to_string() };
    std::fs::write(staged.path().join(SCENARIO_FILE), scenario.to_toml()).map_err(|e| werr(SCENARIO_FILE, &e))?;
    let tables = crate::law::tables::all(&solved).map_err(|message| LawError::Write { path: out.to_owned(), message })?;
    for (def, table) in &tables {
        table.write_parquet(&staged.path().join(def.file)).map_err(|e| werr(def.file, &e))?;
    }
    let mut figures = vec![crate::figures::exact::stationary_density(&solved.density)];
    if solved.asked.1 {
        figures.push(crate::figures::exact::densities(&solved.densities));
    }
    for f in &figures {
        crate::figures::render::save(f, staged.path()).map_err(|e| werr(&format!("{}.png", f.name), &e))?;
    }
    staged.commit()?;
    Ok((solved, tables))
}
