//! Parameter sweeps: one full analysis per cell, and a table of per-cell summaries.
//!
//! A sweep dataset holds one directory per cell, `DIR/key=value/…/part-*.parquet` (hive layout).
//! `analyze` writes each cell's analysis to `ADIR/key=value/…/` (so `ADIR/**/moments.parquet`
//! reads as one table with the keys as hive columns) and `ADIR/sweep.parquet`, one row per cell:
//! the swept keys, `realizations`, `mean_S_T` (± `mean_S_T_se`), `stick_fraction` (mean time
//! stuck / t_a), `mean_D` and `mean_H` (D_1..D_K and H_1..H_K pooled: they are identically
//! distributed), `var_T_slope` (± `var_T_slope_se`, the growth of Var T_k with k), and
//! `mean_T_slope` (the mean cycle length), both over the indices that
//! [`super::GROWTH_MIN_REACHED`] of the cell's realizations reach, and `T_k_max`, the largest;
//! then, each with `_lo`/`_hi` (95 %): `sticks_per_second` (sticks per second, E[S_T]/t_a),
//! `longest_stick` (its mean, s), `severity` (its mean; schema v3), and from the tails
//! `breakaway_fraction`, `p_longest_stick_gt_<T>` and `p_severity_gt_<s>` for the asked thresholds.

use std::path::Path;

use super::accum::Moments;
use super::input::open_cells;
use super::{analyze_cells, output, Analysis, AnalysisError, Options};
use crate::observables::Observable;
use crate::outdir::{Kind, StagedDir};
use crate::table::{Col, Table};

/// The summary of one sweep cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellSummary {
    /// (key, value) parsed from the cell path
    pub keys: Vec<(String, f64)>,
    pub realizations: u64,
    pub mean_st: f64,
    pub mean_st_se: Option<f64>,
    pub stick_fraction: f64,
    /// 95 % jackknife interval of the stick fraction
    pub stick_fraction_interval: Option<(f64, f64)>,
    pub mean_d: Option<f64>,
    pub mean_h: Option<f64>,
    pub var_t_slope: Option<f64>,
    pub var_t_slope_se: Option<f64>,
    pub mean_t_slope: Option<f64>,
    /// the largest index k the growth fits use (those [`super::GROWTH_MIN_REACHED`] of the
    /// realizations reach); None without a fit
    pub t_k_max: Option<u32>,
    /// each with its 95 % interval: sticks per second E[S_T]/t_a [1/s], the mean longest stick
    /// [s], the mean severity, and (from the tails) the fraction of sticks ending by breakaway
    /// and P(longest stick > T), P(severity > s) as (column name, value, interval)
    pub sticks_per_second: Estimate,
    pub longest_stick: Estimate,
    pub severity: Estimate,
    pub tails: Vec<(String, Estimate)>,
}

/// A value and its 95 % interval (None: not available for the cell).
pub type Estimate = Option<(f64, Option<(f64, f64)>)>;

/// The mean of a scalar observable with its interval.
fn mean_of(a: &Analysis, o: Observable, scale: f64) -> Estimate {
    let s = a.get(o)?;
    (s.moments.n > 0).then(|| (s.moments.mean / scale, s.interval(|m| (m.n > 0).then_some(m.mean)).map(|(lo, hi)| (lo / scale, hi / scale))))
}

/// The mean of a duration family's values over every analysed index k (D_1..D_K pooled).
fn pooled(a: &Analysis, family: Observable) -> Option<f64> {
    let m = a
        .stats
        .iter()
        .filter(|s| s.series.index().is_some() && s.series.variable() == family.variable())
        .fold(Moments::default(), |acc, s| acc.merge(&s.moments));
    (m.n > 0).then_some(m.mean)
}

/// Order sweep cells by their keys' numeric values (`switch_rate=5` before `switch_rate=20`),
/// component by component; a value that is not a number sorts after the numbers, by text.
pub fn cell_order(a: &str, b: &str) -> std::cmp::Ordering {
    let parts = |p: &str| -> Vec<(String, Option<f64>, String)> {
        p.split('/')
            .filter(|c| !c.is_empty())
            .map(|c| match c.split_once('=') {
                Some((k, v)) => (k.to_string(), v.parse::<f64>().ok().filter(|x| x.is_finite()), v.to_string()),
                None => (c.to_string(), None, String::new()),
            })
            .collect()
    };
    let (pa, pb) = (parts(a), parts(b));
    for ((ka, xa, ta), (kb, xb, tb)) in pa.iter().zip(&pb) {
        let o = ka.cmp(kb).then_with(|| match (xa, xb) {
            (Some(x), Some(y)) => x.total_cmp(y),
            (Some(_), None) => std::cmp::Ordering::Less,
            (None, Some(_)) => std::cmp::Ordering::Greater,
            (None, None) => ta.cmp(tb),
        });
        if o.is_ne() {
            return o;
        }
    }
    pa.len().cmp(&pb.len())
}

