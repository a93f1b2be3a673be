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
//! **The telegraph belt** (forward at v_f, left at rate λ_f; reverse at −v_r, left at λ_r):
//! the two states are no longer one frame by symmetry. Each has its own frame (the belt at +v_s
//! there, flips at λ_s; the reverse frame reflected, X = −x), and a flip, still the point
//! reflection (X, V) → (−X, −V), carries a state into the other state's frame. The chain's
//! post-flip measure then lives on one mesh per state ([`chain::Chain`]): a step walks state s's
//! measure in its frame and deposits what the flips leave into the other state's. Each state is
//! entered once per cycle of the belt, whose mean length is 1/λ_f + 1/λ_r, so the per-cycle sums
//! of the tallies over both states times ρ = 1/(1/λ_f + 1/λ_r) are rates per second (one state:
//! ρ = λ), and each state's measure is renormalised to 1.
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
//! the symmetric or the telegraph belt, every flip rate > 0, fixed parameters. Anything else
//! is refused with the reason.

mod anderson;
pub(crate) mod chain;
pub(crate) mod clock;
pub mod counts;
pub mod densities;
pub mod density;
pub(crate) mod flow;
pub(crate) mod kept;
mod output;
pub(crate) mod passage;
pub mod sticks;
pub(crate) mod window;

pub(crate) use output::{densities_table, guarded, survival_table, Order};
pub use output::{estimates, markdown, run, Found, LawError, Options, LEVELS, SCENARIO_FILE};

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

/// The frames of a scene's belt states (one for the symmetric belt, two for an asymmetric
/// telegraph belt: forward, reverse; [`chain::Chain`]), or why the method does not hold for it.
pub(crate) fn frames(scene: &Scene) -> Result<Vec<Frame>, String> {
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
    // The dashpot: the closed forms hold any damping, but the grid must hold the stick region
    // shifted by c v0/k (2 ζ v0/ω) and the walks slow down as the slip turns over-damped (at
    // --resolution 8: 5.7 s at ζ = 1/8, 15 s at 0.75, 27 s at 1, 55 s at 1.25, past a minute at
    // 2.5; at ζ = 2.5e8 the grid would not fit in memory). Checked against Monte Carlo up to
    // ζ = 1/2 (tests/it/law.rs).
    let zeta = p.damping / (2.0 * (p.stiffness * p.mass).sqrt());
    if !(zeta <= ZETA_MAX) {
        return Err(format!(
            "model.damping = {} N*s/m gives the damping ratio zeta = c/(2 sqrt(k m)) = {zeta:.3}: the method is implemented for zeta <= {ZETA_MAX} (simulate instead)",
            p.damping
        ));
    }
    // (speed, rate, the key of the rate) per belt state
    let states = match &scene.belt.process {
        Process::Symmetric(s) => vec![(s.speed, s.switch_rate, "belt.switch_rate")],
        Process::Telegraph(t) if t.forward_speed == t.reverse_speed && t.forward_rate == t.reverse_rate => {
            vec![(t.forward_speed, t.forward_rate, "belt.switch_rate")]
        }
        Process::Telegraph(t) => vec![(t.forward_speed, t.forward_rate, "belt.switch_rate"), (t.reverse_speed, t.reverse_rate, "belt.reverse_switch_rate")],
        other => return Err(format!("the belt is \"{}\", not a two-state flip process", other.name())),
    };
    if let Some((_, _, key)) = states.iter().find(|s| !(s.1 > 0.0)) {
        return Err(format!("{key} is 0: without flips the motion is deterministic and has no stationary law"));
    }
    let u = p.per_unit_mass();
    // A flip rate far below ω: the walks last ~41/λ seconds of ~ω radians each, and the moments
    // of the durations (E[D²] ~ 2/λ²) lose every digit to cancellation (λ/ω = 1e-20 gave NaN).
    if let Some(&(_, rate, key)) = states.iter().find(|s| !(s.1 >= MIN_RATE_PER_OMEGA * u.omega)) {
        return Err(format!(
            "{key} = {} 1/s is below {MIN_RATE_PER_OMEGA:e} ω = {} 1/s (ω = √(k/m)): the method is implemented for flip rates λ ≥ {MIN_RATE_PER_OMEGA:e} ω (simulate instead)",
            crate::scenario::short(rate),
            crate::scenario::short(MIN_RATE_PER_OMEGA * u.omega)
        ));
    }
    if u.breakaway <= 0.0 {
        return Err("the static friction is 0: the mass never sticks".into());
    }
    if u.kinetic < 1e-6 * u.breakaway {
        // (a slip then hardly loses energy between belt speed crossings, and after a breakaway
        // it returns to belt speed at the very edge of the stick region: −c_s + 2 c_k)
        return Err("the kinetic friction is below 1e-6 of the static friction (mu_k / mu_s): not supported".into());
    }
    let damped = (u.gamma > 0.0).then(|| <crate::physics::Damped as crate::physics::SlipForm>::new(&u));
    states
        .iter()
        .map(|&(speed, rate, _)| {
            checked(Frame { omega: u.omega, v0: speed, w0: speed / u.omega, ck: u.kinetic / u.omega2, cs: u.breakaway / u.omega2, lambda: rate, damped })
        })
        .collect()
}

