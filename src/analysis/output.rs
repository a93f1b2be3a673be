//! Writing an [`Analysis`]: tidy Parquet tables, `summary.json` and `table1.md`, atomically.
//!
//! Files in ADIR:
//! - `moments.parquet`: variable, index, n, n_truncated_excluded, mean, variance (unbiased), mode,
//!   skewness, kurtosis (Pearson), mean_se, variance_se, min, max, and a 95 % interval
//!   `<stat>_lo`, `<stat>_hi` for each of mean, variance, mode, skewness, kurtosis
//!   ([`super::jackknife`]);
//! - `histograms.parquet`: variable, index, bin, lo, hi, count, density (densities integrate to 1;
//!   for the counts S_T, S_L, Q the bins are the integers and density is the PMF);
//! - `joint_histograms.parquet`: x, y, x_bin, y_bin, x_lo, x_hi, y_lo, y_hi, count, density,
//!   product_density (the product of the two marginals on the same grid);
//! - `independence.parquet`: x, y, n, rows, cols, chi2, df, chi2_p_value, g, g_p_value,
//!   mutual_information, mi_null_mean, mi_p_value, permutations, verdict;
//! - `growth.parquet`: variable, statistic, slope, intercept, r2, slope_se, points, slope_lo,
//!   slope_hi (95 % jackknife);
//! - `convergence.parquet`: variable, index, realizations, n, mean, mean_lo, mean_hi — the running
//!   mean of S_T, T_1, D_1, H_1 with its 95 % interval (mean ± 1.96 se) at 10 realization counts
//!   per decade (the paper's question: how many realizations?);
//! - `survival.parquet` (unless `--no-tails`): variable (`D`, `H`), index (k; null pooled over
//!   every interval), method (`kaplan_meier`, `naive`, `conditional`), n, n_censored, t, survival
//!   (P(duration > t)), lo, hi (95 %) — see [`super::tails`];
//! - `tails.parquet` (schema-v3 datasets): statistic (`breakaway_fraction`, `longest_stick`,
//!   `severity`), threshold, value (the fraction, or P(statistic > threshold)), lo, hi, n;
//! - `summary.json`: provenance, policies, counts, regressions, renewal check, tests;
//! - `table1.md`: our Table 1 beside the paper's;
//! - `trajectory_samples.parquet`, `trajectory_events.parquet`: the trajectory tables beside the
//!   dataset, copied when the simulation sampled trajectories (the paper's Fig. 4).
//!
//! Everything is written into a staging directory that replaces ADIR only when complete
//! ([`crate::outdir`]).

use std::path::Path;

use super::paper;
use super::summary::{Bins, CountSummary, DatasetSummary, GrowthSummary, OptionsSummary, Policies, RenewalSummary, Summary, TestSummary};
use super::tables::{convergence, growth, histograms, independence, joint_histograms, moments, survival, tails};
use super::{Analysis, AnalysisError};
use crate::outdir::{Kind, StagedDir};
use crate::table::{Col, Column, Def, Table};

/// Significance level of the reported verdicts.
pub const ALPHA: f64 = 0.05;

fn f(v: Option<f64>) -> Option<f64> {
    v.filter(|x| x.is_finite())
}

