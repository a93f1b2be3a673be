//! The `analyze` stage: a dataset in, tidy statistics tables out.
//!
//! polars computes (`query.rs`): one lazy query over `scan_parquet` of the part files, on the
//! streaming engine, aggregates per jackknife group the power sums and ranges of every analysed
//! observable ([`crate::observables`], the one home of what is measured and of the censoring
//! rule), their counts on dyadic histogram grids, the exact distributions of the counts, the
//! joint counts of the requested pairs and the running sums of the convergence table, and
//! checks every value on the way. Rust finishes on those small tables: central moments and their
//! jackknife intervals ([`jackknife`]), the sketches and histograms ([`sketch`], [`density`]),
//! kernel-density modes, independence tests ([`independence`]), growth regressions ([`growth`]);
//! everything is written atomically into ADIR ([`output`]).
//!
//! **Censored intervals.** The interval running at t_a is cut there; its length is a censored
//! observation, not a draw of D_k or H_k, so it is left out of D_k / H_k (column
//! `n_truncated_excluded` counts them); see [`crate::observables`] for the one rule.

pub mod accum;
pub(crate) mod density;
mod exact;
mod fold;
pub(crate) mod growth;
pub(crate) mod independence;
pub mod input;
pub(crate) mod jackknife;
pub mod output;
pub mod paper;
mod query;
mod rules;
pub(crate) mod sketch;
pub(crate) mod summary;
pub(crate) mod sweep;
pub mod tables;
mod tail_counts;
pub mod tails;

use std::collections::BTreeMap;
use std::path::Path;

use accum::{Histogram, Moments};
use growth::{Line, Renewal};
use independence::Independence;
use input::Dataset;
use rayon::prelude::*;
use sketch::{Sketch, Sketch2};

use crate::observables::Observable;
use crate::progress::{Cancelled, Control};

mod error;
mod options;
pub use error::AnalysisError;
pub use options::{Options, Pair, DEFAULT_MAX_INDEX, DEFAULT_PERMUTATIONS, DEFAULT_SEVERITY, GROWTH_MIN_REACHED, MAX_BINS, MAX_INDEX};

/// Statistics of one observable.
#[derive(Debug, Clone)]
pub struct SeriesStats {
    /// the observable
    pub series: Observable,
    /// its moments over the values present (censored D_k, H_k left out)
    pub moments: Moments,
    /// censored values excluded: the D_k or H_k cut at t_a (column `n_truncated_excluded`; 0 for
    /// the others)
    pub truncated: u64,
    /// realizations that have the quantity, or (D_k, H_k) its censored value: for an indexed
    /// quantity, those that reach the k-th interval
    pub reached: u64,
    /// the mode: of the kernel density estimate, or for a count the most frequent value
    pub mode: Option<f64>,
    /// 1-D histogram (for counts: unit bins centred on the integers).
    pub histogram: Histogram,
    /// the moments and the mode without each realization-index group ([`jackknife`])
    pub loo_moments: Vec<Moments>,
    /// the mode without each realization-index group (as `loo_moments`)
    pub loo_mode: Vec<Option<f64>>,
}

impl SeriesStats {
    /// The 95 % jackknife interval of a statistic of the moments.
    pub fn interval(&self, stat: impl Fn(&Moments) -> Option<f64>) -> Option<jackknife::Interval> {
        jackknife::interval(stat(&self.moments), &self.loo_moments.iter().map(&stat).collect::<Vec<_>>())
    }

    /// The 95 % interval of the skewness: the jackknife with the degrees of freedom of
    /// [`jackknife::moment_interval`] (the leave-one-group-out skewness of a heavy-tailed variable
    /// is itself heavy-tailed).
    pub fn skewness_interval(&self) -> Option<jackknife::Interval> {
        jackknife::moment_interval(self.moments.skewness(), &self.loo_moments.iter().map(Moments::skewness).collect::<Vec<_>>())
    }

    /// Whether the skewness interval is approximate: the variable's kurtosis is above
    /// [`HEAVY_TAIL`], where its measured coverage falls below 0.93.
    pub fn skewness_approximate(&self) -> bool {
        self.moments.kurtosis().is_some_and(|k| k > HEAVY_TAIL)
    }

