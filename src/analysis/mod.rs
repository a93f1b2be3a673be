//! The `analyze` stage: a dataset in, tidy statistics tables out.
//!
//! One streaming pass over the dataset (see [`frame`]) accumulates, in realization order, the
//! mergeable moments of every series, the exact distributions of the counts, and dyadic histogram
//! sketches of the continuous series and of the requested pairs ([`sketch`]). The histograms, the
//! mode, the independence tests and the growth regressions are then computed from those
//! summaries, and everything is written atomically into ADIR.
//!
//! **Truncated intervals.** The interval running at t_a is cut there; its length is a censored
//! observation, not a draw of D_k or H_k, so it is *excluded* from the statistics of D_k / H_k
//! (column `n_truncated_excluded` counts them). Start instants T_k, L_k are never censored and
//! are always included.

pub mod accum;
pub mod density;
pub mod frame;
pub mod growth;
pub mod independence;
pub mod jackknife;
pub mod input;
pub mod output;
pub mod paper;
pub mod series;
pub mod sketch;
pub mod summary;
pub mod sweep;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use accum::{Histogram, Moments};
use frame::Batch;
use growth::{Line, Renewal};
use independence::Independence;
use input::{Dataset, InputError};
use sketch::{Sketch, Sketch2};
use series::{Pair, Series, Variable};

/// How to analyse.
#[derive(Debug, Clone)]
pub struct Options {
    /// Largest event index k analysed for T_k, L_k, D_k, H_k (and Y_k).
    pub max_index: u32,
    /// Fixed number of histogram bins (default: Scott's rule, see [`density`]).
    pub bins: Option<usize>,
    /// Joint histograms and independence tests.
    pub pairs: Vec<Pair>,
    /// Permutations for the mutual-information null.
    pub permutations: u32,
    /// Analyse a dataset with missing realization ranges (recorded in `summary.json`).
    pub allow_partial: bool,
    /// Show a progress bar on stderr while reading.
    pub progress: bool,
}

/// Default largest event index analysed (the paper's Table 1 goes to 6).
pub const DEFAULT_MAX_INDEX: u32 = 6;
/// Largest `--max-index` (each index adds four series with their sketches).
pub const MAX_INDEX: u32 = 1000;

/// Default number of permutations of the mutual-information null.
pub const DEFAULT_PERMUTATIONS: u32 = 199;

/// Most histogram bins (`--bins`).
pub const MAX_BINS: usize = 100_000;

