//! The law without sampling: the long-run (stationary) stick-slip quantities computed from the
//! equations of the process, with no Monte Carlo noise and an error estimate from refinement.
//!
//! **The process.** Between belt flips the oscillator moves deterministically in closed form;
//! flips come at the exponential times of a Poisson process of rate λ. It is a piecewise-
//! deterministic Markov process, and the state just after each flip is a Markov chain: walk the
//! flow for an Exp(λ) time, flip. This module computes that chain's stationary measure ν and
//! reads every long-run quantity off the walks from it (renewal–reward: flips come at rate λ in
//! the long run, so a per-flip mean times λ is a per-second rate).
//!
//! **The frame.** With the belt at s·v0 (s = ±1) write X = s x, V = s ẋ: the belt then always
//! moves at +v0, and a flip is the point reflection (X, V) → (−X, −V) (the symmetric belt and
//! Coulomb friction are odd). With ω² = k/m, a_k = μ_k n/m, a_s = μ_s n/m, c_k = a_k/ω²,
//! c_s = a_s/ω², w0 = v0/ω, in the plane (X, W = V/ω):
//!
//! ```text
//!     slip below belt speed (V < v0):  Ẍ = −ω²(X − c_k)   clockwise circles about (+c_k, 0)
//!     slip above belt speed (V > v0):  Ẍ = −ω²(X + c_k)   clockwise circles about (−c_k, 0)
//!     X = C + r sin φ,  W = r cos φ,  φ̇ = ω
//!     arrival at V = v0: rising at X_a = c_k − √(r² − w0²) (below), falling at −c_k + √(r² − w0²)
//!                         (above); −c_s ≤ X_a < c_s → stick, else it passes belt speed
//!     stick: Ẋ = v0 until X = c_s (breakaway after d(X_e) = (c_s − X_e)/v0)
//! ```
//!
//! A circle below the belt line with r < w0 never reaches belt speed (it slips until a flip);
//! after a breakaway the slip leaves (c_s, v0) on the circle of radius √((c_s − c_k)² + w0²)
//! about c_k — for μ_s = μ_k the grazing circle r = w0, which touches the belt line again after
//! 2π/ω and goes on (a touch is not a stick), for μ_s > μ_k a slip back to a stick at 2c_k − c_s:
//! either way the same periodic continuation for every breakaway, summed once in closed form
//! over its repetitions (`chain::continuation`).
//!
//! **The dashpot** (c > 0, γ = c/m): the Coulomb slip is the damped linear oscillator
//! Ẍ = σ a_k − ω² X − γ Ẋ about the same centres, a spiral in the plane instead of a circle, in
//! the closed forms of [`crate::physics::damped`] (whose first return to belt speed is bracketed
//! by the velocity's turning points: it cannot be missed). The point reflection still maps the
//! flow onto itself (the dashpot is odd too). While stuck the holding force per unit mass is
//! ω² X + γ v0, so the stick region is shifted by −γ v0/ω²: −c_s − γv0/ω² ≤ X < x_b = c_s − γv0/ω²
//! ([`flow::Frame::hold_lo`], [`flow::Frame::hold_hi`]), and a stick entered at X_e breaks away
//! after (x_b − X_e)/v0. A spiral below belt speed that does not come back to it never will
//! (the energy only falls), so it has no periodic repetition: it is walked, like every slip,
//! until its weight e^{−λt} is negligible. With μ_s = μ_k the breakaway slip leaves at a
//! velocity maximum and never returns to belt speed; with μ_s > μ_k it may stick again, and
//! that cycle repeats as without the dashpot.
//!
//! **The chain.** ν lives on three supports: the line {(−y, −v0) : −c_s ≤ y ≤ c_s} (a flip during
//! a stick at y; nodes every h/4, linear), the images of the breakaway slip's samples (exact
//! points), and a grid of the plane of spacing h (bilinear): the measure of the post-flip
//! state after a flip at time t of a walk is deposited with weight λ e^{−λt} dt. Each atom
//! also carries its slip's age-mass (mass × the time since the slip began), so that the second
//! moment of the slip duration is a renewal–reward too: ∫ age dt over a slip is H²/2. One
//! step walks every atom's flow in closed form (`flow::Frame::walk`); the stationary ν is the
//! fixed point of the steps, iterated with Anderson mixing and renormalised (mass leaving the
//! grid's box is counted and reported).
//!
//! **The quantities**, per unit mass of ν, with the walk's integrals T_stick = E∫e^{−λt}1{stuck},
//! T_slip, A_slip = E∫e^{−λt}·age·1{slip}, N = E Σ_entries e^{−λ t_e}, B = E Σ_breakaways e^{−λ t_b}:
//!
//! ```text
//!     stick fraction = λ T_stick,   sticks per second = λ N,   breakaway fraction = B / N
//!     E[D] = T_stick / N,   E[D²] = Σ e^{−λt_e} (2/λ²)(1 − e^{−λd}(1 + λd)) / N   (D = min(Exp(λ), d))
//!     E[H] = T_slip / N,    E[H²] = 2 A_slip / N,   mean cycle E[D] + E[H] (the slope of E[T_k])
//! ```
//!
//! **Accuracy.** The walks are exact (closed forms; the times of every sample integrated
//! exactly); the discretisation is where ν is held: a post-flip state is moved to the nodes
//! around it (at most h away). Below and above belt speed the flow differs (the friction
//! reverses), so each side has its own rows of nodes, one on the belt line each, and no
//! interpolation crosses the line (with one shared grid the error was first order). The error
//! is then second order in h (paper scene, sticks per second: the change shrinks by 4.5 from
//! n = 20, 40 to 80 and by 3.3 from n = 80, 160 to 320), and `exact-law` extrapolates
//! (Richardson) from the two finest of three nested resolutions, with the change of that
//! extrapolation from the coarser pair as its error.
//!
//! **Where it holds**: Coulomb friction (μ_s ≥ μ_k), any dashpot c ≥ 0, no viscous friction, k > 0,
//! the symmetric belt (or a telegraph belt with equal rates and speeds), λ > 0, fixed
//! parameters. Anything else is refused with the reason.

