//! The next stick from a given state (`stickslip predict`), without sampling: the law of the
//! time τ to the next stick start, of that stick's duration D and of the slip H after it, as
//! means and variances (and D's survival curve), from the same closed-form flow as the
//! stationary chain of [`super`]; and the sequence of sticks after a start (Table 1).
//!
//! **First passage.** From a slip state z the flow ([`Frame::walk`]) reaches a stick at a time
//! t_e before the next flip with probability e^{−λ t_e} — then τ = t_e and the stick is entered
//! at x_e — or the belt flips first, at t < t_e (density λ e^{−λt}), and the walk starts again
//! from the reflected state, t later. So the measure of the post-flip states that have not yet
//! stuck is pushed through the chain's kernel with the stick absorbing, each atom carrying its
//! clocks' moments (mass; ∫ t, ∫ t² with t the time since the origin; ∫ a, ∫ a² with a the time
//! since the last stick ended, [`Clock`]), and the absorbed
//! entries accumulate the joint law of (τ, x_e). The mass left decays geometrically (from every
//! state a stick comes before the next flip with a probability bounded below); the sum stops
//! when less than 1e-13 is left.
//!
//! **Time moments through a deposit.** A flip in [s, s + dt) of a walk (u = t − s distributed
//! ∝ e^{−λu} on [0, dt): mean c = [`centroid`], second moment q = [`second_moment`]) takes
//! an atom of clock moments (m0, m1, m2) to
//!
//! ```text
//!     w (m0,  m1 + a m0,  m2 + 2a m1 + b m0),   a = s + c,  b = s² + 2sc + q
//! ```
//!
//! (E(A + s + u)² = E A² + 2(s + c) E A + s² + 2sc + E u²), w the flip's probability; a stick
//! entry at t_e shifts by t_e with weight e^{−λ t_e}. A periodic slip (under the belt line)
//! repeats its samples at s + jP, j ≥ 0, weights q^j (q = e^{−λP}), summed in closed form with
//! Σ q^j = 1/(1 − q), Σ j q^j = q/(1 − q)², Σ j² q^j = q(1 + q)/(1 − q)³.
//!
//! **The stick** entered at x_e ends at D = min(F, d): F ~ Exp(λ) the next flip (memoryless),
//! d = (x_b − x_e)/v0 the breakaway (x_b = c_s − γv0/ω², c_s without a dashpot).
//! E[D] = (1 − e^{−λd})/λ, E[D²] = (2/λ²)(1 − e^{−λd}(1 + λd)),
//! P(D > t) = e^{−λt} 1{t < d}. It ends by a flip at y ∈ [x_e, x_b) (leaving the slip state
//! (−y, −v0) in the new frame, as in the chain) or by the breakaway with probability e^{−λd}
//! (leaving (x_b, v0), below belt speed).
//!
//! **The slip after it** H: the first passage again, from those exits, on a clock started at the
//! stick's end. From a stuck state (`--stuck`) the current stick is such a stick entered at the
//! given x (its remaining time R closed form), and τ = R + the passage from its exits, on one
//! clock.
//!
//! **Accuracy**: as the chain's (second order in the grid spacing h: the start and the
//! breakaway are walked exactly, every later state is held on the grid's nodes), extrapolated
//! from three resolutions by [`super::richardson::extrapolate`].

use std::f64::consts::TAU;

use super::chain::{Mesh, CHUNKS};
use super::clock::{Clocks, Moments};
use super::flow::one_minus_exp_poly;
use super::flow::{decay, Frame, Slip, Visitor};
use super::stationary::STOPPED;

/// An atom's clocks for Table 1: its mass; ∫ t dμ and ∫ t² dμ, t the time since the origin;
/// ∫ a dμ and ∫ a² dμ, a the time since the last stick ended (since the origin before the
/// first) [1, s, s², s, s²] ([`super::clock`]).
pub(crate) type Clock = Moments;

/// The states a passage starts from in one belt state (every later state is on the grid,
/// [`passage`]): line nodes (a flip during a stick of the state before, at y: the slip from
/// (−y, −v0) in this frame), the breakaway (x_b, v0) and the starts, with their clocks.
#[derive(Debug, Clone)]
struct Cloud<C> {
    line: Vec<C>,
    breakaway: C,
    starts: Vec<(Slip, C)>,
}

