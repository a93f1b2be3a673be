//! The `exact-law` stage: solve at three resolutions, write `stationary.parquet` (the values
//! extrapolated from the finest two, each with an error estimate from all three) and
//! `convergence.parquet` (every resolution), and the Markdown table the command prints.

use std::path::{Path, PathBuf};

use super::density::Density;
use super::sticks;
use super::{Level, QUANTITIES};
use crate::figures::chart::{Figure, Panel, Series};
use crate::outdir::{Kind, StagedDir};
use crate::progress::{Cancelled, Control};
use crate::scenario::{Scenario, ScenarioError};
use crate::table::{Col, Table};

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

/// The resolutions `exact-law` solves at: a quarter of the finest, a half, itself.
pub const LEVELS: u32 = 3;

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

/// What `exact-law` found: the long run's levels, Table 1's rows (with S_T and S_L when
/// counted), the counts' laws, the densities and the window's warning.
pub type Found = (Vec<Level>, Vec<sticks::Row>, Vec<super::counts::CountRow>, Vec<super::densities::DensityRow>, Option<String>);

/// Solve the scenario's stationary law at [`LEVELS`] resolutions up to `finest` and write `out`
/// (replaced when complete). `ctl` hears each resolution's result as a note when it is done, each
/// iteration as a status (resolution, iteration, change of the measure; for the counts:
/// resolution, stick k, P(T_k ≤ t_a)) and each sequence's time as a note; it is asked between
/// resolutions and sequences. D_k's law (`survival.parquet`) is evaluated on a grid of times with
/// `tail_times` [s] added; with `counts`, the laws of S_T and S_L are written to `counts.parquet`
/// and their means and variances added to `moments.parquet`.
pub fn run(scenario: &Scenario, opts: &Options, out: &Path, ctl: Control) -> Result<Found, LawError> {
    let note = |what: &str, n: u32, seconds: f64| ctl.progress.note(&format!("{what} from the initial conditions, resolution {n:>3}: {seconds:.1} s"));
    let step = |n: u32, i: u32, change: f64| ctl.progress.status(&format!("resolution {n:>3}: iteration {i}, change {change:.1e}"));
    let (finest, tail_times, counts) = (opts.finest, &opts.tail_times, opts.counts);
    let scene = scenario.scene()?;
    let frames = super::frames(&scene).map_err(LawError::Refused)?;
    let ladder = super::ladder(&frames, finest, LEVELS).map_err(LawError::Refused)?;
    sticks::check(scenario, &frames, &ladder).map_err(LawError::Refused)?;
    if counts.is_some() {
        super::counts::check(&frames, scenario.run.duration).map_err(LawError::Refused)?;
    }
    let densities_ladder = opts.densities.map(|n| super::ladder(&frames, n, LEVELS)).transpose().map_err(LawError::Refused)?;
    if densities_ladder.is_some() {
        super::densities::check(scenario).map_err(LawError::Refused)?;
    }
    let staged = StagedDir::new(out, Kind::ExactLaw, "--out", &[])?;
    let (mut levels, mut density) = (Vec::new(), None);
    for rung in &ladder {
        let (n, start) = (rung.0, std::time::Instant::now());
        ctl.check()?;
        let (level, d) = super::solve(&frames, rung, n == finest, &mut |i, change| step(n, i, change)).map_err(LawError::Failed)?;
        ctl.progress.note(&format!("resolution {:>3}: {} iterations, {:.1} s", level.n, level.iterations, start.elapsed().as_secs_f64()));
        levels.push(level);
        density = d.or(density);
    }
    let density = density.expect("the finest resolution computes the density");
    ctl.check()?;
    let after = sticks::solve(scenario, &frames, &ladder, &mut |n, s| note("sticks 1-6", n, s)).map_err(LawError::Failed)?;
    let order = sticks::order(scenario);
    let mut rows = sticks::rows(&after, order);
    let counts = match counts {
        Some(n) => {
            let ladder = super::ladder(&frames, n, LEVELS).map_err(LawError::Refused)?;
            ctl.check()?;
            let counting = |n: u32, k: usize, p: f64| ctl.progress.status(&format!("S_T and S_L, resolution {n:>3}: stick {k}, P(T_k <= t_a) = {p:.1e}"));
            let solved = super::counts::solve(scenario, &frames, &ladder, &mut |n, s| note("S_T and S_L", n, s), &mut |n, k, p| counting(n, k, p))
                .map_err(LawError::Failed)?;
            super::counts::reach(&solved, &mut rows);
            super::counts::rows(&solved)
        }
        None => (Vec::new(), Vec::new()),
    };
    rows.extend(counts.1);
    let (densities, characteristic) = match &densities_ladder {
        Some(ladder) => {
            let t_a = scenario.run.duration;
            let half_period = super::densities::half_period(t_a, after.last().map_or((f64::NAN, f64::NAN), |(_, s)| s.next_start));
            ctl.check()?;
            let solved = super::densities::solve(scenario, &frames, ladder, half_period, &mut |n, s| note("densities of T_k, L_k, H_k", n, s))
                .map_err(LawError::Failed)?;
            super::window::windowed(&solved, half_period, t_a, &mut rows);
            (super::densities::rows(&solved, half_period, t_a), super::densities::characteristic_table(&solved, half_period))
        }
        None => (Vec::new(), Table::default()),
    };
    let laws = sticks::survival_rows(&frames, &after, &super::density::survival_times(&frames, tail_times), order);
    let warning = after.last().and_then(|(_, s)| sticks::window_warning(s.next_start, scenario.run.duration));
    let werr = |name: &str, e: &dyn std::fmt::Display| LawError::Write { path: out.join(name), message: e.to_string() };
    // the scene the law is of (the report refuses a law of another scene beside a dataset)
    std::fs::write(staged.path().join(SCENARIO_FILE), scenario.to_toml()).map_err(|e| werr(SCENARIO_FILE, &e))?;
    stationary_table(&levels).write_parquet(&staged.path().join("stationary.parquet")).map_err(|e| werr("stationary.parquet", &e))?;
    convergence_table(&levels, &ladder, &after).write_parquet(&staged.path().join("convergence.parquet")).map_err(|e| werr("convergence.parquet", &e))?;
    density_table(&density).write_parquet(&staged.path().join("density.parquet")).map_err(|e| werr("density.parquet", &e))?;
    let mut survival = Table::default();
    survival
        .push("t", Col::Float(density.stick_survival.iter().map(|p| Some(p.0)).collect()))
        .push("survival", Col::Float(density.stick_survival.iter().map(|p| Some(p.1)).collect()));
    survival.write_parquet(&staged.path().join("stick_survival.parquet")).map_err(|e| werr("stick_survival.parquet", &e))?;
    crate::figures::render::save(&density_figure(&density), staged.path()).map_err(|e| werr("stationary_density.png", &e))?;
    moments_table(&rows).write_parquet(&staged.path().join("moments.parquet")).map_err(|e| werr("moments.parquet", &e))?;
    survival_table(&laws).write_parquet(&staged.path().join("survival.parquet")).map_err(|e| werr("survival.parquet", &e))?;
    if opts.counts.is_some() {
        counts_table(&counts.0).write_parquet(&staged.path().join("counts.parquet")).map_err(|e| werr("counts.parquet", &e))?;
    }
    if opts.densities.is_some() {
        densities_table(&densities).write_parquet(&staged.path().join("densities.parquet")).map_err(|e| werr("densities.parquet", &e))?;
        crate::figures::render::save(&super::densities::figure(&densities), staged.path()).map_err(|e| werr("densities.png", &e))?;
        characteristic.write_parquet(&staged.path().join("characteristic.parquet")).map_err(|e| werr("characteristic.parquet", &e))?;
    }
    staged.commit()?;
    Ok((levels, rows, counts.0, densities, warning))
}

