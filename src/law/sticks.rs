//! The paper's Table 1 without sampling: the means and variances of T_k, L_k, D_k and H_k
//! (k = 1 … [`STICKS`]) from the scenario's initial conditions — the stick sequence of
//! [`super::passage`] started from the initial law (the uniform box of (x, ẋ), or a point, with
//! the belt's initial sign).
//!
//! **The initial law** is held on exact points (walked exactly from where they are; a point is
//! one start), in the belt's frame (a belt starting in reverse reflects the box;
//! `initial_sign = "random"` takes both halves): the box is cut into cells h/2 wide in x and in
//! ẋ/ω, and each cell is integrated by the midpoint rule where the future of its states is
//! smooth. It is not smooth everywhere: without a flip a start follows one deterministic path,
//! and the kind of that path ([`Fate`]: how many arcs it slips, and whether it then sticks,
//! slips forever under the belt line or leaves by the breakaway) jumps across curves — circles
//! about ±c_k in the undamped frame: r = w0 (inside, it never reaches belt speed), r = √(w0² +
//! (c_k + c_s)²) (outside, it passes belt speed instead of sticking), and their successors. A
//! midpoint rule on a cell cut by such a curve puts a share of the cell on the wrong side: an
//! error of the order of the cell's width along the curve, first order in h with an erratic
//! sign, which spoiled the extrapolation (T_1's mean changed by 1.68e-4 and then 6.9e-5 from
//! n = 40 to 80 to 160, a ratio of 2.4 instead of 4). So a cell whose corners and centre do not
//! share one fate is split into quarters, down to [`SPLIT_DEPTH`] levels (2^−10 of the cell):
//! each fate's share is the area of its leaves, and it is held on one start at that area's
//! centroid (second order within a smooth piece) where the centroid has the fate too, else on
//! the pieces its quarters make. The share's error is then about 2^−10 of the midpoint rule's.
//!
//! **The window.** These are the laws of the process, not cut at t_a: a realization counts for
//! T_k in a table of [0, t_a] only if its k-th stick starts before t_a. The difference is the
//! chance that it does not — on the paper scene 48 in 10^7 realizations have fewer than 6
//! sticks and 369 fewer than 7, which moves E[T_6] by about 3e-5 s and Var T_6 by about 2e-4
//! relative ([`window_warning`] flags a window that may matter).

use super::flow::{Frame, Slip, Visitor};
use super::passage::{self, MeanVar, Sequence, Start};
use super::stationary::Rung;
use crate::observables::Observable;
use crate::scenario::Scenario;
use crate::simulation::belt::InitialSign;

/// How many sticks the table follows (the paper's Table 1: k = 1 … 6).
pub const STICKS: usize = 6;

/// The variables, in analyze's names: T_k (stick starts), L_k (slip starts, the ends of the
/// sticks), D_k (stick durations), H_k (slip durations).
pub const VARIABLES: [&str; 4] = [
    Observable::StickStart(1).variable(),
    Observable::SlipStart(1).variable(),
    Observable::StickDuration(1).variable(),
    Observable::SlipDuration(1).variable(),
];

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
    /// the estimated discretisation error of the mean ([`super::richardson::guarded`])
    pub error: f64,
    /// the estimated discretisation error of the variance
    pub variance_error: f64,
    /// the share of realizations that reach this row within [0, t_a], as analyze's
    /// `reached_fraction` (T_k, D_k: P(S_T ≥ k); L_k, H_k: P(S_L ≥ k)) — known with
    /// `--counts` ([`super::counts`]) with its error estimate, none otherwise
    pub reached: Option<(f64, f64)>,
    /// T_k and L_k with `--densities`: the mean and variance within the window, of the law
    /// conditioned on X ≤ t_a — what a Monte Carlo table of [0, t_a] estimates — each with its
    /// error estimate: [mean, error, variance, variance_error] ([`super::window::windowed`])
    pub windowed: Option<[f64; 4]>,
}

/// How deep a cell of the box cut by a curve of [`Fate`]s is split: 2^−10 of its width.
const SPLIT_DEPTH: u32 = 10;

