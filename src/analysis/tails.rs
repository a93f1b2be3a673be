//! Tails: survival curves of stick and slip durations with the interval cut at t_a treated as
//! censored, an exact-in-t conditional estimator of the stick tail, and the extremes.
//!
//! Counted in the analysis' one scan (`query.rs`, keys and columns in `tail_counts.rs`): the
//! durations, one integer key per interval — its time cell, index k, whether it is the censored
//! one and its jackknife group — counted per key (per batch, then summed by polars); the stick
//! entries (x, belt velocity), one key per entry with the bin of its holding time and its belt
//! state; and per group the exceedances of the longest stick and the severity and the stick
//! ends by breakaway. Rust finishes on those counts ([`finish`]), whose plan ([`TailPlan`]) is
//! fixed before the scan.
//!
//! **Time cells.** Durations are counted on cells of width ρ = t_a 2^-16 (0.15 ms at t_a = 10 s)
//! split at the user's times τ (`--tail-times`): d is in cell φ(d) = ⌊d/ρ⌋ + #{τ ≤ d}, so every
//! cell edge and every τ is a boundary, and a curve read at a grid point or at a τ counts exactly
//! the durations below it (reading it at ⌊t/ρ⌋ρ instead biased P(D > t) up by f(t)·ρ: 0.5 % at
//! t = 0.5 s in a 100 s window). Ties within a cell follow the usual convention: events before
//! censorings.
//!
//! **Kaplan–Meier (product limit).** With n_c intervals at risk (duration ≥ the cell) and e_c of
//! them ending in cell c, `S(t) = Π_{cells before t} (1 − e_c / n_c)`; a censored interval (the
//! one running at t_a, whose length is only a lower bound) leaves the risk set without an event.
//! It estimates P(D > t) for the duration D of a stick begun in [0, t_a], however long it lasts,
//! when a stick's duration does not depend on when it began; near t = 0 the law of the entry
//! state still changes with time, so in a short window (where early sticks are the only ones
//! observed long) it can differ slightly from the conditional estimator below, which has no such
//! assumption.
//! The **naive** curve drops the censored intervals and takes the empirical survival of the rest:
//! it is biased low wherever long intervals are the ones the horizon cuts.
//!
//! **Conditional (exact in t).** While stuck, the mass moves with the belt, so a stick entered at x
//! on belt velocity v_s ends at the earlier of the belt's next change — exponential with the rate
//! λ_s of leaving state s, whatever happened before (a Poisson flip process is memoryless) — and
//! the breakaway after the holding time d_s(x) = `PerUnitMass::stick_duration(x, v_s)` (closed form;
//! ∞ without a spring; damping and μ_s ≥ μ_k only move the holding limit). Hence
//!
//! ```text
//!     P(D > t | x, s) = exp(−λ_s t) · 1{t < d_s(x)},     P̂(D > t) = (1/N) Σ_i exp(−λ_{s_i} t) 1{t < d_{s_i}(x_i)}
//! ```
//!
//! averaged over the N observed stick entries: unbiased for P(D > t) (the entries are the same
//! population the product limit estimates), with no noise from the belt's clock, so it resolves
//! probabilities far below 1/N. It needs the belt to be a Poisson flip process with known rates
//! (the symmetric and the telegraph belts) and fixed parameters; it is refused, with the reason,
//! otherwise (drawn parameters change d_s per realization), and for datasets without the entry
//! state (schema v1, v2).
//!
//! **Intervals (95 %).** Realizations are independent but the sticks of one realization are not,
//! so every interval is the delete-a-group jackknife over the 20 realization groups
//! ([`super::jackknife`]), which keeps that dependence: on the complementary log-log scale
//! ln(−ln S) for the product-limit and naive curves (bands inside (0, 1)), on the log scale for
//! the conditional estimator and the exceedances. Where the estimate is 0 or 1 no band is given.
//! The jackknife needs counts per group; on the fine cells those are a hash table of ~10^6 keys
//! at 10^6 realizations (most of the tails' cost), so the estimate is taken on the fine cells with
//! the groups pooled and the leave-one-group-out curves on cells `COARSE` times wider: the
//! spread of those curves (the jackknife's variance) does not depend on reading each up to one
//! coarse cell early, and the interval is centred on the fine estimate.

