//! `stickslip predict`: the next stick from a given state — the time to its start, its duration,
//! the slip after it and whether it ends by breakaway — computed without sampling where the
//! scene allows ([`crate::law::passage`]: Coulomb friction with or without a dashpot, the symmetric or telegraph belt,
//! fixed parameters) and by conditional Monte Carlo everywhere: futures simulated from the same
//! state with the scenario's solver (the same realizations, seeds and generator as `simulate`,
//! from the point initial condition and the belt in the given state).

use std::path::Path;

use rayon::prelude::*;

use crate::law::flow::{Frame, Slip};
use crate::law::passage::{self, Start};
pub use crate::law::LawError;
use crate::observables::Statistic;
use crate::outdir::{Kind, StagedDir};
use crate::scenario::{Scenario, ScenarioError};
use crate::simulation::belt::{InitialSign, Process};
use crate::simulation::ensemble::Outcome;
use crate::simulation::events::StickEnd;
use crate::stats::Moments;
use crate::table::{table, Col, Table};

/// The state a prediction starts from, in the lab frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// x, m
    pub x: f64,
    /// ẋ, m/s
    pub velocity: f64,
    /// the belt's velocity, m/s: one of its states' (±v0; +v_f or −v_r for a telegraph belt)
    pub belt: f64,
    /// the mass is stuck (ẋ equals the belt's velocity and the spring holds)
    pub stuck: bool,
}

/// The predicted variables, in the names of `prediction.parquet`.
pub const VARIABLES: [&str; 5] = crate::observables::names(crate::observables::Statistic::PREDICTED);

/// One row of the prediction: a variable's mean and variance by one method.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// one of [`VARIABLES`]: `remaining_stick` R (stuck starts), `time_to_stick` τ (to the next
    /// stick's start), `stick_duration` D (of that stick), `slip_duration` H (of the slip after
    /// it, to the stick after that), `breakaway` (1 if that stick ends by breakaway, else 0: its
    /// mean is the probability)
    pub variable: &'static str,
    /// `exact` or `monte_carlo`
    pub method: &'static str,
    /// the mean (s; for `breakaway` the probability)
    pub mean: f64,
    /// the variance (s²)
    pub variance: f64,
    /// exact: the estimated discretisation error of the mean; Monte Carlo: its standard error
    pub error: f64,
    /// the same for the variance (Monte Carlo: from the fourth central moment; NaN below 4 futures)
    pub variance_error: f64,
    /// Monte Carlo: the futures that reached this variable (the others were cut by the horizon)
    pub futures: Option<u64>,
}

/// What to compute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// the exact method's finest resolution (three resolutions, as `exact-law`)
    pub resolution: u32,
    /// conditional Monte Carlo futures (None: only when the exact method does not hold, then
    /// [`DEFAULT_FUTURES`])
    pub futures: Option<u64>,
    /// the futures' horizon, s (None: [`default_horizon`])
    pub horizon: Option<f64>,
    /// the finest resolution of the exact densities of τ and H (None: not computed;
    /// [`crate::law::densities::predicted`])
    pub densities: Option<u32>,
}

/// Futures simulated when the exact method does not hold and `--futures` is not given.
pub const DEFAULT_FUTURES: u64 = 100_000;

/// What `predict` found: the rows, why the exact method was not used (if it was not), the
/// futures cut by the horizon before their slip ended, and the horizon.
#[derive(Debug, Clone)]
pub struct Prediction {
    /// exact rows first, then Monte Carlo's
    pub rows: Vec<Row>,
    /// why the exact method does not hold (None: it ran)
    pub exact_refused: Option<String>,
    /// futures whose slip after the next stick had not ended at the horizon
    pub censored: u64,
    /// the futures' horizon, s
    pub horizon: f64,
    /// the exact law of each stick's duration from the state, at each resolution
    survival: Option<Vec<crate::law::sticks::SurvivalRow>>,
    /// the exact densities of τ and H (with `--densities`)
    densities: Option<Vec<crate::law::densities::DensityRow>>,
}