/// The kind of a slipping start's deterministic path (no flip), which decides where the future
/// of a state jumps (module docs): how many slip arcs it follows, and how it ends — 0 cut by
/// the horizon, 1 a periodic slip under the belt line, 2 a stick, 3 the breakaway slip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Fate {
    arcs: u32,
    end: u8,
}

impl Visitor for Fate {
    fn slip(&mut self, _x: f64, _v: f64, _t: f64, _dt: f64, _age: f64) {
        self.arcs += 1;
    }
    fn periodic(&mut self, _start: Slip, _t: f64, _age: f64, _period: f64) {
        self.end = 1;
    }
    fn stick(&mut self, _x_e: f64, _t: f64) {
        self.end = 2;
    }
    fn breakaway_slip(&mut self, _t: f64, _age: f64) {
        self.end = 3;
    }
}

impl Fate {
    /// The fate of the slipping start (x, v) in `frame` (one sample per arc: no spacing).
    fn of(frame: &Frame, x: f64, v: f64) -> Fate {
        let mut fate = Fate::default();
        frame.walk(Slip::at(x, v, frame.v0), 0.0, f64::INFINITY, f64::INFINITY, &mut fate);
        fate
    }
}

/// A share of a cell held on one start: its fate, its area and the area-weighted sums of x, v.
#[derive(Debug, Clone, Copy)]
struct Piece {
    fate: Fate,
    area: f64,
    x: f64,
    v: f64,
}

/// The pieces of the cell [x0, x1] × [v0, v1] whose corner fates are `corners` (at (x0, v0),
/// (x1, v0), (x0, v1), (x1, v1)), split `depth` more times where the fates differ (module
/// docs); each piece's centroid has the piece's fate.
fn pieces(fate: &dyn Fn(f64, f64) -> Fate, [x0, x1]: [f64; 2], [v0, v1]: [f64; 2], corners: [Fate; 4], depth: u32, out: &mut Vec<Piece>) {
    let (xm, vm) = (0.5 * (x0 + x1), 0.5 * (v0 + v1));
    let centre = fate(xm, vm);
    let area = (x1 - x0) * (v1 - v0);
    if depth == 0 || corners.iter().all(|&c| c == centre) {
        out.push(Piece { fate: centre, area, x: area * xm, v: area * vm });
        return;
    }
    let (bottom, top, left, right) = (fate(xm, v0), fate(xm, v1), fate(x0, vm), fate(x1, vm));
    let first = out.len();
    let [c00, c10, c01, c11] = corners;
    pieces(fate, [x0, xm], [v0, vm], [c00, bottom, left, centre], depth - 1, out);
    pieces(fate, [xm, x1], [v0, vm], [bottom, c10, centre, right], depth - 1, out);
    pieces(fate, [x0, xm], [vm, v1], [left, centre, c01, top], depth - 1, out);
    pieces(fate, [xm, x1], [vm, v1], [centre, right, top, c11], depth - 1, out);
    // merge each fate's pieces into one where their centroid has that fate
    let mine = out.split_off(first);
    let mut fates: Vec<Fate> = mine.iter().map(|p| p.fate).collect();
    fates.sort_by_key(|f| (f.arcs, f.end));
    fates.dedup();
    for f in fates {
        let of: Vec<&Piece> = mine.iter().filter(|p| p.fate == f).collect();
        let (a, x, v) = of.iter().fold((0.0, 0.0, 0.0), |(a, x, v), p| (a + p.area, x + p.x, v + p.v));
        if of.len() > 1 && fate(x / a, v / a) == f {
            out.push(Piece { fate: f, area: a, x, v });
        } else {
            out.extend(of.into_iter().copied());
        }
    }
}