use crate::observables::{Observable, Statistic};
use polars::prelude::*;

use super::input::{scan_all, Dataset};
use super::jackknife::{self, Interval, GROUPS};
pub use super::tail_counts::TailOptions;
pub(crate) use super::tail_counts::{BeltRates, Counts, TailPlan, CELLS_PER_WINDOW, COARSE};
use crate::scenario::ProcessName;
use crate::simulation::dataset::columns as name;

/// The times `reproduce` asks of the paper scene's tails [s]: up to its longest sticks (≈ 2.4 s,
/// the holding time from the far end of the stick region).
pub const PAPER_TAIL_TIMES: [f64; 5] = [0.5, 1.0, 1.5, 2.0, 2.4];

/// Points of each curve between 0 and its largest duration.
pub const CURVE_POINTS: usize = 200;

/// One survival curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// `D` or `H`
    pub variable: &'static str,
    /// k, or None pooled over every interval
    pub index: Option<u32>,
    /// `kaplan_meier`, `naive` or `conditional`
    pub method: &'static str,
    /// intervals (stick entries for `conditional`) the curve is estimated from, and how many of
    /// them are censored
    pub n: u64,
    /// of those, the censored ones (0 for `conditional`)
    pub censored: u64,
    /// (t, P(duration > t), 95 % interval)
    pub points: Vec<(f64, f64, Option<Interval>)>,
}

/// A probability or a fraction with its interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Exceedance {
    /// `longest_stick`, `severity` (P(value > threshold)) or `breakaway_fraction` (the share of
    /// sticks that end by breakaway, threshold None)
    pub statistic: &'static str,
    /// s or T of P(statistic > threshold); None for `breakaway_fraction`
    pub threshold: Option<f64>,
    /// the probability or the fraction
    pub value: f64,
    /// its 95 % jackknife interval (None where the estimate is 0 or 1)
    pub interval: Option<Interval>,
    /// realizations (sticks for the breakaway fraction) it is estimated from
    pub n: u64,
}

/// Everything the tails analysis computes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tails {
    /// survival curves of D and H, per index and pooled, by each method
    pub curves: Vec<Curve>,
    /// P(longest stick > T), P(severity > s) and the breakaway fraction
    pub exceedances: Vec<Exceedance>,
    /// why the conditional estimator was not computed (None: it was)
    pub conditional_refused: Option<String>,
}

impl Tails {
    /// What `analyze` prints of the tails: pooled P(D > t) at each of `times` by the product
    /// limit and the conditional estimator, then every exceedance, with their 95 % intervals.
    pub fn lines(&self, times: &[f64]) -> Vec<String> {
        let band = |i: Option<Interval>| i.map_or(String::new(), |(lo, hi)| format!(" [{lo:.3e}, {hi:.3e}]"));
        let at = |method: &str, time: f64| {
            let c = self.curves.iter().find(|c| c.method == method && c.variable == "D" && c.index.is_none())?;
            c.points.iter().find(|p| p.0 == time).map(|p| format!("{:.4e}{}", p.1, band(p.2)))
        };
        let mut out: Vec<String> = times
            .iter()
            .map(|&time| {
                let (km, cond) = (at("kaplan_meier", time).unwrap_or_else(|| "–".into()), at("conditional", time).unwrap_or_else(|| "–".into()));
                format!("P(D > {time} s): Kaplan-Meier {km}; conditional {cond}")
            })
            .collect();
        out.extend(self.exceedances.iter().map(|e| match e.threshold {
            Some(x) => format!("P({} > {x}) = {:.4e}{} ({} realizations)", e.statistic, e.value, band(e.interval), e.n),
            None => format!("{} = {:.4}{} ({} sticks)", e.statistic, e.value, band(e.interval), e.n),
        }));
        out
    }
}