/// The state a flip from s leads to among n ([`super::chain::Chain`]).
fn next(n: usize, s: usize) -> usize {
    (s + 1) % n
}

/// The state whose flips lead to d among n.
fn prev(n: usize, d: usize) -> usize {
    (d + n - 1) % n
}

impl<C: Clocks> Cloud<C> {
    /// The empty cloud of every state of `meshes`.
    fn zero(meshes: &[Mesh]) -> Vec<Cloud<C>> {
        (0..meshes.len()).map(|d| Cloud { line: vec![C::zero(); meshes[prev(meshes.len(), d)].n_line + 1], breakaway: C::zero(), starts: Vec::new() }).collect()
    }

    /// Every atom of state d's cloud: its slip state (in d's frame) and clock.
    fn atoms(&self, meshes: &[Mesh], d: usize) -> Vec<(Slip, C)> {
        let (f, from) = (meshes[d].frame, &meshes[prev(meshes.len(), d)]);
        let mut out: Vec<(Slip, C)> = self.starts.clone();
        for (k, &c) in self.line.iter().enumerate() {
            if c.mass() > 1e-300 {
                let y = from.frame.hold_lo() + k as f64 * from.h_line;
                out.push((Slip::at(-y, -from.frame.v0, f.v0), c));
            }
        }
        if self.breakaway.mass() > 1e-300 {
            out.push((f.breakaway(), self.breakaway));
        }
        out
    }
}

/// One step's walks on `src`: the next post-flip states on `dst`'s grid (the next belt state),
/// the stick entries (per stick node of `src`, the entry position x_e split linearly) and the
/// mass deposited outside the grid.
struct Pass<'a, C: Clocks> {
    ctx: &'a C::Ctx,
    src: &'a Mesh,
    dst: &'a Mesh,
    /// the grid's clocks
    next: &'a mut [C],
    entries: &'a mut [C],
    clock: C,
    lost: f64,
}

impl<C: Clocks> Pass<'_, C> {
    /// A flip at (x, v): the reflected state's nodes get `clock`.
    fn put(&mut self, x: f64, v: f64, clock: C) {
        match self.dst.corners(-x, -v) {
            Some(corners) => corners.into_iter().for_each(|(k, w)| self.next[k].add(&clock, w)),
            None => self.lost += clock.mass(),
        }
    }
}

impl<C: Clocks> Visitor for Pass<'_, C> {
    fn slip(&mut self, x: f64, v: f64, t: f64, dt: f64, _age: f64) {
        let lambda = self.src.frame.lambda;
        let w = lambda * decay(lambda, t, t + dt);
        self.put(x, v, self.clock.later(self.ctx, w, t, lambda, dt));
    }

    fn periodic(&mut self, start: Slip, t: f64, _age: f64, period: f64) {
        let f = self.src.frame;
        let lambda = f.lambda;
        let m = self.clock;
        for (offset, dt, (x, v)) in f.period_samples(start, period, self.src.h) {
            let s = t + offset;
            let w = lambda * decay(lambda, s, s + dt);
            self.put(x, v, m.repeating(self.ctx, w, s, lambda, dt, period));
        }
    }

    fn stick(&mut self, x_e: f64, t: f64) {
        let (mesh, f) = (self.src, self.src.frame);
        let clock = self.clock.later(self.ctx, (-f.lambda * t).exp(), t, f.lambda, 0.0);
        let fy = ((x_e - f.hold_lo()) / mesh.h_line).clamp(0.0, mesh.n_line as f64);
        let k = (fy as usize).min(mesh.n_line - 1);
        let frac = fy - k as f64;
        self.entries[k].add(&clock, 1.0 - frac);
        self.entries[k + 1].add(&clock, frac);
    }

    fn breakaway_slip(&mut self, t: f64, age: f64) {
        // (μ_s = μ_k: the slip touches the belt line at the breakaway point and goes on around
        // the same circle, once per period 2π/ω, until a flip)
        let f = self.src.frame;
        self.periodic(f.breakaway(), t, age, TAU / f.omega);
    }
}

/// The passage's fixed-point iteration stops when every clock moment changes by less than this
/// (L1, relative) — or fails after `MAX_ITERATIONS`.
const TOLERANCE: f64 = 1e-12;
const MAX_ITERATIONS: u32 = 1000;

