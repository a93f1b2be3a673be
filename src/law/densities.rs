//! The densities of T_k, L_k and H_k (k = 1 … [`STICKS`]) without sampling, on a grid of
//! [0, t_a], from the scenario's initial conditions (`exact-law --densities N`).
//!
//! **The transform.** The sequence of passages of [`super::passage`] carries, instead of the
//! clocks' moments, the characteristic function of t at ω_j = πj/P (j = 0 … J, [`TERMS`] = J;
//! [`super::clock::Points::cosine`]): the k-th passage's entries hold E[e^{−iω T_k}], its
//! sticks' ends E[e^{−iω L_k}]; a second walk whose clock restarts at every stick's end holds
//! E[e^{−iω H_k}] in the entries of passage k + 1 (H_k runs from the end of stick k to the start
//! of stick k + 1). Every operation of the walks is exact on the transform (the flips' delays,
//! the periodic slips' repetitions in closed form); the discretisation is the grid that holds
//! the measure, extrapolated from three resolutions as every table of `exact-law`.
//!
//! **The inversion** is the cosine series of the law's even extension to [−P, P]
//! (Dubner & Abate 1968, with no damping), integrated over the cells of the grid:
//!
//! ```text
//!     f(t) = (1/P) [Re φ(0) + 2 Σ_{j≥1} Re φ(ω_j) cos(ω_j t)] − Σ_{n≥1} [f(2nP − t) + f(2nP + t)],
//!     φ(ω) = E[e^{−iωT}],  ω_j = πj/P,
//!     (1/Δ) ∫_a^b f = (1/(PΔ)) [Re φ(0) Δ + 2 Σ_{j=1}^{J} Re φ(ω_j) (sin ω_j b − sin ω_j a)/ω_j],  Δ = b − a
//! ```
//!
//! The value written is the density averaged over each of [`GRID`] cells of [0, t_a] — what a
//! histogram of a Monte Carlo dataset on the same cells estimates — whose series converges one
//! order faster than the density's at a point. The even extension is continuous at 0 (a density
//! that jumps at t = 0+, as T_1's from the paper's box does, costs the series nothing there),
//! and its aliasing is the law's density beyond P: P is the larger of t_a and the mean plus six
//! standard deviations of the stick after the last followed (T_7,
//! [`super::passage::Sequence::next_start`]). A jump inside (0, P) — H_k has one where the slips
//! after a flip first return to belt speed — makes the terms decay like 1/j² only (a kink like
//! 1/j³): the truncation error is estimated as twice the largest change from J/2 to J terms over
//! the cell and its two neighbours on each side (against the closed forms of an Erlang law, an
//! exponential law and one shifted to jump inside, this bounded the error with room: at most
//! 0.69 of it), and added to the error of the extrapolation over the resolutions. The grid's
//! atoms (the flip-free walks from the points of the initial box) are too many and too close to
//! be seen at ω_J. A point initial condition gives T_1 a point mass (the path without a flip)
//! and no density: it is refused.
//!
//! **The point masses of H_k.** Every breakaway leaves the same state (x_b, v0), so where the
//! slip after it returns to a stick without a flip (μ_s > μ_k: at 2c_k − c_s after t_r, the
//! same for every breakaway of the belt state; [`super::kept::restick`]), H_k = t_r exactly with probability
//! m = P(stick k ends by breakaway in that state) × P(the flips leave that slip unchanged) —
//! e^{−λ t_r}, but for the stretches where the mass outruns both belt velocities, where flips
//! change nothing if the belt is back when they end ([`super::kept::path`]). That mass is taken out of the
//! transform before the series (m e^{−iω t_r} subtracted) and written as the cell's
//! `point_mass`: the density is the rest's. P(breakaway) per state is summed from the stick's
//! entries as the passage does (e^{−λ d(x_e)}, d the holding time). T_k and L_k have no such
//! mass: L_k is T_k plus a stick, and T_{k+1} is L_k plus a slip, each with a density.

use super::clock::{Laplace, Points, C64};
use super::flow::Frame;
use super::kept::{restick, start_point, Path};
use super::passage::{self, Start, Step};
use super::stationary::Rung;
use super::sticks::STICKS;
use crate::observables::{Observable, Statistic};
use crate::scenario::Scenario;