fn moments_table(a: &Analysis) -> Table {
    let mut t = Table::default();
    let s = &a.stats;
    let float = |g: &dyn Fn(&super::SeriesStats) -> Option<f64>| Col::Float(s.iter().map(|x| f(g(x))).collect());
    t.put(&moments::VARIABLE, Col::Str(s.iter().map(|x| x.series.variable().to_string()).collect()))
        .put(&moments::INDEX, Col::Int(s.iter().map(|x| x.series.index().map(i64::from)).collect()))
        .put(&moments::N, Col::Int(s.iter().map(|x| Some(x.moments.n as i64)).collect()))
        .put(&moments::N_TRUNCATED_EXCLUDED, Col::Int(s.iter().map(|x| Some(x.truncated as i64)).collect()))
        .put(&moments::MEAN, float(&|x| (x.moments.n > 0).then_some(x.moments.mean)))
        .put(&moments::VARIANCE, float(&|x| x.moments.variance()))
        .put(&moments::MODE, float(&|x| x.mode))
        .put(&moments::SKEWNESS, float(&|x| x.moments.skewness()))
        .put(&moments::KURTOSIS, float(&|x| x.moments.kurtosis()))
        .put(&moments::MEAN_SE, float(&|x| x.moments.mean_se()))
        .put(&moments::VARIANCE_SE, float(&|x| x.moments.variance_se()))
        .put(&moments::MIN, float(&|x| (x.moments.n > 0).then_some(x.moments.min)))
        .put(&moments::MAX, float(&|x| (x.moments.n > 0).then_some(x.moments.max)));
    let mean = |m: &super::Moments| (m.n > 0).then_some(m.mean);
    let rows = a.dataset.rows.max(1) as f64;
    use moments::{KURTOSIS_HI, KURTOSIS_LO, MEAN_HI, MEAN_LO, MODE_HI, MODE_LO, SKEWNESS_HI, SKEWNESS_LO, VARIANCE_HI, VARIANCE_LO};
    let intervals: [(Column, Column, Box<dyn Fn(&super::SeriesStats) -> Option<(f64, f64)>>); 5] = [
        (MEAN_LO, MEAN_HI, Box::new(move |x| x.interval(mean))),
        (VARIANCE_LO, VARIANCE_HI, Box::new(|x| x.interval(super::Moments::variance))),
        (MODE_LO, MODE_HI, Box::new(|x| x.mode_interval())),
        (SKEWNESS_LO, SKEWNESS_HI, Box::new(|x| x.skewness_interval())),
        (KURTOSIS_LO, KURTOSIS_HI, Box::new(|x| x.kurtosis_interval())),
    ];
    for (lo, hi, iv) in &intervals {
        t.put(lo, float(&|x| iv(x).map(|i| i.0)));
        t.put(hi, float(&|x| iv(x).map(|i| i.1)));
    }
    let realizations = a.dataset.rows;
    t.put(&moments::SKEWNESS_APPROXIMATE, Col::Int(s.iter().map(|x| Some(i64::from(x.skewness_approximate()))).collect()))
        .put(&moments::KURTOSIS_APPROXIMATE, Col::Int(s.iter().map(|x| Some(i64::from(x.kurtosis_approximate(realizations)))).collect()));
    // no silent survivorship: how many realizations the statistics of each row describe
    t.put(&moments::REACHED, Col::Int(s.iter().map(|x| Some(x.reached as i64)).collect()))
        .put(&moments::REACHED_FRACTION, float(&|x| Some(x.reached as f64 / rows)));
    t
}

fn histogram_table(a: &Analysis) -> Table {
    let (mut var, mut idx) = (Vec::new(), Vec::new());
    let (mut bin, mut count) = (Vec::new(), Vec::new());
    let (mut lo, mut hi, mut dens) = (Vec::new(), Vec::new(), Vec::new());
    for s in a.stats.iter().filter(|s| s.histogram.total() > 0) {
        let h = &s.histogram;
        for i in 0..h.bins() {
            let (l, r) = h.edges(i);
            var.push(s.series.variable().to_string());
            idx.push(s.series.index().map(i64::from));
            bin.push(Some(i as i64));
            count.push(Some(h.counts[i] as i64));
            lo.push(Some(l));
            hi.push(Some(r));
            dens.push(Some(h.density(i)));
        }
    }
    let mut t = Table::default();
    t.put(&histograms::VARIABLE, Col::Str(var))
        .put(&histograms::INDEX, Col::Int(idx))
        .put(&histograms::BIN, Col::Int(bin))
        .put(&histograms::LO, Col::Float(lo))
        .put(&histograms::HI, Col::Float(hi))
        .put(&histograms::COUNT, Col::Int(count))
        .put(&histograms::DENSITY, Col::Float(dens));
    t
}