/// Walk `atoms` of `src` once: their post-flip deposits on `dst`'s grid, their stick entries
/// (on `src`'s stick nodes) and the mass lost off the grid (in fixed chunks, summed in order:
/// the same for any number of threads). `scratch` holds the chunks' grids across calls
/// (allocating them afresh each time cost a third of the run in page faults).
fn walk_all<C: Clocks>(ctx: &C::Ctx, src: &Mesh, dst: &Mesh, atoms: &[(Slip, C)], scratch: &mut Vec<Vec<C>>) -> (Vec<C>, Vec<C>, f64) {
    use rayon::prelude::*;
    let nodes = dst.nx * dst.nw;
    let size = atoms.len().div_ceil(CHUNKS).max(1);
    scratch.resize_with(CHUNKS, || vec![C::zero(); nodes]);
    let parts: Vec<(Vec<C>, f64)> = atoms
        .par_chunks(size)
        .zip(scratch.par_iter_mut())
        .map(|(chunk, grid)| {
            grid.fill(C::zero());
            let mut got = vec![C::zero(); src.n_line + 1];
            let mut pass = Pass { ctx, src, dst, next: grid, entries: &mut got, clock: C::zero(), lost: 0.0 };
            for &(z, clock) in chunk {
                pass.clock = clock;
                src.frame.walk(z, 0.0, src.h, src.horizon, &mut pass);
            }
            let lost = pass.lost;
            (got, lost)
        })
        .collect();
    // each node's sum over the chunks in their order, the nodes in parallel
    let used = &scratch[..parts.len()];
    let mut grid = vec![C::zero(); nodes];
    const SPAN: usize = 4096;
    grid.par_chunks_mut(SPAN).enumerate().for_each(|(c, out)| {
        for g in used {
            out.iter_mut().zip(&g[c * SPAN..]).for_each(|(a, b)| a.add(b, 1.0));
        }
    });
    let (mut entries, mut lost) = (vec![C::zero(); src.n_line + 1], 0.0);
    for (got, l) in &parts {
        entries.iter_mut().zip(got).for_each(|(a, b)| a.add(b, 1.0));
        lost += l;
    }
    (grid, entries, lost)
}

/// Walk every state's atoms once: the grids of the next post-flip states (state s's walks land
/// on state s + 1's grid), each state's stick entries, and the mass lost. `scratch` per state.
fn walk_states<C: Clocks>(ctx: &C::Ctx, meshes: &[Mesh], atoms: &[Vec<(Slip, C)>], scratch: &mut [Vec<Vec<C>>]) -> (Vec<Vec<C>>, Vec<Vec<C>>, f64) {
    let n = meshes.len();
    let mut grids: Vec<Vec<C>> = meshes.iter().map(|_| Vec::new()).collect();
    let (mut entries, mut lost) = (Vec::with_capacity(n), 0.0);
    for (s, atoms) in atoms.iter().enumerate() {
        let d = next(n, s);
        let (grid, got, l) = walk_all(ctx, &meshes[s], &meshes[d], atoms, &mut scratch[d]);
        grids[d] = grid;
        entries.push(got);
        lost += l;
    }
    (grids, entries, lost)
}