    /// Whether the kurtosis interval is approximate: the variable's kurtosis is above
    /// [`HEAVY_TAIL`] and fewer than [`KURTOSIS_COVERED_FROM`] realizations were analysed.
    pub fn kurtosis_approximate(&self, realizations: u64) -> bool {
        self.skewness_approximate() && realizations < KURTOSIS_COVERED_FROM
    }

    /// The 95 % interval of the kurtosis: the jackknife on the log scale (the sample kurtosis is
    /// skewed to the right, more so the heavier the tail) with the degrees of freedom of
    /// [`jackknife::moment_interval`], its half-width widened by [`KURTOSIS_WIDENING`]. Measured by an earlier, pooled version of
    /// `benches/interval_coverage.py` (100 datasets of 1,500 realizations against 200,000; T_1,
    /// L_1, D_1, H_1, S_T, stick fraction): the plain jackknife covered 0.863 on the paper scene,
    /// on the log scale 0.887 (0.877 on the damped scene), and widened 0.945 (0.943). Today's
    /// coverage per column is in the book (docs/src/benchmarks.md, "Interval coverage").
    pub fn kurtosis_interval(&self) -> Option<jackknife::Interval> {
        let ln = |x: f64| (x > 0.0).then(|| x.ln());
        let t = self.moments.kurtosis().and_then(ln)?;
        let loo: Vec<Option<f64>> = self.loo_moments.iter().map(|m| m.kurtosis().and_then(ln)).collect();
        // the interval on the log scale, widened about t, mapped back
        let (a, b) = jackknife::moment_interval(Some(t), &loo)?;
        Some(((t - KURTOSIS_WIDENING * (t - a)).exp(), (t + KURTOSIS_WIDENING * (b - t)).exp()))
    }

    /// The 95 % jackknife interval of the mode; for a count (whose mode is an integer) rounded
    /// outward to integers.
    pub fn mode_interval(&self) -> Option<jackknife::Interval> {
        let i = jackknife::interval(self.mode, &self.loo_mode)?;
        Some(if self.series.is_count() { (i.0.floor(), i.1.ceil()) } else { i })
    }
}

/// A joint histogram on the two observables' 1-D bins.
#[derive(Debug, Clone)]
pub struct Joint {
    /// the two observables (x, y)
    pub pair: Pair,
    /// the 1-D bins of x
    pub x: Histogram,
    /// the 1-D bins of y
    pub y: Histogram,
    /// `counts[i][j]`: realizations with x in bin i of `x` and y in bin j of `y`
    pub counts: Vec<Vec<u64>>,
    /// the χ², G and mutual-information tests of independence (None when the table cannot be
    /// tested)
    pub test: Option<Independence>,
}

/// OLS of a statistic of T_k or L_k over the indices k that at least [`GROWTH_MIN_REACHED`] of
/// the realizations reach.
#[derive(Debug, Clone)]
pub struct GrowthFit {
    /// the family (T or L), at k = 1
    pub family: Observable,
    /// `mean` or `variance`
    pub statistic: &'static str,
    /// the fitted line of the statistic against k
    pub line: Line,
    /// the largest index k fitted
    pub k_max: u32,
    /// 95 % jackknife interval of the slope
    pub slope_interval: Option<jackknife::Interval>,
}

/// Everything `analyze` computes.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// the dataset analysed
    pub dataset: Dataset,
    /// the options used (`permutations` as capped for the dataset's size)
    pub options: Options,
    /// statistics of each observable analysed
    pub stats: Vec<SeriesStats>,
    /// joint histograms and independence tests of the requested pairs
    pub joints: Vec<Joint>,
    /// growth regressions of the mean and variance of T_k and L_k on k
    pub growth: Vec<GrowthFit>,
    /// the renewal check: S_T's mean and variance predicted from the growth of T_k beside the
    /// measured ones (None without the fits or with a slope ≤ 0)
    pub renewal: Option<Renewal>,
    /// running means of [`CONVERGENCE`]'s observables
    pub convergence: Vec<Convergence>,
    /// None when not asked for (`--no-tails`)
    pub tails: Option<tails::Tails>,
}

