//! The laws of the counts without sampling: S_T, the number of sticks that start in [0, t_a],
//! and S_L, the number of slips that start there (a slip starts where a stick ends), from the
//! scenario's initial conditions.
//!
//! **From the start instants.** The k-th stick starts at T_k and ends at L_k = T_k + D_k, so
//!
//! ```text
//!     P(S_T ≥ k) = P(T_k ≤ t_a),   P(S_L ≥ k) = P(L_k ≤ t_a),   P(S = n) = P(S ≥ n) − P(S ≥ n + 1),
//!     E[S] = Σ_{k≥1} P(S ≥ k),     E[S²] = Σ_{k≥1} (2k − 1) P(S ≥ k).
//! ```
//!
//! The sequence of passages of [`super::passage`] carries, instead of the clocks' moments, the
//! Laplace transform of t at the 2M + 1 points of Euler's inversion at t_a ([`super::clock`]);
//! the k-th passage's absorbed entries hold E[e^{−z T_k}] and its sticks' ends E[e^{−z L_k}],
//! and each is inverted to P(· ≤ t_a). The sequence stops once P(T_k ≤ t_a) is below
//! [`NEGLIGIBLE`] past the counts' mode (or at [`MAX_STICKS`]). Like every table of
//! `exact-law`, the values are extrapolated from three resolutions, with an error estimate
//! ([`super::richardson::guarded`]).

use super::clock::{Euler, Points};
use super::flow::Frame;
use super::passage::{self, Step};
use super::stationary::Rung;
use crate::observables::Observable;
use crate::scenario::Scenario;

/// Where the sequence stops: P(T_k ≤ t_a) below this (past the mode) — the inversion's own
/// accuracy is about 1e-8.
pub const NEGLIGIBLE: f64 = 1e-8;
/// The most sticks followed: a window where more can start (about 240 s on the paper scene)
/// fails, after following them, with the reason.
pub const MAX_STICKS: usize = 400;

/// The variables, in analyze's names.
pub const VARIABLES: [&str; 2] = [Observable::Sticks.variable(), Observable::Slips.variable()];

/// One resolution's P(S ≥ k), k = 1, 2, … (S_T, S_L).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Tails {
    pub sticks: Vec<f64>,
    pub slips: Vec<f64>,
}

/// P(S_T ≥ k) and P(S_L ≥ k) from the weighted `starts` at one resolution (module docs).
/// `tick` hears each stick k followed, with P(T_k ≤ t_a).
pub(crate) fn tails(
    frames: &[Frame],
    h: &[f64],
    half: f64,
    starts: &[(usize, passage::Start, f64)],
    t_a: f64,
    tick: &mut dyn FnMut(usize, f64),
    go_on: &dyn Fn() -> bool,
) -> Result<Tails, String> {
    let points = Points::at(t_a, &frames.iter().map(|f| f.lambda).collect::<Vec<_>>());
    let mut out = Tails { sticks: Vec::new(), slips: Vec::new() };
    let mut peak = 0.0f64;
    passage::walk_sequence::<Euler>(&points, frames, h, half, starts, MAX_STICKS, go_on, &mut |step: Step<Euler>| {
        let all = passage::total(&step.entries.concat());
        let p = points.cdf(&all.t).clamp(0.0, 1.0);
        out.sticks.push(p);
        tick(out.sticks.len(), p);
        if let Some(held) = step.held {
            out.slips.push(points.cdf(&held.ends.t).clamp(0.0, 1.0));
        }
        // the mode of S_T is where P(S_T ≥ k) falls fastest; past it, a negligible tail ends the sequence
        let fall = out.sticks.len().checked_sub(2).map_or(1.0 - p, |i| out.sticks[i] - p);
        peak = peak.max(fall);
        !(p < NEGLIGIBLE && fall < peak)
    })?;
    if out.sticks.len() > MAX_STICKS {
        return Err(format!("more than {MAX_STICKS} sticks may start in run.duration = {t_a} s: the law of the counts is not computed for so long a window"));
    }
    Ok(out)
}