fn joint_table(a: &Analysis) -> Table {
    let (mut x, mut y, mut xb, mut yb, mut count) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut xlo, mut xhi, mut ylo, mut yhi) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut dens, mut prod) = (Vec::new(), Vec::new());
    for j in &a.joints {
        let n: u64 = j.counts.iter().flatten().sum();
        if n == 0 {
            continue;
        }
        let (wx, wy) = (j.x.width(), j.y.width());
        let rows: Vec<u64> = j.counts.iter().map(|r| r.iter().sum()).collect();
        let cols: Vec<u64> = (0..j.y.bins()).map(|c| j.counts.iter().map(|r| r[c]).sum()).collect();
        let nf = n as f64;
        for (i, row) in j.counts.iter().enumerate() {
            for (k, &c) in row.iter().enumerate() {
                let ((l1, h1), (l2, h2)) = (j.x.edges(i), j.y.edges(k));
                x.push(j.pair.0.to_string());
                y.push(j.pair.1.to_string());
                xb.push(Some(i as i64));
                yb.push(Some(k as i64));
                xlo.push(Some(l1));
                xhi.push(Some(h1));
                ylo.push(Some(l2));
                yhi.push(Some(h2));
                count.push(Some(c as i64));
                dens.push(Some(c as f64 / (nf * wx * wy)));
                prod.push(Some(rows[i] as f64 / (nf * wx) * (cols[k] as f64 / (nf * wy))));
            }
        }
    }
    let mut t = Table::default();
    t.put(&joint_histograms::X, Col::Str(x))
        .put(&joint_histograms::Y, Col::Str(y))
        .put(&joint_histograms::X_BIN, Col::Int(xb))
        .put(&joint_histograms::Y_BIN, Col::Int(yb))
        .put(&joint_histograms::X_LO, Col::Float(xlo))
        .put(&joint_histograms::X_HI, Col::Float(xhi))
        .put(&joint_histograms::Y_LO, Col::Float(ylo))
        .put(&joint_histograms::Y_HI, Col::Float(yhi))
        .put(&joint_histograms::COUNT, Col::Int(count))
        .put(&joint_histograms::DENSITY, Col::Float(dens))
        .put(&joint_histograms::PRODUCT_DENSITY, Col::Float(prod));
    t
}

/// "independent" / "dependent" at level [`ALPHA`] by the χ² test.
pub fn verdict(p: f64) -> &'static str {
    if p < ALPHA {
        "dependent"
    } else {
        "independent"
    }
}

fn independence_table(a: &Analysis) -> Table {
    let tests: Vec<_> = a.joints.iter().filter_map(|j| j.test.as_ref().map(|t| (j.pair, t))).collect();
    let float = |g: &dyn Fn(&super::independence::Independence) -> Option<f64>| Col::Float(tests.iter().map(|(_, t)| f(g(t))).collect());
    let int = |g: &dyn Fn(&super::independence::Independence) -> i64| Col::Int(tests.iter().map(|(_, t)| Some(g(t))).collect());
    let mut t = Table::default();
    t.put(&independence::X, Col::Str(tests.iter().map(|(p, _)| p.0.to_string()).collect()))
        .put(&independence::Y, Col::Str(tests.iter().map(|(p, _)| p.1.to_string()).collect()))
        .put(&independence::N, int(&|t| t.n as i64))
        .put(&independence::ROWS, int(&|t| t.rows as i64))
        .put(&independence::COLS, int(&|t| t.cols as i64))
        .put(&independence::CHI2, float(&|t| Some(t.chi2)))
        .put(&independence::DF, float(&|t| Some(t.df)))
        .put(&independence::CHI2_P_VALUE, float(&|t| Some(t.chi2_p_value)))
        .put(&independence::G, float(&|t| Some(t.g)))
        .put(&independence::G_P_VALUE, float(&|t| Some(t.g_p_value)))
        .put(&independence::MUTUAL_INFORMATION, float(&|t| Some(t.mutual_information)))
        .put(&independence::MI_NULL_MEAN, float(&|t| t.mi_null_mean))
        .put(&independence::MI_P_VALUE, float(&|t| Some(t.mi_p_value)))
        .put(&independence::PERMUTATIONS, int(&|t| t.permutations as i64))
        .put(&independence::VERDICT, Col::Str(tests.iter().map(|(_, t)| verdict(t.chi2_p_value).to_string()).collect()));
    t
}