/// The running mean of one observable against the number of realizations read, at a geometric
/// grid of realization counts (10 per decade from 10, and the last): (realizations, values,
/// mean, standard error of the mean).
#[derive(Debug, Clone, PartialEq)]
pub struct Convergence {
    /// the observable
    pub series: Observable,
    /// (realizations read, values, running mean, standard error of the mean) at each checkpoint
    pub points: Vec<(u64, u64, f64, Option<f64>)>,
}

/// The observables of the convergence figure.
pub const CONVERGENCE: [Observable; 4] = [Observable::Sticks, Observable::StickStart(1), Observable::StickDuration(1), Observable::SlipDuration(1)];

/// The checkpoints of the convergence grid up to `n` realizations: round(10^(j/10)) for j ≥ 10.
fn checkpoints(n: u64) -> Vec<u64> {
    (10..).map(|j| 10f64.powf(j as f64 / 10.0).round() as u64).take_while(|&c| c <= n).collect()
}

impl Analysis {
    /// The statistics of `series`, if it was analysed.
    pub fn get(&self, series: Observable) -> Option<&SeriesStats> {
        self.stats.iter().find(|s| s.series == series)
    }
}

/// The factor on the half-width of the kurtosis interval (log scale): the jackknife's standard
/// error of a sample kurtosis is itself small exactly when the sample misses the tail that makes
/// the kurtosis large, so the plain interval covers less than it claims (see
/// [`SeriesStats::kurtosis_interval`] for the measurements that set it).
pub const KURTOSIS_WIDENING: f64 = 1.25;

/// The kurtosis above which a variable's skewness interval, and below
/// [`KURTOSIS_COVERED_FROM`] realizations its kurtosis interval, are flagged approximate
/// (columns `skewness_approximate`, `kurtosis_approximate`; the report does not judge them).
///
/// Measured by `benches/interval_coverage.py` (200 datasets per scene and N against 10^6
/// realizations, 2026-11-28; the book's Benchmarks, "Interval coverage"): the skewness interval
/// of the Table 1 variables with kurtosis above 3.5 (T_k, L_k, D_k, H_k) covered 0.875–0.975 on
/// the paper and damped scenes at N = 1,500 and 18,000, below 0.93 in about half of the cells;
/// that of S_T and S_L (kurtosis ≈ 3) 0.93–0.96. Their kurtosis interval covered 0.865–0.965 at
/// N = 1,500 and 0.92–0.99 at 18,000 (no cell below 0.93 by more than two binomial standard
/// errors). No interval tried reached 0.93 in every cell (the book lists them); these flags say
/// where ours does not.
pub const HEAVY_TAIL: f64 = 3.5;

/// Realizations from which the kurtosis interval of a heavy-tailed variable is not flagged
/// ([`HEAVY_TAIL`]).
pub const KURTOSIS_COVERED_FROM: u64 = 18_000;