/// P(S = n) for n = 0, 1, … from P(S ≥ k), k ≥ 1.
pub(crate) fn probabilities(at_least: &[f64]) -> Vec<f64> {
    let ge = |k: usize| if k == 0 { 1.0 } else { at_least.get(k - 1).copied().unwrap_or(0.0) };
    (0..=at_least.len()).map(|n| (ge(n) - ge(n + 1)).max(0.0)).collect()
}

/// (E[S], Var S) from P(S ≥ k), k ≥ 1.
pub(crate) fn mean_var(at_least: &[f64]) -> (f64, f64) {
    let mean: f64 = at_least.iter().sum();
    let second: f64 = at_least.iter().enumerate().map(|(i, p)| (2 * i + 1) as f64 * p).sum();
    (mean, (second - mean * mean).max(0.0))
}

/// One row of `counts.parquet`: P(S = n) extrapolated, with its error estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct CountRow {
    /// "S_T" or "S_L"
    pub variable: &'static str,
    /// n
    pub value: u32,
    /// P(S = n)
    pub probability: f64,
    /// its estimated discretisation error
    pub error: f64,
}

/// Whether the inversion holds for the scene's window: λ t_a ≥ [`super::clock::MIN_RATE_WINDOW`]
/// for the smallest flip rate λ (the point masses of flip-free paths, [`super::clock`]).
pub(crate) fn check(frames: &[Frame], t_a: f64) -> Result<(), String> {
    let lambda = frames.iter().map(|f| f.lambda).fold(f64::INFINITY, f64::min);
    let need = super::clock::MIN_RATE_WINDOW;
    if lambda * t_a < need {
        return Err(format!(
            "--counts: the flip rate {lambda} /s times run.duration = {t_a} s is {:.3}, below {need}: over so short a window the paths without a flip keep point masses near t_a that the Laplace inversion cannot resolve (use a run.duration of at least {:.3} s)",
            lambda * t_a,
            need / lambda
        ));
    }
    Ok(())
}

/// The count laws at the ladder's spacings (coarsest first), with the scenario's initial law.
/// `progress` hears each resolution (n, seconds) when done, `tick` each stick (n, k, P(T_k ≤ t_a)).
pub(crate) fn solve(
    scenario: &Scenario,
    frames: &[Frame],
    ladder: &[Rung],
    progress: &mut dyn FnMut(u32, f64),
    tick: &mut dyn FnMut(u32, usize, f64),
    go_on: &dyn Fn() -> bool,
) -> Result<Vec<(f64, Tails)>, String> {
    let mut out = Vec::new();
    for (n, h) in ladder {
        let (starts, half) = super::sticks::held_starts(scenario, frames, h[0]);
        let t = std::time::Instant::now();
        out.push((h[0], tails(frames, h, half, &starts, scenario.run.duration, &mut |k, p| tick(*n, k, p), go_on)?));
        progress(*n, t.elapsed().as_secs_f64());
    }
    Ok(out)
}

/// What the counts' resolutions show of the order ([`super::richardson::Order`]): they follow ~37 sticks at
/// coarse resolutions (4 to 32), before their changes settle — at `--counts 16` the
/// extrapolation's change on E S_T (0.003) fell 1.9× short of its distance to 10^7 realizations
/// (0.0057) — so one ratio in range is no evidence there.
const ORDER: super::richardson::Order = super::richardson::Order::Irregular;

