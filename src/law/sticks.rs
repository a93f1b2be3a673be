//! The paper's Table 1 without sampling: the means and variances of T_k, L_k, D_k and H_k
//! (k = 1 … [`STICKS`]) from the scenario's initial conditions — the stick sequence of
//! [`super::passage`] started from the initial law (the uniform box of (x, ẋ), or a point, with
//! the belt's initial sign).
//!
//! **The initial law** is held on exact points: the midpoints of a grid of the box, h/2 apart
//! in x and in ẋ/ω (walked exactly from where they are; a point is one start), each of weight
//! 1/(number of points), in the belt's frame (a belt starting in reverse reflects the box;
//! `initial_sign = "random"` takes both halves). The midpoint rule is second order, like the
//! rest, and the three resolutions extrapolate both.
//!
//! **The window.** These are the laws of the process, not cut at t_a: a realization counts for
//! T_k in a table of [0, t_a] only if its k-th stick starts before t_a. The difference is the
//! chance that it does not — on the paper scene 48 in 10^7 realizations have fewer than 6
//! sticks and 369 fewer than 7, which moves E[T_6] by about 3e-5 s and Var T_6 by about 2e-4
//! relative ([`window_warning`] flags a window that may matter).

use super::flow::{Frame, Slip};
use super::passage::{self, MeanVar, Sequence, Start};
use crate::scenario::Scenario;
use crate::simulation::belt::InitialSign;

/// How many sticks the table follows (the paper's Table 1: k = 1 … 6).
pub const STICKS: usize = 6;

/// The variables, in analyze's names: T_k (stick starts), L_k (slip starts, the ends of the
/// sticks), D_k (stick durations), H_k (slip durations).
pub const VARIABLES: [&str; 4] = ["T", "L", "D", "H"];

/// One row of `moments.parquet`.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// one of [`VARIABLES`]
    pub variable: &'static str,
    /// k, 1-based
    pub index: u32,
    /// the mean, s
    pub mean: f64,
    /// the variance, s²
    pub variance: f64,
    /// the estimated discretisation error of the mean ([`super::guarded`])
    pub error: f64,
    /// the estimated discretisation error of the variance
    pub variance_error: f64,
}

/// The starts of the scenario's initial law at grid spacing h, in the belt's frame, with
/// their weights (summing to 1).
pub(crate) fn starts(scenario: &Scenario, frame: Frame, h: f64) -> Vec<(Start, f64)> {
    let ([x0, x1], [v0, v1]) = (scenario.initial_conditions.position, scenario.initial_conditions.velocity);
    let cells = |lo: f64, hi: f64, step: f64| if hi > lo { ((hi - lo) / step).ceil().max(1.0) as usize } else { 1 };
    let (nx, nv) = (cells(x0, x1, h / 2.0), cells(v0, v1, frame.omega * h / 2.0));
    let mid = |lo: f64, hi: f64, n: usize, i: usize| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
    let signs: &[(f64, f64)] = match scenario.belt.initial_sign.0 {
        InitialSign::Positive => &[(1.0, 1.0)],
        InitialSign::Negative => &[(-1.0, 1.0)],
        InitialSign::Random => &[(1.0, 0.5), (-1.0, 0.5)],
    };
    let w = 1.0 / (nx * nv) as f64;
    let mut out = Vec::with_capacity(nx * nv * signs.len());
    for &(s, ws) in signs {
        for i in 0..nx {
            for j in 0..nv {
                let (x, v) = (s * mid(x0, x1, nx, i), s * mid(v0, v1, nv, j));
                out.push((Start::Slip(Slip::at(x, v, frame.v0)), w * ws));
            }
        }
    }
    out
}

/// Whether the initial law can start the sequence: a start moving with the belt within the
/// holding limit is a stick of its own (a point initial condition there is refused: `predict
/// --stuck` answers that question).
pub(crate) fn check_starts(starts: &[(Start, f64)], frame: Frame) -> Result<(), String> {
    match starts.iter().find(|(s, _)| matches!(s, Start::Slip(z) if z.v == frame.v0 && (frame.hold_lo()..frame.hold_hi()).contains(&z.x))) {
        Some(_) => {
            Err("the initial condition moves with the belt within the holding limit (it starts stuck): the table follows the sticks after a slipping start"
                .into())
        }
        None => Ok(()),
    }
}

/// One sequence's (variable, k, mean, variance), in the order of the rows.
pub(crate) fn values(s: &Sequence) -> Vec<(&'static str, u32, MeanVar)> {
    VARIABLES
        .iter()
        .enumerate()
        .flat_map(|(v, variable)| {
            s.sticks.iter().take(STICKS).enumerate().map(move |(k, st)| (*variable, k as u32 + 1, [st.start, st.end, st.duration, st.slip][v]))
        })
        .collect()
}