/// The observables analysed for a dataset: T_k, L_k, D_k, H_k (and Y_k with switch times) for
/// k ≤ max_index, those of the pairs, and [`Observable::ANALYSED_SCALARS`] (those that need the
/// tails' state only with it).
fn series_list(opts: &Options, switch_times: bool, tails_state: bool) -> Vec<Observable> {
    let mut out: Vec<Observable> = Vec::new();
    for family in Observable::FAMILIES {
        if family.needs_switch_times() && !switch_times {
            continue;
        }
        out.extend((1..=opts.max_index).filter_map(|k| family.at(k)));
    }
    for p in &opts.pairs {
        for s in [p.0, p.1] {
            if !out.contains(&s) {
                out.push(s);
            }
        }
    }
    for s in Observable::ANALYSED_SCALARS.into_iter().filter(|s| tails_state || !s.needs_tails_state()) {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}

/// polars' knob of how many values of a row group one thread decodes: with its default
/// (16,777,216) a row group of 131,072 realizations (about 2.2·10^6 values per list column) is
/// decoded on one thread, so each run of the main pass (one row group, `query::RUN_ROWS`) would
/// be decoded on one core.
pub const DECODE_VALUES_PER_THREAD: &str = "POLARS_PARQUET_DECODE_TARGET_VALUES_PER_THREAD";

/// Let polars decode a row group's columns on every core ([`DECODE_VALUES_PER_THREAD`] =
/// 131,072, unless the user set it): `analyze` of 10^6 paper realizations 2.35 s against 2.62 s.
/// polars reads the variable when it plans a scan, and panics on a value that is not a whole
/// number, so a value the user set is checked (`Err`: the message). Call it before any thread
/// starts (setting the environment is not thread-safe): the CLI's `main` and the Python
/// module's initialisation do.
pub fn decode_on_every_core() -> Result<(), String> {
    match std::env::var_os(DECODE_VALUES_PER_THREAD) {
        None => std::env::set_var(DECODE_VALUES_PER_THREAD, "131072"),
        Some(v) if v.to_str().and_then(|s| s.parse::<usize>().ok()).is_some() => {}
        Some(v) => return Err(format!("{DECODE_VALUES_PER_THREAD}={}: not a whole number of values (unset it for stickslip's default)", v.to_string_lossy())),
    }
    Ok(())
}

/// Analyse the dataset below `dir` (one scenario; see [`sweep`] for parameter sweeps).
pub fn analyze(dir: &Path, opts: &Options) -> Result<Analysis, AnalysisError> {
    analyze_dataset(input::open_partial(dir, opts.allow_partial)?, opts)
}

/// Analyse one checked dataset.
pub fn analyze_dataset(data: Dataset, opts: &Options) -> Result<Analysis, AnalysisError> {
    Ok(analyze_cells(vec![data], opts, Control::silent())?.remove(0))
}

/// Analyse checked datasets (the cells of a sweep) in one scan; `ctl` is told the realizations
/// read and asked between runs of the query.
pub fn analyze_cells(cells: Vec<Dataset>, opts: &Options, ctl: Control) -> Result<Vec<Analysis>, AnalysisError> {
    opts.check()?;
    let kind = |d: &Dataset| (d.switch_times, d.tails_state);
    let (switch_times, tails_state) = kind(&cells[0]);
    if cells.iter().any(|d| kind(d) != kind(&cells[0])) {
        // cells that store switch_times have the Y_k observables, those with the tails' state
        // (schema v3) the severity and breakaways, the others not: one scan per kind
        let mut kinds: Vec<(bool, bool)> = cells.iter().map(kind).collect();
        kinds.sort_unstable();
        kinds.dedup();
        let mut indexed: Vec<Option<Dataset>> = cells.into_iter().map(Some).collect();
        let mut out: Vec<(usize, Analysis)> = Vec::new();
        for k in kinds {
            let order: Vec<usize> = (0..indexed.len()).filter(|&i| indexed[i].as_ref().is_some_and(|d| kind(d) == k)).collect();
            let data: Vec<Dataset> = order.iter().map(|&i| indexed[i].take().expect("each cell once")).collect();
            out.extend(order.into_iter().zip(analyze_cells(data, opts, ctl)?));
        }
        out.sort_by_key(|(i, _)| *i);
        return Ok(out.into_iter().map(|(_, a)| a).collect());
    }
    if let Some(p) = opts.pairs.iter().find(|p| [p.0, p.1].iter().any(|s| s.needs_switch_times()) && !switch_times) {
        return Err(AnalysisError::Options(format!("--pair {},{}: the dataset has no switch_times (simulate with output.switch_times = true)", p.0, p.1)));
    }
    if let Some(p) = opts.pairs.iter().find(|p| [p.0, p.1].iter().any(|s| s.needs_tails_state()) && !tails_state) {
        return Err(AnalysisError::Options(format!(
            "--pair {},{}: the dataset has no stick ends or severity (schema v1 or v2): simulate it again with this version",
            p.0, p.1
        )));
    }
    let series = series_list(opts, switch_times, tails_state);
    let index_of = |s: &Observable| series.iter().position(|x| x == s).expect("pair series are analysed");
    let pairs: Vec<(usize, usize)> = opts.pairs.iter().map(|p| (index_of(&p.0), index_of(&p.1))).collect();
    let convergence: Vec<usize> = CONVERGENCE.iter().filter_map(|o| series.iter().position(|s| s == o)).collect();
    let most = cells.iter().map(|d| d.rows).max().unwrap_or(0);
    let grid = checkpoints(most);
    let refs: Vec<&Dataset> = cells.iter().collect();
    let failed = |e: polars::prelude::PolarsError| {
        // polars appends the query plan to its messages: one line is what a user reads
        let full = e.to_string();
        let message = full.split("Resolved plan").next().unwrap_or(&full).lines().next().unwrap_or_default().trim().to_string();
        // a message naming a file already says where; otherwise name the dataset's first file
        let path = refs.iter().flat_map(|d| &d.files).find(|f| message.contains(&*f.to_string_lossy())).cloned();
        match path {
            Some(path) => AnalysisError::Read { message: message.replacen(&format!("{}: ", path.display()), "", 1), path },
            None => AnalysisError::Read { path: refs[0].files[0].clone(), message },
        }
    };
    // what the tails count is fixed before the scan (module docs of `tails`)
    let tail_plans: Option<Vec<tails::TailPlan>> =
        opts.tails.then(|| refs.iter().map(|d| tails::TailPlan::new(d, opts.max_index, &opts.tail)).collect::<Result<_, _>>()).transpose().map_err(failed)?;
    let plan = query::Plan { series: &series, pairs: &pairs, convergence: &convergence, checkpoints: &grid, tails: tail_plans.as_deref() };
    let mut pilots = query::pilots(&refs, &plan).map_err(failed)?;
    ctl.check()?;
    let aggregates = query::aggregate(&refs, &plan, &mut pilots, ctl).map_err(|e| if ctl.check().is_err() { Cancelled.into() } else { failed(e) })?;
    ctl.progress.finish();
    let tails: Vec<Option<tails::Tails>> =
        aggregates.iter().enumerate().map(|(c, agg)| tail_plans.as_ref().map(|p| tails::finish(&p[c], &agg.tails))).collect();
    let mut out = Vec::with_capacity(cells.len());
    for (((data, agg), pilot), tails) in cells.into_iter().zip(aggregates).zip(&pilots).zip(tails) {
        if agg.rows != data.rows {
            return Err(AnalysisError::Read { path: data.files[0].clone(), message: format!("{} rows read, the footers declare {}", agg.rows, data.rows) });
        }
        out.push(Analysis { tails, ..finish(data, opts, &series, &pairs, &grid, &agg, pilot) });
    }
    Ok(out)
}

/// The analysis of one cell from what the scan aggregated.
fn finish(
    data: Dataset,
    opts: &Options,
    series: &[Observable],
    pairs: &[(usize, usize)],
    grid: &[u64],
    agg: &query::Aggregates,
    pilot: &query::Pilot,
) -> Analysis {
    let n = series.len();
    let t_a = data.scenario.run.duration;
    let groups = 0..jackknife::GROUPS;
    let group_moments: Vec<Vec<Moments>> =
        (0..n).map(|i| agg.sums[i].iter().map(|s| s.moments(pilot.center[i], &exact::quanta(pilot.bound[i], pilot.rows))).collect()).collect();
    let moments: Vec<Moments> = group_moments.iter().map(|g| g.iter().fold(Moments::default(), |a, m| a.merge(m))).collect();
    // per group: the sketch of a continuous observable, the distribution of a count
    let group_sketches: Vec<Option<Vec<Sketch>>> = (0..n)
        .map(|i| (!series[i].is_count()).then(|| agg.bins[i].iter().map(|b| Sketch::from_counts(series[i].scale(t_a), pilot.exp[i], b)).collect()))
        .collect();
    let group_pmf: Vec<Vec<BTreeMap<i64, u64>>> = (0..n)
        .map(
            |i| if series[i].is_count() { agg.bins[i].iter().map(|b| b.iter().copied().collect()).collect() } else { vec![BTreeMap::new(); jackknife::GROUPS] },
        )
        .collect();
    let merge_pmf = |a: &BTreeMap<i64, u64>, b: &BTreeMap<i64, u64>| {
        let mut m = a.clone();
        for (v, c) in b {
            *m.entry(*v).or_default() += c;
        }
        m
    };
    let sketches: Vec<Option<Sketch>> =
        (0..n).map(|i| group_sketches[i].as_ref().map(|g| g.iter().fold(Sketch::new(series[i].scale(t_a)), |a, s| a.merge(s)))).collect();
    let pmf: Vec<BTreeMap<i64, u64>> = group_pmf.iter().map(|g| g.iter().fold(BTreeMap::new(), |a, p| merge_pmf(&a, p))).collect();
    let joints: Vec<Sketch2> = pairs.iter().enumerate().map(|(p, &(i, _))| Sketch2::from_counts(series[i].scale(t_a), pilot.joint[p], &agg.joint[p])).collect();

    // Histogram grids: power-of-two widths no finer than any sketch holding the observable.
    let hist: Vec<Histogram> = (0..n)
        .map(|i| {
            let m = &moments[i];
            match &sketches[i] {
                None => {
                    // unit bins centred on the integers, filled from the exact distribution
                    let (lo, hi) = if m.n > 0 { (m.min, m.max) } else { (0.0, 0.0) };
                    let mut h = Histogram::new(lo - 0.5, hi + 0.5, (hi - lo) as usize + 1);
                    for (&v, &c) in &pmf[i] {
                        h.counts[(v - lo as i64) as usize] += c;
                    }
                    h
                }
                Some(sketch) => {
                    let mut finest = sketch.exponent();
                    for (p, &(x, y)) in pairs.iter().enumerate() {
                        let (ex, ey) = joints[p].exponents();
                        finest = finest.max(if x == i { ex } else { i32::MIN }).max(if y == i { ey } else { i32::MIN });
                    }
                    sketch.histogram(density::grid_exponent(m, opts.bins, finest))
                }
            }
        })
        .collect();

    // (kernel-density modes on every leave-one-group-out sketch: the observables in parallel)
    let stats: Vec<SeriesStats> = series
        .par_iter()
        .enumerate()
        .map(|(i, s)| {
            let m = moments[i];
            let pmf_mode = |pmf: &BTreeMap<i64, u64>| pmf.iter().max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0))).map(|(v, _)| *v as f64);
            let mode = match &sketches[i] {
                Some(sketch) => density::kde_mode(&sketch.fine(), &m),
                None => pmf_mode(&pmf[i]),
            };
            let loo_moments = jackknife::leave_one_out(&group_moments[i], &Moments::default(), Moments::merge);
            let loo_mode = match &group_sketches[i] {
                Some(groups) => jackknife::leave_one_out(groups, &Sketch::new(s.scale(t_a)), Sketch::merge)
                    .iter()
                    .zip(&loo_moments)
                    .map(|(sk, lm)| density::kde_mode(&sk.fine(), lm))
                    .collect(),
                None => jackknife::leave_one_out(&group_pmf[i], &BTreeMap::new(), merge_pmf).iter().map(pmf_mode).collect(),
            };
            let truncated = agg.sums[i].iter().map(|g| g.cut).sum();
            SeriesStats { series: *s, moments: m, truncated, reached: m.n + truncated, mode, histogram: hist[i].clone(), loo_moments, loo_mode }
        })
        .collect();

    let rows = data.rows.max(1);
    // Cap the permutation work at about 2e7 shuffled labels per test (at least 19 permutations).
    let permutations = opts.permutations.min((2e7 / rows as f64).max(19.0) as u32);
    let joints = opts
        .pairs
        .par_iter()
        .zip(pairs)
        .zip(&joints)
        .map(|((p, &(i, j)), sketch)| {
            let counts = sketch.table(&hist[i], &hist[j]);
            Joint { pair: *p, x: hist[i].clone(), y: hist[j].clone(), test: independence::test(&counts, permutations, data.scenario.run.seed), counts }
        })
        .collect();

    // The growth lines and the renewal check, from the whole sample's moments (`None`) or from
    // those without jackknife group g (`Some(g)`).
    let moments_of = |s: &SeriesStats, g: Option<usize>| g.map_or(s.moments, |g| s.loo_moments[g]);
    // the indices the fits use: those enough realizations reach
    let fitted = |family: Observable| -> Vec<&SeriesStats> {
        (1..=opts.max_index)
            .filter_map(|k| stats.iter().find(|s| Some(s.series) == family.at(k)))
            .filter(|s| s.reached as f64 >= GROWTH_MIN_REACHED * data.rows as f64)
            .collect()
    };
    let fit = |family: Observable, statistic: &str, g: Option<usize>| -> Option<Line> {
        let f: fn(&Moments) -> Option<f64> = if statistic == "mean" { |m| (m.n > 0).then_some(m.mean) } else { Moments::variance };
        let pts: Vec<(f64, f64)> = fitted(family).iter().filter_map(|s| Some((s.series.index()? as f64, f(&moments_of(s, g))?))).collect();
        growth::ols(&pts)
    };
    let k_max = |family: Observable| fitted(family).last().and_then(|s| s.series.index()).unwrap_or(0);
    let mut growth = Vec::new();
    for family in [Observable::StickStart(1), Observable::SlipStart(1)] {
        for statistic in ["mean", "variance"] {
            if let Some(line) = fit(family, statistic, None) {
                let loo: Vec<Option<f64>> = groups.clone().map(|g| fit(family, statistic, Some(g)).map(|l| l.slope)).collect();
                growth.push(GrowthFit { family, statistic, slope_interval: jackknife::interval(Some(line.slope), &loo), line, k_max: k_max(family) });
            }
        }
    }
    let st = stats.iter().find(|s| s.series == Observable::Sticks);
    let renewal_at = |g: Option<usize>| -> Option<Renewal> {
        let st = moments_of(st?, g);
        growth::renewal(
            t_a,
            &fit(Observable::StickStart(1), "mean", g)?,
            &fit(Observable::StickStart(1), "variance", g)?,
            st.mean,
            st.variance().unwrap_or(0.0),
        )
    };
    let renewal = renewal_at(None).map(|r| {
        let loo: Vec<Option<Renewal>> = groups.clone().map(|g| renewal_at(Some(g))).collect();
        Renewal {
            predicted_mean_interval: jackknife::interval(Some(r.predicted_mean), &loo.iter().map(|x| x.as_ref().map(|x| x.predicted_mean)).collect::<Vec<_>>()),
            predicted_variance_interval: jackknife::interval(
                Some(r.predicted_variance),
                &loo.iter().map(|x| x.as_ref().map(|x| x.predicted_variance)).collect::<Vec<_>>(),
            ),
            ..r
        }
    });

    // The running means at the checkpoints: cumulative sums of the buckets between them.
    let convergence = CONVERGENCE
        .iter()
        .filter_map(|o| series.iter().position(|s| s == o))
        .enumerate()
        .map(|(slot, i)| {
            // the running sums (integers, exact) up to each checkpoint, and their moments
            let mut running = exact::Sums::default();
            let mut points = Vec::new();
            for (b, bucket) in agg.convergence[slot].iter().enumerate() {
                running.add(bucket);
                if let Some(&read) = grid.get(b).filter(|&&r| r <= data.rows) {
                    let m = running.moments(pilot.center[i], &exact::quanta(pilot.bound[i], pilot.rows));
                    points.push((read, m.n, m.mean, m.mean_se()));
                }
            }
            // the last point is the whole sample's
            let whole = moments[i];
            match points.last_mut() {
                Some(p) if p.0 == data.rows => *p = (data.rows, whole.n, whole.mean, whole.mean_se()),
                _ => points.push((data.rows, whole.n, whole.mean, whole.mean_se())),
            }
            Convergence { series: series[i], points }
        })
        .collect();
    let options = Options { permutations, ..opts.clone() };
    Analysis { dataset: data, options, stats, joints, growth, renewal, convergence, tails: None }
}