/// The starts of the scenario's initial law at grid spacing h (of the first belt state's mesh),
/// in the belt state's frame, with their weights (summing to 1): (belt state, start, weight).
/// The symmetric belt's one state holds both signs (a belt starting in reverse reflects the
/// box); the telegraph belt starts in its forward state 0 or, reflected, its reverse state 1.
/// A point is one start; a box is integrated cell by cell along the fates (module docs).
pub(crate) fn starts(scenario: &Scenario, frames: &[Frame], h: f64) -> Vec<(usize, Start, f64)> {
    let ([x0, x1], [v0, v1]) = (scenario.initial_conditions.position, scenario.initial_conditions.velocity);
    let omega = frames[0].omega;
    let cells = |lo: f64, hi: f64, step: f64| if hi > lo { ((hi - lo) / step).ceil().max(1.0) as usize } else { 1 };
    let (nx, nv) = (cells(x0, x1, h / 2.0), cells(v0, v1, omega * h / 2.0));
    let edge = |lo: f64, hi: f64, n: usize, i: usize| lo + (hi - lo) * i as f64 / n as f64;
    let signs: &[(f64, f64)] = match scenario.belt.initial_sign.0 {
        InitialSign::Positive => &[(1.0, 1.0)],
        InitialSign::Negative => &[(-1.0, 1.0)],
        InitialSign::Random => &[(1.0, 0.5), (-1.0, 0.5)],
    };
    let w = 1.0 / (nx * nv) as f64;
    let mut out = Vec::with_capacity(nx * nv * signs.len());
    for &(s, ws) in signs {
        let state = if s > 0.0 { 0 } else { frames.len() - 1 };
        let frame = frames[state];
        let start = |x: f64, v: f64| Start::Slip(Slip::at(s * x, s * v, frame.v0));
        if x1 <= x0 || v1 <= v0 {
            // a point, or a box of zero width: the midpoints
            for i in 0..nx {
                for j in 0..nv {
                    out.push((
                        state,
                        start(0.5 * (edge(x0, x1, nx, i) + edge(x0, x1, nx, i + 1)), 0.5 * (edge(v0, v1, nv, j) + edge(v0, v1, nv, j + 1))),
                        w * ws,
                    ));
                }
            }
            continue;
        }
        // (a state on the box's edge is taken from just inside: an edge on the belt line, as
        // the paper's ẋ = v0, would otherwise arrive at once, a fate of its own)
        let (ex, ev) = (1e-9 * (x1 - x0), 1e-9 * (v1 - v0));
        let fate = |x: f64, v: f64| Fate::of(&frame, s * x.clamp(x0 + ex, x1 - ex), s * v.clamp(v0 + ev, v1 - ev));
        let corner: Vec<Vec<Fate>> = (0..=nx).map(|i| (0..=nv).map(|j| fate(edge(x0, x1, nx, i), edge(v0, v1, nv, j))).collect()).collect();
        let mut cell = Vec::new();
        for i in 0..nx {
            for j in 0..nv {
                let (xs, vs) = ([edge(x0, x1, nx, i), edge(x0, x1, nx, i + 1)], [edge(v0, v1, nv, j), edge(v0, v1, nv, j + 1)]);
                cell.clear();
                pieces(&fate, xs, vs, [corner[i][j], corner[i + 1][j], corner[i][j + 1], corner[i + 1][j + 1]], SPLIT_DEPTH, &mut cell);
                let area = (xs[1] - xs[0]) * (vs[1] - vs[0]);
                out.extend(cell.iter().map(|p| (state, start(p.x / p.area, p.v / p.area), w * ws * p.area / area)));
            }
        }
    }
    out
}