/// The rows from sequences at the ladder's spacings (coarsest first).
pub(crate) fn rows(levels: &[(f64, Sequence)]) -> Vec<Row> {
    let per: Vec<(f64, Vec<(&'static str, u32, MeanVar)>)> = levels.iter().map(|(h, s)| (*h, values(s))).collect();
    (0..per.first().map_or(0, |p| p.1.len()))
        .map(|i| {
            let (variable, index, _) = per[0].1[i];
            let mean = super::guarded(&per.iter().map(|(h, v)| (*h, v[i].2 .0)).collect::<Vec<_>>());
            let variance = super::guarded(&per.iter().map(|(h, v)| (*h, v[i].2 .1)).collect::<Vec<_>>());
            Row { variable, index, mean: mean.0, variance: variance.0.max(0.0), error: mean.1, variance_error: variance.1 }
        })
        .collect()
}

/// Whether the scenario's initial law can start the sequence ([`check_starts`] at the coarsest
/// spacing: the check depends on the initial conditions only).
pub(crate) fn check(scenario: &Scenario, frame: Frame, ladder: &[(u32, f64)]) -> Result<(), String> {
    ladder.first().map_or(Ok(()), |&(_, h)| check_starts(&starts(scenario, frame, h), frame))
}

/// The sequences of the scenario's initial law at the ladder's spacings (after [`check`]).
pub(crate) fn solve(scenario: &Scenario, frame: Frame, ladder: &[(u32, f64)], progress: &mut dyn FnMut(u32, f64)) -> Result<Vec<(f64, Sequence)>, String> {
    let mut out = Vec::new();
    for &(n, h) in ladder {
        let starts = starts(scenario, frame, h);
        let half = starts.iter().map(|(s, _)| passage::half_width(frame, *s)).fold(0.0, f64::max);
        let t = std::time::Instant::now();
        out.push((h, passage::sequence(frame, h, half, &starts, STICKS)?));
        progress(n, t.elapsed().as_secs_f64());
    }
    Ok(out)
}

/// A warning when the window t_a may cut the table: the latest start it needs, T_{K+1} (where
/// H_K ends; computed by the sequence's last passage), lies within 4 standard deviations of t_a
/// (a heuristic: the laws here are those of the process without the window; on the paper scene
/// T_7 is 4.016 ± 1.072 s against t_a = 10 s, and 369 in 10^7 realizations have fewer than 7 sticks).
pub fn window_warning(next_start: MeanVar, t_a: f64) -> Option<String> {
    let (mean, sd) = (next_start.0, next_start.1.sqrt());
    (mean + 4.0 * sd > t_a).then(|| {
        format!(
            "warning: the window run.duration = {t_a} s may cut this table: stick {} starts at about {mean:.3} ± {sd:.3} s (these are the laws without the window; a Monte Carlo table counts only the realizations that reach each index within it)",
            STICKS + 1
        )
    })
}

/// The Markdown table `exact-law` prints after the long-run one.
pub fn markdown(rows: &[Row]) -> String {
    let mut m = String::from("| variable | k | mean | error | variance | error |\n|---|---:|---:|---:|---:|---:|\n");
    for r in rows {
        m += &format!("| {} | {} | {:.6} | {:.1e} | {:.6} | {:.1e} |\n", r.variable, r.index, r.mean, r.error, r.variance, r.variance_error);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// λ → 0 from a point at rest (μ_s = 0.6): the deterministic motion — the first stick after
    /// asin(w0/r)/ω, held to the breakaway, then the cycle of a slip back to 2c_k − c_s and a
    /// stick from there (module docs of [`super::super::flow`]).
    #[test]
    fn rare_flips_from_a_point_follow_the_deterministic_sticks() {
        let sc = Scenario::resolve(
            None,
            &[
                "model.static_friction_coefficient=0.6",
                "belt.switch_rate=1e-6",
                "initial_conditions.position=[0.5, 0.5]",
                "initial_conditions.velocity=[0.0, 0.0]",
            ]
            .map(String::from),
        )
        .unwrap();
        let frame = super::super::frame(&sc.scene().unwrap()).unwrap();
        let ladder = super::super::ladder(frame, 16, 3).unwrap();
        let rows = rows(&solve(&sc, frame, &ladder, &mut |_, _| {}).unwrap());
        let (omega, v0, w0) = (2.0f64, 1.0, 0.5);
        let (ck, cs) = (0.51 * 9.8 / 4.0, 0.6 * 9.8 / 4.0);
        let r: f64 = ck - 0.5;
        let (t1, x1) = ((w0 / r).asin() / omega, ck - (r * r - w0 * w0).sqrt());
        let slip = (std::f64::consts::TAU - 2.0 * (cs - ck).atan2(w0)) / omega;
        let (d1, d) = ((cs - x1) / v0, 2.0 * (cs - ck) / v0);
        let mut t = t1;
        for k in 1..=STICKS as u32 {
            let held = if k == 1 { d1 } else { d };
            let want = [("T", t), ("L", t + held), ("D", held), ("H", slip)];
            for (v, x) in want {
                let got = rows.iter().find(|r| r.variable == v && r.index == k).unwrap();
                assert!((got.mean - x).abs() < 1e-3 * x, "{v}_{k}: {} against {x}", got.mean);
            }
            t += held + slip;
        }
    }

    #[test]
    fn a_window_near_the_last_stick_is_flagged() {
        // stick 7 at 4.0 ± 1.0 s: flagged when t_a < 8 s
        assert!(window_warning((4.0, 1.0), 10.0).is_none() && window_warning((4.0, 1.0), 8.1).is_none());
        assert!(window_warning((4.0, 1.0), 7.9).unwrap().contains("run.duration = 7.9 s"));
    }

    #[test]
    fn the_box_is_held_on_midpoints_of_equal_weight_and_a_random_sign_takes_both_halves() {
        let sc = Scenario::resolve(None, &["belt.initial_sign=\"random\"".to_string()]).unwrap();
        let frame = super::super::frame(&sc.scene().unwrap()).unwrap();
        let s = starts(&sc, frame, 0.1);
        // [−1, 1] × [−1, 1] m, m/s at spacings 0.05 m and ω h/2 = 0.1 m/s: 40 × 20, twice
        assert_eq!(s.len(), 2 * 40 * 20);
        assert!((s.iter().map(|p| p.1).sum::<f64>() - 1.0).abs() < 1e-12);
        let mean_x: f64 = s.iter().map(|(p, w)| if let Start::Slip(z) = p { z.x * w } else { f64::NAN }).sum();
        assert!(mean_x.abs() < 1e-12);
    }
}
