//! The `sensitivity` stage: first-order and total Sobol indices of per-realization outputs with
//! respect to each random scene key, and to the intrinsic randomness (belt and initial
//! conditions) as one more input.
//!
//! Pick-freeze design with two independent samples A and B of every input (A_j: realization j,
//! B_j: realization N + j) and, for each input i, AB⁽ⁱ⁾_j: A_j with input i taken from B_j. Every
//! random key and the intrinsic draws have their own sub-streams of a realization's generator
//! ([`crate::simulation::keys`], [`crate::simulation::rng`]), so AB⁽ⁱ⁾_j shares every draw with A_j except input i —
//! exactly. Estimators, with V the variance of f over A and B together:
//!
//! ```text
//!   first order (A. Saltelli et al., "Variance based sensitivity analysis of model output",
//!   Comput. Phys. Commun. 181, 2010):   S_i  = mean_j f(B_j) (f(AB⁽ⁱ⁾_j) − f(A_j)) / V
//!   total (M. J. W. Jansen, "Analysis of variance designs for model output", Comput. Phys.
//!   Commun. 117, 1999):                 ST_i = mean_j (f(A_j) − f(AB⁽ⁱ⁾_j))² / (2 V)
//! ```
//!
//! 95 % intervals: percentile bootstrap over j (200 replicates, resampling drawn from ChaCha8
//! seeded by the run's seed). Cost: N (d + 3) realizations for d random keys (d + 1 inputs).
//! Outputs per realization, as [`crate::observables`] defines them: S_T, the stick fraction (time
//! in stick / t_a), the mean stick duration and the mean slip duration (the durations cut at t_a
//! censored, left out). A pick-freeze sample j in one of whose d + 3 realizations an output has no
//! value (a mean stick duration where a realization has no uncensored stick) is left out of that
//! output's indices — never filled in; `samples` in `sobol.parquet` says how many were used.

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::figures::{render, Figure, Panel, Series};
use crate::observables::Observable;
use crate::outdir::{Kind, StagedDir};
use crate::scenario::{Scenario, ScenarioError};
use crate::simulation::ensemble::{Outcome, RunError};
use crate::table::{table, Col, Table};

/// The per-realization outputs whose variance is apportioned.
pub const OUTPUTS: [Observable; 4] = [Observable::Sticks, Observable::StickFraction, Observable::MeanStickDuration, Observable::MeanSlipDuration];

/// Bootstrap replicates of the intervals.
pub const REPLICATES: usize = 200;

/// The name of the intrinsic-randomness input.
pub const INTRINSIC: &str = "intrinsic (belt, initial conditions)";

/// Why `sensitivity` failed.
#[derive(Debug, thiserror::Error)]
pub enum SensitivityError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The caller cancelled the run (Ctrl-C in a Python session).
    #[error("interrupted")]
    Cancelled(#[from] crate::progress::Cancelled),
    /// The scenario has no random key to apportion the variance to.
    #[error("the scenario has no random key: make at least one [model] or [belt] key a distribution, e.g. --set 'model.friction_coefficient={{dist = \"uniform\", low = 0.3, high = 0.7}}'")]
    NoRandomKey,
    /// A realization failed.
    #[error(transparent)]
    Run(#[from] RunError),
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
    /// The samples' outputs would take more than [`MAX_MEMORY_GIB`].
    #[error("--realizations {n}: the {d} random keys' N·(d+3) outputs are held in memory, about {gib:.1} GiB; at most {MAX_MEMORY_GIB} GiB: use N <= {most}")]
    TooLarge {
        /// N, the pick-freeze samples asked for
        n: u64,
        /// d, the random keys
        d: usize,
        /// the memory they would take [GiB]
        gib: f64,
        /// the largest N that fits
        most: u64,
    },
}

impl crate::blame::Blame for SensitivityError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            SensitivityError::Scenario(_) | SensitivityError::NoRandomKey => Some(crate::blame::Culprit::Scenario),
            SensitivityError::TooLarge { .. } => Some(crate::blame::Culprit::Usage),
            SensitivityError::Out(o) => o.blame(),
            SensitivityError::Run(_) | SensitivityError::Write { .. } | SensitivityError::Cancelled(_) => None,
        }
    }
}

/// Most memory the samples' outputs may take [GiB] (they are held for the bootstrap).
pub const MAX_MEMORY_GIB: f64 = 4.0;

/// Bytes one pick-freeze sample holds: its vector (header and allocation) and d + 3 output rows.
fn sample_bytes(d: usize) -> f64 {
    (24 + 16 + (d + 3) * std::mem::size_of::<[Option<f64>; 4]>()) as f64
}