/// J, the highest term of the cosine series (on the paper scene, P = 10.4 s: ω_J = 77 rad/s, a
/// resolution of about P/J = 0.04 s).
pub const TERMS: usize = 256;
/// The transform's points: j = 0 … J.
pub(crate) const N: usize = TERMS + 1;
/// The cells of [0, t_a] the densities are averaged over.
pub const GRID: usize = 100;
/// The variables, in analyze's names.
pub const VARIABLES: [&str; 3] = [Observable::StickStart(1).variable(), Observable::SlipStart(1).variable(), Observable::SlipDuration(1).variable()];

/// One variable's transform at one resolution: φ of its law at the points, less its point
/// masses (module docs), and those: (t, mass).
#[derive(Debug, Clone)]
pub(crate) struct Transform {
    pub variable: &'static str,
    pub index: u32,
    pub phi: Box<[C64; N]>,
    pub points: Vec<(f64, f64)>,
}

/// The transforms of one resolution.
pub(crate) type Transforms = Vec<Transform>;

/// One row of `densities.parquet`.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityRow {
    /// one of [`VARIABLES`] (`exact-law`), or `time_to_stick`, `slip_duration` (`predict`)
    pub variable: &'static str,
    /// k, 1-based
    pub index: u32,
    /// the cell's start [s]
    pub t_lo: f64,
    /// the cell's end [s] (the cell is [t_lo, t_hi))
    pub t_hi: f64,
    /// the density averaged over the cell [1/s] (P(t_lo ≤ · < t_hi) / (t_hi − t_lo)), ≥ 0 (an
    /// overshoot of the series below 0 is written as 0, its size added to `error`)
    pub density: f64,
    /// the estimated error: the extrapolation's over the resolutions plus the series'
    /// truncation (the change from J/2 to J terms), plus the point mass's extrapolation spread
    /// over the cell's width
    pub error: f64,
    /// the probability of the point masses in the cell (H_k of a scene whose breakaway slip
    /// sticks again without a flip; 0 elsewhere), not part of `density`
    pub point_mass: f64,
}

/// Whether the densities exist for the scenario's initial law: not for a point.
pub(crate) fn check(scenario: &Scenario) -> Result<(), String> {
    let ic = &scenario.initial_conditions;
    if ic.position[0] == ic.position[1] && ic.velocity[0] == ic.velocity[1] {
        return Err(
            "--densities: the initial condition is a point, so T_1 has a point mass (the path without a flip) and no density: give initial_conditions a range"
                .into(),
        );
    }
    Ok(())
}

/// The cosine series averaged over [a, b] with the terms j ≤ `terms` (module docs).
pub(crate) fn cell(phi: &[C64], half_period: f64, a: f64, b: f64, terms: usize) -> f64 {
    let w = std::f64::consts::PI / half_period;
    let sum: f64 =
        phi.iter().enumerate().take(terms + 1).skip(1).map(|(j, f)| f.re * ((w * j as f64 * b).sin() - (w * j as f64 * a).sin()) / (w * j as f64)).sum();
    (phi[0].re * (b - a) + 2.0 * sum) / (half_period * (b - a))
}

/// φ less a point mass m at t (m e^{−iωt} subtracted at every point).
fn without(phi: &mut [C64; N], points: &Points<N>, t: f64, m: f64) {
    phi.iter_mut().zip(&points.z).for_each(|(p, z)| {
        let e = z.exp_neg(t);
        *p = C64::new(p.re - m * e.re, p.im - m * e.im);
    });
}

/// Per belt state, the mass of the sticks entered in `step` that end by breakaway (e^{−λ d(x_e)},
/// d the holding time, as the passage's `leave`).
fn breakaway_masses(step: &Step<Laplace<N>>) -> Vec<f64> {
    step.entries
        .iter()
        .zip(step.meshes)
        .map(|(e, mesh)| {
            let f = mesh.frame;
            e.iter().enumerate().map(|(i, c)| c.mass * (-f.lambda * (f.hold_hi() - (f.hold_lo() + i as f64 * mesh.h_line)).max(0.0) / f.v0).exp()).sum()
        })
        .collect()
}

/// φ of the slip after the sticks of the step before (`breakaways`, [`breakaway_masses`]) less
/// its point masses (the breakaway slips that stick again without a flip, per belt state:
/// `resticks`), and those.
fn slip_law(phi: [C64; N], points: &Points<N>, resticks: &[Option<Path>], breakaways: &[f64]) -> (Box<[C64; N]>, Vec<(f64, f64)>) {
    let (mut phi, mut out) = (Box::new(phi), Vec::new());
    for (s, b) in breakaways.iter().enumerate() {
        let Some(r) = resticks[s] else { continue };
        let m = b * r.kept;
        without(&mut phi, points, r.t, m);
        out.push((r.t, m));
    }
    (phi, out)
}