fn survival_table(t: &super::tails::Tails) -> Table {
    let rows: Vec<(&super::tails::Curve, &(f64, f64, Option<(f64, f64)>))> = t.curves.iter().flat_map(|c| c.points.iter().map(move |p| (c, p))).collect();
    let mut out = Table::default();
    out.put(&survival::VARIABLE, Col::Str(rows.iter().map(|r| r.0.variable.to_string()).collect()))
        .put(&survival::INDEX, Col::Int(rows.iter().map(|r| r.0.index.map(i64::from)).collect()))
        .put(&survival::METHOD, Col::Str(rows.iter().map(|r| r.0.method.to_string()).collect()))
        .put(&survival::N, Col::Int(rows.iter().map(|r| Some(r.0.n as i64)).collect()))
        .put(&survival::N_CENSORED, Col::Int(rows.iter().map(|r| Some(r.0.censored as i64)).collect()))
        .put(&survival::T, Col::Float(rows.iter().map(|r| f(Some(r.1 .0))).collect()))
        .put(&survival::SURVIVAL, Col::Float(rows.iter().map(|r| f(Some(r.1 .1))).collect()))
        .put(&survival::LO, Col::Float(rows.iter().map(|r| f(r.1 .2.map(|i| i.0))).collect()))
        .put(&survival::HI, Col::Float(rows.iter().map(|r| f(r.1 .2.map(|i| i.1))).collect()));
    out
}

fn tails_table(t: &super::tails::Tails) -> Table {
    let e = &t.exceedances;
    let mut out = Table::default();
    out.put(&tails::STATISTIC, Col::Str(e.iter().map(|x| x.statistic.to_string()).collect()))
        .put(&tails::THRESHOLD, Col::Float(e.iter().map(|x| f(x.threshold)).collect()))
        .put(&tails::VALUE, Col::Float(e.iter().map(|x| f(Some(x.value))).collect()))
        .put(&tails::LO, Col::Float(e.iter().map(|x| f(x.interval.map(|i| i.0))).collect()))
        .put(&tails::HI, Col::Float(e.iter().map(|x| f(x.interval.map(|i| i.1))).collect()))
        .put(&tails::N, Col::Int(e.iter().map(|x| Some(x.n as i64)).collect()));
    out
}

fn growth_table(a: &Analysis) -> Table {
    let g = &a.growth;
    let mut t = Table::default();
    t.put(&growth::VARIABLE, Col::Str(g.iter().map(|x| x.family.variable().to_string()).collect()))
        .put(&growth::STATISTIC, Col::Str(g.iter().map(|x| x.statistic.to_string()).collect()))
        .put(&growth::SLOPE, Col::Float(g.iter().map(|x| f(Some(x.line.slope))).collect()))
        .put(&growth::INTERCEPT, Col::Float(g.iter().map(|x| f(Some(x.line.intercept))).collect()))
        .put(&growth::R2, Col::Float(g.iter().map(|x| f(Some(x.line.r2))).collect()))
        .put(&growth::SLOPE_SE, Col::Float(g.iter().map(|x| f(x.line.slope_se)).collect()))
        .put(&growth::POINTS, Col::Int(g.iter().map(|x| Some(x.line.points as i64)).collect()))
        .put(&growth::SLOPE_LO, Col::Float(g.iter().map(|x| f(x.slope_interval.map(|i| i.0))).collect()))
        .put(&growth::SLOPE_HI, Col::Float(g.iter().map(|x| f(x.slope_interval.map(|i| i.1))).collect()))
        .put(&growth::K_MAX, Col::Int(g.iter().map(|x| Some(x.k_max as i64)).collect()))
        .put(&growth::MIN_REACHED_FRACTION, Col::Float(g.iter().map(|_| Some(super::GROWTH_MIN_REACHED)).collect()));
    t
}