/// The first passage from the clouds `first` of the states of `meshes` (module docs): each
/// state's stick entries' clocks are added to `entries`; returns the mass lost off the grid.
///
/// Every flip leaves its state on the grid, so the occupation measure of the post-flip states,
/// x = Σ_{j≥1} K^j μ0 (K the kernel with sticks absorbing, μ0 = `first`), solves the fixed point
/// x = K μ0 + K x, and the entries are A μ0 + A x (A: the absorption of a walk). The Neumann
/// series converges like 0.66^j on the paper scene (72 steps to 1e-13); Anderson mixing, as for
/// the stationary measure, needs a third of that.
fn passage<C: Clocks>(ctx: &C::Ctx, meshes: &[Mesh], first: Vec<Cloud<C>>, entries: &mut [Vec<C>]) -> Result<f64, String> {
    let mut scratch: Vec<Vec<Vec<C>>> = meshes.iter().map(|_| Vec::new()).collect();
    let atoms0: Vec<Vec<(Slip, C)>> = first.iter().enumerate().map(|(d, c)| c.atoms(meshes, d)).collect();
    let (k0, a0, lost0) = walk_states(ctx, meshes, &atoms0, &mut scratch);
    // the mixing's unit of time: the first walks' mean time (the moments then weigh alike)
    let (m0, m1) = k0.iter().flatten().chain(a0.iter().flatten()).fold((0.0, 0.0), |(a, b), c| (a + c.mass(), b + c.time_sum()));
    let unit = if m0 > 0.0 && m1 > 0.0 { m1 / m0 } else { 1.0 };
    let flat = |x: &[Vec<C>], unit: f64| {
        let mut out = Vec::with_capacity(x.iter().map(Vec::len).sum::<usize>() * C::len(ctx));
        x.iter().flatten().for_each(|c| c.write(unit, &mut out));
        out
    };
    let width = C::len(ctx);
    let mut x = k0.clone();
    let mut anderson = super::anderson::Anderson::new(super::stationary::DEPTH);
    let mut change = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        let atoms: Vec<Vec<(Slip, C)>> = meshes
            .iter()
            .zip(&x)
            .map(|(mesh, x)| {
                (0..mesh.nx)
                    .flat_map(|i| (0..mesh.nw).map(move |j| (i, j)))
                    .filter_map(|(i, j)| {
                        let c = x[i * mesh.nw + j];
                        c.nonzero().then(|| (mesh.node(i, j), c))
                    })
                    .collect()
            })
            .collect();
        let (kx, ax, lost) = walk_states(ctx, meshes, &atoms, &mut scratch);
        let g: Vec<Vec<C>> = k0
            .iter()
            .zip(&kx)
            .map(|(k0, kx)| {
                k0.iter()
                    .zip(kx)
                    .map(|(a, b)| {
                        let mut c = *a;
                        c.add(b, 1.0);
                        c
                    })
                    .collect()
            })
            .collect();
        let (gs, xs) = (flat(&g, 1.0), flat(&x, 1.0));
        change = (0..width)
            .map(|c| {
                let size: f64 = gs.iter().skip(c).step_by(width).map(|v| v.abs()).sum();
                let diff: f64 = gs.iter().skip(c).step_by(width).zip(xs.iter().skip(c).step_by(width)).map(|(a, b)| (a - b).abs()).sum();
                if size > 0.0 {
                    diff / size
                } else {
                    diff
                }
            })
            .fold(0.0, f64::max);
        if change <= TOLERANCE {
            for (e, (a, b)) in entries.iter_mut().zip(a0.iter().zip(&ax)) {
                for (e, (a, b)) in e.iter_mut().zip(a.iter().zip(b)) {
                    e.add(a, 1.0);
                    e.add(b, 1.0);
                }
            }
            return Ok(lost0 + lost);
        }
        let mixed = anderson.mix(flat(&x, unit), flat(&g, unit));
        let mut rest = mixed.chunks(width).map(|c| C::read(ctx, unit, c));
        for xs in x.iter_mut() {
            xs.iter_mut().for_each(|v| *v = rest.next().expect("the mixed vector's length"));
        }
    }
    Err(format!("the passage to the next stick did not converge in {MAX_ITERATIONS} iterations (last change {change:.1e})"))
}

/// What sticks entered with clocks (a measure of the entries) do: Σ mass, Σ mass E[D],
/// Σ mass E[D²], Σ mass P(breakaway), and the clocks at their ends (their t the stick's end L).
pub(crate) struct Held<C> {
    pub mass: f64,
    pub d1: f64,
    pub d2: f64,
    pub breakaway: f64,
    pub ends: C,
}

impl<C: Clocks> Held<C> {
    fn new() -> Held<C> {
        Held { mass: 0.0, d1: 0.0, d2: 0.0, breakaway: 0.0, ends: C::zero() }
    }

    fn add(&mut self, o: &Held<C>) {
        self.mass += o.mass;
        self.d1 += o.d1;
        self.d2 += o.d2;
        self.breakaway += o.breakaway;
        self.ends.add(&o.ends, 1.0);
    }

    /// (mean, variance) of the duration.
    fn duration(&self) -> MeanVar {
        let mean = self.d1 / self.mass;
        (mean, self.d2 / self.mass - mean * mean)
    }
}

