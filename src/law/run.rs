//! The exact law of a scenario as data: [`plan`] checks that the method holds for the scene and
//! the options (every refusal before any solve), [`solve`] computes the long run at [`LEVELS`]
//! resolutions, Table 1's rows, D_k's law and, when asked, the counts' laws and the densities.
//! Nothing here writes a file: the `exact-law` stage writes [`Solved`] as its tables
//! ([`super::tables`]) and figures.

use std::path::PathBuf;

use super::counts::CountRow;
use super::densities::DensityRow;
use super::density::Density;
use super::flow::Frame;
use super::passage::Sequence;
use super::richardson::LEVELS;
use super::stationary::{frames, ladder, Level, Rung};
use super::sticks::{self, Row, SurvivalRow};
use crate::progress::{Cancelled, Control};
use crate::scenario::{Scenario, ScenarioError};
use crate::table::Table;

/// Why `exact-law` or `predict` failed.
#[derive(Debug, thiserror::Error)]
pub enum LawError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The method does not hold for the scene, or the state or options do not fit it.
    #[error("{0}")]
    Refused(String),
    /// The solve failed (it did not converge), or a future could not be simulated.
    #[error("{0}")]
    Failed(String),
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
    /// The caller cancelled the run (Ctrl-C in a Python session).
    #[error("interrupted")]
    Cancelled(#[from] Cancelled),
}

impl crate::blame::Blame for LawError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            LawError::Scenario(e) => e.blame(),
            LawError::Refused(_) => Some(crate::blame::Culprit::Scenario),
            LawError::Failed(_) | LawError::Write { .. } | LawError::Cancelled(_) => None,
            LawError::Out(e) => e.blame(),
        }
    }
}

/// What `exact-law` computes beyond the long run: the resolution of the long run and Table 1
/// (`finest`), the times added to D_k's law, and the finest resolution of the counts' laws
/// (S_T, S_L; none: not computed) and of the densities of T_k, L_k and H_k.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// the finest resolution of the long run and Table 1
    pub finest: u32,
    /// times [s] added to D_k's law
    pub tail_times: Vec<f64>,
    /// the finest resolution of the counts' laws, or none
    pub counts: Option<u32>,
    /// the finest resolution of the densities of T_k, L_k, H_k, or none
    pub densities: Option<u32>,
}

/// The file of an `exact-law` directory that records the resolved scenario the law is of.
pub const SCENARIO_FILE: &str = "scenario.toml";

/// A checked request: the scene's frames and the ladders of resolutions it is solved on.
#[derive(Debug, Clone)]
pub struct Plan {
    frames: Vec<Frame>,
    ladder: Vec<Rung>,
    counts: Option<Vec<Rung>>,
    densities: Option<Vec<Rung>>,
    finest: u32,
    tail_times: Vec<f64>,
}

/// What the exact law computed.
#[derive(Debug, Clone)]
pub struct Solved {
    /// the long run at each resolution
    pub levels: Vec<Level>,
    /// the resolutions (n, spacings) of the long run and Table 1
    pub ladder: Vec<Rung>,
    /// the stationary density at the finest resolution
    pub density: Density,
    /// each resolution's sequence of sticks from the initial conditions
    pub(crate) sticks: Vec<(f64, Sequence)>,
    /// Table 1's rows (with S_T and S_L when counted)
    pub rows: Vec<Row>,
    /// D_k's law on its grid of times
    pub survival: Vec<SurvivalRow>,
    /// the counts' laws (empty unless asked for)
    pub counts: Vec<CountRow>,
    /// the densities (empty unless asked for)
    pub densities: Vec<DensityRow>,
    /// the densities' characteristic functions (empty unless asked for)
    pub characteristic: Table,
    /// whether the counts and the densities were asked for
    pub asked: (bool, bool),
    /// a warning on the window t_a, if the sticks reach past it
    pub warning: Option<String>,
}

/// Check that the exact method holds for `scenario` and `opts`: every refusal, before any solve.
pub fn plan(scenario: &Scenario, opts: &Options) -> Result<Plan, LawError> {
    let scene = scenario.scene()?;
    let frames = frames(&scene).map_err(LawError::Refused)?;
    let main = ladder(&frames, opts.finest, LEVELS).map_err(LawError::Refused)?;
    sticks::check(scenario, &frames, &main).map_err(LawError::Refused)?;
    if opts.counts.is_some() {
        super::counts::check(&frames, scenario.run.duration).map_err(LawError::Refused)?;
    }
    let densities = opts.densities.map(|n| ladder(&frames, n, LEVELS)).transpose().map_err(LawError::Refused)?;
    if densities.is_some() {
        super::densities::check(scenario).map_err(LawError::Refused)?;
    }
    let counts = opts.counts.map(|n| ladder(&frames, n, LEVELS)).transpose().map_err(LawError::Refused)?;
    Ok(Plan { frames, ladder: main, counts, densities, finest: opts.finest, tail_times: opts.tail_times.clone() })
}

