//! The `tradeoff` stage: the same realizations through every solver over a ladder of settings,
//! measured against a reference, and the cheapest setting that is accurate enough.
//!
//! Every setting runs realizations 0..n of the scenario (same belt switches, same initial
//! conditions: the random draws do not depend on the solver) on one thread, timed. The reference
//! is `exact` where the scene has closed forms; otherwise rk45 at rtol = atol = 1e-14, accepted
//! only if rk45 at 1e-13 gives the same events on every realization within [`REFERENCE_AGREEMENT`]
//! (shown converged, or the stage fails). Why that tight: velocity weakening makes the approach
//! to belt speed unstable — as u → 0 the friction grows, which pulls u to 0 faster, at a rate up
//! to (μ_s − μ_k) n / (m v_s) for δ = 1 (59 /s for μ_s − μ_k = 0.3, v_s = 0.05) — so a state
//! error can grow a few hundredfold before the stick, and an event time errs by ~300× the
//! tolerance (seen: 2.2e-8 s at 1e-11, 3.4e-9 s at 1e-12, 3e-10 s at 1e-13, 2.4e-11 s at 1e-14,
//! against 1e-15). The difference of two tolerances a decade apart bounds the looser one's
//! error, so the reference at 1e-14 is within about a tenth of that difference.
//!
//! Stick and slip starts are matched to the reference's in time order (two pointers, window
//! [`MATCH_WINDOW`]): unmatched reference sticks are *missed*, unmatched other ones *spurious*;
//! matched ones give the event-time error.
//!
//! **The question users ask** — which is the cheapest setting whose bias is below a fraction of
//! the Monte Carlo standard error at my N? For each setting and each Table 1 statistic s
//! (E T_k, E D_k, E L_k, E H_k for k ≤ 6, E S_T, E S_L, as [`crate::observables`] defines them:
//! a duration cut at t_a is censored, left out): bias_s = mean_setting − mean_reference
//! over the same realizations, and SE_s = sd_reference / √(N · p_s) the standard error of the
//! mean at the scenario's `run.realizations` N (p_s: the fraction of realizations that have the
//! k-th interval). The setting's score is max_s |bias_s| / SE_s; the recommendation is the
//! cheapest setting scoring below `--bias-fraction` (default 0.1). "Cheapest" is counted, not
//! timed, so that the same inputs give the same answer on a loaded machine: `exact` first where
//! the scene has it (no integration at all), then the fewest right-hand-side evaluations per
//! realization ([`SolverKind::evaluations_per_step`] × attempted steps), ties in ladder order.
//! The measured CPU time is reported beside it. With fewer than [`MIN_REALIZATIONS`]
//! realizations no standard error can be estimated: the score is empty and nothing is
//! recommended.
//!
//! Output: `DIR/tradeoff.parquet`, one row per (solver, setting) with `max_bias_over_se` and
//! `recommended`, and the work-precision plot `DIR/work_precision.{png,svg}` (log10 RMS
//! event-time error against log10 CPU time per realization, the recommendation marked).

use std::path::Path;
use std::time::Instant;

use crate::figures::{render, Figure, Panel, Series};
use crate::observables::Observable;
use crate::outdir::{Kind, StagedDir};
use crate::scenario::{Numerics, Scenario, ScenarioError};
use crate::simulation::ensemble::{Outcome, RunError};
use crate::solver::SolverKind;
use crate::table::{table, Col, Table};

/// Largest time difference [s] at which a numerical event is matched to an exact one.
pub const MATCH_WINDOW: f64 = 0.05;

/// The two tight rk45 runs must agree to this on every event [s] for the reference to count.
pub const REFERENCE_AGREEMENT: f64 = 1e-9;

/// The default `--bias-fraction`.
pub const BIAS_FRACTION: f64 = 0.1;