/// Sticks of state s entered at (x_e, clocks) end (module docs): their exits are added to the
/// clouds — a flip to the next state's line, a breakaway to s's own — t running on and a
/// restarted.
fn leave<C: Clocks>(ctx: &C::Ctx, meshes: &[Mesh], s: usize, entries: impl Iterator<Item = (f64, C)>, clouds: &mut [Cloud<C>]) -> Held<C> {
    let (mesh, d) = (&meshes[s], next(meshes.len(), s));
    let f = mesh.frame;
    let lambda = f.lambda;
    let mut held = Held::<C>::new();
    for (x_e, m) in entries {
        let d_hold = (f.hold_hi() - x_e).max(0.0) / f.v0;
        let x = lambda * d_hold;
        let mass = m.mass();
        held.mass += mass;
        held.d1 += mass * -(-x).exp_m1() / lambda;
        held.d2 += mass * 2.0 * one_minus_exp_poly(x) / (lambda * lambda);
        for (offset, dt, _, k, frac) in mesh.stick_intervals(x_e) {
            let w = lambda * decay(lambda, offset, offset + dt);
            let clock = m.later(ctx, w, offset, lambda, dt).restart(ctx);
            clouds[d].line[k].add(&clock, 1.0 - frac);
            clouds[d].line[k + 1].add(&clock, frac);
            held.ends.add(&clock, 1.0);
        }
        let e = (-x).exp();
        held.breakaway += mass * e;
        let clock = m.later(ctx, e, d_hold, lambda, 0.0).restart(ctx);
        clouds[s].breakaway.add(&clock, 1.0);
        held.ends.add(&clock, 1.0);
    }
    held
}

/// Where a prediction starts, in the belt's frame (the belt at +v0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Start {
    /// slipping at this state
    Slip(Slip),
    /// stuck at this position (on the stick region [`Frame::hold_lo`] ≤ X < x_b), moving with the belt
    Stuck(f64),
}

/// (mean, variance) of a variable.
pub(crate) type MeanVar = (f64, f64);

/// The k-th stick of a sequence: when it starts (T_k), how long it lasts (D_k), when it ends
/// (L_k = T_k + D_k), the slip after it (H_k, to the start of stick k + 1) and the probability
/// that it ends by breakaway.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stick {
    pub start: MeanVar,
    pub duration: MeanVar,
    pub end: MeanVar,
    pub slip: MeanVar,
    pub breakaway: f64,
}

/// The laws of the sticks that follow a start.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Sequence {
    /// the current stick's remaining time (a stuck start)
    pub current: Option<MeanVar>,
    /// sticks 1, 2, … after the start
    pub sticks: Vec<Stick>,
    /// the start of the stick after the last (where the last slip ends)
    pub next_start: MeanVar,
    /// the mass lost off the grid (of 1)
    pub lost: f64,
    /// per stick k, the law of its entry position: per belt state the line's node spacing and
    /// the weights absorbed on its nodes ([`super::density::stick_law`] gives D_k's law)
    pub entries: Vec<Vec<(f64, Vec<f64>)>>,
}

impl Sequence {
    /// P(D_k > t) and the density of D_k at the increasing `times` (k from 0: the first stick).
    pub(crate) fn stick_law(&self, frames: &[Frame], k: usize, times: &[f64]) -> Vec<(f64, f64, f64)> {
        super::density::stick_law(frames, &self.entries[k], times)
    }
}

/// The box the grid covers for starts out to (X, V): the stationary chain's, widened to hold the
/// start's circle about the farther slip centre (the flips move a state by at most 2 c_k of
/// amplitude per half-turn).
pub(crate) fn half_width(frame: Frame, start: Start) -> f64 {
    let base = frame.box_half();
    let (x, w) = match start {
        Start::Slip(z) => (z.x, z.v / frame.omega),
        Start::Stuck(x) => (x, frame.w0),
    };
    base.max((x.abs() + frame.ck).hypot(w) + frame.ck + frame.w0)
}

/// Mean and variance of t (`at` = 1) or a (`at` = 3) from the clock sums.
fn moments(c: Clock, at: usize) -> MeanVar {
    let mean = c[at] / c[0];
    (mean, (c[at + 1] / c[0] - mean * mean).max(0.0))
}