/// A note on the time a scene's law takes, said before it runs when it is far above the paper
/// scene's: the sequence of sticks from the initial conditions (Table 1) slows as the stick region
/// widens against the kinetic one. Measured at `--resolution 8` on 2 cores (the paper scene, μ_k =
/// 0.51, μ_s varied; `stickslip exact-law --resolution 8 --set model.static_friction_coefficient=…`):
/// μ_s/μ_k = 1: 3.8 s, 2: 8.0 s, 2.9: 15.9 s, 4: 34 s; higher resolutions take longer still.
pub fn cost_note(scene: &Scene) -> Option<String> {
    let ratio = scene.params.static_ / scene.params.kinetic;
    (ratio > 1.5).then(|| {
        format!(
            "note: mu_s/mu_k = {ratio:.2}: the exact law takes longer as the stick region widens (measured on 2 cores at --resolution 8: mu_s/mu_k = 1: 4 s, 2: 8 s, 3: 16 s, 4: 34 s; more at higher resolutions)"
        )
    })
}

/// The least flip rate per natural frequency, λ/ω, the exact law takes ([`frames`]).
const MIN_RATE_PER_OMEGA: f64 = 1e-7;

/// The largest damping ratio ζ = c/(2√(k m)) the exact law takes ([`frames`]).
const ZETA_MAX: f64 = 0.5;

/// A belt state's frame, if the grid and the walks can hold it.
fn checked(f: Frame) -> Result<Frame, String> {
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
    /// the grid spacing of the first belt state's mesh [m, in the plane (X, V/ω)] ([`ladder`])
    pub h: f64,
    /// the values, in the order of [`QUANTITIES`]
    pub values: [f64; 8],
    /// power iterations to the fixed point
    pub iterations: u32,
    /// mass per cycle of the belt (per flip for the symmetric belt) leaving the grids' boxes
    /// (renormalised away)
    pub lost: f64,
    /// the last iteration's change of the measure (L1)
    pub change: f64,
    /// ρ Σ_s (T_stick + T_slip): the share of the time the walks accounted for (1 but for the
    /// mass lost and the walks' horizon e^{−41.4}; ρ the belt's cycles per second)
    pub covered: f64,
}

/// Steps remembered by the Anderson mixing of [`solve`].
pub(crate) const DEPTH: usize = 8;
/// The change of the measure (L1) at which the power iteration stops.
const TOLERANCE: f64 = 1e-12;
/// The iteration limit (the chain mixes in a few flips: ~40 iterations reach the tolerance).
const MAX_ITERATIONS: u32 = 1000;

/// A resolution: n, and the grid spacing of each belt state's mesh ([`ladder`]).
pub type Rung = (u32, Vec<f64>);