mod anderson;
pub(crate) mod chain;
pub mod density;
pub(crate) mod flow;
mod output;
pub(crate) mod passage;
pub mod sticks;

pub(crate) use output::guarded;
pub use output::{estimates, markdown, run, LawError, LEVELS};

use crate::physics::Law;
use crate::simulation::belt::Process;
use crate::simulation::keys::Scene;

use chain::{Mesh, Tally};
use flow::Frame;

/// 1 − e^{−x}(1 + x), accurate for small x (x²/2 − x³/3 + x⁴/8 − …).
pub(crate) fn one_minus_exp_poly(x: f64) -> f64 {
    if x < 1e-3 {
        x * x * (0.5 - x / 3.0 + x * x / 8.0 - x * x * x / 30.0)
    } else {
        1.0 - (-x).exp() * (1.0 + x)
    }
}

/// The long-run quantities, in the names of `stationary.parquet`.
pub const QUANTITIES: [&str; 8] = [
    "stick_fraction",
    "mean_stick_duration",
    "mean_slip_duration",
    "var_stick_duration",
    "var_slip_duration",
    "sticks_per_second",
    "breakaway_fraction",
    "mean_cycle",
];

/// The frame of a scene, or why the method does not hold for it.
pub(crate) fn frame(scene: &Scene) -> Result<Frame, String> {
    if !scene.random.is_empty() {
        return Err("parameters are drawn per realization (the long-run law is computed for fixed parameters)".into());
    }
    let p = scene.params;
    if p.viscous != 0.0 {
        return Err("model.viscous_friction is not 0: the viscous term's closed forms are not implemented here (the dashpot model.damping is)".into());
    }
    if p.static_ != p.kinetic && matches!(p.law, Law::Stribeck(_)) {
        return Err("Stribeck friction with mu_s > mu_k has no closed-form slip".into());
    }
    if p.stiffness <= 0.0 {
        return Err("model.stiffness is 0: without a spring there is no stick region to return to (the stick ends only by a flip)".into());
    }
    let (speed, rate) = match &scene.belt.process {
        Process::Symmetric(s) => (s.speed, s.switch_rate),
        Process::Telegraph(t) if t.forward_speed == t.reverse_speed && t.forward_rate == t.reverse_rate => (t.forward_speed, t.forward_rate),
        Process::Telegraph(_) => return Err("the telegraph belt is asymmetric: only the symmetric belt is implemented".into()),
        other => return Err(format!("the belt is \"{}\", not a two-state flip process", other.name())),
    };
    if rate <= 0.0 {
        return Err("belt.switch_rate is 0: without flips the motion is deterministic and has no stationary law".into());
    }
    let u = p.per_unit_mass();
    if u.breakaway <= 0.0 {
        return Err("the static friction is 0: the mass never sticks".into());
    }
    if u.kinetic < 1e-6 * u.breakaway {
        // (a slip then hardly loses energy between belt speed crossings, and after a breakaway
        // it returns to belt speed at the very edge of the stick region: −c_s + 2 c_k)
        return Err("the kinetic friction is below 1e-6 of the static friction (mu_k / mu_s): not supported".into());
    }
    let damped = (u.gamma > 0.0).then(|| <crate::physics::Damped as crate::physics::SlipForm>::new(&u));
    let f = Frame { omega: u.omega, v0: speed, w0: speed / u.omega, ck: u.kinetic / u.omega2, cs: u.breakaway / u.omega2, lambda: rate, damped };
    // The grid must resolve both lengths of the plane, the belt's velocity scale w0 = v0/ω and
    // the stick region's half-width c_s, and a walk crosses belt speed about w0/c_k times before
    // it sticks (each crossing loses 2 c_k of amplitude): outside this range the grid or the
    // walks grow past minutes (the paper scene: w0/c_s = w0/c_k = 0.40; w0/c_s = 0.02 ran past
    // 2 minutes at resolution 16, w0/c_k = 4.1 took 50 s)
    let (wide, crossings) = (f.w0 / f.cs, f.w0 / f.ck);
    if !(wide >= 0.1 && crossings <= 5.0) {
        return Err(format!(
            "the belt's velocity scale v0/omega = {:.3e} m against mu_s n/k = {:.3e} m and mu_k n/k = {:.3e} m: the method is implemented for (v0/omega)/(mu_s n/k) >= 0.1 and (v0/omega)/(mu_k n/k) <= 5 (here {wide:.2e} and {crossings:.2e})",
            f.w0, f.cs, f.ck
        ));
    }
    Ok(f)
}