impl Prediction {
    /// Its tables, with their definitions (what `--out` holds): `prediction.parquet`, and where
    /// the exact method ran `stick_survival.parquet`, with `--densities` `densities.parquet`.
    pub fn tables(&self) -> Vec<(&'static crate::table::Def, Table)> {
        let mut out = vec![(&prediction::DEF, table(&self.rows))];
        out.extend(self.survival.as_ref().map(|s| (&STICK_SURVIVAL, crate::law::tables::survival(s))));
        out.extend(self.densities.as_ref().map(|d| (&DENSITIES, crate::law::tables::densities(d))));
        out
    }
}

/// Two velocities equal but for rounding (1e-9 relative): a typed belt or mass velocity names
/// the belt state's exact one.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The belt state of velocity `v` (+1 forward, −1 reverse) and that state's exact velocity
/// ([`same`]), or why there is none.
fn belt_state(process: &Process, v: f64) -> Result<(i32, f64), String> {
    let Some(t) = process.two_state() else {
        return Err(format!(
            "the belt is \"{}\": predict needs a two-state belt (symmetric or telegraph), whose state the belt velocity names",
            process.name()
        ));
    };
    let (forward, reverse) = (t.forward_speed, t.reverse_speed);
    if same(v, forward) {
        Ok((1, forward))
    } else if same(v, -reverse) {
        Ok((-1, -reverse))
    } else {
        Err(format!("the belt velocity {v} m/s is not a state of this belt (+{forward} or -{reverse} m/s)"))
    }
}

/// The futures' default horizon: 100 mean times between flips (of the slower belt state),
/// between 10 and 10,000 periods 2π/ω of the spring (10,000 s without a spring or flips).
pub fn default_horizon(scenario: &Scenario) -> Result<f64, ScenarioError> {
    let scene = scenario.scene()?;
    let u = scene.params.per_unit_mass();
    let period = if u.omega2 > 0.0 { std::f64::consts::TAU / u.omega2.sqrt() } else { f64::INFINITY };
    let rate = scene.belt.process.two_state().map_or(0.0, |t| t.forward_rate.min(t.reverse_rate));
    let flips = if rate > 0.0 { 100.0 / rate } else { f64::INFINITY };
    Ok(if period.is_finite() {
        flips.clamp(10.0 * period, 1e4 * period)
    } else if flips.is_finite() {
        flips.min(1e6)
    } else {
        1e4
    })
}