/// One row of `sobol.parquet`.
#[derive(Debug, Clone, PartialEq)]
pub struct Index {
    /// the input: a random key's column name (e.g. `friction_coefficient`) or [`INTRINSIC`]
    pub parameter: String,
    /// the output whose variance is apportioned (one of [`OUTPUTS`])
    pub output: Observable,
    /// pick-freeze samples whose realizations all have the output
    pub samples: usize,
    /// S_i, the first-order Sobol index (NaN with fewer than two samples)
    pub first_order: f64,
    /// S_i's 95 % percentile-bootstrap interval
    pub first_order_ci: (f64, f64),
    /// ST_i, the total Sobol index (NaN with fewer than two samples)
    pub total: f64,
    /// ST_i's 95 % percentile-bootstrap interval
    pub total_ci: (f64, f64),
}

/// The outputs of one realization ([`OUTPUTS`]; None where it has no value).
pub fn outputs(o: &Outcome) -> [Option<f64>; 4] {
    OUTPUTS.map(|q| q.value(o))
}

/// (first order, total) from f(A), f(B), f(AB⁽ⁱ⁾) over the samples `js` (module docs).
pub fn estimate(fa: &[f64], fb: &[f64], fab: &[f64], js: &[usize]) -> (f64, f64) {
    let n = js.len() as f64;
    let all = js.iter().flat_map(|&j| [fa[j], fb[j]]);
    let mean = all.clone().sum::<f64>() / (2.0 * n);
    let var = all.map(|x| (x - mean) * (x - mean)).sum::<f64>() / (2.0 * n);
    if !(var > 0.0) {
        return (0.0, 0.0);
    }
    let first = js.iter().map(|&j| fb[j] * (fab[j] - fa[j])).sum::<f64>() / n / var;
    let total = js.iter().map(|&j| (fa[j] - fab[j]) * (fa[j] - fab[j])).sum::<f64>() / n / (2.0 * var);
    (first, total)
}

/// The estimates and their percentile-bootstrap 95 % intervals.
pub fn with_intervals(fa: &[f64], fb: &[f64], fab: &[f64], seed: u64) -> ((f64, (f64, f64)), (f64, (f64, f64))) {
    let n = fa.len();
    let all: Vec<usize> = (0..n).collect();
    let (s, t) = estimate(fa, fb, fab, &all);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut ss, mut ts) = (Vec::with_capacity(REPLICATES), Vec::with_capacity(REPLICATES));
    for _ in 0..REPLICATES {
        let js: Vec<usize> = (0..n).map(|_| (rng.next_u64() % n as u64) as usize).collect();
        let (a, b) = estimate(fa, fb, fab, &js);
        ss.push(a);
        ts.push(b);
    }
    let pct = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (v[(0.025 * REPLICATES as f64) as usize], v[((0.975 * REPLICATES as f64) as usize).min(REPLICATES - 1)])
    };
    ((s, pct(&mut ss)), (t, pct(&mut ts)))
}

/// Compute every index on N pick-freeze samples of `scenario`.
pub fn compute(scenario: &Scenario, n: u64) -> Result<Vec<Index>, SensitivityError> {
    let ens = scenario.ensemble()?;
    let keys = ens.scene().columns();
    if keys.is_empty() {
        return Err(SensitivityError::NoRandomKey);
    }
    let d = keys.len();
    let gib = n as f64 * sample_bytes(d) / f64::from(1u32 << 30);
    if gib > MAX_MEMORY_GIB {
        let most = (MAX_MEMORY_GIB * f64::from(1u32 << 30) / sample_bytes(d)) as u64;
        return Err(SensitivityError::TooLarge { n, d, gib, most });
    }
    // per sample j: f(A), f(B), f(AB⁽ⁱ⁾) for each key i, then for the intrinsic input
    let samples: Vec<Vec<[Option<f64>; 4]>> = (0..n)
        .into_par_iter()
        .map(|j| -> Result<Vec<[Option<f64>; 4]>, RunError> {
            let (a, b) = (j, n + j);
            let mut out = Outcome::default();
            let mut run = |intrinsic: u64, from: &[u64]| -> Result<[Option<f64>; 4], RunError> {
                ens.realization_mixed(intrinsic, from, &mut out)?;
                Ok(outputs(&out))
            };
            let mut f = vec![run(a, &vec![a; d])?, run(b, &vec![b; d])?];
            for i in 0..d {
                let from: Vec<u64> = (0..d).map(|k| if k == i { b } else { a }).collect();
                f.push(run(a, &from)?);
            }
            f.push(run(b, &vec![a; d])?);
            Ok(f)
        })
        .collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    let names: Vec<String> = keys.iter().map(|k| k.to_string()).chain(std::iter::once(INTRINSIC.to_string())).collect();
    for (o, &output) in OUTPUTS.iter().enumerate() {
        // the complete samples: every one of their d + 3 realizations has the output
        let kept: Vec<&Vec<[Option<f64>; 4]>> = samples.iter().filter(|f| f.iter().all(|r| r[o].is_some())).collect();
        let col = |c: usize| kept.iter().map(|f| f[c][o].unwrap_or(f64::NAN)).collect::<Vec<f64>>();
        let (fa, fb) = (col(0), col(1));
        for (i, name) in names.iter().enumerate() {
            let ((s, s_ci), (t, t_ci)) = if kept.len() >= 2 {
                with_intervals(&fa, &fb, &col(2 + i), scenario.run.seed ^ (o as u64 * 1000 + i as u64))
            } else {
                ((f64::NAN, (f64::NAN, f64::NAN)), (f64::NAN, (f64::NAN, f64::NAN)))
            };
            rows.push(Index { parameter: name.clone(), output, samples: kept.len(), first_order: s, first_order_ci: s_ci, total: t, total_ci: t_ci });
        }
    }
    Ok(rows)
}