/// The transforms of `predict --densities` from `start` in belt state `at`: τ (`time_to_stick`,
/// its flip-free point mass taken out, [`start_point`]) and H (`slip_duration`, the slip after
/// that stick).
pub(crate) fn predicted(frames: &[Frame], h: &[f64], half: f64, at: usize, start: Start, half_period: f64) -> Result<Transforms, String> {
    let lambdas: Vec<f64> = frames.iter().map(|f| f.lambda).collect();
    let starts = [(at, start, 1.0)];
    let mut out: Transforms = Vec::new();
    let origin = Points::<N>::cosine(half_period, &lambdas, false);
    passage::walk_sequence::<Laplace<N>>(&origin, frames, h, half, &starts, 0, &|| true, &mut |step: Step<Laplace<N>>| {
        let mut phi = Box::new(passage::total(&step.entries.concat()).t);
        let mut points = Vec::new();
        if let Some((t, m)) = start_point(frames, at, start) {
            without(&mut phi, &origin, t, m);
            points.push((t, m));
        }
        out.push(Transform { variable: Statistic::TimeToStick.name(), index: 1, phi, points });
        false
    })?;
    let since_end = Points::<N>::cosine(half_period, &lambdas, true);
    let resticks: Vec<Option<Path>> = (0..frames.len()).map(|s| restick(frames, s)).collect();
    let mut breakaways = Vec::new();
    passage::walk_sequence::<Laplace<N>>(&since_end, frames, h, half, &starts, 1, &|| true, &mut |step: Step<Laplace<N>>| {
        if step.held.is_some() {
            breakaways = breakaway_masses(&step);
            return true;
        }
        let (phi, points) = slip_law(passage::total(&step.entries.concat()).t, &since_end, &resticks, &breakaways);
        out.push(Transform { variable: Statistic::SlipDuration.name(), index: 1, phi, points });
        false
    })?;
    Ok(out)
}

/// The transforms of T_k, L_k and H_k (k = 1 … [`STICKS`]) from the weighted `starts` at one
/// resolution (two walks: t since the origin, then since the last stick's end), H_k's point
/// masses taken out (module docs).
fn transforms(
    frames: &[Frame],
    h: &[f64],
    half: f64,
    starts: &[(usize, passage::Start, f64)],
    half_period: f64,
    go_on: &dyn Fn() -> bool,
) -> Result<Transforms, String> {
    let lambdas: Vec<f64> = frames.iter().map(|f| f.lambda).collect();
    let mut out: Transforms = Vec::new();
    let origin = Points::<N>::cosine(half_period, &lambdas, false);
    passage::walk_sequence::<Laplace<N>>(&origin, frames, h, half, starts, STICKS, go_on, &mut |step: Step<Laplace<N>>| {
        let Some(held) = step.held else { return false };
        let index = out.len() as u32 / 2 + 1;
        out.push(Transform { variable: VARIABLES[0], index, phi: Box::new(passage::total(&step.entries.concat()).t), points: Vec::new() });
        out.push(Transform { variable: VARIABLES[1], index, phi: Box::new(held.ends.t), points: Vec::new() });
        (index as usize) < STICKS
    })?;
    let since_end = Points::<N>::cosine(half_period, &lambdas, true);
    let resticks: Vec<Option<Path>> = (0..frames.len()).map(|s| restick(frames, s)).collect();
    // per belt state, the mass of the last passage's sticks that end by breakaway
    let (mut k, mut breakaways) = (0u32, Vec::<f64>::new());
    passage::walk_sequence::<Laplace<N>>(&since_end, frames, h, half, starts, STICKS, go_on, &mut |step: Step<Laplace<N>>| {
        if k > 0 {
            let (phi, points) = slip_law(passage::total(&step.entries.concat()).t, &since_end, &resticks, &breakaways);
            out.push(Transform { variable: VARIABLES[2], index: k, phi, points });
        }
        breakaways = breakaway_masses(&step);
        k += 1;
        step.held.is_some()
    })?;
    Ok(out)
}