/// Whether the initial law can start the sequence: a start moving with the belt within the
/// holding limit is a stick of its own (a point initial condition there is refused: `predict
/// --stuck` answers that question).
pub(crate) fn check_starts(starts: &[(usize, Start, f64)], frames: &[Frame]) -> Result<(), String> {
    let stuck = |s: usize, z: &Slip| {
        let f = frames[s];
        z.v == f.v0 && (f.hold_lo()..f.hold_hi()).contains(&z.x)
    };
    match starts.iter().find(|(s, p, _)| matches!(p, Start::Slip(z) if stuck(*s, z))) {
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

/// What the resolutions of the scenario's initial law show of the order ([`super::richardson::Order`]): a
/// box of positive area is regular, a point (or a segment) is not.
pub(crate) fn order(scenario: &Scenario) -> super::richardson::Order {
    let ic = &scenario.initial_conditions;
    if ic.position[1] > ic.position[0] && ic.velocity[1] > ic.velocity[0] {
        super::richardson::Order::Regular
    } else {
        super::richardson::Order::Irregular
    }
}

/// The rows from sequences at the ladder's spacings (coarsest first), of the initial law's `order`.
pub(crate) fn rows(levels: &[(f64, Sequence)], order: super::richardson::Order) -> Vec<Row> {
    let per: Vec<(f64, Vec<(&'static str, u32, MeanVar)>)> = levels.iter().map(|(h, s)| (*h, values(s))).collect();
    (0..per.first().map_or(0, |p| p.1.len()))
        .map(|i| {
            let (variable, index, _) = per[0].1[i];
            let mean = super::richardson::guarded(&per.iter().map(|(h, v)| (*h, v[i].2 .0)).collect::<Vec<_>>(), order);
            let variance = super::richardson::guarded(&per.iter().map(|(h, v)| (*h, v[i].2 .1)).collect::<Vec<_>>(), order);
            Row { variable, index, mean: mean.0, variance: variance.0.max(0.0), error: mean.1, variance_error: variance.1, reached: None, windowed: None }
        })
        .collect()
}

/// One point of D_k's law (`survival.parquet`): P(D_k > t), extrapolated from the ladder's
/// resolutions, and the density of D_k at t at the finest, each with its error estimate
/// ([`super::richardson::guarded`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SurvivalRow {
    /// k, 1-based
    pub index: u32,
    /// t [s]
    pub t: f64,
    /// P(D_k > t), in [0, 1]
    pub survival: f64,
    /// its estimated discretisation error
    pub error: f64,
    /// the density of D_k at t [1/s] (≥ 0)
    pub density: f64,
    /// its estimated discretisation error
    pub density_error: f64,
}

/// D_k's law for every stick the sequences follow (k = 1 … [`STICKS`] for Table 1, k = 1 for
/// `predict`) at the increasing `times`, from sequences at the ladder's spacings (coarsest
/// first): [`passage::Sequence::stick_law`] per level, per point.
pub(crate) fn survival_rows(frames: &[Frame], levels: &[(f64, Sequence)], times: &[f64], order: super::richardson::Order) -> Vec<SurvivalRow> {
    let mut out = Vec::new();
    for k in 0..levels.first().map_or(0, |(_, s)| s.entries.len()) {
        let laws: Vec<(f64, Vec<(f64, f64, f64)>)> = levels.iter().map(|(h, s)| (*h, s.stick_law(frames, k, times))).collect();
        for (j, &t) in times.iter().enumerate() {
            let (survival, error) = super::richardson::guarded(&laws.iter().map(|(h, l)| (*h, l[j].1)).collect::<Vec<_>>(), order);
            // the density at the finest level (non-negative, of mass 1: an extrapolation of
            // entry densities spread over cells of three widths can overshoot where the law is
            // narrower than the coarse cells), with the extrapolation's error as its estimate
            let density = laws.last().map_or(0.0, |(_, l)| l[j].2);
            let (_, density_error) = super::richardson::guarded(&laws.iter().map(|(h, l)| (*h, l[j].2)).collect::<Vec<_>>(), order);
            out.push(SurvivalRow { index: k as u32 + 1, t, survival: survival.clamp(0.0, 1.0), error, density, density_error });
        }
    }
    out
}

/// Whether the scenario's initial law can start the sequence ([`check_starts`] at the coarsest
/// spacing: the check depends on the initial conditions only).
pub(crate) fn check(scenario: &Scenario, frames: &[Frame], ladder: &[Rung]) -> Result<(), String> {
    ladder.first().map_or(Ok(()), |(_, h)| check_starts(&starts(scenario, frames, h[0]), frames))
}

/// The scenario's initial law at spacing h ([`starts`]) and the half-width of the box whose
/// grid holds it and the chain ([`passage::half_width`]).
pub(crate) fn held_starts(scenario: &Scenario, frames: &[Frame], h: f64) -> (Vec<(usize, Start, f64)>, f64) {
    let starts = starts(scenario, frames, h);
    let half = starts.iter().map(|(s, p, _)| passage::half_width(frames[*s], *p)).chain(frames.iter().map(|f| f.box_half())).fold(0.0, f64::max);
    (starts, half)
}

/// The sequences of the scenario's initial law at the ladder's spacings (after [`check`]).
pub(crate) fn solve(
    scenario: &Scenario,
    frames: &[Frame],
    ladder: &[Rung],
    progress: &mut dyn FnMut(u32, f64),
    go_on: &dyn Fn() -> bool,
) -> Result<Vec<(f64, Sequence)>, String> {
    let mut out = Vec::new();
    for (n, h) in ladder {
        let (starts, half) = held_starts(scenario, frames, h[0]);
        let t = std::time::Instant::now();
        out.push((h[0], passage::sequence_until(frames, h, half, &starts, STICKS, go_on)?));
        progress(*n, t.elapsed().as_secs_f64());
    }
    Ok(out)
}

/// A warning when the window t_a may cut the table: the share of realizations whose stick
/// K + 1 (where H_K ends; its start computed by the sequence's last passage) starts after t_a,
/// estimated by the gamma law of the same mean μ and variance σ² (shape μ²/σ², scale σ²/μ: a
/// sum of about K + 1 cycles, skewed right), is above 1e-4. A heuristic: the laws here are those
/// of the process without the window. Measured against 10^6–10^7 realizations, the gamma tail
/// underestimates the true share by 2.7–3.7×: the paper scene (stick 7 at 4.016 ± 1.072 s, 3.7e-5
/// below 7 sticks in 10 s, gamma 2.0e-5: no warning, E[T_6] moved ~3e-5 s) and the asymmetric
/// belt (4.49 ± 1.30 s, 2.0e-3 in 10 s, gamma 5.3e-4: warned, E[T_6] moved ~5e-3 s).
pub fn window_warning(next_start: MeanVar, t_a: f64) -> Option<String> {
    let (mean, var) = next_start;
    let share = crate::special::gamma_q(mean * mean / var, t_a * mean / var);
    (share > 1e-4).then(|| {
        format!(
            "warning: the window run.duration = {t_a} s may cut this table: stick {} starts at about {mean:.3} ± {:.3} s, after t_a in about {share:.1e} of the realizations (gamma tail; these are the laws without the window, a Monte Carlo table counts only the realizations that reach each index within it)",
            STICKS + 1,
            var.sqrt()
        )
    })
}

/// The Markdown table `exact-law` prints after the long-run one.
pub fn markdown(rows: &[Row]) -> String {
    let mut m = String::from("| variable | k | mean | error | variance | error |\n|---|---:|---:|---:|---:|---:|\n");
    for r in rows {
        let k = if r.index > 0 { r.index.to_string() } else { String::new() };
        m += &format!("| {} | {k} | {:.6} | {:.1e} | {:.6} | {:.1e} |\n", r.variable, r.mean, r.error, r.variance, r.variance_error);
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
        let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
        let ladder = super::super::stationary::ladder(&frames, 16, 3).unwrap();
        let solved = solve(&sc, &frames, &ladder, &mut |_, _| {}, &|| true).unwrap();
        let rows = rows(&solved, order(&sc));
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
            // D_k's law: (almost) surely held for `held` — P(D_k > t) ≈ 1 before, 0 after, and
            // the density's mass near it (within the coarsest level's two line nodes, 0.25 s)
            let times = [held - 0.3, held + 0.3];
            let law: Vec<SurvivalRow> = survival_rows(&frames, &solved, &super::super::density::survival_times(&frames, &times), order(&sc));
            let at = |x: f64| law.iter().find(|r| r.index == k && r.t == x).unwrap().survival;
            assert!(at(times[0]) > 0.999 && at(times[1]) < 1e-3, "D_{k}: P(D > {held} ∓ 0.3) = {}, {}", at(times[0]), at(times[1]));
            let mine: Vec<&SurvivalRow> = law.iter().filter(|r| r.index == k).collect();
            let near: f64 =
                mine.windows(2).filter(|w| w[0].t >= times[0] && w[1].t <= times[1]).map(|w| 0.5 * (w[0].density + w[1].density) * (w[1].t - w[0].t)).sum();
            assert!((near - 1.0).abs() < 1e-2, "D_{k}: the density's mass within 0.3 s of {held}: {near}");
            t += held + slip;
        }
    }

    #[test]
    fn a_window_near_the_last_stick_is_flagged() {
        // stick 7 at 4.0 ± 1.0 s: the gamma law of shape 16, scale 1/4 passes 1e-4 at
        // t_a = 8.8214 s (scipy.stats.gamma.sf: 6.5e-5 at 9 s, 2.1e-4 at 8.5 s)
        assert!(window_warning((4.0, 1.0), 10.0).is_none() && window_warning((4.0, 1.0), 9.0).is_none());
        assert!(window_warning((4.0, 1.0), 8.5).unwrap().contains("run.duration = 8.5 s"));
        assert!(window_warning((4.0, 1.0), 8.80).is_some() && window_warning((4.0, 1.0), 8.84).is_none());
    }

    #[test]
    fn the_box_is_held_on_cells_of_equal_weight_and_a_random_sign_takes_both_halves() {
        let sc = Scenario::resolve(None, &["belt.initial_sign=\"random\"".to_string()]).unwrap();
        let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
        let s = starts(&sc, &frames, 0.1);
        // [−1, 1] × [−1, 1] m, m/s in cells 0.05 m by ω h/2 = 0.1 m/s: 40 × 20, twice, and the
        // cells cut by a fate's curve hold more than one start
        assert!(s.len() > 2 * 40 * 20 && s.len() < 2 * 40 * 20 + 2000, "{}", s.len());
        assert!((s.iter().map(|p| p.2).sum::<f64>() - 1.0).abs() < 1e-12);
        let mean = |f: fn(&Slip) -> f64| -> f64 { s.iter().map(|(_, p, w)| if let Start::Slip(z) = p { f(z) * w } else { f64::NAN }).sum() };
        assert!(mean(|z| z.x).abs() < 1e-12 && mean(|z| z.v).abs() < 1e-12);
        // E[X²] of the uniform box: 1/3 (the cells' midpoints alone give 1/3 − 0.05²/12)
        assert!((mean(|z| z.x * z.x) - 1.0 / 3.0).abs() < 0.05 * 0.05 / 12.0 + 1e-6);
    }

    /// The share of the paper's box whose start never reaches belt speed (the fate "periodic":
    /// inside the circle r = w0 = 0.5 m about (c_k, 0) in (X, ẋ/ω)) is the circular segment
    /// the box's edge X = 1 cuts off, r² acos(d/r) − d √(r² − d²) with d = c_k − 1, over the
    /// box's area 2 × 1 m² — within 1e-6, where the cells' midpoints alone miss it by ~1e-3.
    #[test]
    fn the_cells_cut_by_a_fate_are_split_along_it() {
        let sc = Scenario::resolve(None, &[]).unwrap();
        let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
        let f = frames[0];
        let (r, d) = (f.w0, f.ck - 1.0);
        let segment = (r * r * (d / r).acos() - d * (r * r - d * d).sqrt()) / 2.0;
        for h in [0.1, 0.037] {
            let s = starts(&sc, &frames, h);
            let inside: f64 = s.iter().filter(|(_, p, _)| matches!(p, Start::Slip(z) if Fate::of(&f, z.x, z.v).end == 1)).map(|p| p.2).sum();
            assert!((inside - segment).abs() < 1e-6, "h = {h}: {inside} against {segment}");
            // every start has the fate of the piece it holds: those inside the circle are inside
            for (_, p, _) in &s {
                let Start::Slip(z) = p else { panic!() };
                let (rr, _) = f.polar(f.ck, z.x, z.v);
                assert_eq!(rr < r, Fate::of(&f, z.x, z.v).end == 1, "{z:?}");
            }
        }
    }
}