/// The file of an `exact-law` directory that records the resolved scenario the law is of.
pub const SCENARIO_FILE: &str = "scenario.toml";

/// `moments.parquet`: variable, index, mean, variance, error (of the mean), variance_error,
/// reached_fraction (with `--counts` or `--densities`; null otherwise), windowed_mean,
/// windowed_error, windowed_variance, windowed_variance_error (T_k and L_k conditioned on
/// X ≤ t_a, with `--densities`; null otherwise).
/// (S_T and S_L, whose rows have index 0, have a null index, as in analyze's.)
fn moments_table(rows: &[sticks::Row]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| (r.index > 0).then_some(i64::from(r.index))).collect()))
        .push("mean", Col::Float(rows.iter().map(|r| Some(r.mean)).collect()))
        .push("variance", Col::Float(rows.iter().map(|r| Some(r.variance)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .push("variance_error", Col::Float(rows.iter().map(|r| Some(r.variance_error)).collect()))
        .push("reached_fraction", Col::Float(rows.iter().map(|r| r.reached.map(|x| x.0)).collect()))
        .push("windowed_mean", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[0])).collect()))
        .push("windowed_error", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[1])).collect()))
        .push("windowed_variance", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[2])).collect()))
        .push("windowed_variance_error", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[3])).collect()));
    t
}