/// Predict from `state`; `out` (if given) gets `prediction.parquet` (and the exact
/// `stick_survival.parquet`). `ctl` hears what is being done (notes) and is asked between the
/// parts.
pub fn run(scenario: &Scenario, state: State, opts: Options, out: Option<&Path>, ctl: crate::progress::Control) -> Result<Prediction, LawError> {
    let progress = |line: &str| ctl.progress.note(line);
    let scene = scenario.scene()?;
    if scene.chain.is_some() {
        return Err(LawError::Refused(crate::chain::NO_CLOSED_LAW.into()));
    }
    if !(state.x.is_finite() && state.velocity.is_finite() && state.belt.is_finite()) {
        let shown = crate::scenario::short;
        return Err(LawError::Refused(format!("--state {},{},{}: must be three finite numbers", shown(state.x), shown(state.velocity), shown(state.belt))));
    }
    use crate::simulation::keys::Key;
    if let Some((key, _)) = scene.random.iter().find(|(k, _)| matches!(k, Key::Speed | Key::ReverseSpeed)) {
        return Err(LawError::Refused(format!("{} is drawn per realization: a belt velocity names no state", key.dotted())));
    }
    let (sign, belt) = belt_state(&scene.belt.process, state.belt).map_err(LawError::Refused)?;
    // the state on the belt's exact velocity (and a mass velocity that matches it, on it too)
    let state = State { belt, velocity: if same(state.velocity, belt) { belt } else { state.velocity }, ..state };
    if state.stuck && state.velocity != state.belt {
        return Err(LawError::Refused(format!(
            "--stuck: the mass velocity {} must equal the belt velocity {} (a stuck mass moves with the belt)",
            state.velocity, state.belt
        )));
    }
    stuck_or_not(&scene, state, sign).map_err(LawError::Refused)?;
    // the flags and the futures' scenario checked before anything runs (the exact part takes
    // seconds), each refusal naming its flag
    let horizon = match opts.horizon {
        Some(h) => h,
        None => default_horizon(scenario)?,
    };
    let (lo, hi) = crate::scenario::DURATION_RANGE;
    if !(horizon >= lo && horizon <= hi) {
        return Err(LawError::Refused(format!("--horizon {}: must be between {lo:e} and {hi:e} s", crate::scenario::short(horizon))));
    }
    if let Some(n) = opts.futures.filter(|&n| n == 0 || n > crate::scenario::MAX_REALIZATIONS) {
        return Err(LawError::Refused(format!("--futures {n}: must be between 1 and {}", crate::scenario::MAX_REALIZATIONS)));
    }
    let futures_scenario = futures_scenario(scenario, state, sign, opts.futures.unwrap_or(DEFAULT_FUTURES), horizon)?;
    let staged = out.map(|o| StagedDir::new(o, Kind::Predict, "--out", &[])).transpose()?;
    let mut rows = Vec::new();
    let mut survival = None;
    // exact, where the scene allows
    let exact = crate::law::frames(&scene).and_then(|f| {
        let ladder = crate::law::ladder(&f, opts.resolution, crate::law::LEVELS)?;
        // the symmetric belt's one frame holds both signs; the telegraph's reverse state is its second
        let at = if sign > 0 { 0 } else { f.len() - 1 };
        exact_start(f[at], state, sign).map(|s| (f, ladder, at, s))
    });
    let exact_refused = exact.as_ref().err().cloned();
    if opts.densities.is_some() && (out.is_none() || exact.is_err()) {
        let why = exact
            .as_ref()
            .err()
            .map_or("it needs --out DIR (it writes DIR/densities.parquet)".to_string(), |e| format!("the exact method does not hold here ({e})"));
        return Err(LawError::Refused(format!("--densities: {why}")));
    }
    let mut densities = None;
    if let Ok((frames, ladder, at, start)) = exact {
        ctl.check()?;
        progress("exact: three resolutions");
        let (r, s) = exact_rows(&frames, &ladder, at, start).map_err(LawError::Failed)?;
        if let Some(n) = opts.densities {
            ctl.check()?;
            progress("exact densities of the time to the next stick and of the slip after it: three resolutions");
            densities = Some(density_rows(&frames, n, at, start, &r).map_err(LawError::Failed)?);
        }
        rows.extend(r);
        survival = Some(s);
    }
    let futures = opts.futures.or(if exact_refused.is_some() { Some(DEFAULT_FUTURES) } else { None });
    let mut censored = 0;
    if let Some(n) = futures {
        ctl.check()?;
        progress(&format!("conditional Monte Carlo: {n} futures over {} s", crate::scenario::short(horizon)));
        let (r, c) = monte_carlo(&futures_scenario, state.stuck, n)?;
        rows.extend(r);
        censored = c;
    }
    let prediction = Prediction { rows, exact_refused, censored, horizon, survival, densities };
    if let Some(staged) = staged {
        let werr = |name: &str, e: &dyn std::fmt::Display| LawError::Write { path: staged.path().join(name), message: e.to_string() };
        for (def, t) in prediction.tables() {
            def.check(&t).map_err(|e| werr(def.file, &e))?;
            t.write_parquet(&staged.path().join(def.file)).map_err(|e| werr(def.file, &e))?;
        }
        staged.commit()?;
    }
    Ok(prediction)
}

/// Whether --stuck agrees with the state: a stuck mass moves with the belt and the spring (and
/// damper) force k x + c v stays within the holding limit μ_s n (in the belt's frame, as the
/// solvers: −μ_s n ≤ s (k x + c v) < μ_s n). Scenes with drawn parameters are checked per
/// future instead.
fn stuck_or_not(scene: &crate::simulation::keys::Scene, state: State, sign: i32) -> Result<(), String> {
    if !scene.random.is_empty() {
        return Ok(());
    }
    let u = scene.params.per_unit_mass();
    let force = f64::from(sign) * (u.omega2 * state.x + u.gamma * state.belt);
    let held = (-u.breakaway..u.breakaway).contains(&force);
    let m = scene.params.mass;
    match (state.stuck, held && state.velocity == state.belt) {
        (true, _) if !held => Err(format!(
            "--stuck at x = {}: the spring and damper force {:.6e} N exceeds the holding limit mu_s n = {:.6e} N: the mass slips at once",
            state.x,
            force.abs() * m,
            u.breakaway * m
        )),
        (false, true) => Err(format!("the mass moves with the belt at x = {} within the holding limit: it is stuck (add --stuck)", state.x)),
        _ => Ok(()),
    }
}