/// The transforms at the ladder's spacings (coarsest first), with the scenario's initial law
/// and the series' half-period; `progress` hears each resolution (n, seconds).
pub(crate) fn solve(
    scenario: &Scenario,
    frames: &[Frame],
    ladder: &[Rung],
    half_period: f64,
    progress: &mut dyn FnMut(u32, f64),
    go_on: &dyn Fn() -> bool,
) -> Result<Vec<(f64, Transforms)>, String> {
    let mut out = Vec::new();
    for (n, h) in ladder {
        let (starts, half) = super::sticks::held_starts(scenario, frames, h[0]);
        let t = std::time::Instant::now();
        out.push((h[0], transforms(frames, h, half, &starts, half_period, go_on)?));
        progress(*n, t.elapsed().as_secs_f64());
    }
    Ok(out)
}

/// The series' half-period P: t_a, or the mean plus six standard deviations of the stick after
/// the last followed if later (module docs).
pub(crate) fn half_period(t_a: f64, next_start: passage::MeanVar) -> f64 {
    let reach = next_start.0 + 6.0 * next_start.1.max(0.0).sqrt();
    if reach.is_finite() {
        t_a.max(reach)
    } else {
        t_a
    }
}

/// The density of transform `i` (of every level's) averaged over each cell between
/// consecutive `edges`, and the point masses in it: (value ≥ 0, error, point mass) — the extrapolation over the levels (coarsest first)
/// with its spread, plus twice the largest change from J/2 to J terms at the finest over the
/// cell and two neighbours each side, plus any overshoot below 0 and the point mass's spread
/// over the width (module docs).
pub(crate) fn averages(levels: &[(f64, Transforms)], half_period: f64, i: usize, edges: &[f64], order: super::richardson::Order) -> Vec<(f64, f64, f64)> {
    let Some((_, finest)) = levels.last() else { return Vec::new() };
    let phi = &finest[i].phi[..];
    let cells = edges.len().saturating_sub(1);
    // every level's J-term averages, the finest's reused for the truncation estimate
    let full: Vec<Vec<f64>> =
        levels.iter().map(|(_, l)| (0..cells).map(|g| cell(&l[i].phi[..], half_period, edges[g], edges[g + 1], TERMS)).collect()).collect();
    let finest_full = full.last().expect("a level");
    let change: Vec<f64> = (0..cells).map(|g| (finest_full[g] - cell(phi, half_period, edges[g], edges[g + 1], TERMS / 2)).abs()).collect();
    (0..cells)
        .map(|g| {
            let per: Vec<(f64, f64)> = levels.iter().zip(&full).map(|((h, _), f)| (*h, f[g])).collect();
            let (value, spread) = super::richardson::guarded(&per, order);
            let truncation = 2.0 * change[g.saturating_sub(2)..(g + 3).min(cells)].iter().copied().fold(0.0, f64::max);
            let inside = |l: &Transforms| l[i].points.iter().filter(|(t, _)| (edges[g]..edges[g + 1]).contains(t)).map(|p| p.1).sum::<f64>();
            let (mass, mass_spread) = super::richardson::guarded(&levels.iter().map(|(h, l)| (*h, inside(l))).collect::<Vec<_>>(), order);
            let width = edges[g + 1] - edges[g];
            (value.max(0.0), spread + truncation + (-value).max(0.0) + mass_spread / width, mass.max(0.0))
        })
        .collect()
}

/// The rows of `densities.parquet` on the [`GRID`] cells of [0, t_a] from the levels (coarsest
/// first).
pub(crate) fn rows(levels: &[(f64, Transforms)], half_period: f64, t_a: f64) -> Vec<DensityRow> {
    let edges: Vec<f64> = (0..=GRID).map(|g| t_a * g as f64 / GRID as f64).collect();
    rows_on(levels, half_period, &edges, super::richardson::Order::Regular)
}

/// The rows of every transform of the levels (coarsest first) on the cells between `edges`.
pub(crate) fn rows_on(levels: &[(f64, Transforms)], half_period: f64, edges: &[f64], order: super::richardson::Order) -> Vec<DensityRow> {
    let mut out = Vec::new();
    for (i, x) in levels.last().map_or(&[][..], |l| &l.1[..]).iter().enumerate() {
        for (g, (density, error, point_mass)) in averages(levels, half_period, i, edges, order).into_iter().enumerate() {
            out.push(DensityRow { variable: x.variable, index: x.index, t_lo: edges[g], t_hi: edges[g + 1], density, error, point_mass });
        }
    }
    out
}