/// The resolutions of a solve whose finest is `finest`, coarsest first, `count` of them, each
/// half as fine as the next: n and, per belt state, h = w0 / rows, rows a whole number (the
/// rows of nodes are then at whole multiples of h, and the density's cells hold whole rows) and
/// the grids nested (h doubles exactly: Richardson's extrapolation needs the ratio), about
/// (c_s + w0)/n; a later state shares the first's h where its w0 is a whole number of them.
pub(crate) fn ladder(frames: &[Frame], finest: u32, count: u32) -> Result<Vec<Rung>, String> {
    let step = 1u32 << (count - 1);
    let mut out: Vec<Rung> = (0..count).rev().map(|k| (finest >> k, Vec::new())).collect();
    let mut first: Option<f64> = None;
    for frame in frames {
        let rows = (f64::from(finest) * frame.w0 / (frame.cs + frame.w0) / f64::from(step)).ceil().max(1.0) * f64::from(step);
        // a later belt state whose belt line falls on a whole row of the first state's finest
        // grid shares its spacings (its rows are then on the density's cells too: no stripes)
        let finest_h = match first {
            Some(h0) if ((frame.w0 / h0).round() - frame.w0 / h0).abs() < 1e-9 * (frame.w0 / h0) && frame.w0 / h0 >= 0.5 => h0,
            _ => frame.w0 / rows,
        };
        first.get_or_insert(finest_h);
        for (k, rung) in (0..count).rev().zip(out.iter_mut()) {
            rung.1.push(finest_h * f64::from(1u32 << k));
        }
        // the measure is held on nodes h apart: the flow between two flips must carry a state
        // across a good part of that (a stick moves v0/λ on average), or the walks end about
        // where they began and the measure stays on its nodes (λ = 10^6 on the paper scene did
        // not converge in 1000 iterations)
        let (travel, coarsest) = (frame.v0 / frame.lambda, *out[0].1.last().expect("a spacing"));
        if coarsest > 4.0 * travel {
            return Err(format!(
                "the mass moves about v0/lambda = {travel:.2e} m between belt flips, less than a quarter of the coarsest grid spacing {coarsest:.2e} m: raise --resolution (up to 320) or simulate instead"
            ));
        }
    }
    Ok(out)
}

/// Solve for the stationary law at resolution n, grid spacings h ([`ladder`]); `step` hears
/// each iteration's number and change.
pub(crate) fn solve(frames: &[Frame], (n, h): &Rung, with_density: bool, step: &mut dyn FnMut(u32, f64)) -> Result<(Level, Option<density::Density>), String> {
    let chain = chain::Chain::new(frames.iter().zip(h).map(|(f, &h)| Mesh::new(*f, h, f.box_half())).collect());
    let mut nu = chain.zero();
    for m in nu.iter_mut() {
        let share = 1.0 / m.line.len() as f64;
        m.line.iter_mut().for_each(|m| *m = share);
    }
    let (mut tallies, mut iterations, mut change) = (Vec::new(), 0, f64::INFINITY);
    // The step is linear (but for the renormalisation) and its slowest modes are an oscillating
    // pair of modulus ≈ 0.8 per flip on the paper scene (the stick position's walk over the
    // stick region): plain power iteration needs ~120 steps to 1e-12; Anderson mixing over the
    // last `DEPTH` steps (a GMRES in disguise for a linear map) removes those modes. Each
    // state's measure is one flip into it per cycle of the belt: each is renormalised to 1.
    let mut anderson = anderson::Anderson::new(DEPTH);
    let flat = |nu: &[chain::Measure]| nu.iter().flat_map(|m| m.flat()).collect::<Vec<f64>>();
    while iterations < MAX_ITERATIONS && change > TOLERANCE {
        let (mut next, t) = chain::step(&chain, &nu);
        tallies = t;
        next.iter_mut().for_each(|m| m.scale(1.0 / m.total()));
        change = next.iter().zip(&nu).map(|(a, b)| a.distance(b)).sum();
        iterations += 1;
        step(iterations, change);
        let mixed = anderson.mix(flat(&nu), flat(&next));
        let mut rest = &mixed[..];
        for m in nu.iter_mut() {
            let (mine, more) = rest.split_at(m.flat_len());
            m.set_flat(mine);
            m.scale(1.0 / m.total());
            rest = more;
        }
    }
    if change > TOLERANCE {
        return Err(format!("the stationary measure did not converge at resolution {n} ({iterations} iterations, last change {change:.1e})"));
    }
    let (values, covered, lost) = quantities(&tallies, frames);
    let level = Level { n: *n, h: h[0], values, iterations, lost, change, covered };
    Ok((level, with_density.then(|| density::occupation(&chain, &nu))))
}