/// One rung of the ladder: a solver, its setting's label and parameter, and the numerics it sets.
pub struct Setting {
    /// the solver the setting runs
    pub solver: SolverKind,
    /// the setting, as shown (e.g. `rtol=atol=1e-6`)
    pub label: String,
    /// the setting's number: the tolerance (rk45, dop853), the step [s] (rk4, moreau), ε = stick_velocity
    /// [m/s] (smooth); 0 for exact
    pub parameter: f64,
    /// set the setting on a scenario's `[numerics]`
    pub apply: Box<dyn Fn(&mut Numerics)>,
}

/// The ladder: exact, then every numerical solver over its settings.
pub fn ladder(duration: f64) -> Vec<Setting> {
    let rung = |solver, label: String, parameter, apply: Box<dyn Fn(&mut Numerics)>| Setting { solver, label, parameter, apply };
    let mut out = vec![rung(SolverKind::Exact, "exact".into(), 0.0, Box::new(|_| {}))];
    // rk45 at rtol = atol = tol, with the step limit `max_step` (t_a: none)
    let rk45 = |label: String, tol: f64, max_step: f64| {
        rung(SolverKind::Rk45, label, tol, Box::new(move |n: &mut Numerics| (n.rtol, n.atol, n.max_step) = (tol, tol, max_step)))
    };
    for tol in [1e-3, 1e-6, 1e-9] {
        out.push(rk45(format!("rtol=atol={tol:e}"), tol, duration));
    }
    out.push(rk45("rtol=atol=1e-6, max_step=1e-4".into(), 1e-6, 1e-4));
    out.push(rk45("paper ode45: rtol=atol=1e-9, max_step=1e-4".into(), 1e-9, 1e-4));
    // dop853, the accurate end: down to 1e-12
    for tol in [1e-3, 1e-6, 1e-9, 1e-12] {
        out.push(rung(
            SolverKind::Dop853,
            format!("rtol=atol={tol:e}"),
            tol,
            Box::new(move |n: &mut Numerics| (n.rtol, n.atol, n.max_step) = (tol, tol, duration)),
        ));
    }
    for solver in [SolverKind::Rk4, SolverKind::Moreau] {
        for h in [1e-2, 1e-3, 1e-4] {
            out.push(rung(solver, format!("step={h:e}"), h, Box::new(move |n: &mut Numerics| n.step = h)));
        }
    }
    for eps in [1e-2, 1e-3, 1e-4] {
        out.push(rung(
            SolverKind::Smooth,
            format!("epsilon=stick_velocity={eps:e}, rtol=1e-6"),
            eps,
            Box::new(move |n: &mut Numerics| (n.epsilon, n.stick_velocity, n.rtol, n.atol, n.max_step) = (eps, eps, 1e-6, 1e-6, duration)),
        ));
    }
    out
}

/// Matching of one realization's event times against exact: (errors, missed, spurious).
pub fn match_events(exact: &[f64], other: &[f64]) -> (Vec<f64>, u64, u64) {
    let (mut i, mut j) = (0, 0);
    let (mut errors, mut missed, mut spurious) = (Vec::new(), 0, 0);
    while i < exact.len() && j < other.len() {
        let d = other[j] - exact[i];
        if d.abs() <= MATCH_WINDOW {
            errors.push(d);
            i += 1;
            j += 1;
        } else if d < 0.0 {
            spurious += 1;
            j += 1;
        } else {
            missed += 1;
            i += 1;
        }
    }
    (errors, missed + (exact.len() - i) as u64, spurious + (other.len() - j) as u64)
}