/// The Markdown table `exact-law --densities` prints: per variable and k, the cell of the
/// density's largest value (its centre, the value and its error), and the integral over [0, t_a] —
/// the cells' probabilities and point masses summed: P(X ≤ t_a) but for the series' error (below
/// 1 where the window cuts the law).
pub fn markdown(rows: &[DensityRow]) -> String {
    let mut m = String::from("| variable | k | mode [s] | density there [1/s] | error | ∫ over [0, t_a] |\n|---|---:|---:|---:|---:|---:|\n");
    for v in VARIABLES {
        for k in 1..=STICKS as u32 {
            let mine: Vec<&DensityRow> = rows.iter().filter(|r| r.variable == v && r.index == k).collect();
            let Some(top) = mine.iter().max_by(|a, b| a.density.total_cmp(&b.density)) else { continue };
            let total: f64 = mine.iter().map(|r| r.density * (r.t_hi - r.t_lo) + r.point_mass).sum();
            m += &format!("| {v} | {k} | {:.3} | {:.4} | {:.1e} | {total:.5} |\n", 0.5 * (top.t_lo + top.t_hi), top.density, top.error);
        }
    }
    m
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::law::flow::Slip;
    use crate::law::kept::tests::kept_breakaway_slip;

    /// a / b
    pub(crate) fn div(a: C64, b: C64) -> C64 {
        let d = b.re * b.re + b.im * b.im;
        C64::new((a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d)
    }

    /// The cell averages of a law with the CDF `cdf` and the characteristic function `phi` on
    /// cells of width 0.1 over [0, 6], against the closed form: the largest error and the
    /// largest ratio of the error to its estimate (twice the largest change from J/2 to J terms
    /// over the cell and two neighbours each side, as [`rows`]).
    fn errors(p: &Points<N>, phi: &[C64], cdf: impl Fn(f64) -> f64) -> (f64, f64) {
        let (width, cells) = (0.1, 60);
        let e = |g: usize| g as f64 * width;
        let change: Vec<f64> = (0..cells).map(|g| (cell(phi, p.t, e(g), e(g + 1), TERMS) - cell(phi, p.t, e(g), e(g + 1), TERMS / 2)).abs()).collect();
        (0..cells).fold((0.0f64, 0.0f64), |(worst, ratio), g| {
            let err = (cell(phi, p.t, e(g), e(g + 1), TERMS) - (cdf(e(g + 1)) - cdf(e(g))) / width).abs();
            let estimate = 2.0 * change[g.saturating_sub(2)..(g + 3).min(cells)].iter().copied().fold(0.0, f64::max);
            (worst.max(err), ratio.max(err / estimate))
        })
    }

    #[test]
    fn the_series_inverts_laws_whose_distribution_is_known() {
        // the paper scene's half-period, P = 10.4 s; λ = 2
        let (lambda, p) = (2.0, Points::<N>::cosine(10.4, &[], false));
        let exp: Vec<C64> = p.z.iter().map(|z| div(C64::new(lambda, 0.0), C64::new(lambda + z.re, z.im))).collect();
        let mul = |a: C64, b: C64| C64::new(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
        // Erlang(3, λ): (λ/(λ + z))³, smooth (its even extension too): converged to 1e-5
        let erlang: Vec<C64> = exp.iter().map(|&e| mul(mul(e, e), e)).collect();
        let (worst, ratio) = errors(&p, &erlang, |t| 1.0 - (-lambda * t).exp() * (1.0 + lambda * t + (lambda * t).powi(2) / 2.0));
        assert!(worst < 1e-5 && ratio < 1.0, "Erlang: error {worst:.1e}, error / estimate {ratio:.2}");
        // Exp(λ): its density jumps at 0+, where the even extension is continuous (a kink)
        let (worst, ratio) = errors(&p, &exp, |t| -(-lambda * t).exp_m1());
        assert!(worst < 1e-3 && ratio < 1.0, "Exp: error {worst:.1e}, error / estimate {ratio:.2}");
        // Exp(λ) shifted by 1 s (e^{−z} λ/(λ + z)): a jump of λ inside; the cells next to it
        // are off by about 5 % of the jump, and the estimate covers every cell
        let shifted: Vec<C64> = exp.iter().zip(&p.z).map(|(&e, z)| mul(e, C64::new(z.im.cos(), -z.im.sin()))).collect();
        let (worst, ratio) = errors(&p, &shifted, |t| if t > 1.0 { -(-lambda * (t - 1.0)).exp_m1() } else { 0.0 });
        assert!(worst < 0.1 * lambda && ratio < 1.0, "shifted Exp: error {worst:.1e}, error / estimate {ratio:.2}");
    }

    /// E[T] and E[T²] of a law on [0, P] from its cosine series, integrated term by term
    /// (∫_0^P t cos(ω_j t) dt = ((−1)^j − 1)/ω_j², ∫_0^P t² cos(ω_j t) dt = 2P(−1)^j/ω_j²), and
    /// its point masses.
    fn series_moments(x: &Transform, p: f64) -> (f64, f64) {
        let phi = &x.phi;
        let (mut m1, mut m2) = (phi[0].re * p * p / 2.0, phi[0].re * p * p * p / 3.0);
        for (j, f) in phi.iter().enumerate().skip(1) {
            let (w, sign) = (std::f64::consts::PI * j as f64 / p, if j % 2 == 0 { 1.0 } else { -1.0 });
            m1 += 2.0 * f.re * (sign - 1.0) / (w * w);
            m2 += 2.0 * f.re * 2.0 * p * sign / (w * w);
        }
        let mass = phi[0].re + x.points.iter().map(|q| q.1).sum::<f64>();
        let (a1, a2) = x.points.iter().fold((0.0, 0.0), |(a, b), (t, m)| (a + m * t, b + m * t * t));
        ((m1 / p + a1) / mass, (m2 / p + a2) / mass)
    }

    #[test]
    fn the_transforms_carry_the_moments_of_the_moment_clocks() {
        // one coarse resolution: the same grid, the same walks, two algebras (the moments of
        // [`passage::sequence`], the characteristic function here): the means and variances of
        // T_k, L_k, H_k agree but for the series' truncation and aliasing (measured on the
        // paper scene: T_1's mean 3.5e-4 relative — the flip-free walks from this resolution's
        // few starts are point masses whose terms do not decay —, T_6's variance 7e-5 — its mass
        // beyond P —, every other mean within 4e-5). With μ_s = 0.6 the breakaway slip sticks
        // again without a flip: H_k's point mass, taken out and added back, must keep them so.
        // (the second scene at λ = 1, where the point mass is about 0.013)
        for sets in [&[][..], &["model.static_friction_coefficient=0.6".to_string(), "belt.switch_rate=1".to_string()][..]] {
            let sc = crate::scenario::Scenario::resolve(None, sets).unwrap();
            let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
            let ladder = super::super::stationary::ladder(&frames, 8, 3).unwrap();
            let h = &ladder[0].1;
            let (starts, half) = super::super::sticks::held_starts(&sc, &frames, h[0]);
            let moments = passage::sequence(&frames, h, half, &starts, STICKS).unwrap();
            let p = half_period(sc.run.duration, moments.next_start);
            let got = transforms(&frames, h, half, &starts, p, &|| true).unwrap();
            assert_eq!(got.len(), 3 * STICKS);
            // (the second scene's T_k and L_k are left out: at λ = 1 the flip-free walks from this
            // resolution's few starts carry most of T_1, point masses the series reads to 2e-3)
            for x in got.iter().filter(|x| sets.is_empty() || x.variable == "H") {
                assert_eq!(x.points.len(), usize::from(!sets.is_empty() && x.variable == "H"), "{sets:?} {}_{}: {:?}", x.variable, x.index, x.points);
                let st = moments.sticks[x.index as usize - 1];
                let want = match x.variable {
                    "T" => st.start,
                    "L" => st.end,
                    _ => st.slip,
                };
                if let Some(&(t_r, m)) = x.points.first() {
                    // the moment sequence's breakaway share of stick k times the chance that
                    // the breakaway slip is kept ([`kept_breakaway_slip`])
                    let (want, kept) = kept_breakaway_slip(frames[0]);
                    assert!((t_r - want).abs() < 1e-9, "the re-stick after {t_r} s against {want}");
                    let mass = st.breakaway * kept;
                    assert!((m - mass).abs() < 1e-4 * mass, "H_{}'s point mass {m} against {mass}", x.index);
                }
                let (m1, m2) = series_moments(x, p);
                let var = m2 - m1 * m1;
                let what = format!("{sets:?} {}_{}", x.variable, x.index);
                assert!((m1 - want.0).abs() < 1e-3 * want.0, "E {what}: {m1} against {}", want.0);
                assert!((var - want.1).abs() < 2e-3 * want.1, "Var {what}: {var} against {}", want.1);
            }
        }
    }

    #[test]
    fn the_prediction_carries_its_moments_and_its_point_mass() {
        // from rest at x = 0.5 on the paper scene (slipping) and stuck at 0.3 with μ_s = 0.6 and
        // λ = 1: τ and H at one coarse resolution against the moment clocks' sequence from the
        // same start, and τ's flip-free point mass against the closed form — from rest, the
        // circle about c_k of radius r = c_k − 0.5 rises to belt speed after asin(w0/r)/ω; stuck,
        // the breakaway after (x_b − 0.3)/v0 and the breakaway slip's re-stick
        let cases: [(&[&str], Start); 2] =
            [(&[], Start::Slip(Slip::at(0.5, 0.0, 1.0))), (&["model.static_friction_coefficient=0.6", "belt.switch_rate=1"], Start::Stuck(0.3))];
        for (sets, start) in cases {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            let sc = crate::scenario::Scenario::resolve(None, &sets).unwrap();
            let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
            let f = frames[0];
            let h = &super::super::stationary::ladder(&frames, 8, 3).unwrap()[0].1;
            let half = f.box_half().max(passage::half_width(f, start));
            let moments = passage::sequence(&frames, h, half, &[(0, start, 1.0)], 1).unwrap();
            let p = 10.0;
            let got = predicted(&frames, h, half, 0, start, p).unwrap();
            assert_eq!(got.iter().map(|x| x.variable).collect::<Vec<_>>(), ["time_to_stick", "slip_duration"]);
            // (from rest the slip stays within (−v0, v0): kept e^{−λ t_e}; stuck: no flip in the
            // stick, then the breakaway slip kept)
            let (t_e, mass) = match start {
                Start::Slip(_) => {
                    let t = (f.w0 / (f.ck - 0.5)).asin() / f.omega;
                    (t, (-f.lambda * t).exp())
                }
                Start::Stuck(x) => {
                    let (d, (t_r, kept)) = ((f.cs - x) / f.v0, kept_breakaway_slip(f));
                    (d + t_r, (-f.lambda * d).exp() * kept)
                }
            };
            let (t, m) = got[0].points[0];
            assert!((t - t_e).abs() < 1e-9 && (m - mass).abs() < 1e-5 * mass, "{sets:?}: τ's point mass {m} at {t} against {mass} at {t_e}");
            for (x, want) in got.iter().zip([moments.sticks[0].start, moments.sticks[0].slip]) {
                let (m1, m2) = series_moments(x, p);
                let var = m2 - m1 * m1;
                assert!((m1 - want.0).abs() < 2e-3 * want.0, "{sets:?} E {}: {m1} against {}", x.variable, want.0);
                assert!((var - want.1).abs() < 1e-2 * want.1, "{sets:?} Var {}: {var} against {}", x.variable, want.1);
            }
        }
    }

    #[test]
    fn the_printed_table_finds_the_mode_and_sums_the_cells_and_point_masses() {
        // H_2 on cells of 0.5 s: densities 0.2, 1.0, 0.4 and a point mass of 0.1 in the last:
        // the mode's cell is [0.5, 1), P(≤ t_a) = 0.1 + 0.5 + 0.2 + 0.1 = 0.9
        let row = |g: usize, density: f64, point_mass: f64| DensityRow {
            variable: "H",
            index: 2,
            t_lo: 0.5 * g as f64,
            t_hi: 0.5 * (g + 1) as f64,
            density,
            error: 0.01,
            point_mass,
        };
        let m = markdown(&[row(0, 0.2, 0.0), row(1, 1.0, 0.0), row(2, 0.4, 0.1)]);
        assert!(m.contains("| H | 2 | 0.750 | 1.0000 | 1.0e-2 | 0.90000 |"), "{m}");
        assert_eq!(m.lines().count(), 3, "{m}");
    }

    #[test]
    fn the_half_period_covers_the_window_and_the_next_stick() {
        assert_eq!(half_period(10.0, (4.0, 1.0)), 10.0);
        assert_eq!(half_period(10.0, (8.0, 4.0)), 20.0);
        assert_eq!(half_period(10.0, (f64::NAN, f64::NAN)), 10.0);
    }
}
