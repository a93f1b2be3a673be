//! The `exact-law` stage: solve at three resolutions, write `stationary.parquet` (the values
//! extrapolated from the finest two, each with an error estimate from all three) and
//! `convergence.parquet` (every resolution), and the Markdown table the command prints.

use std::path::{Path, PathBuf};

use super::{Level, QUANTITIES};
use crate::outdir::{Kind, StagedDir};
use crate::scenario::{Scenario, ScenarioError};
use crate::table::{Col, Table};

/// Why `exact-law` failed.
#[derive(Debug, thiserror::Error)]
pub enum LawError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The method does not hold for the scene.
    #[error("{0}")]
    Refused(String),
    /// Writing an output file failed.
    #[error("writing {}: {message}", path.display())]
    Write {
        /// the file
        path: PathBuf,
        /// what went wrong
        message: String,
    },
    /// The output directory could not be staged or replaced.
    #[error(transparent)]
    Out(#[from] crate::outdir::OutDirError),
}

impl crate::blame::Blame for LawError {
    fn blames_input(&self) -> bool {
        match self {
            LawError::Scenario(e) => e.blames_input(),
            LawError::Refused(_) => true,
            LawError::Write { .. } => false,
            LawError::Out(e) => e.blames_input(),
        }
    }
}

/// The resolutions of a run whose finest is `finest`: a quarter, a half and itself.
pub fn resolutions(finest: u32) -> [u32; 3] {
    [finest / 4, finest / 2, finest]
}

/// Solve the scenario's stationary law at [`resolutions`]`(finest)` and write `out` (replaced
/// when complete); `progress` hears each resolution's result as it is done.
pub fn run(scenario: &Scenario, finest: u32, out: &Path, progress: &mut dyn FnMut(&Level, f64)) -> Result<Vec<Level>, LawError> {
    let scene = scenario.scene()?;
    let frame = super::frame(&scene).map_err(LawError::Refused)?;
    let staged = StagedDir::new(out, Kind::ExactLaw, "--out", &[])?;
    let mut levels = Vec::new();
    for n in resolutions(finest) {
        let start = std::time::Instant::now();
        let level = super::solve(frame, n);
        progress(&level, start.elapsed().as_secs_f64());
        levels.push(level);
    }
    let werr = |name: &str, e: &dyn std::fmt::Display| LawError::Write { path: out.join(name), message: e.to_string() };
    stationary_table(&levels).write_parquet(&staged.path().join("stationary.parquet")).map_err(|e| werr("stationary.parquet", &e))?;
    convergence_table(&levels).write_parquet(&staged.path().join("convergence.parquet")).map_err(|e| werr("convergence.parquet", &e))?;
    staged.commit()?;
    Ok(levels)
}

/// (value, error) of each quantity from solves at resolutions n/4, n/2, n (or fewer): the
/// error is second order in 1/n (module docs of [`super`]), so the value is Richardson's
/// R_n = v_n + (v_n − v_{n/2})/3, and its error estimate the change |R_n − R_{n/2}| (the error
/// of R_{n/2} bounds it); with two levels, v_n and |v_n − v_{n/2}|; with one, v_n and NaN.
pub fn estimates(levels: &[Level]) -> Vec<(f64, f64)> {
    let k = levels.len();
    (0..QUANTITIES.len())
        .map(|q| {
            let v = |i: usize| levels[i].values[q];
            let richardson = |i: usize| v(i) + (v(i) - v(i - 1)) / 3.0;
            match k {
                0 => (f64::NAN, f64::NAN),
                1 => (v(0), f64::NAN),
                2 => (v(1), (v(1) - v(0)).abs()),
                _ => (richardson(k - 1), (richardson(k - 1) - richardson(k - 2)).abs()),
            }
        })
        .collect()
}

/// `stationary.parquet`: quantity, value, error.
fn stationary_table(levels: &[Level]) -> Table {
    let est = estimates(levels);
    let mut t = Table::default();
    t.push("quantity", Col::Str(QUANTITIES.iter().map(|q| q.to_string()).collect()))
        .push("value", Col::Float(est.iter().map(|e| Some(e.0)).collect()))
        .push("error", Col::Float(est.iter().map(|e| Some(e.1)).collect()));
    t
}

/// `convergence.parquet`: resolution, h, quantity, value, iterations, lost (one row per
/// resolution and quantity).
fn convergence_table(levels: &[Level]) -> Table {
    let rows: Vec<(&Level, usize)> = levels.iter().flat_map(|l| (0..QUANTITIES.len()).map(move |q| (l, q))).collect();
    let mut t = Table::default();
    t.push("resolution", Col::Int(rows.iter().map(|(l, _)| Some(i64::from(l.n))).collect()))
        .push("h", Col::Float(rows.iter().map(|(l, _)| Some(l.h)).collect()))
        .push("quantity", Col::Str(rows.iter().map(|&(_, q)| QUANTITIES[q].to_string()).collect()))
        .push("value", Col::Float(rows.iter().map(|&(l, q)| Some(l.values[q])).collect()))
        .push("iterations", Col::Int(rows.iter().map(|(l, _)| Some(i64::from(l.iterations))).collect()))
        .push("lost", Col::Float(rows.iter().map(|(l, _)| Some(l.lost)).collect()));
    t
}

/// The table `exact-law` prints: each quantity at every resolution, the value and its error.
pub fn markdown(levels: &[Level]) -> String {
    let est = estimates(levels);
    let mut m = String::from("| quantity |");
    for l in levels {
        m += &format!(" n = {} |", l.n);
    }
    m += " value | error |\n|---|";
    m += &"---:|".repeat(levels.len() + 2);
    m += "\n";
    for (q, name) in QUANTITIES.iter().enumerate() {
        m += &format!("| {name} |");
        for l in levels {
            m += &format!(" {:.6} |", l.values[q]);
        }
        m += &format!(" {:.6} | {:.1e} |\n", est[q].0, est[q].1);
    }
    m
}
