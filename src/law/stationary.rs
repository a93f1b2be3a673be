//! The long-run law: the belt's frames of a scene, the ladder of resolutions, the fixed point of
//! the chain of post-flip states at one resolution ([`solve`]) and the long-run quantities
//! ([`QUANTITIES`]) with their extrapolated values ([`estimates`]).

use crate::simulation::keys::Scene;

use super::anderson;
use super::chain::{self, Mesh, Tally};
use super::density;
use super::flow::Frame;
use super::richardson::extrapolate;

/// The long-run quantities, in the names of `stationary.parquet`.
pub const QUANTITIES: [&str; 8] = crate::observables::names(crate::observables::Statistic::LONG_RUN);

/// The frames of a scene's belt states (one for the symmetric belt, two for an asymmetric
/// telegraph belt: forward, reverse; [`chain::Chain`]), or why the method does not hold for it.
pub(crate) fn frames(scene: &Scene) -> Result<Vec<Frame>, String> {
    if scene.chain.is_some() {
        return Err(crate::chain::NO_CLOSED_LAW.into());
    }
    if !scene.random.is_empty() {
        return Err("parameters are drawn per realization (the long-run law is computed for fixed parameters)".into());
    }
    let p = scene.params;
    if p.viscous != 0.0 {
        return Err("model.viscous_friction is not 0: the viscous term's closed forms are not implemented here (the dashpot model.damping is)".into());
    }
    if !p.law.name().has_closed_forms(p.static_ == p.kinetic) {
        return Err(format!("{} friction with mu_s > mu_k has no closed-form slip", p.law.name().title()));
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
    let states = match scene.belt.process.two_state() {
        // (one frame holds both signs when the states are alike)
        Some(t) if t.forward_speed == t.reverse_speed && t.forward_rate == t.reverse_rate => vec![(t.forward_speed, t.forward_rate, "belt.switch_rate")],
        Some(t) => vec![(t.forward_speed, t.forward_rate, "belt.switch_rate"), (t.reverse_speed, t.reverse_rate, "belt.reverse_switch_rate")],
        None => return Err(format!("the belt is \"{}\", not a two-state flip process", scene.belt.process.name())),
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

/// What [`solve`] returns when its `step` asks it to stop, and a walk of passages when its `go_on`
/// says no ([`super::passage::walk_sequence`]).
pub(crate) const STOPPED: &str = "stopped";

/// Solve for the stationary law at resolution n, grid spacings h ([`ladder`]); `step` hears
/// each iteration's number and change, and answers whether to go on (false: the solve stops
/// with [`STOPPED`], how a cancelled stage ends within an iteration of about a second).
pub(crate) fn solve(
    frames: &[Frame],
    (n, h): &Rung,
    with_density: bool,
    step: &mut dyn FnMut(u32, f64) -> bool,
) -> Result<(Level, Option<density::Density>), String> {
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
        if !step(iterations, change) {
            return Err(STOPPED.into());
        }
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
    ladder(&frames, finest, count)?.iter().map(|r| Ok(solve(&frames, r, false, &mut |_, _| true)?.0)).collect()
}

/// (value, error) of each quantity from solves at resolutions n/4, n/2, n (or fewer): the
/// error is second order in the spacing h (module docs of [`crate::law`]), so the value is
/// Richardson's R = v_n + (v_n − v_{n/2}) / ((h_{n/2}/h_n)² − 1) (÷ 3 when h halves), and its
/// error estimate the change of R from the coarser pair (whose error bounds it); with two
/// levels, v_n and |v_n − v_{n/2}|; with one, v_n and NaN.
pub fn estimates(levels: &[Level]) -> Vec<(f64, f64)> {
    (0..QUANTITIES.len()).map(|q| extrapolate(&levels.iter().map(|l| (l.h, l.values[q])).collect::<Vec<_>>())).collect()
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
        let a = solve(&one, &ladder(&one, 16, 1).unwrap()[0], false, &mut |_, _| true).unwrap().0;
        let b = solve(&two, &ladder(&two, 16, 1).unwrap()[0], false, &mut |_, _| true).unwrap().0;
        for (q, (x, y)) in QUANTITIES.iter().zip(a.values.iter().zip(b.values)) {
            assert!((x - y).abs() <= 1e-9 * x.abs(), "{q}: one state {x}, two states {y}");
        }
        assert!((a.covered - b.covered).abs() < 1e-12, "{} {}", a.covered, b.covered);
    }
}