/// The evaluation points of a curve on the cells of `cell` (`width` = `COARSE`^`coarse` ρ): the
/// grid's (t, ⌊t/ρ⌋) mapped to (t, φ(t)).
fn on_cells(grid: &[(f64, i64)], times: &[f64], coarse: bool) -> Vec<(f64, i64)> {
    let step = if coarse { COARSE } else { 1 };
    grid.iter().map(|&(t, c)| (t, c / step + times.iter().filter(|&&x| x <= t).count() as i64)).collect()
}

/// The longest stick of the dataset [s] (0 without sticks).
fn longest(data: &Dataset) -> PolarsResult<f64> {
    let df = scan_all(data, false)?.select([col(name::LONGEST_STICK).max()]).collect_with_engine(Engine::Streaming)?.unwrap_single();
    Ok(df.column(name::LONGEST_STICK)?.f64()?.get(0).unwrap_or(0.0))
}

/// The scene of the conditional estimator with its belt's flip rates (λ forward, λ reverse) and
/// speeds (v_f, v_r), or why it does not hold for this dataset.
fn conditional_scene(data: &Dataset) -> Result<(crate::simulation::keys::Scene, BeltRates), String> {
    if !data.tails_state {
        return Err("the dataset has no stick entry state (schema v1 or v2): simulate it again with this version".into());
    }
    let name = data.scenario.process_name();
    if !matches!(name, ProcessName::Symmetric | ProcessName::Telegraph) {
        return Err(format!("the belt is \"{}\", not a two-state flip process (symmetric or telegraph)", name.as_str()));
    }
    let scene = data.scenario.scene().map_err(|e| format!("its scene cannot be rebuilt: {e}"))?;
    if scene.chain.is_some() {
        return Err(crate::chain::NO_CLOSED_LAW.into());
    }
    if !scene.random.is_empty() {
        return Err("parameters are drawn per realization, so the holding time d_s(x) differs between realizations".into());
    }
    let Some(t) = scene.belt.process.two_state() else {
        return Err(format!("the belt is \"{}\", not a two-state flip process", scene.belt.process.name()));
    };
    let rates = ((t.forward_rate, t.reverse_rate), (t.forward_speed, t.reverse_speed));
    Ok((scene, rates))
}

/// What the main pass counted for one cell's tails.
#[derive(Debug, Clone, Default)]
pub(crate) struct TailCounts {
    /// per sink (`tail_counts::SINKS`), the count of each (group, k, cell, flag)
    pub sinks: Vec<super::tail_counts::HashCounts>,
    /// [group][column of `tail_counts::extreme_columns`] (with the tails' state)
    pub extremes: Vec<Vec<u64>>,
}

impl TailPlan {
    /// The plan of `data`'s tails; with the conditional estimator, its longest stick is read
    /// first (the entries are binned on the D curve's times).
    pub(crate) fn new(data: &Dataset, max_index: u32, opts: &TailOptions) -> PolarsResult<TailPlan> {
        let rho = data.scenario.run.duration / CELLS_PER_WINDOW;
        let scene = conditional_scene(data);
        let mut times: Vec<f64> = opts.times.iter().copied().filter(|t| t.is_finite() && *t > 0.0).collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        let entry_grid = match &scene {
            // (clamped: the scan that validates the longest stick, the main one, comes after)
            Ok(_) => Some(grid((longest(data)? / rho).clamp(0.0, 2.0 * CELLS_PER_WINDOW) as i64 + 1, rho, &times)),
            Err(_) => None,
        };
        Ok(TailPlan { max_index, rho, times, scene, entry_grid, tails_state: data.tails_state, opts: opts.clone() })
    }
}