/// Summarize one cell's analysis.
pub fn summarize(path: &str, a: &Analysis) -> CellSummary {
    let keys = path.split('/').filter_map(|part| part.split_once('=')).map(|(k, v)| (k.to_string(), v.parse().unwrap_or(f64::NAN))).collect();
    let st = a.get(Observable::Sticks).map(|s| s.moments).unwrap_or_default();
    let stick = a.get(Observable::StickFraction).map(|s| s.moments).unwrap_or_default();
    let line = |stat: &str| a.growth.iter().find(|g| g.family == Observable::StickStart(1) && g.statistic == stat).map(|g| g.line.clone());
    CellSummary {
        keys,
        realizations: a.dataset.rows,
        mean_st: st.mean,
        mean_st_se: st.mean_se(),
        stick_fraction: stick.mean,
        stick_fraction_interval: mean_of(a, Observable::StickFraction, 1.0).and_then(|e| e.1),
        mean_d: pooled(a, Observable::StickDuration(1)),
        mean_h: pooled(a, Observable::SlipDuration(1)),
        var_t_slope: line("variance").map(|l| l.slope),
        var_t_slope_se: line("variance").and_then(|l| l.slope_se),
        mean_t_slope: line("mean").map(|l| l.slope),
        t_k_max: a.growth.iter().find(|g| g.family == Observable::StickStart(1)).map(|g| g.k_max),
        sticks_per_second: mean_of(a, Observable::Sticks, a.dataset.scenario.run.duration),
        longest_stick: mean_of(a, Observable::LongestStick, 1.0),
        severity: mean_of(a, Observable::Severity, 1.0),
        tails: a
            .tails
            .iter()
            .flat_map(|t| &t.exceedances)
            .map(|e| {
                let name = match e.threshold {
                    Some(x) => format!("p_{}_gt_{}", e.statistic, crate::scenario::short(x)),
                    None => e.statistic.to_string(),
                };
                (name, Some((e.value, e.interval)))
            })
            .collect(),
    }
}

crate::table::table! {
    /// `sweep.parquet`: one row per cell of a sweep. Its columns are the swept keys' first (one
    /// float64 each, named by the key's last component), then these, then the tails' exceedance
    /// fractions of the analysis (`breakaway_fraction`, `p_longest_stick_gt_T`, …, each with
    /// `_lo` and `_hi`) — the ones a sweep has ([`crate::table::Def::check_span`]).
    sweep = "sweep.parquet", "one row per cell of a sweep: the swept keys' values, then what each cell's analysis found" {
        REALIZATIONS: "realizations", Int, "realizations analysed in the cell";
        MEAN_S_T: "mean_S_T", Float, "E[S_T], the mean number of sticks";
        MEAN_S_T_SE: "mean_S_T_se", Float, "its standard error";
        STICK_FRACTION: "stick_fraction", Float, "the mean fraction of [0, t_a] stuck";
        STICK_FRACTION_LO: "stick_fraction_lo", Float, "its 95 % interval, lower end";
        STICK_FRACTION_HI: "stick_fraction_hi", Float, "its 95 % interval, upper end";
        MEAN_D: "mean_D", Float, "E[D], the mean stick duration, pooled over k [s]";
        MEAN_H: "mean_H", Float, "E[H], the mean slip duration, pooled over k [s]";
        VAR_T_SLOPE: "var_T_slope", Float, "the slope of Var T_k in k [s²]";
        VAR_T_SLOPE_SE: "var_T_slope_se", Float, "its standard error [s²]";
        MEAN_T_SLOPE: "mean_T_slope", Float, "the slope of E[T_k] in k: the mean cycle E[D] + E[H] [s]";
        T_K_MAX: "T_k_max", Int, "the largest k the fits use";
        STICKS_PER_SECOND: "sticks_per_second", Float, "E[S_T]/t_a [1/s]";
        STICKS_PER_SECOND_LO: "sticks_per_second_lo", Float, "its 95 % interval, lower end";
        STICKS_PER_SECOND_HI: "sticks_per_second_hi", Float, "its 95 % interval, upper end";
        LONGEST_STICK: "longest_stick", Float, "the mean longest stick [s]";
        LONGEST_STICK_LO: "longest_stick_lo", Float, "its 95 % interval, lower end";
        LONGEST_STICK_HI: "longest_stick_hi", Float, "its 95 % interval, upper end";
        SEVERITY: "severity", Float, "the mean severity";
        SEVERITY_LO: "severity_lo", Float, "its 95 % interval, lower end";
        SEVERITY_HI: "severity_hi", Float, "its 95 % interval, upper end";
    }
}