/// One solve at one resolution.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// nodes per c_s + w0 (the grid spacing is about (c_s + w0)/n)
    pub n: u32,
    /// the grid spacing [m, in the plane (X, V/ω)] ([`ladder`])
    pub h: f64,
    /// the values, in the order of [`QUANTITIES`]
    pub values: [f64; 8],
    /// power iterations to the fixed point
    pub iterations: u32,
    /// mass per flip leaving the grid's box (renormalised away)
    pub lost: f64,
    /// the last iteration's change of the measure (L1)
    pub change: f64,
    /// λ (T_stick + T_slip): the share of the time to the next flip the walks accounted for
    /// (1 but for the mass lost and the walks' horizon e^{−41.4})
    pub covered: f64,
}

/// Steps remembered by the Anderson mixing of [`solve`].
pub(crate) const DEPTH: usize = 8;
/// The change of the measure (L1) at which the power iteration stops.
const TOLERANCE: f64 = 1e-12;
/// The iteration limit (the chain mixes in a few flips: ~40 iterations reach the tolerance).
const MAX_ITERATIONS: u32 = 1000;

/// The resolutions of a solve whose finest is `finest`, coarsest first, `count` of them, each
/// half as fine as the next: (n, h) with h = w0 / rows, rows a whole number (the rows of nodes
/// are then at whole multiples of h, and the density's cells hold whole rows) and the grids
/// nested (h doubles exactly: Richardson's extrapolation needs the ratio), about (c_s + w0)/n.
pub(crate) fn ladder(frame: Frame, finest: u32, count: u32) -> Result<Vec<(u32, f64)>, String> {
    let step = 1u32 << (count - 1);
    let rows = (f64::from(finest) * frame.w0 / (frame.cs + frame.w0) / f64::from(step)).ceil().max(1.0) * f64::from(step);
    let out: Vec<(u32, f64)> = (0..count).rev().map(|k| (finest >> k, frame.w0 / rows * f64::from(1u32 << k))).collect();
    // the measure is held on nodes h apart: the flow between two flips must carry a state
    // across a good part of that (a stick moves v0/λ on average), or the walks end about where
    // they began and the measure stays on its nodes (λ = 10^6 on the paper scene did not
    // converge in 1000 iterations)
    let travel = frame.v0 / frame.lambda;
    if out[0].1 > 4.0 * travel {
        return Err(format!(
            "the mass moves about v0/lambda = {travel:.2e} m between belt flips, less than a quarter of the coarsest grid spacing {:.2e} m: raise --resolution (up to 320) or simulate instead",
            out[0].1
        ));
    }
    Ok(out)
}