fn convergence_table(a: &Analysis) -> Table {
    let rows: Vec<(&super::Convergence, &(u64, u64, f64, Option<f64>))> = a.convergence.iter().flat_map(|c| c.points.iter().map(move |p| (c, p))).collect();
    let half = |p: &(u64, u64, f64, Option<f64>)| p.3.map(|se| 1.96 * se);
    let mut t = Table::default();
    t.put(&convergence::VARIABLE, Col::Str(rows.iter().map(|(c, _)| c.series.variable().to_string()).collect()))
        .put(&convergence::INDEX, Col::Int(rows.iter().map(|(c, _)| c.series.index().map(i64::from)).collect()))
        .put(&convergence::REALIZATIONS, Col::Int(rows.iter().map(|(_, p)| Some(p.0 as i64)).collect()))
        .put(&convergence::N, Col::Int(rows.iter().map(|(_, p)| Some(p.1 as i64)).collect()))
        .put(&convergence::MEAN, Col::Float(rows.iter().map(|(_, p)| f((p.1 > 0).then_some(p.2))).collect()))
        .put(&convergence::MEAN_LO, Col::Float(rows.iter().map(|(_, p)| f(half(p).map(|h| p.2 - h))).collect()))
        .put(&convergence::MEAN_HI, Col::Float(rows.iter().map(|(_, p)| f(half(p).map(|h| p.2 + h))).collect()));
    t
}

/// An interval as `[lo, hi]`, its ends `null` where not finite.
fn pair(i: Option<(f64, f64)>) -> Option<[Option<f64>; 2]> {
    i.map(|i| [f(Some(i.0)), f(Some(i.1))])
}