/// The start in the belt's frame (the belt at +v0: X = s x, V = s ẋ for the belt state s), or
/// why the exact method cannot start from it.
fn exact_start(frame: Frame, state: State, sign: i32) -> Result<Start, String> {
    let s = f64::from(sign);
    let (x, v) = (s * state.x, s * state.velocity);
    let start = if state.stuck { Start::Stuck(x) } else { Start::Slip(Slip::at(x, v, frame.v0)) };
    // the grid's box grows with the start's amplitude; far out, the grid would be huge
    let (half, base) = (passage::half_width(frame, start), frame.box_half());
    if half > 10.0 * base {
        return Err(format!("the state lies {:.1} times further out than the motion settles (the exact method's grid would not hold it)", half / base));
    }
    Ok(start)
}

/// The exact rows from three resolutions (extrapolated, with the error estimate), and the stick
/// duration's law, as `exact-law`'s D_1 ([`crate::law::sticks::survival_rows`]).
fn exact_rows(frames: &[Frame], ladder: &[crate::law::Rung], at: usize, start: Start) -> Result<(Vec<Row>, Vec<crate::law::sticks::SurvivalRow>), String> {
    let half = frames.iter().map(|f| f.box_half()).fold(passage::half_width(frames[at], start), f64::max);
    let mut solved = Vec::new();
    for (_, h) in ladder {
        solved.push((h[0], passage::sequence(frames, h, half, &[(at, start, 1.0)], 1)?));
    }
    let pick =
        |f: &dyn Fn(&passage::Sequence) -> f64| crate::law::guarded(&solved.iter().map(|(h, s)| (*h, f(s))).collect::<Vec<_>>(), crate::law::Order::Irregular);
    let mut rows = Vec::new();
    let mut row = |variable: &'static str, mean: &dyn Fn(&passage::Sequence) -> f64, variance: &dyn Fn(&passage::Sequence) -> f64| {
        let ((m, e), (v, ve)) = (pick(mean), pick(variance));
        rows.push(Row { variable, method: "exact", mean: m, variance: v.max(0.0), error: e, variance_error: ve, futures: None });
    };
    if matches!(start, Start::Stuck(_)) {
        row(Statistic::RemainingStick.name(), &|s| s.current.unwrap().0, &|s| s.current.unwrap().1);
    }
    row(Statistic::TimeToStick.name(), &|s| s.sticks[0].start.0, &|s| s.sticks[0].start.1);
    row(Statistic::StickDuration.name(), &|s| s.sticks[0].duration.0, &|s| s.sticks[0].duration.1);
    row(Statistic::SlipDuration.name(), &|s| s.sticks[0].slip.0, &|s| s.sticks[0].slip.1);
    row(Statistic::Breakaway.name(), &|s| s.sticks[0].breakaway, &|s| s.sticks[0].breakaway * (1.0 - s.sticks[0].breakaway));
    let survival = crate::law::sticks::survival_rows(frames, &solved, &crate::law::density::survival_times(frames, &[]), crate::law::Order::Irregular);
    Ok((rows, survival))
}

/// The densities of τ and H from `start` ([`crate::law::densities::predicted`]) at three
/// resolutions up to `finest`, on [`crate::law::densities::GRID`] cells of [0, c], c the
/// larger mean plus six standard deviations of the two (from the exact `rows`), the series'
/// half-period the larger mean plus ten.
fn density_rows(frames: &[Frame], finest: u32, at: usize, start: Start, rows: &[Row]) -> Result<Vec<crate::law::densities::DensityRow>, String> {
    let reach = |sds: f64| {
        rows.iter()
            .filter(|r| [Statistic::TimeToStick.name(), Statistic::SlipDuration.name()].contains(&r.variable))
            .map(|r| r.mean + sds * r.variance.sqrt())
            .fold(0.0, f64::max)
    };
    let (cells, half_period) = (reach(6.0), reach(10.0));
    let ladder = crate::law::ladder(frames, finest, crate::law::LEVELS)?;
    let half = frames.iter().map(|f| f.box_half()).fold(passage::half_width(frames[at], start), f64::max);
    let levels = ladder
        .iter()
        .map(|(_, h)| Ok((h[0], crate::law::densities::predicted(frames, h, half, at, start, half_period)?)))
        .collect::<Result<Vec<_>, String>>()?;
    let grid = crate::law::densities::GRID;
    let edges: Vec<f64> = (0..=grid).map(|g| cells * g as f64 / grid as f64).collect();
    Ok(crate::law::densities::rows_on(&levels, half_period, &edges, crate::law::Order::Irregular))
}