/// The tails of one cell from what the main pass counted (module docs).
pub(crate) fn finish(plan: &TailPlan, counts: &TailCounts) -> Tails {
    let TailPlan { max_index, rho, ref times, ref scene, ref entry_grid, tails_state, ref opts } = *plan;
    let mut out = Tails { conditional_refused: scene.as_ref().err().cloned(), ..Tails::default() };
    let sink = |i: usize| counts.sinks.get(i).map(super::tail_counts::rows).unwrap_or_default();
    for (stick, variable) in [(true, "D"), (false, "H")] {
        let first = if stick { 0 } else { 3 };
        let (fine, coarse) = (sink(first), sink(first + 1));
        let grid = match (stick, &entry_grid) {
            (true, Some(g)) => g.clone(),
            _ => grid(fine.iter().map(|r| r.2).max().unwrap_or(0) + 1, rho, times),
        };
        let (fine_grid, coarse_grid) = (on_cells(&grid, times, false), on_cells(&grid, times, true));
        for index in indices(max_index) {
            let of_k =
                |rows: &Counts, censored: bool| -> Counts { rows.iter().filter(|r| index.is_none_or(|k| r.1 == k) && (censored || !r.3)).copied().collect() };
            let (fine_k, coarse_k) = (of_k(&fine, true), of_k(&coarse, true));
            if fine_k.is_empty() {
                continue;
            }
            for (method, censored) in [("kaplan_meier", true), ("naive", false)] {
                let (f, c) = if censored { (fine_k.clone(), coarse_k.clone()) } else { (of_k(&fine_k, false), of_k(&coarse_k, false)) };
                let n = f.iter().map(|r| r.4).sum();
                let n_censored = f.iter().filter(|r| r.3).map(|r| r.4).sum();
                let points = curve((&f, &fine_grid), (&c, &coarse_grid), product_limit, CLOGLOG);
                out.curves.push(Curve { variable, index, method, n, censored: n_censored, points });
            }
        }
        if let (true, Some(grid), Ok((_, (rates, _)))) = (stick, entry_grid, scene) {
            let e = sink(2);
            // held past grid[j].t exactly when the bin exceeds j (`tail_counts::EntryBin`)
            let bins: Vec<(f64, i64)> = grid.iter().enumerate().map(|(j, g)| (g.0, j as i64 + 1)).collect();
            for index in indices(max_index) {
                let kept: Counts = e.iter().filter(|r| index.is_none_or(|k| r.1 == k)).copied().collect();
                if kept.is_empty() {
                    continue;
                }
                let n = kept.iter().map(|r| r.4).sum();
                let estimator = move |cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)]| conditional(cells, counts, at, *rates);
                let points = curve((&kept, &bins), (&kept, &bins), estimator, LN);
                out.curves.push(Curve { variable, index, method: "conditional", n, censored: 0, points });
            }
        }
    }
    if tails_state {
        let extremes = &counts.extremes;
        let per_group = if extremes.is_empty() { vec![vec![0; super::tail_counts::extreme_columns(plan).len()]; GROUPS] } else { extremes.clone() };
        let total = |j: usize, g: Option<usize>| -> u64 { per_group.iter().enumerate().filter(|(h, _)| Some(*h) != g).map(|(_, r)| r[j]).sum() };
        let ratio = |num: usize, den: usize, g: Option<usize>| -> Option<f64> { (total(den, g) > 0).then(|| total(num, g) as f64 / total(den, g) as f64) };
        let mut push = |statistic: &'static str, threshold: Option<f64>, num: usize, den: usize| {
            let Some(value) = ratio(num, den, None) else { return };
            let loo: Vec<Option<f64>> = (0..GROUPS).map(|g| ratio(num, den, Some(g))).collect();
            out.exceedances.push(Exceedance { statistic, threshold, value, interval: transformed(value, &loo, LN), n: total(den, None) });
        };
        push(Statistic::BreakawayFraction.name(), None, 2, 1);
        for (i, t) in opts.times.iter().enumerate() {
            push(Observable::LongestStick.variable(), Some(*t), 3 + i, 0);
        }
        for (i, s) in opts.severity.iter().enumerate() {
            push(Observable::Severity.variable(), Some(*s), 3 + opts.times.len() + i, 0);
        }
    }
    out
}

/// None (pooled), then k = 1..=max_index.
fn indices(max_index: u32) -> impl Iterator<Item = Option<u32>> {
    std::iter::once(None).chain((1..=max_index).map(Some))
}