/// The sum of the clocks `v`.
pub(crate) fn total<C: Clocks>(v: &[C]) -> C {
    v.iter().fold(C::zero(), |mut a, c| {
        a.add(c, 1.0);
        a
    })
}

/// One step of [`walk_sequence`]: a passage's absorbed entries (per belt state, per
/// stick node) and, unless it is the last, what the sticks entered there did.
pub(crate) struct Step<'a, C> {
    pub meshes: &'a [Mesh],
    pub entries: &'a [Vec<C>],
    pub held: Option<&'a Held<C>>,
}

/// The sticks after the weighted `starts` (belt state, start, weight; weights summing to 1;
/// stuck starts have a current stick first), on grids of spacings `h` (per belt state of
/// `frames`) over the box `half` ([`half_width`]), in the clock algebra C: passage k = 0, 1, …
/// from the exits of the sticks before, each reported to `step`, up to `count` (the last
/// without its sticks' exits) or until `step` says stop. `go_on` is asked before each passage
/// (a stick, a few seconds at the finest resolution); when it says no the walk ends with the
/// error [`STOPPED`]. Returns the current stick's (a stuck start's) and the mass lost off the grid.
// (the grid, the starts, how far and whether to go on, and the step: one walk's inputs)
#[allow(clippy::too_many_arguments)]
pub(crate) fn walk_sequence<C: Clocks>(
    ctx: &C::Ctx,
    frames: &[Frame],
    h: &[f64],
    half: f64,
    starts: &[(usize, Start, f64)],
    count: usize,
    go_on: &dyn Fn() -> bool,
    step: &mut dyn FnMut(Step<C>) -> bool,
) -> Result<(Option<Held<C>>, f64), String> {
    let meshes: Vec<Mesh> = frames.iter().zip(h).map(|(f, &h)| Mesh::new(*f, h, half)).collect();
    let n = meshes.len();
    let mut clouds = Cloud::zero(&meshes);
    let mut stuck: Vec<Vec<(f64, C)>> = vec![Vec::new(); n];
    for &(s, start, w) in starts {
        match start {
            Start::Slip(z) => clouds[s].starts.push((z, C::unit(w))),
            Start::Stuck(x) => stuck[s].push((x, C::unit(w))),
        }
    }
    let current = stuck.iter().any(|v| !v.is_empty()).then(|| {
        let mut held = Held::new();
        for (s, v) in stuck.into_iter().enumerate() {
            held.add(&leave(ctx, &meshes, s, v.into_iter(), &mut clouds));
        }
        held
    });
    let node = |s: usize, k: usize| meshes[s].frame.hold_lo() + k as f64 * meshes[s].h_line;
    let mut lost = 0.0;
    for k in 0..=count {
        if !go_on() {
            return Err(STOPPED.into());
        }
        let mut entries: Vec<Vec<C>> = meshes.iter().map(|m| vec![C::zero(); m.n_line + 1]).collect();
        lost += passage(ctx, &meshes, clouds, &mut entries)?;
        if k == count {
            step(Step { meshes: &meshes, entries: &entries, held: None });
            break;
        }
        clouds = Cloud::zero(&meshes);
        let mut held = Held::new();
        for (s, e) in entries.iter().enumerate() {
            held.add(&leave(ctx, &meshes, s, e.iter().enumerate().map(|(k, &c)| (node(s, k), c)), &mut clouds));
        }
        if !step(Step { meshes: &meshes, entries: &entries, held: Some(&held) }) {
            break;
        }
    }
    Ok((current, lost))
}

/// The first `count` sticks after the weighted `starts` ([`walk_sequence`] with the moment
/// clocks): count + 1 first passages, each from the exits of the sticks before.
pub(crate) fn sequence(frames: &[Frame], h: &[f64], half: f64, starts: &[(usize, Start, f64)], count: usize) -> Result<Sequence, String> {
    sequence_until(frames, h, half, starts, count, &|| true)
}