/// Solve the planned law of `scenario`. `ctl` hears each resolution's result as a note when it is
/// done, each iteration as a status (resolution, iteration, change of the measure; for the
/// counts: resolution, stick k, P(T_k ≤ t_a)) and each sequence's time as a note; it is asked
/// after each iteration of the stationary solve and each passage of the walks. D_k's law is evaluated on a grid of times with the
/// plan's tail times added.
pub fn solve(scenario: &Scenario, plan: &Plan, ctl: Control) -> Result<Solved, LawError> {
    let note = |what: &str, n: u32, seconds: f64| ctl.progress.note(&format!("{what} from the initial conditions, resolution {n:>3}: {seconds:.1} s"));
    let step = |n: u32, i: u32, change: f64| ctl.progress.status(&format!("resolution {n:>3}: iteration {i}, change {change:.1e}"));
    let Plan { frames, ladder, .. } = plan;
    // every solve below asks the cancel token as it goes (the stationary one after each
    // iteration, the walks after each passage: a stick, a few seconds at the finest resolution);
    // a solve it stopped fails, told from a failure by asking the token again
    let go_on = || !(ctl.cancel)();
    let failed = |e: String| -> LawError {
        if ctl.check().is_err() {
            Cancelled.into()
        } else {
            LawError::Failed(e)
        }
    };
    let (mut levels, mut density) = (Vec::new(), None);
    for rung in ladder {
        let (n, start) = (rung.0, std::time::Instant::now());
        ctl.check()?;
        let iterated = &mut |i, change| {
            step(n, i, change);
            go_on()
        };
        let (level, d) = super::stationary::solve(frames, rung, n == plan.finest, iterated).map_err(failed)?;
        ctl.progress.note(&format!("resolution {:>3}: {} iterations, {:.1} s", level.n, level.iterations, start.elapsed().as_secs_f64()));
        levels.push(level);
        density = d.or(density);
    }
    let density = density.expect("the finest resolution computes the density");
    ctl.check()?;
    let after = sticks::solve(scenario, frames, ladder, &mut |n, s| note("sticks 1-6", n, s), &go_on).map_err(failed)?;
    let order = sticks::order(scenario);
    let mut rows = sticks::rows(&after, order);
    let counts = match &plan.counts {
        Some(ladder) => {
            ctl.check()?;
            let mut counting = |n: u32, k: usize, p: f64| ctl.progress.status(&format!("S_T and S_L, resolution {n:>3}: stick {k}, P(T_k <= t_a) = {p:.1e}"));
            let solved = super::counts::solve(scenario, frames, ladder, &mut |n, s| note("S_T and S_L", n, s), &mut counting, &go_on).map_err(failed)?;
            super::counts::reach(&solved, &mut rows);
            super::counts::rows(&solved)
        }
        None => (Vec::new(), Vec::new()),
    };
    rows.extend(counts.1);
    let (densities, characteristic) = match &plan.densities {
        Some(ladder) => {
            let t_a = scenario.run.duration;
            let half_period = super::densities::half_period(t_a, after.last().map_or((f64::NAN, f64::NAN), |(_, s)| s.next_start));
            ctl.check()?;
            let solved =
                super::densities::solve(scenario, frames, ladder, half_period, &mut |n, s| note("densities of T_k, L_k, H_k", n, s), &go_on).map_err(failed)?;
            super::window::windowed(&solved, half_period, t_a, &mut rows);
            (super::densities::rows(&solved, half_period, t_a), super::characteristic::characteristic_table(&solved, half_period))
        }
        None => (Vec::new(), Table::default()),
    };
    let survival = sticks::survival_rows(frames, &after, &super::density::survival_times(frames, &plan.tail_times), order);
    let warning = after.last().and_then(|(_, s)| sticks::window_warning(s.next_start, scenario.run.duration));
    Ok(Solved {
        levels,
        ladder: ladder.clone(),
        density,
        sticks: after,
        rows,
        survival,
        counts: counts.0,
        densities,
        characteristic,
        asked: (plan.counts.is_some(), plan.densities.is_some()),
        warning,
    })
}