/// Why `tradeoff` failed.
#[derive(Debug, thiserror::Error)]
pub enum TradeoffError {
    /// The scenario, or a setting applied to it, is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The caller cancelled the run (Ctrl-C in a Python session).
    #[error("interrupted")]
    Cancelled(#[from] crate::progress::Cancelled),
    /// A realization could not be solved under a setting.
    #[error("{solver} ({setting}): {source}")]
    Run {
        /// the solver's name
        solver: String,
        /// the setting's label
        setting: String,
        /// the realization and why it failed
        source: RunError,
    },
    /// Writing an output file failed.
    #[error("writing {}: {message}", path.display())]
    Write {
        /// the file
        path: std::path::PathBuf,
        /// what went wrong
        message: String,
    },
    /// The output directory could not be staged or replaced.
    #[error(transparent)]
    Out(#[from] crate::outdir::OutDirError),
    /// The rk45 reference at 1e-13 and 1e-14 disagree (a scene without closed forms).
    #[error("the reference is not converged: rk45 at rtol = atol = 1e-13 and 1e-14 differ on realization {realization} ({detail}); the scene may be too stiff for an explicit method (a very small model.stribeck_velocity?)")]
    Reference {
        /// the first realization on which they differ
        realization: u64,
        /// what differs
        detail: String,
    },
}

impl crate::blame::Blame for TradeoffError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            TradeoffError::Scenario(_) => Some(crate::blame::Culprit::Scenario),
            TradeoffError::Out(o) => o.blame(),
            TradeoffError::Run { .. } | TradeoffError::Write { .. } | TradeoffError::Reference { .. } | TradeoffError::Cancelled(_) => None,
        }
    }
}

/// Fewest realizations whose spread estimates a standard error (below it: no score, no
/// recommendation).
pub const MIN_REALIZATIONS: u64 = 10;

/// One measured setting.
#[derive(Debug, Clone)]
pub struct Row {
    /// the solver's name (`run.solver`)
    pub solver: &'static str,
    /// the setting's label
    pub setting: String,
    /// the setting's number (see [`Setting::parameter`])
    pub parameter: f64,
    /// time per realization [s], solving only, on one thread
    pub seconds_per_realization: f64,
    /// right-hand-side evaluations per realization, counted (the ranking's cost)
    pub evaluations_per_realization: f64,
    /// largest |event-time error| over the matched stick and slip starts [s]
    /// (`event_time_error_max`)
    pub error_max: f64,
    /// RMS event-time error over the matched stick and slip starts [s] (`event_time_error_rms`)
    pub error_rms: f64,
    /// stick and slip starts matched to the reference's (`matched_events`)
    pub matched: u64,
    /// reference sticks without a match
    pub missed_sticks: u64,
    /// sticks without a match in the reference
    pub spurious_sticks: u64,
    /// largest |bias| of E T_k over k = 1..6 [s] (`bias_mean_T_k_max`)
    pub bias_t: f64,
    /// bias of the mean of D_1..D_6 pooled, censored ones left out [s] (`bias_mean_D`)
    pub bias_d: f64,
    /// bias of the mean of H_1..H_6 pooled, censored ones left out [s] (`bias_mean_H`)
    pub bias_h: f64,
    /// bias of E S_T (`bias_mean_S_T`)
    pub bias_st: f64,
    /// max over the Table 1 statistics of |bias| / (Monte Carlo SE at run.realizations); None
    /// with fewer than [`MIN_REALIZATIONS`]
    pub max_bias_over_se: Option<f64>,
    /// the cheapest setting with `max_bias_over_se` below `--bias-fraction`
    pub recommended: bool,
}

/// What running one setting gave: the records of realizations 0..n, the CPU seconds per
/// realization of solving them alone (keeping the records is not timed) and the counted
/// right-hand-side evaluations per realization.
struct Measured {
    records: Vec<Outcome>,
    seconds: f64,
    evaluations: f64,
}

fn run_all(sc: &Scenario, n: u64) -> Result<Measured, TradeoffError> {
    let ens = sc.ensemble()?;
    let mut out = Outcome::default();
    let (mut seconds, mut steps) = (0.0, 0u64);
    let mut records = Vec::with_capacity(n as usize);
    for i in 0..n {
        let start = Instant::now();
        ens.realization(i, &mut out).map_err(|source| TradeoffError::Run { solver: sc.solver().name().into(), setting: String::new(), source })?;
        seconds += start.elapsed().as_secs_f64();
        steps += out.steps;
        records.push(out.clone());
    }
    let per = |x: f64| x / n.max(1) as f64;
    Ok(Measured { records, seconds: per(seconds), evaluations: per((steps * sc.solver().evaluations_per_step()) as f64) })
}