/// One future's values (None: not reached within the horizon).
#[derive(Debug, Clone, Copy, Default)]
struct Future {
    remaining: Option<f64>,
    to_stick: Option<f64>,
    stick: Option<f64>,
    slip: Option<f64>,
    breakaway: Option<f64>,
}

/// Futures per parallel chunk (fixed: the rows do not depend on the threads).
const CHUNK: u64 = 1024;

/// The scenario of the futures: the point initial state, the belt in its state, the window the
/// horizon and `n` realizations, checked (a state the solvers are not proven on is refused
/// naming `--state`).
fn futures_scenario(scenario: &Scenario, state: State, sign: i32, n: u64, horizon: f64) -> Result<Scenario, LawError> {
    let mut s = scenario.clone();
    s.initial_conditions.position = [state.x; 2];
    s.initial_conditions.velocity = [state.velocity; 2];
    s.belt.initial_sign = crate::scenario::Sign(if sign > 0 { InitialSign::Positive } else { InitialSign::Negative });
    s.run.duration = horizon;
    s.run.realizations = n;
    s.check().map_err(|e| {
        let shown = |x: f64| crate::scenario::short(x);
        match e {
            ScenarioError::Invalid { key, reason, .. } if key.starts_with("initial_conditions") => {
                LawError::Refused(format!("--state {},{},{}: {reason}", shown(state.x), shown(state.velocity), shown(state.belt)))
            }
            e => LawError::Refused(format!("the futures' scenario: {e}")),
        }
    })?;
    Ok(s)
}

/// The conditional Monte Carlo rows from `n` futures, and how many were cut by the horizon.
fn monte_carlo(s: &Scenario, stuck: bool, n: u64) -> Result<(Vec<Row>, u64), LawError> {
    let ensemble = s.ensemble()?;
    // per chunk, the moments of each variable (in the order of VARIABLES) and the futures cut by
    // the horizon; merged in chunk order (the same for any number of threads), nothing per future
    // kept
    type Sums = ([Moments; 5], u64);
    let chunks: Vec<Result<Sums, LawError>> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut out = Outcome::default();
            let mut sums: Sums = Default::default();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                ensemble.realization(i, &mut out).map_err(|e| LawError::Failed(e.to_string()))?;
                let f = future(&out, stuck)?;
                for (m, x) in sums.0.iter_mut().zip([f.remaining, f.to_stick, f.stick, f.slip, f.breakaway]) {
                    if let Some(x) = x {
                        m.add(x);
                    }
                }
                sums.1 += u64::from(f.slip.is_none());
            }
            Ok(sums)
        })
        .collect();
    let mut all: Sums = Default::default();
    for c in chunks {
        let c = c?;
        all.0.iter_mut().zip(&c.0).for_each(|(a, b)| *a = a.merge(b));
        all.1 += c.1;
    }
    let rows = VARIABLES
        .iter()
        .zip(&all.0)
        .filter_map(|(&variable, m)| {
            let (variance, error) = (m.variance()?, m.mean_se()?);
            Some(Row {
                variable,
                method: "monte_carlo",
                mean: m.mean,
                variance,
                error,
                variance_error: m.variance_se().unwrap_or(f64::NAN),
                futures: Some(m.n),
            })
        })
        .collect();
    Ok((rows, all.1))
}