/// The quantities from the tallies of each state's walks, per unit mass of its measure (module
/// docs): each state is entered once per cycle of the belt, a cycle lasts Σ 1/λ_s on average,
/// so a sum over the states per cycle times ρ = 1/Σ(1/λ_s) is a rate per second (ρ = λ for one
/// state, taken as λ: 1/(1/λ) can differ in the last bit). Returns the values, the share of the
/// time the walks accounted for, ρ Σ (T_stick + T_slip) (1 but for the mass lost and the walks'
/// horizon e^{−41.4}), and the mass lost per cycle.
fn quantities(tallies: &[Tally], frames: &[Frame]) -> ([f64; 8], f64, f64) {
    let rho = if frames.len() == 1 { frames[0].lambda } else { 1.0 / frames.iter().map(|f| 1.0 / f.lambda).sum::<f64>() };
    let t = tallies.iter().fold(Tally::default(), |mut a, b| {
        a.add(b, 1.0);
        a
    });
    let n = t.entries;
    let (d, h) = (t.d1 / n, t.slip_time / n);
    let values = [rho * t.stick_time, d, h, t.d2 / n - d * d, 2.0 * t.slip_age_time / n - h * h, rho * n, t.breakaways / n, d + h];
    (values, rho * (t.stick_time + t.slip_time), t.lost)
}

/// The long-run law of a scene at `count` resolutions up to `finest` ([`ladder`]), or why it
/// cannot be computed (module docs).
pub fn stationary(scene: &Scene, finest: u32, count: u32) -> Result<Vec<Level>, String> {
    let frames = frames(scene)?;
    ladder(&frames, finest, count)?.iter().map(|r| Ok(solve(&frames, r, false, &mut |_, _| {})?.0)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper scene's one belt frame forced through the two-state chain (one mesh per state,
    /// both the same frame) must give the one-state values: the alternation, the per-state
    /// renormalisation and the per-cycle rates (ρ = 1/(1/λ + 1/λ) per cycle of two flips) reduce
    /// to the one-state chain's.
    #[test]
    fn two_equal_belt_states_give_the_one_state_values() {
        let sc = crate::scenario::Scenario::resolve(None, &[]).unwrap();
        let one = frames(&sc.scene().unwrap()).unwrap();
        let two = [one[0], one[0]];
        let a = solve(&one, &ladder(&one, 16, 1).unwrap()[0], false, &mut |_, _| {}).unwrap().0;
        let b = solve(&two, &ladder(&two, 16, 1).unwrap()[0], false, &mut |_, _| {}).unwrap().0;
        for (q, (x, y)) in QUANTITIES.iter().zip(a.values.iter().zip(b.values)) {
            assert!((x - y).abs() <= 1e-9 * x.abs(), "{q}: one state {x}, two states {y}");
        }
        assert!((a.covered - b.covered).abs() < 1e-12, "{} {}", a.covered, b.covered);
    }

    /// The guard's two regimes: a power law v_h = V + a h^p (+ a smaller h^{p+1} term) in the
    /// asymptotic range gets the change of the extrapolation, which bounds the error; first
    /// order (p = 1, ratio 2) and sign changes get the finest change, which bounds it there.
    #[test]
    fn the_guard_trusts_the_extrapolation_only_in_the_asymptotic_range() {
        let (big, h) = (0.3f64, [0.04f64, 0.02, 0.01]);
        for p in [1.0, 1.5, 2.0, 2.5, 3.0] {
            let pts: Vec<(f64, f64)> = h.iter().map(|&h| (h, big + 2.0 * h.powf(p) + 0.5 * h.powf(p + 1.0))).collect();
            let (value, error) = guarded(&pts, Order::Regular);
            let finest = (pts[2].1 - pts[1].1).abs();
            assert!((value - big).abs() <= error, "p = {p}: {value} ± {error}");
            if (1.5..=2.5).contains(&p) {
                assert!(error < 0.9 * finest, "p = {p}: {error} against the finest change {finest}");
            } else if p == 1.0 {
                assert_eq!(error, finest, "p = {p}");
            }
        }
        // changes 1.2e-4, 1e-4 (ratio 1.2, no power law): the finest change is the floor over
        // the extrapolation's change, 9.3e-5
        let (_, error) = guarded(&[(0.04, 0.3), (0.02, 0.30012), (0.01, 0.30022)], Order::Regular);
        assert!((error - 1e-4).abs() < 1e-12, "{error}");
        // the breakaway probability after a point start (Order::Irregular's docs): changes
        // +4.9e-4, +1.2e-4 (ratio 4.1) trusted would say 3e-6; the floor is the finest change
        let pts = [(0.17, 0.0), (0.085, 4.9e-4), (0.0425, 6.1e-4)];
        assert!(guarded(&pts, Order::Regular).1 < 1e-5);
        assert!((guarded(&pts, Order::Irregular).1 - 1.2e-4).abs() < 1e-12);
    }
}