table! {
    /// `sobol.parquet`: one row per (input, output).
    sobol = "sobol.parquet", "first-order and total Sobol indices with bootstrap 95 % intervals" {
        PARAMETER: "parameter", Str, "the random scenario key (or the intrinsic noise)";
        OUTPUT: "output", Str, "the per-realization output (an observable)";
        SAMPLES: "samples", Int, "pick-freeze samples used";
        FIRST_ORDER: "first_order", Float, "first-order index (Saltelli 2010)";
        FIRST_ORDER_LO: "first_order_lo", Float, "its 95 % interval, lower end";
        FIRST_ORDER_HI: "first_order_hi", Float, "its 95 % interval, upper end";
        TOTAL: "total", Float, "total index (Jansen 1999)";
        TOTAL_LO: "total_lo", Float, "its 95 % interval, lower end";
        TOTAL_HI: "total_hi", Float, "its 95 % interval, upper end";
    }
}

/// The tables of the indices, with their definitions (what the stage writes).
pub fn tables(rows: &[Index]) -> Vec<(&'static crate::table::Def, Table)> {
    vec![(&sobol::DEF, table(rows))]
}

/// The indices as `sobol.parquet`.
pub fn table(rows: &[Index]) -> Table {
    let f = |g: &dyn Fn(&Index) -> f64| Col::Float(rows.iter().map(|r| Some(g(r)).filter(|x| x.is_finite())).collect());
    let mut t = Table::default();
    t.put(&sobol::PARAMETER, Col::Str(rows.iter().map(|r| r.parameter.clone()).collect()))
        .put(&sobol::OUTPUT, Col::Str(rows.iter().map(|r| r.output.to_string()).collect()))
        .put(&sobol::SAMPLES, Col::Int(rows.iter().map(|r| Some(r.samples as i64)).collect()))
        .put(&sobol::FIRST_ORDER, f(&|r| r.first_order))
        .put(&sobol::FIRST_ORDER_LO, f(&|r| r.first_order_ci.0))
        .put(&sobol::FIRST_ORDER_HI, f(&|r| r.first_order_ci.1))
        .put(&sobol::TOTAL, f(&|r| r.total))
        .put(&sobol::TOTAL_LO, f(&|r| r.total_ci.0))
        .put(&sobol::TOTAL_HI, f(&|r| r.total_ci.1));
    t
}

/// One panel per output: first-order (points) and total (points) indices per input, with
/// their intervals as error bars (the larger side of the percentile interval).
pub fn figure(rows: &[Index]) -> Figure {
    let panels = OUTPUTS
        .iter()
        .map(|output| {
            let mine: Vec<&Index> = rows.iter().filter(|r| r.output == *output).collect();
            let series = |label: &str, color: usize, shift: f64, get: &dyn Fn(&Index) -> (f64, (f64, f64))| Series {
                label: label.into(),
                color,
                // (an index without enough complete samples is not drawn)
                points: mine.iter().enumerate().filter(|(_, r)| get(r).0.is_finite()).map(|(i, r)| (i as f64 + shift, get(r).0)).collect(),
                errors: mine
                    .iter()
                    .filter(|r| get(r).0.is_finite())
                    .map(|r| {
                        let (x, (lo, hi)) = get(r);
                        (x - lo).max(hi - x).max(0.0)
                    })
                    .collect(),
            };
            let short = |p: &str| if p == INTRINSIC { "intrinsic".to_string() } else { p.to_string() };
            Panel {
                title: output.to_string(),
                x_label: "input".into(),
                x_ticks: mine.iter().enumerate().map(|(i, r)| (i as f64, short(&r.parameter))).collect(),
                y_label: "Sobol index".into(),
                points: vec![series("first order", 0, -0.1, &|r| (r.first_order, r.first_order_ci)), series("total", 1, 0.1, &|r| (r.total, r.total_ci))],
                x_range: Some((-0.5, mine.len() as f64 - 0.5)),
                y_range: Some((-0.1, 1.1)),
                ..Default::default()
            }
        })
        .collect();
    Figure { name: "sobol".into(), title: "Sobol indices with bootstrap 95 % intervals".into(), rows: 2, cols: 2, size: (1200, 800), panels }
}