/// A future's values from its record; an error if the simulated start disagrees with --stuck.
fn future(out: &Outcome, stuck: bool) -> Result<Future, LawError> {
    let r = &out.record;
    let started_stuck = r.stick_start.first() == Some(&0.0);
    if started_stuck != stuck {
        // (the scene's parameters are drawn: the state sticks for some of them and not others)
        return Err(LawError::Refused(if stuck {
            "--stuck: with the parameters drawn for a future the force exceeds the holding limit (the mass slips at once)".into()
        } else {
            "the mass moves with the belt within the holding limit of the parameters drawn for a future: it is stuck (add --stuck)".into()
        }));
    }
    // the index of the next stick: the first, or the one after the current
    let k = usize::from(stuck);
    let done = |i: usize| r.stick_end.get(i).filter(|e| **e != StickEnd::Horizon);
    let mut f = Future { remaining: if stuck { done(0).map(|_| r.stick_duration[0]) } else { None }, ..Future::default() };
    f.to_stick = r.stick_start.get(k).copied();
    f.stick = done(k).map(|_| r.stick_duration[k]);
    f.breakaway = done(k).map(|e| if *e == StickEnd::Breakaway { 1.0 } else { 0.0 });
    // the slip after stick k ended in stick k + 1
    f.slip = r.stick_start.get(k + 1).map(|_| r.slip_duration[k]);
    Ok(f)
}

/// `stick_survival.parquet` of `predict`: exact-law's `survival.parquet` columns, of the sticks
/// from the state.
pub const STICK_SURVIVAL: crate::table::Def = crate::table::Def {
    file: "stick_survival.parquet",
    meaning: "P(D_k > t) of the k-th stick from the state, exact (the columns of exact-law's survival.parquet)",
    columns: crate::law::defs::survival::DEF.columns,
};

/// `densities.parquet` of `predict` (with `--densities`): exact-law's `densities.parquet`
/// columns, of τ and H from the state.
pub const DENSITIES: crate::table::Def = crate::table::Def {
    file: "densities.parquet",
    meaning: "the densities of the time to the next stick and of the slip after it (the columns of exact-law's densities.parquet)",
    columns: crate::law::defs::densities::DEF.columns,
};

table! {
    /// `prediction.parquet`: one row per (variable, method).
    prediction = "prediction.parquet", "the next stick from a state: mean and variance of each variable, exact and by conditional Monte Carlo" {
        VARIABLE: "variable", Str, "time_to_stick, stick_duration, slip_duration or breakaway";
        METHOD: "method", Str, "exact or monte_carlo";
        MEAN: "mean", Float, "the mean [s; a probability for breakaway]";
        VARIANCE: "variance", Float, "the variance [s²]";
        ERROR: "error", Float, "error of the mean (the extrapolation's, or the standard error)";
        VARIANCE_ERROR: "variance_error", Float, "error of the variance (null where undefined)";
        FUTURES: "futures", Int, "Monte Carlo futures (null for exact)";
    }
}

/// `prediction.parquet`: variable, method, mean, variance, error, variance_error (null where
/// undefined), futures.
fn table(rows: &[Row]) -> Table {
    let mut t = Table::default();
    t.put(&prediction::VARIABLE, Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .put(&prediction::METHOD, Col::Str(rows.iter().map(|r| r.method.to_string()).collect()))
        .put(&prediction::MEAN, Col::Float(rows.iter().map(|r| Some(r.mean)).collect()))
        .put(&prediction::VARIANCE, Col::Float(rows.iter().map(|r| Some(r.variance)).collect()))
        .put(&prediction::ERROR, Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .put(&prediction::VARIANCE_ERROR, Col::Float(rows.iter().map(|r| Some(r.variance_error).filter(|e| e.is_finite())).collect()))
        .put(&prediction::FUTURES, Col::Int(rows.iter().map(|r| r.futures.map(|n| n as i64)).collect()));
    t
}

/// The table `predict` prints: per variable, the exact mean and standard deviation with the
/// discretisation error, and the Monte Carlo mean ± 1.96 standard errors.
pub fn markdown(p: &Prediction) -> String {
    let mut m = String::from("| variable | method | mean | sd | error of the mean | futures |\n|---|---|---:|---:|---:|---:|\n");
    for v in VARIABLES {
        for r in p.rows.iter().filter(|r| r.variable == v) {
            let (error, n) = match r.futures {
                Some(n) => (format!("± {:.2e} (95 %)", 1.96 * r.error), n.to_string()),
                None => (format!("{:.1e}", r.error), String::new()),
            };
            let six = crate::figures::format::six_decimals;
            m += &format!("| {} | {} | {} | {} | {error} | {n} |\n", r.variable, r.method.replace('_', " "), six(r.mean), six(r.variance.sqrt()));
        }
    }
    m
}