/// The per-cell summaries as a table.
pub fn table(cells: &[CellSummary]) -> Table {
    let mut t = Table::default();
    for (i, (key, _)) in cells.first().map(|c| c.keys.clone()).unwrap_or_default().iter().enumerate() {
        t.push(key, Col::Float(cells.iter().map(|c| c.keys.get(i).map(|k| k.1)).collect()));
    }
    let f = |g: &dyn Fn(&CellSummary) -> Option<f64>| Col::Float(cells.iter().map(|c| g(c).filter(|x| x.is_finite())).collect());
    t.put(&sweep::REALIZATIONS, Col::Int(cells.iter().map(|c| Some(c.realizations as i64)).collect()))
        .put(&sweep::MEAN_S_T, f(&|c| Some(c.mean_st)))
        .put(&sweep::MEAN_S_T_SE, f(&|c| c.mean_st_se))
        .put(&sweep::STICK_FRACTION, f(&|c| Some(c.stick_fraction)))
        .put(&sweep::STICK_FRACTION_LO, f(&|c| c.stick_fraction_interval.map(|i| i.0)))
        .put(&sweep::STICK_FRACTION_HI, f(&|c| c.stick_fraction_interval.map(|i| i.1)))
        .put(&sweep::MEAN_D, f(&|c| c.mean_d))
        .put(&sweep::MEAN_H, f(&|c| c.mean_h))
        .put(&sweep::VAR_T_SLOPE, f(&|c| c.var_t_slope))
        .put(&sweep::VAR_T_SLOPE_SE, f(&|c| c.var_t_slope_se))
        .put(&sweep::MEAN_T_SLOPE, f(&|c| c.mean_t_slope))
        .put(&sweep::T_K_MAX, Col::Int(cells.iter().map(|c| c.t_k_max.map(i64::from)).collect()));
    let estimate = |t: &mut Table, name: &str, get: &dyn Fn(&CellSummary) -> Estimate| {
        t.push(name, f(&|c| get(c).map(|e| e.0)));
        t.push(&format!("{name}_lo"), f(&|c| get(c).and_then(|e| e.1).map(|i| i.0)));
        t.push(&format!("{name}_hi"), f(&|c| get(c).and_then(|e| e.1).map(|i| i.1)));
    };
    estimate(&mut t, sweep::STICKS_PER_SECOND.name, &|c| c.sticks_per_second);
    estimate(&mut t, sweep::LONGEST_STICK.name, &|c| c.longest_stick);
    estimate(&mut t, sweep::SEVERITY.name, &|c| c.severity);
    // the tails' columns, in the order of the first cell that has each
    let mut names: Vec<&String> = Vec::new();
    for (n, _) in cells.iter().flat_map(|c| &c.tails) {
        if !names.contains(&n) {
            names.push(n);
        }
    }
    for n in names {
        estimate(&mut t, n, &|c| c.tails.iter().find(|(m, _)| m == n).and_then(|(_, e)| *e));
    }
    t
}

/// Analyse every cell of the dataset below `dir` into `out` (replaced when complete; none: the
/// analyses are only returned). A plain dataset (one cell at `dir` itself) gets the ordinary
/// analysis; returns the analyses by cell.
pub fn analyze_all(dir: &Path, opts: &Options, out: Option<&Path>, ctl: crate::progress::Control) -> Result<Vec<(String, Analysis)>, AnalysisError> {
    opts.check()?;
    let staged = out.map(|out| StagedDir::new(out, Kind::Analysis, "--out", &[dir])).transpose()?;
    let mut cells = open_cells(dir, opts.allow_partial)?;
    cells.sort_by(|a, b| cell_order(&a.0, &b.0));
    let (paths, datasets): (Vec<String>, Vec<_>) = cells.into_iter().unzip();
    // every cell in one scan
    let analyses = analyze_cells(datasets, opts, ctl)?;
    ctl.check()?;
    let (Some(staged), Some(out)) = (staged, out) else {
        return Ok(paths.into_iter().zip(analyses).collect());
    };
    let mut done = Vec::with_capacity(paths.len());
    for (path, a) in paths.into_iter().zip(analyses) {
        let cell_dir = staged.path().join(&path);
        std::fs::create_dir_all(&cell_dir).map_err(|e| AnalysisError::Write { path: out.join(&path), message: e.to_string() })?;
        output::write_into(&a, &cell_dir, &out.join(&path))?;
        done.push((path, a));
    }
    if done.len() > 1 || done.first().is_some_and(|(p, _)| !p.is_empty()) {
        let summaries: Vec<CellSummary> = done.iter().map(|(p, a)| summarize(p, a)).collect();
        let (file, t) = (sweep::DEF.file, table(&summaries));
        let werr = |message: String| AnalysisError::Write { path: out.join(file), message };
        sweep::DEF.check_span(&t).map_err(werr)?;
        t.write_parquet(&staged.path().join(file)).map_err(|e| werr(e.to_string()))?;
    }
    staged.commit()?;
    Ok(done)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observables::Statistic;

    #[test]
    fn the_sweeps_estimates_are_named_as_the_quantities_they_estimate() {
        assert_eq!(sweep::STICKS_PER_SECOND.name, Statistic::SticksPerSecond.name());
        assert_eq!(sweep::LONGEST_STICK.name, Observable::LongestStick.variable());
        assert_eq!(sweep::SEVERITY.name, Observable::Severity.variable());
        assert_eq!(sweep::STICK_FRACTION.name, Observable::StickFraction.variable());
    }
}