/// Solve for the stationary law at resolution n, grid spacing h ([`ladder`]); `step` hears
/// each iteration's number and change.
pub(crate) fn solve(frame: Frame, (n, h): (u32, f64), with_density: bool, step: &mut dyn FnMut(u32, f64)) -> Result<(Level, Option<density::Density>), String> {
    let mesh = Mesh::new(frame, h, frame.box_half());
    let cont = chain::continuation(&mesh);
    let mut nu = chain::Measure::zero(&mesh, cont.samples.len());
    let share = 1.0 / nu.line.len() as f64;
    nu.line.iter_mut().for_each(|m| *m = share);
    let (mut tally, mut iterations, mut change, mut lost) = (Tally::default(), 0, f64::INFINITY, 0.0);
    // The step is linear (but for the renormalisation) and its slowest modes are an oscillating
    // pair of modulus ≈ 0.8 per flip on the paper scene (the stick position's walk over the
    // stick region): plain power iteration needs ~120 steps to 1e-12; Anderson mixing over the
    // last `DEPTH` steps (a GMRES in disguise for a linear map) removes those modes.
    let mut anderson = anderson::Anderson::new(DEPTH);
    while iterations < MAX_ITERATIONS && change > TOLERANCE {
        let (mut next, t) = chain::step(&mesh, &cont, &nu);
        lost = t.lost;
        tally = t;
        next.scale(1.0 / next.total());
        change = next.distance(&nu);
        iterations += 1;
        step(iterations, change);
        let mixed = anderson.mix(nu.flat(), next.flat());
        nu.set_flat(&mixed);
        nu.scale(1.0 / nu.total());
    }
    if change > TOLERANCE {
        return Err(format!("the stationary measure did not converge at resolution {n} ({iterations} iterations, last change {change:.1e})"));
    }
    let level =
        Level { n, h, values: quantities(&tally, frame.lambda), iterations, lost, change, covered: frame.lambda * (tally.stick_time + tally.slip_time) };
    Ok((level, with_density.then(|| density::occupation(&mesh, &cont, &nu))))
}

/// The quantities from the tallies (module docs).
fn quantities(t: &Tally, lambda: f64) -> [f64; 8] {
    let n = t.entries;
    let (d, h) = (t.d1 / n, t.slip_time / n);
    [lambda * t.stick_time, d, h, t.d2 / n - d * d, 2.0 * t.slip_age_time / n - h * h, lambda * n, t.breakaways / n, d + h]
}

/// The long-run law of a scene at `count` resolutions up to `finest` ([`ladder`]), or why it
/// cannot be computed (module docs).
pub fn stationary(scene: &Scene, finest: u32, count: u32) -> Result<Vec<Level>, String> {
    let frame = frame(scene)?;
    ladder(frame, finest, count)?.into_iter().map(|r| Ok(solve(frame, r, false, &mut |_, _| {})?.0)).collect()
}