/// [`sequence`], asking `go_on` before each passage ([`walk_sequence`]).
pub(crate) fn sequence_until(
    frames: &[Frame],
    h: &[f64],
    half: f64,
    starts: &[(usize, Start, f64)],
    count: usize,
    go_on: &dyn Fn() -> bool,
) -> Result<Sequence, String> {
    let (mut sticks, mut laws, mut next_start) = (Vec::<Stick>::new(), Vec::new(), (f64::NAN, f64::NAN));
    let (current, lost) = walk_sequence::<Clock>(&(), frames, h, half, starts, count, go_on, &mut |step: Step<Clock>| {
        let all = total(&step.entries.concat());
        if let Some(before) = sticks.last_mut() {
            before.slip = moments(all, 3);
        }
        let Some(held) = step.held else {
            next_start = moments(all, 1);
            return false;
        };
        laws.push(step.entries.iter().zip(step.meshes).map(|(e, m)| (m.h_line, e.iter().map(|c| c[0]).collect())).collect());
        sticks.push(Stick {
            start: moments(all, 1),
            duration: held.duration(),
            end: moments(held.ends, 1),
            slip: (f64::NAN, f64::NAN),
            breakaway: held.breakaway / held.mass,
        });
        true
    })?;
    Ok(Sequence { current: current.map(|h| h.duration()), sticks, lost, entries: laws, next_start })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER: Frame = Frame { omega: 2.0, v0: 1.0, w0: 0.5, ck: 1.2495, cs: 1.2495, lambda: 5.0, damped: None };

    /// (μ_s = 0.6: c_s = 1.47) λ → 0: the walks are the deterministic motion
    #[test]
    fn without_flips_the_next_stick_is_the_deterministic_one() {
        let f = Frame { cs: 1.47, lambda: 1e-6, ..PAPER };
        // the breakaway slip: about c_k, radius ρ from the angle φ_b = atan2(c_s − c_k, w0)
        // clockwise to 2π − φ_b, where it meets belt speed at 2c_k − c_s (and sticks there)
        let phi_b = (f.cs - f.ck).atan2(f.w0);
        let after_breakaway = (TAU - 2.0 * phi_b) / f.omega;
        let held = |x_e: f64| (f.cs - x_e) / f.v0;
        let close = |got: f64, want: f64, what: &str| assert!((got - want).abs() < 1e-3 * want, "{what}: {got} against {want}");
        // from rest at X = 0.5: the circle about c_k of radius r = c_k − 0.5 rises to belt speed
        // after asin(w0/r)/ω at X_a = c_k − √(r² − w0²)
        let r = f.ck - 0.5;
        let (tau, x_a) = ((f.w0 / r).asin() / f.omega, f.ck - (r * r - f.w0 * f.w0).sqrt());
        let start = Start::Slip(Slip::at(0.5, 0.0, f.v0));
        let got = sequence(&[f], &[0.05], half_width(f, start), &[(0, start, 1.0)], 2).unwrap();
        let s = got.sticks[0];
        close(s.start.0, tau, "E T_1");
        close(s.duration.0, held(x_a), "E D_1");
        close(s.end.0, tau + held(x_a), "E L_1");
        close(s.slip.0, after_breakaway, "E H_1");
        close(s.breakaway, 1.0, "P(breakaway)");
        // then the cycle: a stick at 2c_k − c_s, the same slip
        let s = got.sticks[1];
        let cycle = held(2.0 * f.ck - f.cs) + after_breakaway;
        close(s.start.0, tau + held(x_a) + after_breakaway, "E T_2");
        close(s.end.0, tau + held(x_a) + cycle, "E L_2");
        close(s.slip.0, after_breakaway, "E H_2");
        // (the variances are not small: a flip, rare as it is, can leave the mass on a circle
        // under the belt line, where it slips until the next flip, ~1/λ later)
        assert!(got.current.is_none() && got.lost == 0.0);
        // stuck at 0: the stick holds for c_s/v0, the breakaway slip, a stick at 2c_k − c_s
        let start = Start::Stuck(0.0);
        let got = sequence(&[f], &[0.05], half_width(f, start), &[(0, start, 1.0)], 1).unwrap();
        let s = got.sticks[0];
        close(got.current.unwrap().0, held(0.0), "E R");
        close(s.start.0, held(0.0) + after_breakaway, "E T_1 (stuck)");
        close(s.duration.0, held(2.0 * f.ck - f.cs), "E D_1 (stuck)");
        close(s.slip.0, after_breakaway, "E H_1 (stuck)");
    }
}