/// The typed `summary.json` ([`Summary`]).
pub fn summary(a: &Analysis) -> Summary {
    let sc = &a.dataset.scenario;
    let paper_scene = sc.is_paper_scene();
    let counts = a
        .stats
        .iter()
        .filter(|s| s.series.is_count())
        .map(|s| {
            let m = &s.moments;
            let paper = paper::COUNTS.iter().find(|c| c.0 == s.series).filter(|_| paper_scene);
            let count = CountSummary {
                n: m.n,
                mean: f(Some(m.mean)),
                variance: f(m.variance()),
                mean_se: f(m.mean_se()),
                variance_se: f(m.variance_se()),
                mode: f(s.mode),
                paper_mean: paper.map(|p| p.1),
                paper_variance: paper.map(|p| p.2),
            };
            (s.series.to_string(), count)
        })
        .collect();
    let growth = a
        .growth
        .iter()
        .map(|g| GrowthSummary {
            variable: g.family.variable().into(),
            statistic: g.statistic.into(),
            slope: f(Some(g.line.slope)),
            intercept: f(Some(g.line.intercept)),
            r2: f(Some(g.line.r2)),
            slope_se: f(g.line.slope_se),
            slope_95: pair(g.slope_interval),
        })
        .collect();
    let independence = a
        .joints
        .iter()
        .filter_map(|j| j.test.as_ref().map(|t| (j, t)))
        .map(|(j, t)| TestSummary {
            x: j.pair.0.to_string(),
            y: j.pair.1.to_string(),
            n: t.n,
            table: [t.rows, t.cols],
            chi2: f(Some(t.chi2)),
            df: t.df,
            chi2_p_value: f(Some(t.chi2_p_value)),
            g: f(Some(t.g)),
            g_p_value: f(Some(t.g_p_value)),
            mutual_information: f(Some(t.mutual_information)),
            mi_null_mean: f(t.mi_null_mean),
            mi_p_value: f(Some(t.mi_p_value)),
            permutations: t.permutations,
            alpha: ALPHA,
            verdict: verdict(t.chi2_p_value).into(),
        })
        .collect();
    let renewal_check = a.renewal.as_ref().map(|r| RenewalSummary {
        predicted_mean: f(Some(r.predicted_mean)),
        measured_mean: f(Some(r.measured_mean)),
        predicted_variance: f(Some(r.predicted_variance)),
        measured_variance: f(Some(r.measured_variance)),
        predicted_mean_95: pair(r.predicted_mean_interval),
        predicted_variance_95: pair(r.predicted_variance_interval),
        formula: "E[S_T] ~ t_a / slope(E T_k); Var[S_T] ~ t_a slope(Var T_k) / slope(E T_k)^3".into(),
    });
    Summary {
        stickslip_version: env!("CARGO_PKG_VERSION").into(),
        dataset: DatasetSummary {
            files: a.dataset.files.iter().map(|p| p.display().to_string()).collect(),
            realizations: a.dataset.rows,
            seed: sc.run.seed,
            solver: sc.solver().name().into(),
            scenario: sc.to_toml(),
            complete: a.dataset.missing.is_empty(),
            realizations_of_the_run: a.dataset.expected_rows,
            missing_ranges: a.dataset.missing.iter().map(|r| format!("{}..{}", r.start, r.end)).collect(),
        },
        options: OptionsSummary {
            max_index: a.options.max_index,
            bins: a.options.bins.map_or(Bins::Rule("scott".into()), Bins::Fixed),
            permutations: a.options.permutations,
        },
        policies: Policies {
            truncated_intervals: "The interval running at t_a is cut there and flagged; its length is censored, so it is excluded from D_k and H_k (moments.n_truncated_excluded counts them). T_k and L_k always include every realization that has a k-th event.".into(),
            moments: "variance unbiased (n-1); skewness m3/m2^1.5 and kurtosis m4/m2^2 (Pearson, 3 for a normal) with population moments, as MATLAB's skewness/kurtosis; mean_se = sqrt(s^2/n); variance_se = sqrt((m4 - (n-3)/(n-1) s^4)/n)".into(),
            intervals: "95 % intervals <stat>_lo/_hi by the delete-a-group jackknife: realization i is in group i mod 20; each statistic is recomputed without each group (theta_g) and se^2 = (G-1)/G sum (theta_g - mean theta_g)^2, interval = estimate -/+ t(nu, 0.975) se; nu = 19, but for the skewness and the kurtosis nu = 2/(2/19 + k/20) clamped to [2, 19] with k the excess kurtosis of the theta_g (heavy-tailed leave-one-out values: fewer degrees of freedom, a wider interval; never narrower than nu = 19); the kurtosis interval on the log scale, widened 1.25; skewness_approximate / kurtosis_approximate flag the intervals whose measured coverage falls below 0.93 (kurtosis above 3.5; for the kurtosis also fewer than 18,000 realizations); the same for any thread count or shard split".into(),
            mode: "maximum of a Gaussian KDE (Silverman bandwidth 0.9 sigma n^-1/5, reflected at 0) evaluated on the (up to 4096) bins of the one-pass sketch, a maximum in the first bin at 0 reported as 0; counts: most frequent value".into(),
            bins: "equal width over the sample range; Scott's rule 3.49 sigma n^-1/3 clamped to 10..200 bins, or --bins".into(),
            independence: "contingency table of the joint histogram merged to <= 10x10 cells of ~equal marginal mass; Pearson chi2 and G tests; mutual information with a permutation null".into(),
        },
        counts,
        growth,
        renewal_check,
        independence,
    }
}