impl Options {
    /// Refuse options that cannot work, before any input is read.
    pub fn check(&self) -> Result<(), AnalysisError> {
        if self.max_index == 0 || self.max_index > MAX_INDEX {
            return Err(AnalysisError::Options(format!("--max-index {}: must be between 1 and {MAX_INDEX}", self.max_index)));
        }
        if let Some(b) = self.bins.filter(|&b| b == 0 || b > MAX_BINS) {
            return Err(AnalysisError::Options(format!("--bins {b}: must be between 1 and {MAX_BINS}")));
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        let pair = |a: &str, b: &str| Pair(a.parse().unwrap(), b.parse().unwrap());
        Options {
            max_index: DEFAULT_MAX_INDEX,
            bins: None,
            pairs: vec![pair("T1", "T2"), pair("D1", "D2")],
            permutations: DEFAULT_PERMUTATIONS,
            allow_partial: false,
            progress: false,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("reading {}: {message}", path.display())]
    Read { path: PathBuf, message: String },
    #[error("writing {}: {message}", path.display())]
    Write { path: PathBuf, message: String },
    #[error("{0}")]
    Options(String),
    #[error(transparent)]
    Out(#[from] crate::outdir::OutDirError),
}

/// Statistics of one series.
#[derive(Debug, Clone)]
pub struct SeriesStats {
    pub series: Series,
    pub moments: Moments,
    pub truncated: u64,
    pub mode: Option<f64>,
    /// 1-D histogram (for counts: unit bins centred on the integers).
    pub histogram: Histogram,
    /// the moments and the mode without each realization-index group ([`jackknife`])
    pub loo_moments: Vec<Moments>,
    pub loo_mode: Vec<Option<f64>>,
}

impl SeriesStats {
    /// The 95 % jackknife interval of a statistic of the moments.
    pub fn interval(&self, stat: impl Fn(&Moments) -> Option<f64>) -> Option<jackknife::Interval> {
        jackknife::interval(stat(&self.moments), &self.loo_moments.iter().map(&stat).collect::<Vec<_>>())
    }

    /// The 95 % jackknife interval of the mode; for a count (whose mode is an integer) rounded
    /// outward to integers.
    pub fn mode_interval(&self) -> Option<jackknife::Interval> {
        let i = jackknife::interval(self.mode, &self.loo_mode)?;
        Some(if self.series.var.is_count() { (i.0.floor(), i.1.ceil()) } else { i })
    }
}

/// A joint histogram on the two series' 1-D bins.
#[derive(Debug, Clone)]
pub struct Joint {
    pub pair: Pair,
    pub x: Histogram,
    pub y: Histogram,
    pub counts: Vec<Vec<u64>>,
    pub test: Option<Independence>,
}

/// OLS of a statistic of T_k or L_k over k.
#[derive(Debug, Clone)]
pub struct GrowthFit {
    pub var: Variable,
    pub statistic: &'static str,
    pub line: Line,
    /// 95 % jackknife interval of the slope
    pub slope_interval: Option<jackknife::Interval>,
}

/// Everything `analyze` computes.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub dataset: Dataset,
    pub options: Options,
    pub stats: Vec<SeriesStats>,
    pub joints: Vec<Joint>,
    pub growth: Vec<GrowthFit>,
    pub renewal: Option<Renewal>,
    pub convergence: Vec<Convergence>,
}

/// The running mean of one series against the number of realizations read, at a geometric grid
/// of realization counts (10 per decade from 10, and the last): (realizations, values, mean,
/// standard error of the mean).
#[derive(Debug, Clone, PartialEq)]
pub struct Convergence {
    pub series: Series,
    pub points: Vec<(u64, u64, f64, Option<f64>)>,
}

/// The series of the convergence figure.
pub const CONVERGENCE: [(Variable, Option<u32>); 4] = [(Variable::St, None), (Variable::T, Some(1)), (Variable::D, Some(1)), (Variable::H, Some(1))];

/// The next checkpoint of the convergence grid after `n` realizations: round(10^(j/10)) ≥ 10.
fn next_checkpoint(n: u64) -> u64 {
    let mut j = 10.0;
    loop {
        let c = 10f64.powf(j / 10.0).round() as u64;
        if c > n {
            return c;
        }
        j += 1.0;
    }
}

impl Analysis {
    pub fn get(&self, series: Series) -> Option<&SeriesStats> {
        self.stats.iter().find(|s| s.series == series)
    }
}

/// The series analysed for a dataset.
fn series_list(opts: &Options, switch_times: bool) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for var in Variable::INDEXED {
        if var == Variable::Y && !switch_times {
            continue;
        }
        out.extend((1..=opts.max_index).map(|k| Series::at(var, k)));
    }
    for p in &opts.pairs {
        for s in [p.0, p.1] {
            if !out.contains(&s) {
                out.push(s);
            }
        }
    }
    out.extend(Variable::COUNTS.map(Series::count));
    out.push(Series::count(Variable::StickTime));
    out
}

/// Whether row `r`'s value of series `s` is the truncated last interval (see the module docs).
fn truncated(s: &Series, b: &Batch, r: usize) -> bool {
    let (nt, nl) = (b.n_stick[r] as u64, b.n_slip[r] as u64);
    match (s.var, s.index) {
        (Variable::D, Some(k)) => crate::events::censored(true, u64::from(k), nt, nl, b.last_truncated[r]),
        (Variable::H, Some(k)) => crate::events::censored(false, u64::from(k), nt, nl, b.last_truncated[r]),
        _ => false,
    }
}

/// Value of series `i` in row `r`, unless absent or truncated.
fn value(series: &[Series], i: usize, b: &Batch, r: usize) -> Option<f64> {
    b.values[i][r].filter(|_| !truncated(&series[i], b, r))
}

/// Call `value(i, g, x)` for every present, non-truncated value of series `i` in the batch, g
/// the row's jackknife group (and `cut(i)` for each truncated one), series by series, rows in
/// dataset order.
fn for_each_value(series: &[Series], b: &Batch, mut value: impl FnMut(usize, usize, f64), mut cut: impl FnMut(usize)) {
    for (i, s) in series.iter().enumerate() {
        for (r, v) in b.values[i].iter().enumerate() {
            match *v {
                Some(_) if truncated(s, b, r) => cut(i),
                Some(x) => value(i, jackknife::group(b.first + r as u64), x),
                None => {}
            }
        }
    }
}

/// Stream the dataset through `state`, file by file in realization order; a failure names the
/// file. `progress` shows a bar of realizations read.
fn pass<S>(data: &Dataset, series: &[Series], progress: bool, mut state: S, step: fn(&mut S, &[Series], &Batch)) -> Result<S, AnalysisError> {
    let bar = if progress { indicatif::ProgressBar::new(data.rows) } else { indicatif::ProgressBar::hidden() };
    bar.set_style(
        indicatif::ProgressStyle::with_template("analyze {bar:40} {pos}/{len} realizations  {per_sec}  eta {eta}").expect("valid template"),
    );
    for (i, path) in data.files.iter().enumerate() {
        let part = frame::FilePart { path, rows: data.file_rows[i], first: data.file_starts[i], stamp: data.file_stamps[i], horizon: data.scenario.run.duration };
        frame::stream_file(&part, series, data.switch_times, &mut |b: &Batch| {
            step(&mut state, series, b);
            bar.inc(b.n_stick.len() as u64);
        })
        .map_err(|e| AnalysisError::Read { path: path.clone(), message: e.to_string() })?;
    }
    bar.finish_and_clear();
    Ok(state)
}

/// Everything one pass over the data accumulates.
struct Accumulated {
    moments: Vec<Moments>,
    n_cut: Vec<u64>,
    /// exact distributions of the counts S_T, S_L, Q
    pmf: Vec<BTreeMap<i64, u64>>,
    /// sketches of the continuous series (None for counts)
    sketches: Vec<Option<Sketch>>,
    /// (x series, y series, joint sketch) per requested pair
    joints: Vec<(usize, usize, Sketch2)>,
    /// per jackknife group: moments, and sketches or count distributions
    group_moments: Vec<Vec<Moments>>,
    group_sketches: Vec<Option<Vec<Sketch>>>,
    group_pmf: Vec<Vec<BTreeMap<i64, u64>>>,
    /// per convergence series: (series position, running moments, next checkpoint, points)
    convergence: Vec<(usize, Moments, u64, Vec<(u64, u64, f64, Option<f64>)>)>,
    /// realizations read so far
    read: u64,
}

/// Analyse the dataset below `dir` (one scenario; see [`sweep`] for parameter sweeps).
pub fn analyze(dir: &Path, opts: &Options) -> Result<Analysis, AnalysisError> {
    analyze_dataset(input::open_partial(dir, opts.allow_partial)?, opts)
}

/// Analyse one checked dataset.
pub fn analyze_dataset(data: Dataset, opts: &Options) -> Result<Analysis, AnalysisError> {
    opts.check()?;
    if let Some(p) = opts.pairs.iter().find(|p| [p.0, p.1].iter().any(|s| s.var == Variable::Y) && !data.switch_times) {
        return Err(AnalysisError::Options(format!(
            "--pair {},{}: the dataset has no switch_times (simulate with output.switch_times = true)",
            p.0, p.1
        )));
    }
    let series = series_list(opts, data.switch_times);
    let n = series.len();
    let scale = data.scenario.run.duration;
    let index_of = |s: &Series| series.iter().position(|x| x == s).expect("pair series are analysed");

    // One pass: moments, exact PMFs of the counts, dyadic sketches (see `sketch`).
    let start = Accumulated {
        moments: vec![Moments::default(); n],
        n_cut: vec![0; n],
        pmf: vec![BTreeMap::new(); n],
        sketches: series.iter().map(|s| (!s.var.is_count()).then(|| Sketch::new(scale))).collect(),
        joints: opts.pairs.iter().map(|p| (index_of(&p.0), index_of(&p.1), Sketch2::new(scale))).collect(),
        group_moments: vec![vec![Moments::default(); jackknife::GROUPS]; n],
        group_sketches: series.iter().map(|s| (!s.var.is_count()).then(|| vec![Sketch::new(scale); jackknife::GROUPS])).collect(),
        group_pmf: vec![vec![BTreeMap::new(); jackknife::GROUPS]; n],
        convergence: CONVERGENCE
            .iter()
            .filter_map(|(v, k)| series.iter().position(|s| s.var == *v && s.index == *k))
            .map(|i| (i, Moments::default(), next_checkpoint(0), Vec::new()))
            .collect(),
        read: 0,
    };
    let acc = pass(&data, &series, opts.progress, start, |st, series, b| {
        let Accumulated { moments, n_cut, pmf, sketches, joints, group_moments, group_sketches, group_pmf, convergence, read } = st;
        // running means, in realization order, recorded at the checkpoints
        for (i, m, next, points) in convergence.iter_mut() {
            for r in 0..b.n_stick.len() {
                if let Some(x) = value(series, *i, b, r) {
                    m.add(x);
                }
                let count = *read + r as u64 + 1;
                if count == *next {
                    points.push((count, m.n, m.mean, m.mean_se()));
                    *next = next_checkpoint(count);
                }
            }
        }
        *read += b.n_stick.len() as u64;
        for_each_value(
            series,
            b,
            |i, g, x| {
                moments[i].add(x);
                group_moments[i][g].add(x);
                match (&mut sketches[i], &mut group_sketches[i]) {
                    (Some(sketch), Some(groups)) => {
                        sketch.add(x);
                        groups[g].add(x);
                    }
                    _ => {
                        *pmf[i].entry(x as i64).or_default() += 1;
                        *group_pmf[i][g].entry(x as i64).or_default() += 1;
                    }
                }
            },
            |i| n_cut[i] += 1,
        );
        for (i, j, sketch) in joints.iter_mut() {
            for r in 0..b.n_stick.len() {
                if let (Some(x), Some(y)) = (value(series, *i, b, r), value(series, *j, b, r)) {
                    sketch.add(x, y);
                }
            }
        }
    })?;

    // Histogram grids: power-of-two widths no finer than any sketch holding the series.
    let hist: Vec<Histogram> = (0..n)
        .map(|i| {
            let m = &acc.moments[i];
            match &acc.sketches[i] {
                None => {
                    // unit bins centred on the integers, filled from the exact distribution
                    let (lo, hi) = if m.n > 0 { (m.min, m.max) } else { (0.0, 0.0) };
                    let mut h = Histogram::new(lo - 0.5, hi + 0.5, (hi - lo) as usize + 1);
                    for (&v, &c) in &acc.pmf[i] {
                        h.counts[(v - lo as i64) as usize] += c;
                    }
                    h
                }
                Some(sketch) => {
                    let mut finest = sketch.exponent();
                    for (x, y, joint) in &acc.joints {
                        let (ex, ey) = joint.exponents();
                        finest = finest.max(if *x == i { ex } else { i32::MIN }).max(if *y == i { ey } else { i32::MIN });
                    }
                    sketch.histogram(density::grid_exponent(m, opts.bins, finest))
                }
            }
        })
        .collect();

    let stats: Vec<SeriesStats> = series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let m = acc.moments[i];
            let pmf_mode = |pmf: &BTreeMap<i64, u64>| pmf.iter().max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0))).map(|(v, _)| *v as f64);
            let mode = match &acc.sketches[i] {
                Some(sketch) => density::kde_mode(&sketch.fine(), &m),
                None => pmf_mode(&acc.pmf[i]),
            };
            let loo_moments = jackknife::leave_one_out(&acc.group_moments[i], &Moments::default(), Moments::merge);
            let loo_mode = match &acc.group_sketches[i] {
                Some(groups) => jackknife::leave_one_out(groups, &Sketch::new(scale), Sketch::merge)
                    .iter()
                    .zip(&loo_moments)
                    .map(|(sk, lm)| density::kde_mode(&sk.fine(), lm))
                    .collect(),
                None => acc.group_pmf[i]
                    .iter()
                    .map(|gp| {
                        // the whole distribution minus the group's (exact for counts)
                        let mut rest = acc.pmf[i].clone();
                        for (v, c) in gp {
                            *rest.entry(*v).or_default() -= c;
                        }
                        rest.retain(|_, c| *c > 0);
                        pmf_mode(&rest)
                    })
                    .collect(),
            };
            SeriesStats { series: *s, moments: m, truncated: acc.n_cut[i], mode, histogram: hist[i].clone(), loo_moments, loo_mode }
        })
        .collect();

    let rows = data.rows.max(1);
    // Cap the permutation work at about 2e7 shuffled labels per test (at least 19 permutations).
    let permutations = opts.permutations.min((2e7 / rows as f64).max(19.0) as u32);
    let joints = opts
        .pairs
        .iter()
        .zip(&acc.joints)
        .map(|(p, (i, j, sketch))| {
            let counts = sketch.table(&hist[*i], &hist[*j]);
            Joint {
                pair: *p,
                x: hist[*i].clone(),
                y: hist[*j].clone(),
                test: independence::test(&counts, permutations, data.scenario.run.seed),
                counts,
            }
        })
        .collect();

    // The growth lines and the renewal check, from the whole sample's moments (`None`) or from
    // those without jackknife group g (`Some(g)`).
    let moments_of = |s: &SeriesStats, g: Option<usize>| g.map_or(s.moments, |g| s.loo_moments[g]);
    let fit = |var: Variable, statistic: &str, g: Option<usize>| -> Option<Line> {
        let f: fn(&Moments) -> Option<f64> = if statistic == "mean" { |m| (m.n > 0).then_some(m.mean) } else { Moments::variance };
        let pts: Vec<(f64, f64)> = stats
            .iter()
            .filter(|s| s.series.var == var && s.series.index.is_some_and(|k| k <= opts.max_index))
            .filter_map(|s| Some((s.series.index? as f64, f(&moments_of(s, g))?)))
            .collect();
        growth::ols(&pts)
    };
    let groups = 0..jackknife::GROUPS;
    let mut growth = Vec::new();
    for var in [Variable::T, Variable::L] {
        for statistic in ["mean", "variance"] {
            if let Some(line) = fit(var, statistic, None) {
                let loo: Vec<Option<f64>> = groups.clone().map(|g| fit(var, statistic, Some(g)).map(|l| l.slope)).collect();
                growth.push(GrowthFit { var, statistic, slope_interval: jackknife::interval(Some(line.slope), &loo), line });
            }
        }
    }
    let st = stats.iter().find(|s| s.series == Series::count(Variable::St));
    let renewal_at = |g: Option<usize>| -> Option<Renewal> {
        let st = moments_of(st?, g);
        growth::renewal(data.scenario.run.duration, &fit(Variable::T, "mean", g)?, &fit(Variable::T, "variance", g)?, st.mean, st.variance().unwrap_or(0.0))
    };
    let renewal = renewal_at(None).map(|r| {
        let loo: Vec<Option<Renewal>> = groups.clone().map(|g| renewal_at(Some(g))).collect();
        Renewal {
            predicted_mean_interval: jackknife::interval(Some(r.predicted_mean), &loo.iter().map(|x| x.as_ref().map(|x| x.predicted_mean)).collect::<Vec<_>>()),
            predicted_variance_interval: jackknife::interval(Some(r.predicted_variance), &loo.iter().map(|x| x.as_ref().map(|x| x.predicted_variance)).collect::<Vec<_>>()),
            ..r
        }
    });
    let convergence = acc
        .convergence
        .iter()
        .map(|(i, m, _, points)| {
            let mut points = points.clone();
            if points.last().is_none_or(|p| p.0 < acc.read) {
                points.push((acc.read, m.n, m.mean, m.mean_se()));
            }
            Convergence { series: series[*i], points }
        })
        .collect();
    let options = Options { permutations, ..opts.clone() };
    Ok(Analysis { dataset: data, options, stats, joints, growth, renewal, convergence })
}