/// The evaluation points: `CURVE_POINTS` cells evenly up to `top` cells, and the user's times
/// (t, cell ⌊t/ρ⌋), in increasing t.
fn grid(top: i64, rho: f64, times: &[f64]) -> Vec<(f64, i64)> {
    let mut g: Vec<(f64, i64)> = (0..=CURVE_POINTS as i64).map(|j| j * top / CURVE_POINTS as i64).map(|c| (c as f64 * rho, c)).collect();
    g.extend(times.iter().map(|&t| (t, (t / rho).floor() as i64)));
    g.sort_by(|a, b| a.0.total_cmp(&b.0));
    g.dedup();
    g
}

/// Counts of (group, cell, flag) rows on one sorted axis of cells: `[count without the flag,
/// with it]` per cell, in total and per group (so that each leave-one-group-out sample is the
/// total minus one group, read in one pass).
struct Axis {
    cells: Vec<i64>,
    total: Vec<[u64; 2]>,
    groups: Vec<Vec<[u64; 2]>>,
}

impl Axis {
    fn new(rows: &[(usize, i64, bool, u64)]) -> Axis {
        let mut cells: Vec<i64> = rows.iter().map(|r| r.1).collect();
        cells.sort_unstable();
        cells.dedup();
        let mut groups = vec![vec![[0u64; 2]; cells.len()]; GROUPS];
        for &(g, c, flag, n) in rows {
            let i = cells.binary_search(&c).expect("every cell is on the axis");
            groups[g][i][flag as usize] += n;
        }
        let total = (0..cells.len()).map(|i| groups.iter().fold([0, 0], |a, g| [a[0] + g[i][0], a[1] + g[i][1]])).collect();
        Axis { cells, total, groups }
    }

    /// The counts without group `g` (all with None).
    fn without(&self, g: Option<usize>) -> Vec<[u64; 2]> {
        match g {
            None => self.total.clone(),
            Some(g) => self.total.iter().zip(&self.groups[g]).map(|(t, x)| [t[0] - x[0], t[1] - x[1]]).collect(),
        }
    }
}

/// A curve with its jackknife band on the scale `scale` (and its inverse): the estimate from
/// `full` (rows and the grid's (t, cell) on their cells), the leave-one-group-out values from
/// `loo` (on their own, possibly coarser, cells); `estimate` maps an axis' cells, their counts
/// and the evaluation points to the curve's values.
fn curve(
    full: (&Counts, &[(f64, i64)]),
    loo: (&Counts, &[(f64, i64)]),
    estimate: impl Fn(&[i64], &[[u64; 2]], &[(f64, i64)]) -> Vec<f64>,
    scale: (fn(f64) -> Option<f64>, fn(f64) -> f64),
) -> Vec<(f64, f64, Option<Interval>)> {
    let axis = |rows: &Counts| Axis::new(&rows.iter().map(|r| (r.0, r.2, r.3, r.4)).collect::<Vec<_>>());
    let (whole, parts) = (axis(full.0), axis(loo.0));
    let value = estimate(&whole.cells, &whole.without(None), full.1);
    let loo: Vec<Vec<f64>> = (0..GROUPS).map(|g| estimate(&parts.cells, &parts.without(Some(g)), loo.1)).collect();
    full.1
        .iter()
        .enumerate()
        .map(|(j, &(t, _))| {
            let column: Vec<Option<f64>> = loo.iter().map(|l| Some(l[j])).collect();
            (t, value[j], transformed(value[j], &column, scale))
        })
        .collect()
}

/// The jackknife interval of `value` on the scale `(to, back)`.
fn transformed(value: f64, loo: &[Option<f64>], (to, back): (fn(f64) -> Option<f64>, fn(f64) -> f64)) -> Option<Interval> {
    jackknife::transformed(Some(value), loo, to, back)
}

/// ln(−ln S) and back, for S in (0, 1).
const CLOGLOG: (fn(f64) -> Option<f64>, fn(f64) -> f64) = (|s| (s > 0.0 && s < 1.0).then(|| (-s.ln()).ln()), |y| (-y.exp()).exp());
/// ln p and back, for p > 0.
const LN: (fn(f64) -> Option<f64>, fn(f64) -> f64) = (|p| (p > 0.0).then(|| p.ln()), f64::exp);