/// The trajectory tables beside a dataset ([`crate::simulation::trajectory`]) and their names in an analysis.
pub const TRAJECTORY_TABLES: [(&str, &str); 2] =
    [(crate::simulation::trajectory::SAMPLES, "trajectory_samples.parquet"), (crate::simulation::trajectory::EVENTS, "trajectory_events.parquet")];

/// Our Table 1 beside the paper's (for the paper's scene; other scenes: ours alone), as Markdown.
pub fn table1_markdown(a: &Analysis) -> String {
    let compare = a.dataset.scenario.is_paper_scene();
    let mut out = String::from(if compare {
        "Ours [95 % interval] (paper); ✓ the paper's value inside our interval (widened by its rounding), ✗ outside, ≈ an approximate interval (measured coverage below 0.93), not judged.\n\n"
    } else {
        "Ours [95 % interval]. Not the paper's scene, so not compared with the paper's Table 1.\n\n"
    });
    out += "| variable | n | mean | variance | mode | skewness | kurtosis |\n|---|---|---|---|---|---|---|\n";
    // the rows the report shows too, from the same moments table (Table 1 built once)
    for r in paper::table1(&moments_table(a), compare) {
        let c = |i: usize, digits: usize| r.shown(i, digits).0;
        out += &format!("| {} | {} | {} | {} | {} | {} | {} |\n", r.label, r.n, c(0, 3), c(1, 3), c(2, 3), c(3, 2), c(4, 2));
    }
    out
}

/// Write everything into `out`, replacing it only once complete.
pub fn write(a: &Analysis, out: &Path) -> Result<(), AnalysisError> {
    let inputs: Vec<&Path> = a.dataset.files.iter().map(|f| f.as_path()).collect();
    let staged = StagedDir::new(out, Kind::Analysis, "--out", &inputs)?;
    write_into(a, staged.path(), out)?;
    Ok(staged.commit()?)
}

fn werr(path: &Path, e: &dyn std::fmt::Display) -> AnalysisError {
    AnalysisError::Write { path: path.to_owned(), message: e.to_string() }
}

/// The tables of an analysis with their definitions: moments, histograms, joint_histograms,
/// independence, growth, convergence, and with the tails survival and tails.
/// Each is checked against its definition ([`super::tables`]) first.
pub fn tables(a: &Analysis) -> Result<Vec<(&'static Def, Table)>, AnalysisError> {
    let mut tables = vec![
        (&moments::DEF, moments_table(a)),
        (&histograms::DEF, histogram_table(a)),
        (&joint_histograms::DEF, joint_table(a)),
        (&independence::DEF, independence_table(a)),
        (&growth::DEF, growth_table(a)),
        (&convergence::DEF, convergence_table(a)),
    ];
    if let Some(t) = &a.tails {
        tables.extend([(&survival::DEF, survival_table(t)), (&tails::DEF, tails_table(t))]);
    }
    for (def, t) in &tables {
        def.check(t).map_err(|message| AnalysisError::Write { path: def.file.into(), message })?;
    }
    Ok(tables)
}

/// Write the files of an analysis into the existing directory `dir` (named `shown` in errors).
pub fn write_into(a: &Analysis, dir: &Path, shown: &Path) -> Result<(), AnalysisError> {
    for (def, table) in tables(a)? {
        table.write_parquet(&dir.join(def.file)).map_err(|e| werr(&shown.join(def.file), &e))?;
    }
    std::fs::write(dir.join("summary.json"), summary(a).to_json()).map_err(|e| werr(&shown.join("summary.json"), &e))?;
    std::fs::write(dir.join("table1.md"), table1_markdown(a)).map_err(|e| werr(&shown.join("table1.md"), &e))?;
    if let Some(src) = &a.dataset.trajectories {
        for (from, to) in TRAJECTORY_TABLES {
            std::fs::copy(src.join(from), dir.join(to)).map_err(|e| werr(&shown.join(to), &e))?;
        }
    }
    Ok(())
}