/// Run the stage into `out` (replaced when complete): `sobol.parquet`, `sobol.{png,svg}`,
/// `sobol.md`.
/// `ctl` is asked before the samples run.
pub fn run(scenario: &Scenario, n: u64, out: &Path, ctl: crate::progress::Control) -> Result<Vec<Index>, SensitivityError> {
    let staged = StagedDir::new(out, Kind::Sensitivity, "--out", &[])?;
    ctl.check()?;
    let rows = compute(scenario, n)?;
    let werr = |name: &str, e: &dyn std::fmt::Display| SensitivityError::Write { path: out.join(name), message: e.to_string() };
    for (def, t) in tables(&rows) {
        def.check(&t).map_err(|e| werr(def.file, &e))?;
        t.write_parquet(&staged.path().join(def.file)).map_err(|e| werr(def.file, &e))?;
    }
    render::save(&figure(&rows), staged.path()).map_err(|e| werr("sobol.png", &e))?;
    std::fs::write(staged.path().join("sobol.md"), markdown(&rows, n)).map_err(|e| werr("sobol.md", &e))?;
    staged.commit()?;
    Ok(rows)
}

/// The report section: one table of every index with its interval.
pub fn markdown(rows: &[Index], n: u64) -> String {
    let mut m = format!(
        "## Global sensitivity (Sobol indices, {n} pick-freeze samples)\n\nFirst order (Saltelli 2010) and total (Jansen 1999), bootstrap 95 % intervals.\n\n| output | input | first order | total |\n|---|---|---|---|\n"
    );
    let shown =
        |x: f64, (lo, hi): (f64, f64)| if x.is_finite() { format!("{x:.3} [{lo:.3} – {hi:.3}]") } else { "– (fewer than 2 complete samples)".into() };
    for r in rows {
        m += &format!("| {} | {} | {} | {} |\n", r.output, r.parameter, shown(r.first_order, r.first_order_ci), shown(r.total, r.total_ci));
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimators_recover_the_ishigami_indices() {
        // f = sin x1 + 7 sin² x2 + 0.1 x3⁴ sin x1, x ~ U(−π, π)³: S = (0.3139, 0.4424, 0),
        // ST = (0.5576, 0.4424, 0.2437) (T. Ishigami, T. Homma 1990; Saltelli et al. 2010)
        let f = |x: [f64; 3]| x[0].sin() + 7.0 * x[1].sin().powi(2) + 0.1 * x[2].powi(4) * x[0].sin();
        let n = 40_000;
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut draw = || -> [f64; 3] { std::array::from_fn(|_| (crate::simulation::rng::unit_f64(&mut rng) * 2.0 - 1.0) * std::f64::consts::PI) };
        let (a, b): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (0..n).map(|_| (draw(), draw())).unzip();
        let (fa, fb): (Vec<f64>, Vec<f64>) = (a.iter().map(|&x| f(x)).collect(), b.iter().map(|&x| f(x)).collect());
        let (s_true, t_true) = ([0.3139, 0.4424, 0.0], [0.5576, 0.4424, 0.2437]);
        for i in 0..3 {
            let fab: Vec<f64> = (0..n)
                .map(|j| {
                    let mut x = a[j];
                    x[i] = b[j][i];
                    f(x)
                })
                .collect();
            let ((s, s_ci), (t, t_ci)) = with_intervals(&fa, &fb, &fab, i as u64);
            assert!((s - s_true[i]).abs() < 0.02 && (t - t_true[i]).abs() < 0.02, "x{}: S {s} ST {t}", i + 1);
            assert!(s_ci.0 <= s_true[i] + 0.01 && s_true[i] - 0.01 <= s_ci.1, "x{}: S interval {s_ci:?}", i + 1);
            assert!(t_ci.0 <= t_true[i] + 0.01 && t_true[i] - 0.01 <= t_ci.1, "x{}: ST interval {t_ci:?}", i + 1);
        }
    }
}