/// The mean over `records` of the values of `quantities` (pooled: every realization's value of
/// each quantity it has), 0 without any.
fn pooled(records: &[Outcome], quantities: &[Observable]) -> f64 {
    let v: Vec<f64> = records.iter().flat_map(|r| quantities.iter().filter_map(move |q| q.value(r))).collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// max over the Table 1 statistics ([`Observable::table1`]) of |mean(records) − mean(reference)|
/// / SE at `n_run` realizations.
fn bias_over_se(records: &[Outcome], reference: &[Outcome], n_run: u64) -> f64 {
    let mut worst: f64 = 0.0;
    for q in Observable::table1() {
        let r: Vec<f64> = reference.iter().filter_map(|x| q.value(x)).collect();
        let o: Vec<f64> = records.iter().filter_map(|x| q.value(x)).collect();
        if r.len() < 2 || o.is_empty() {
            continue;
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (mr, mo) = (mean(&r), mean(&o));
        let var = r.iter().map(|x| (x - mr) * (x - mr)).sum::<f64>() / (r.len() - 1) as f64;
        let n_stat = n_run as f64 * r.len() as f64 / reference.len() as f64;
        let se = (var / n_stat).sqrt();
        let bias = (mo - mr).abs();
        worst = worst.max(if se > 0.0 {
            bias / se
        } else if bias > 0.0 {
            f64::INFINITY
        } else {
            0.0
        });
    }
    worst
}

/// The reference records: exact, or rk45 at 1e-14 shown converged against 1e-13 (module docs).
fn reference(base: &Scenario, n: u64) -> Result<(Setting, Measured), TradeoffError> {
    if base.has_closed_forms() {
        let exact = ladder(base.run.duration).into_iter().next().expect("exact is the first rung");
        let mut sc = base.clone();
        sc.run.solver = exact.solver;
        return Ok((exact, run_all(&sc, n)?));
    }
    let tight = |tol: f64| {
        let max_step = 1e-2_f64.min(base.run.duration);
        Setting {
            solver: SolverKind::Rk45,
            label: format!("reference: rtol=atol={tol:e}, max_step={max_step:e}"),
            parameter: tol,
            apply: Box::new(move |n: &mut Numerics| (n.rtol, n.atol, n.max_step, n.peak_guard) = (tol, tol, max_step, true)),
        }
    };
    let run = |s: &Setting| -> Result<Measured, TradeoffError> {
        let mut sc = base.clone();
        sc.run.solver = s.solver;
        (s.apply)(&mut sc.numerics);
        sc.numerics.step_budget = sc.numerics.step_budget.max(1_000_000_000);
        run_all(&sc, n)
    };
    let (check, fine) = (tight(1e-13), tight(1e-14));
    let a = run(&check)?.records;
    let b = run(&fine)?;
    for (i, (x, y)) in a.iter().map(|o| &o.record).zip(b.records.iter().map(|o| &o.record)).enumerate() {
        let detail = if (x.n_stick(), x.n_slip()) != (y.n_stick(), y.n_slip()) {
            Some(format!("S_T {} vs {}, S_L {} vs {}", x.n_stick(), y.n_stick(), x.n_slip(), y.n_slip()))
        } else {
            let worst = x.stick_start.iter().zip(&y.stick_start).chain(x.slip_start.iter().zip(&y.slip_start)).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            (worst > REFERENCE_AGREEMENT).then(|| format!("event times differ by {worst:e} s"))
        };
        if let Some(detail) = detail {
            return Err(TradeoffError::Reference { realization: i as u64, detail });
        }
    }
    Ok((fine, b))
}

/// Measure every setting of the ladder on realizations 0..n of `base`, against the reference;
/// mark the cheapest setting whose [`bias_over_se`] is below `bias_fraction`.
pub fn measure(base: &Scenario, n: u64, bias_fraction: f64, ctl: crate::progress::Control) -> Result<Vec<Row>, TradeoffError> {
    let (reference_setting, measured) = reference(base, n)?;
    let reference = measured.records.clone();
    let mut rows = Vec::new();
    let mut settings: Vec<(Setting, Option<Measured>)> = vec![(reference_setting, Some(measured))];
    settings.extend(ladder(base.run.duration).into_iter().filter(|s| s.solver != SolverKind::Exact).map(|s| (s, None)));
    for (Setting { solver, label: setting, parameter, apply }, done) in settings {
        ctl.check()?;
        let Measured { records, seconds: secs, evaluations } = match done {
            Some(d) => d,
            None => {
                let mut sc = base.clone();
                sc.run.solver = solver;
                apply(&mut sc.numerics);
                sc.check()?;
                run_all(&sc, n).map_err(|e| match e {
                    TradeoffError::Run { solver, source, .. } => TradeoffError::Run { solver, setting: setting.clone(), source },
                    other => other,
                })?
            }
        };
        let solver = solver.name();
        let exact = &reference;
        let (mut errors, mut missed, mut spurious) = (Vec::new(), 0, 0);
        for (e, r) in exact.iter().map(|o| &o.record).zip(records.iter().map(|o| &o.record)) {
            let (err, m, s) = match_events(&e.stick_start, &r.stick_start);
            errors.extend(err);
            (missed, spurious) = (missed + m, spurious + s);
            errors.extend(match_events(&e.slip_start, &r.slip_start).0);
        }
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len().max(1) as f64).sqrt();
        // D_1..D_6 (H_1..H_6) pooled, the censored ones left out (the observables' one rule)
        let durations = |f: fn(u32) -> Observable| (1..=6).map(f).collect::<Vec<_>>();
        rows.push(Row {
            solver,
            setting,
            parameter,
            seconds_per_realization: secs,
            evaluations_per_realization: evaluations,
            error_max: errors.iter().fold(0.0, |m, e| m.max(e.abs())),
            error_rms: rms,
            matched: errors.len() as u64,
            missed_sticks: missed,
            spurious_sticks: spurious,
            bias_t: (1..=6).map(|k| [Observable::StickStart(k)]).map(|q| (pooled(&records, &q) - pooled(exact, &q)).abs()).fold(0.0, f64::max),
            bias_d: pooled(&records, &durations(Observable::StickDuration)) - pooled(exact, &durations(Observable::StickDuration)),
            bias_h: pooled(&records, &durations(Observable::SlipDuration)) - pooled(exact, &durations(Observable::SlipDuration)),
            bias_st: pooled(&records, &[Observable::Sticks]) - pooled(exact, &[Observable::Sticks]),
            max_bias_over_se: (n >= MIN_REALIZATIONS).then(|| bias_over_se(&records, exact, base.run.realizations)),
            recommended: false,
        });
    }
    // counted cost: exact (no integration) first, then the fewest evaluations; `min_by` keeps
    // the first of equals, so ties go to the earlier rung
    let cheapest = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.max_bias_over_se.is_some_and(|b| b < bias_fraction))
        .min_by(|a, b| {
            (a.1.solver != "exact", a.1.evaluations_per_realization)
                .partial_cmp(&(b.1.solver != "exact", b.1.evaluations_per_realization))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .map(|(i, _)| i);
    if let Some(i) = cheapest {
        rows[i].recommended = true;
    }
    Ok(rows)
}

table! {
    /// `tradeoff.parquet`: one row per solver setting.
    tradeoff_table = "tradeoff.parquet", "each solver setting's cost and accuracy against the exact solver on the same realizations" {
        SOLVER: "solver", Str, "the solver (exact, rk45, dop853, rk4, moreau, smooth)";
        SETTING: "setting", Str, "its setting, as words";
        PARAMETER: "parameter", Float, "the setting's number (tolerance, step [s] or regularization [m/s]; 0 for exact)";
        REALIZATIONS: "realizations", Int, "realizations per setting";
        CPU_SECONDS_PER_REALIZATION: "cpu_seconds_per_realization", Float, "CPU time per realization [s]";
        EVALUATIONS_PER_REALIZATION: "evaluations_per_realization", Float, "right-hand-side evaluations per realization";
        EVENT_TIME_ERROR_MAX: "event_time_error_max", Float, "largest event-time error [s]";
        EVENT_TIME_ERROR_RMS: "event_time_error_rms", Float, "RMS event-time error [s]";
        MATCHED_EVENTS: "matched_events", Int, "events matched to the exact ones";
        MISSED_STICKS: "missed_sticks", Int, "exact sticks the setting missed";
        SPURIOUS_STICKS: "spurious_sticks", Int, "sticks the setting found that are not there";
        BIAS_MEAN_T_K_MAX: "bias_mean_T_k_max", Float, "largest bias of E[T_k] [s]";
        BIAS_MEAN_D: "bias_mean_D", Float, "bias of the mean stick duration [s]";
        BIAS_MEAN_H: "bias_mean_H", Float, "bias of the mean slip duration [s]";
        BIAS_MEAN_S_T: "bias_mean_S_T", Float, "bias of E[S_T]";
        MAX_BIAS_OVER_SE: "max_bias_over_se", Float, "the largest Table 1 bias over its standard error at run.realizations";
        RECOMMENDED: "recommended", Int, "1 for the cheapest setting accurate enough, else 0";
    }
}

/// The tables of `n` realizations' rows, with their definitions (what the stage writes).
pub fn tables(rows: &[Row], n: u64) -> Vec<(&'static crate::table::Def, Table)> {
    vec![(&tradeoff_table::DEF, table(rows, n))]
}

/// The rows as a table.
pub fn table(rows: &[Row], n: u64) -> Table {
    let f = |g: &dyn Fn(&Row) -> f64| Col::Float(rows.iter().map(|r| Some(g(r)).filter(|x| x.is_finite())).collect());
    let i = |g: &dyn Fn(&Row) -> u64| Col::Int(rows.iter().map(|r| Some(g(r) as i64)).collect());
    let mut t = Table::default();
    t.put(&tradeoff_table::SOLVER, Col::Str(rows.iter().map(|r| r.solver.to_string()).collect()))
        .put(&tradeoff_table::SETTING, Col::Str(rows.iter().map(|r| r.setting.clone()).collect()))
        .put(&tradeoff_table::PARAMETER, f(&|r| r.parameter))
        .put(&tradeoff_table::REALIZATIONS, i(&|_| n))
        .put(&tradeoff_table::CPU_SECONDS_PER_REALIZATION, f(&|r| r.seconds_per_realization))
        .put(&tradeoff_table::EVALUATIONS_PER_REALIZATION, f(&|r| r.evaluations_per_realization))
        .put(&tradeoff_table::EVENT_TIME_ERROR_MAX, f(&|r| r.error_max))
        .put(&tradeoff_table::EVENT_TIME_ERROR_RMS, f(&|r| r.error_rms))
        .put(&tradeoff_table::MATCHED_EVENTS, i(&|r| r.matched))
        .put(&tradeoff_table::MISSED_STICKS, i(&|r| r.missed_sticks))
        .put(&tradeoff_table::SPURIOUS_STICKS, i(&|r| r.spurious_sticks))
        .put(&tradeoff_table::BIAS_MEAN_T_K_MAX, f(&|r| r.bias_t))
        .put(&tradeoff_table::BIAS_MEAN_D, f(&|r| r.bias_d))
        .put(&tradeoff_table::BIAS_MEAN_H, f(&|r| r.bias_h))
        .put(&tradeoff_table::BIAS_MEAN_S_T, f(&|r| r.bias_st))
        .put(&tradeoff_table::MAX_BIAS_OVER_SE, f(&|r| r.max_bias_over_se.unwrap_or(f64::NAN)))
        .put(&tradeoff_table::RECOMMENDED, i(&|r| r.recommended as u64));
    t
}

/// The work-precision figure.
pub fn figure(rows: &[Row]) -> Figure {
    // (colours: 4 marks the recommendation, 6 the paper's setting)
    let lines = [("rk45", 0), ("dop853", 5), ("rk4", 1), ("moreau", 2), ("smooth", 3)]
        .iter()
        .map(|&(solver, color)| Series {
            label: solver.to_string(),
            color,
            points: rows
                .iter()
                .filter(|r| r.solver == solver && r.error_rms > 0.0 && !r.setting.contains("max_step=1e-4"))
                .map(|r| (r.seconds_per_realization.log10(), r.error_rms.log10()))
                .collect(),
            ..Default::default()
        })
        .collect::<Vec<Series>>();
    let mut points: Vec<Series> = lines.iter().map(|l| Series { label: String::new(), ..l.clone() }).collect();
    points.extend(rows.iter().filter(|r| r.setting.starts_with("paper")).map(|r| Series {
        label: "rk45 at the paper's ode45 settings".into(),
        color: 6,
        points: vec![(r.seconds_per_realization.log10(), r.error_rms.max(1e-16).log10())],
        ..Default::default()
    }));
    points.extend(rows.iter().filter(|r| r.recommended).map(|r| Series {
        label: format!("recommended: {} {}", r.solver, r.setting),
        color: 4,
        points: vec![(r.seconds_per_realization.log10(), r.error_rms.max(1e-16).log10())],
        ..Default::default()
    }));
    let exact = rows.iter().find(|r| r.solver == "exact").map(|r| r.seconds_per_realization.log10());
    // room above the highest point for the legend (upper right)
    let ys: Vec<f64> = lines.iter().chain(&points).flat_map(|s| s.points.iter().map(|p| p.1)).collect();
    let (lo, hi) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &y| (lo.min(y), hi.max(y)));
    let y_range = (lo < hi).then_some((lo - 0.05 * (hi - lo), hi + 0.6 * (hi - lo)));
    Figure {
        name: "work_precision".into(),
        title: "Work-precision: event-time error against cost, same realizations".into(),
        rows: 1,
        cols: 1,
        size: (1000, 650),
        panels: vec![Panel {
            title: exact.map_or(String::new(), |e| format!("exact solver: 10^{e:.1} s per realization, error 0")),
            x_label: "log10 CPU seconds per realization".into(),
            y_label: "log10 RMS event-time error [s]".into(),
            lines,
            points,
            vlines: exact.into_iter().collect(),
            y_range,
            ..Default::default()
        }],
    }
}

/// Run the stage into `out` (replaced when complete).
/// `ctl` is asked between settings.
pub fn run(base: &Scenario, n: u64, bias_fraction: f64, out: &Path, ctl: crate::progress::Control) -> Result<Vec<Row>, TradeoffError> {
    if base.scene()?.chain.is_some() {
        return Err(TradeoffError::Scenario(crate::scenario::ScenarioError::Invalid {
            key: "chain".into(),
            value: "(a chain or a moving anchor)".into(),
            reason: "tradeoff measures the numerical solvers against exact, and they do not take chains yet".into(),
        }));
    }
    let staged = StagedDir::new(out, Kind::Tradeoff, "--out", &[])?;
    let rows = measure(base, n, bias_fraction, ctl)?;
    let werr = |path: &Path, e: &dyn std::fmt::Display| TradeoffError::Write { path: path.to_owned(), message: e.to_string() };
    for (def, t) in tables(&rows, n) {
        def.check(&t).map_err(|e| werr(&out.join(def.file), &e))?;
        t.write_parquet(&staged.path().join(def.file)).map_err(|e| werr(&out.join(def.file), &e))?;
    }
    render::save(&figure(&rows), staged.path()).map_err(|e| werr(&out.join("work_precision.png"), &e))?;
    staged.commit()?;
    Ok(rows)
}