/// `counts.parquet`: variable (S_T, S_L), value n, probability P(S = n), error.
fn counts_table(rows: &[super::counts::CountRow]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("value", Col::Int(rows.iter().map(|r| Some(i64::from(r.value))).collect()))
        .push("probability", Col::Float(rows.iter().map(|r| Some(r.probability)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()));
    t
}

/// `densities.parquet`: variable (T, L, H), index k, the cell t_lo ≤ t < t_hi, its centre t,
/// the density averaged over it [1/s], error, point_mass (the probability of the point masses
/// in it, not part of the density).
pub(crate) fn densities_table(rows: &[super::densities::DensityRow]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .push("t", Col::Float(rows.iter().map(|r| Some(0.5 * (r.t_lo + r.t_hi))).collect()))
        .push("t_lo", Col::Float(rows.iter().map(|r| Some(r.t_lo)).collect()))
        .push("t_hi", Col::Float(rows.iter().map(|r| Some(r.t_hi)).collect()))
        .push("density", Col::Float(rows.iter().map(|r| Some(r.density)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .push("point_mass", Col::Float(rows.iter().map(|r| Some(r.point_mass)).collect()));
    t
}

/// `survival.parquet`, in analyze's columns (`variable` D, `index` k, `method` exact, `t`,
/// `survival` = P(D_k > t), `lo`, `hi`: the value ∓ its error estimate, within [0, 1]) with
/// `error`, `density` (at the finest resolution, [`sticks::SurvivalRow`]) and `density_error`.
pub(crate) fn survival_table(rows: &[sticks::SurvivalRow]) -> Table {
    let f = |g: &dyn Fn(&sticks::SurvivalRow) -> f64| Col::Float(rows.iter().map(|r| Some(g(r))).collect());
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|_| "D".to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .push("method", Col::Str(rows.iter().map(|_| "exact".to_string()).collect()))
        .push("t", f(&|r| r.t))
        .push("survival", f(&|r| r.survival))
        .push("lo", f(&|r| (r.survival - r.error).max(0.0)))
        .push("hi", f(&|r| (r.survival + r.error).min(1.0)))
        .push("error", f(&|r| r.error))
        .push("density", f(&|r| r.density))
        .push("density_error", f(&|r| r.density_error));
    t
}

/// (value, error) of each quantity from solves at resolutions n/4, n/2, n (or fewer): the
/// error is second order in the spacing h (module docs of [`super`]), so the value is
/// Richardson's R = v_n + (v_n − v_{n/2}) / ((h_{n/2}/h_n)² − 1) (÷ 3 when h halves), and its
/// error estimate the change of R from the coarser pair (whose error bounds it); with two
/// levels, v_n and |v_n − v_{n/2}|; with one, v_n and NaN.
pub fn estimates(levels: &[Level]) -> Vec<(f64, f64)> {
    (0..QUANTITIES.len()).map(|q| extrapolate(&levels.iter().map(|l| (l.h, l.values[q])).collect::<Vec<_>>())).collect()
}

/// What the resolutions' changes show of the order ([`guarded`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    /// The laws from a box of starts (split along its fates: module docs of
    /// [`super::sticks`]): their changes fall at a steady order (on the paper scene the Table 1
    /// ratios lie in 2.9–6.2 from n = 20 to 160 and 3.0–4.3 from 80 to 320, D_1's mean apart),
    /// so a ratio in the asymptotic range is evidence.
    Regular,
    /// The laws after a point start: its mass meets the grid's nodes and the fates' curves
    /// all at once, and the changes are erratic — from rest at x = 0.5 on the paper scene the
    /// breakaway probability's changes from h = 0.17 to 0.01 are +4.9e-4, +1.2e-4, +6.0e-5,
    /// +9.8e-6 (ratios 4.1, 2.0, 6.1), so the first ratio, in range, would have trusted an
    /// extrapolation whose change (3e-6) understates its error (about 4e-5) tenfold; stuck at
    /// 0.3: +5.4e-4, −4.9e-4, −1.4e-5, +1.7e-6. One ratio is no evidence there. The laws of
    /// the counts (`--counts`), whose resolutions are coarse, are taken as irregular too.
    Irregular,
}

/// [`extrapolate`]'s value, with an error that the changes support.
///
/// If v_h = V + a h^p, Richardson's R_h = v_h + (v_h − v_{2h})/3 = V + a h^p (4 − 2^p)/3, so
/// the change of R between the pairs is |R_h − R_{2h}| = |R_h − V| (2^p − 1): it bounds R's
/// error whenever p > 1 (by 1.8× at p = 1.5). The order shows in the ratio of the changes,
/// (v_{2h} − v_{4h}) / (v_h − v_{2h}) = 2^p: for [`Order::Regular`] levels whose ratio lies in
/// [2^1.5, 2^3] the change of R is the error (Roache's asymptotic range, *Verification and
/// Validation in Computational Science and Engineering*, 1998, ch. 5). Otherwise — another
/// ratio, or [`Order::Irregular`] levels — the finest change, the size of the finest level's
/// own error, is its floor.
pub(crate) fn guarded(points: &[(f64, f64)], order: Order) -> (f64, f64) {
    let (value, error) = extrapolate(points);
    let change = |w: &[(f64, f64)]| w[1].1 - w[0].1;
    let changes: Vec<f64> = points.windows(2).map(change).collect();
    let finest = changes.last().map_or(0.0, |c| c.abs());
    let ratio = match changes[..] {
        [.., coarse, fine] => coarse / fine,
        _ => f64::NAN,
    };
    if order == Order::Regular && (2f64.powf(1.5)..=8.0).contains(&ratio) {
        (value, error)
    } else {
        (value, error.max(finest))
    }
}

/// (value, error) from the values at spacings h (coarsest first), as [`estimates`].
pub(crate) fn extrapolate(points: &[(f64, f64)]) -> (f64, f64) {
    let k = points.len();
    let v = |i: usize| points[i].1;
    let richardson = |i: usize| v(i) + (v(i) - v(i - 1)) / ((points[i - 1].0 / points[i].0).powi(2) - 1.0);
    match k {
        0 => (f64::NAN, f64::NAN),
        1 => (v(0), f64::NAN),
        2 => (v(1), (v(1) - v(0)).abs()),
        _ => (richardson(k - 1), (richardson(k - 1) - richardson(k - 2)).abs()),
    }
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

/// `convergence.parquet`: resolution, h, quantity, value, iterations, lost — one row per
/// resolution and long-run quantity, then per resolution and Table 1 statistic (`mean_T_1`,
/// `variance_T_1`, …; iterations null).
fn convergence_table(levels: &[Level], ladder: &[super::Rung], sticks: &[(f64, super::passage::Sequence)]) -> Table {
    // (resolution, h, quantity, value, iterations, lost)
    let mut rows: Vec<(u32, f64, String, f64, Option<i64>, f64)> = levels
        .iter()
        .flat_map(|l| QUANTITIES.iter().zip(l.values).map(move |(q, v)| (l.n, l.h, q.to_string(), v, Some(i64::from(l.iterations)), l.lost)))
        .collect();
    for (&(n, _), (h, s)) in ladder.iter().map(|r| (r.0, ())).collect::<Vec<_>>().iter().zip(sticks) {
        for (v, k, (mean, variance)) in sticks::values(s) {
            rows.push((n, *h, format!("mean_{v}_{k}"), mean, None, s.lost));
            rows.push((n, *h, format!("variance_{v}_{k}"), variance, None, s.lost));
        }
    }
    let mut t = Table::default();
    t.push("resolution", Col::Int(rows.iter().map(|r| Some(i64::from(r.0))).collect()))
        .push("h", Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .push("quantity", Col::Str(rows.iter().map(|r| r.2.clone()).collect()))
        .push("value", Col::Float(rows.iter().map(|r| Some(r.3)).collect()))
        .push("iterations", Col::Int(rows.iter().map(|r| r.4).collect()))
        .push("lost", Col::Float(rows.iter().map(|r| Some(r.5)).collect()));
    t
}

/// `density.parquet`: kind (`slip`: a cell of the plane, density in 1/(m · m/s); `stick`: a
/// cell of a stick line ẋ = ±v0, density in 1/m), x and velocity (the cell's centre), density.
fn density_table(d: &Density) -> Table {
    let centres = |e: &[f64]| e.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect::<Vec<f64>>();
    let (xs, vs) = (centres(&d.x_edges), centres(&d.v_edges));
    let mut rows: Vec<(&str, f64, f64, f64)> = Vec::new();
    for (i, &x) in xs.iter().enumerate() {
        for (j, &v) in vs.iter().enumerate() {
            rows.push(("slip", x, v, d.slip[i * vs.len() + j]));
        }
    }
    for (k, (line, v)) in d.stick.iter().zip(d.velocities).enumerate() {
        rows.extend(d.stick_centres(k).into_iter().zip(line).map(|(x, &p)| ("stick", x, v, p)));
    }
    let mut t = Table::default();
    t.push("kind", Col::Str(rows.iter().map(|r| r.0.to_string()).collect()))
        .push("x", Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .push("velocity", Col::Float(rows.iter().map(|r| Some(r.2)).collect()))
        .push("density", Col::Float(rows.iter().map(|r| Some(r.3)).collect()));
    t
}

/// `stationary_density.png`: the slip density over (x, ẋ) and the stick lines' densities.
fn density_figure(d: &Density) -> Figure {
    let n = d.x_edges.len() - 1;
    let m = d.v_edges.len() - 1;
    let heat = (0..n * m)
        .map(|k| {
            let (i, j) = (k / m, k % m);
            [d.x_edges[i], d.x_edges[i + 1], d.v_edges[j], d.v_edges[j + 1], d.slip[k]]
        })
        .collect();
    let line = |k: usize, label: String, color: usize| Series {
        label,
        color,
        points: d.stick_centres(k).into_iter().zip(d.stick[k].iter().copied()).collect(),
        errors: vec![],
    };
    // the axes over the cells above 1e-3 of the largest (the table has them all)
    let top = d.slip.iter().copied().fold(0.0, f64::max);
    let seen = |axis: usize| {
        let edges = if axis == 0 { &d.x_edges } else { &d.v_edges };
        let reach = (0..n * m)
            .filter(|&k| d.slip[k] > 1e-3 * top)
            .map(|k| if axis == 0 { k / m } else { k % m })
            .map(|i| edges[i].abs().max(edges[i + 1].abs()))
            .fold(0.0, f64::max);
        Some((-reach, reach))
    };
    let plane = Panel {
        title: "while slipping".into(),
        x_range: seen(0),
        y_range: seen(1),
        x_label: "x [m]".into(),
        y_label: "velocity [m/s]".into(),
        heat,
        heat_label: "density [1/(m m/s)]".into(),
        ..Default::default()
    };
    let sticks = Panel {
        title: "while stuck (on the belt)".into(),
        x_label: "x [m]".into(),
        y_label: "density [1/m]".into(),
        lines: vec![line(0, format!("velocity = +{} m/s", d.velocities[0]), 0), line(1, format!("velocity = {} m/s", d.velocities[1]), 1)],
        ..Default::default()
    };
    Figure {
        name: "stationary_density".into(),
        title: "Stationary law of the state (x, velocity), without sampling".into(),
        rows: 1,
        cols: 2,
        size: (1400, 620),
        panels: vec![plane, sticks],
    }
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
            m += &format!(" {} |", crate::figures::format::six_decimals(l.values[q]));
        }
        m += &format!(" {} | {:.1e} |\n", crate::figures::format::six_decimals(est[q].0), est[q].1);
    }
    m
}