/// The product limit at the grid's cells `at` (increasing) from the sorted `cells` and their
/// counts [events, censored] (module docs): S just after the events of the cells below each.
fn product_limit(cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)]) -> Vec<f64> {
    let mut at_risk: u64 = counts.iter().map(|c| c[0] + c[1]).sum();
    let (mut s, mut i) = (1.0, 0);
    at.iter()
        .map(|&(_, t)| {
            while i < cells.len() && cells[i] < t {
                let [events, cut] = counts[i];
                if at_risk > 0 {
                    s *= 1.0 - events as f64 / at_risk as f64;
                }
                at_risk -= events + cut;
                i += 1;
            }
            s
        })
        .collect()
}

/// The conditional estimator at the grid's (t, bin) `at` from the sorted holding-time bins
/// `cells` and their counts [reverse state, forward state]: (1/N) Σ_s exp(−λ_s t) #{entries in s
/// held past t}, an entry counting as held past t when its bin is at least the one given with t
/// (`tail_counts::EntryBin`: both the exponential and the indicator exact at t).
fn conditional(cells: &[i64], counts: &[[u64; 2]], at: &[(f64, i64)], (rate_f, rate_r): (f64, f64)) -> Vec<f64> {
    // suffix sums: entries held at or past each cell, per state
    let mut held = vec![[0u64; 2]; cells.len() + 1];
    for i in (0..cells.len()).rev() {
        held[i] = [held[i + 1][0] + counts[i][0], held[i + 1][1] + counts[i][1]];
    }
    let n = held[0][0] + held[0][1];
    at.iter()
        .map(|&(t, c)| {
            if n == 0 {
                return 0.0;
            }
            let [r, f] = held[cells.partition_point(|&x| x < c)];
            ((-rate_f * t).exp() * f as f64 + (-rate_r * t).exp() * r as f64) / n as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_limit_matches_a_hand_computation() {
        // cells 1, 2 (censored), 3, 3, 5: S after cell 1 = 4/5, after 3 = 4/5 · (1 − 2/3)
        let (cells, counts) = ([1, 2, 3, 5], [[1, 0], [0, 1], [2, 0], [1, 0]]);
        let grid = |cells: &[i64]| cells.iter().map(|&c| (c as f64, c)).collect::<Vec<_>>();
        let s = product_limit(&cells, &counts, &grid(&[0, 1, 2, 3, 4, 6]));
        let expect = [1.0, 1.0, 0.8, 0.8, 0.8 * (1.0 - 2.0 / 3.0), 0.0];
        for (a, b) in s.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{s:?}");
        }
        // without censoring it is the empirical survival
        assert_eq!(product_limit(&[1, 4], &[[2, 0], [3, 0]], &grid(&[1, 2, 5])), [1.0, 0.6, 0.0]);
    }

    #[test]
    fn conditional_is_the_mean_of_the_per_entry_survivals() {
        // two entries held to cell 10 (forward, λ = 1), one to cell 3 (reverse, λ = 2); ρ = 0.1
        let s = conditional(&[3, 10], &[[1, 0], [0, 2]], &[(0.0, 0), (0.2, 2), (0.5, 5)], (1.0, 2.0));
        assert!((s[0] - 1.0).abs() < 1e-15);
        assert!((s[1] - (2.0 * (-0.2f64).exp() + (-0.4f64).exp()) / 3.0).abs() < 1e-15);
        assert!((s[2] - 2.0 * (-0.5f64).exp() / 3.0).abs() < 1e-15);
    }

    #[test]
    fn leave_one_group_out_counts_are_the_total_minus_the_group() {
        let rows = [(0, 5, false, 2), (1, 5, true, 1), (0, 7, false, 4)];
        let axis = Axis::new(&rows);
        assert_eq!(axis.cells, [5, 7]);
        assert_eq!(axis.without(None), [[2, 1], [4, 0]]);
        assert_eq!(axis.without(Some(0)), [[0, 1], [0, 0]]);
    }
}