/// The rows of `counts.parquet` and of `moments.parquet` (S_T, S_L: mean, variance, errors)
/// from the levels (coarsest first).
pub(crate) fn rows(levels: &[(f64, Tails)]) -> (Vec<CountRow>, Vec<super::sticks::Row>) {
    let (mut counts, mut moments) = (Vec::new(), Vec::new());
    for (v, variable) in VARIABLES.iter().enumerate() {
        let pick = |t: &Tails| if v == 0 { t.sticks.clone() } else { t.slips.clone() };
        let laws: Vec<(f64, Vec<f64>)> = levels.iter().map(|(h, t)| (*h, probabilities(&pick(t)))).collect();
        let top = laws.iter().map(|(_, l)| l.len()).max().unwrap_or(0);
        for n in 0..top {
            let (p, error) = super::richardson::guarded(&laws.iter().map(|(h, l)| (*h, l.get(n).copied().unwrap_or(0.0))).collect::<Vec<_>>(), ORDER);
            counts.push(CountRow { variable, value: n as u32, probability: p.clamp(0.0, 1.0), error });
        }
        let mv: Vec<(f64, (f64, f64))> = levels.iter().map(|(h, t)| (*h, mean_var(&pick(t)))).collect();
        let mean = super::richardson::guarded(&mv.iter().map(|(h, m)| (*h, m.0)).collect::<Vec<_>>(), ORDER);
        let variance = super::richardson::guarded(&mv.iter().map(|(h, m)| (*h, m.1)).collect::<Vec<_>>(), ORDER);
        moments.push(super::sticks::Row {
            variable,
            index: 0,
            mean: mean.0,
            variance: variance.0.max(0.0),
            error: mean.1,
            variance_error: variance.1,
            reached: None,
            windowed: None,
        });
    }
    (counts, moments)
}

/// The Markdown table `exact-law --counts` prints: P(S = n) of S_T and S_L side by side, for
/// every n either has above 1e-6.
pub fn markdown(rows: &[CountRow]) -> String {
    let mut m = String::from("| n | P(S_T = n) | error | P(S_L = n) | error |\n|---:|---:|---:|---:|---:|\n");
    let of = |v: &str, n: u32| rows.iter().find(|r| r.variable == v && r.value == n);
    let top = rows.iter().map(|r| r.value).max().unwrap_or(0);
    for n in 0..=top {
        let (st, sl) = (of(VARIABLES[0], n), of(VARIABLES[1], n));
        if [st, sl].iter().all(|r| r.is_none_or(|r| r.probability < 1e-6)) {
            continue;
        }
        let cell = |r: Option<&CountRow>| r.map_or(" | ".to_string(), |r| format!("{:.4e} | {:.1e}", r.probability, r.error));
        m += &format!("| {n} | {} | {} |\n", cell(st), cell(sl));
    }
    m
}

/// Each Table 1 row's share of realizations that reach it within [0, t_a] (analyze's
/// `reached_fraction`: T_k and D_k need stick k to start, P(S_T ≥ k); L_k and H_k need it to
/// end, P(S_L ≥ k)), extrapolated from the levels (coarsest first).
pub(crate) fn reach(levels: &[(f64, Tails)], rows: &mut [super::sticks::Row]) {
    for r in rows.iter_mut().filter(|r| r.index > 0) {
        let k = r.index as usize - 1;
        let pick = |t: &Tails| if matches!(r.variable, "T" | "D") { t.sticks.get(k).copied().unwrap_or(0.0) } else { t.slips.get(k).copied().unwrap_or(0.0) };
        let (p, error) = super::richardson::guarded(&levels.iter().map(|(h, t)| (*h, pick(t))).collect::<Vec<_>>(), ORDER);
        r.reached = Some((p.clamp(0.0, 1.0), error));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_count_law_follows_from_its_tails() {
        // S with P(S ≥ 1) = 0.9, P(S ≥ 2) = 0.5, P(S ≥ 3) = 0.1: P = (0.1, 0.4, 0.4, 0.1),
        // E S = 1.5, E S² = 0.4 + 1.6 + 0.9 = 2.9, Var = 0.65
        let at_least = [0.9, 0.5, 0.1];
        let p = probabilities(&at_least);
        for (got, want) in p.iter().zip([0.1, 0.4, 0.4, 0.1]) {
            assert!((got - want).abs() < 1e-15, "{p:?}");
        }
        let (m, v) = mean_var(&at_least);
        assert!((m - 1.5).abs() < 1e-15 && (v - 0.65).abs() < 1e-14, "{m} {v}");
    }
}
