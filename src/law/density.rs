//! The stationary joint density of the state (x, ẋ) in the lab frame: a density over the plane
//! while the mass slips, and line densities on ẋ = v_f and ẋ = −v_r (±v0 for the symmetric belt)
//! while it sticks (module docs of [`super`]). The time spent in each cell per unit time is
//! ρ Σ_s E_{ν_s} ∫ e^{−λ_s t} 1{state in the cell} dt over the walks from each belt state's
//! stationary post-flip measure ν_s, ρ = 1/Σ_s(1/λ_s) the belt's cycles per second. The
//! symmetric belt has one state (ρ = λ) whose two signs are equally likely in the long run, so
//! with q the density in the belt's frame the lab density is p(x, ẋ) = ½ [q(x, ẋ) + q(−x, −ẋ)];
//! the telegraph belt's forward state is the lab frame, its reverse state the reflected one:
//! p(x, ẋ) = q_f(x, ẋ) + q_r(−x, −ẋ).

use super::chain::{self, Chain, Measure};
use super::flow::{decay, Frame, Slip, Visitor};

/// The stationary density on a grid of cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Density {
    /// cell edges in x [m], symmetric about 0
    pub x_edges: Vec<f64>,
    /// cell edges in ẋ [m/s]
    pub v_edges: Vec<f64>,
    /// density while slipping [1/(m · m/s)], cell (i, j) at `slip[i * (v_edges.len() − 1) + j]`
    pub slip: Vec<f64>,
    /// cell edges in x [m] of the stick lines ẋ = +v_f (over the forward frame's [x_lo, x_b],
    /// [`Frame::hold_lo`], [`Frame::hold_hi`]; [−c_s, c_s] without a dashpot) and ẋ = −v_r (the
    /// mirror image of the reverse frame's, [−x_b, −x_lo]: a stick at X in the belt's frame is at
    /// −X in the lab when the belt runs in reverse)
    pub stick_edges: [Vec<f64>; 2],
    /// line density [1/m] on ẋ = +v0 and on ẋ = −v0
    pub stick: [Vec<f64>; 2],
    /// the velocities of the stick lines, v_f and −v_r [m/s]
    pub velocities: [f64; 2],
    /// the share of the time outside the grid
    pub outside: f64,
    /// the stationary survival of the stick duration, (t, P(D > t)) for t from 0 to the longest
    /// holding time 2 c_s/min v_s in [`SURVIVAL_POINTS`] − 1 steps
    pub stick_survival: Vec<(f64, f64)>,
}

impl Density {
    /// The centres of the stick cells of line k (0: ẋ = +v0, 1: ẋ = −v0), in the order of
    /// `stick[k]`.
    pub fn stick_centres(&self, k: usize) -> Vec<f64> {
        self.stick_edges[k].windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
    }
}

/// Points of the stick duration's survival curve.
pub const SURVIVAL_POINTS: usize = 1001;

/// About this many cells per axis of the plane (and exactly this many on the stick lines).
pub const CELLS: usize = 160;

/// The cells of the plane: in (x, ẋ/ω), squares of K node spacings (K odd), x edges at whole
/// multiples of K h and ẋ/ω edges at (m + ½) K h: the nodes' columns sit at (i + ½) h and their
/// rows at whole multiples of h (w0 is a whole number of rows), so every cell holds K × K nodes
/// (a cell holding one row more than its neighbour shows as a stripe: the walks start at the
/// nodes) and the cells are symmetric about 0, as the lab frame's (x, ẋ) ↔ (−x, −ẋ) needs.
/// Returns (K h, cells per half axis in x, in ẋ/ω), covering |x| ≤ c + c_k + 2 w0 and
/// |ẋ/ω| ≤ c + c_k + w0, c the stick regions' larger end (c_s without a dashpot), w0 the larger
/// belt speed's; h is the first state's spacing (the telegraph's reverse state has its own
/// rows, which the cells need not hold whole).
fn cells(frames: &[Frame], h: f64) -> (f64, usize, usize) {
    let reach = frames.iter().map(|f| f.hold_hi().max(-f.hold_lo()) + f.ck).fold(0.0, f64::max);
    let w0 = frames.iter().map(|f| f.w0).fold(0.0, f64::max);
    let (xd, wd) = (reach + 2.0 * w0, reach + w0);
    let k = ((2.0 * xd / (CELLS as f64 * h)).round() as usize).max(1) | 1;
    let size = k as f64 * h;
    (size, (xd / size).ceil() as usize, (wd / size - 0.5).ceil() as usize)
}

struct Occupy<'a> {
    f: Frame,
    spacing: f64,
    /// the weight per unit time: λ for the symmetric belt, the cycles per second ρ else
    rate: f64,
    /// cell size K h, and cells per half axis (`cells`)
    size: f64,
    half: (usize, usize),
    slip: &'a mut [f64],
    stick: &'a mut [f64],
    outside: &'a mut f64,
    m: f64,
    /// Σ mass × e^{−λt} of the breakaways and touches (their continuation is added once)
    follow: f64,
    /// the stick entries (x_e, mass × e^{−λ t_e})
    entries: &'a mut Vec<(f64, f64)>,
}

impl Occupy<'_> {
    fn add(&mut self, x: f64, v: f64, w: f64) {
        let (hx, hw) = self.half;
        let i = (x / self.size).floor() + hx as f64;
        let j = (v / self.f.omega / self.size + 0.5).floor() + hw as f64;
        if (0.0..(2 * hx) as f64).contains(&i) && (0.0..(2 * hw + 1) as f64).contains(&j) {
            self.slip[i as usize * (2 * hw + 1) + j as usize] += w;
        } else {
            *self.outside += w;
        }
    }
}

impl Visitor for Occupy<'_> {
    fn slip(&mut self, x: f64, v: f64, t: f64, dt: f64, _age: f64) {
        let lambda = self.f.lambda;
        self.add(x, v, self.m * self.rate * decay(lambda, t, t + dt));
    }

    fn periodic(&mut self, start: Slip, t: f64, _age: f64, period: f64) {
        let f = self.f;
        let lambda = f.lambda;
        let one = 1.0 / -(-lambda * period).exp_m1();
        for (offset, dt, (x, v)) in f.period_samples(start, period, self.spacing) {
            let s = t + offset;
            self.add(x, v, self.m * self.rate * decay(lambda, s, s + dt) * one);
        }
    }

    fn stick(&mut self, x_e: f64, t: f64) {
        let f = self.f;
        let n = self.stick.len();
        let (lo, hi) = (f.hold_lo(), f.hold_hi());
        let width = 2.0 * f.cs / n as f64;
        let first = (((x_e - lo) / width).floor().max(0.0) as usize).min(n - 1);
        for k in first..n {
            let (a, b) = ((lo + k as f64 * width).max(x_e), lo + (k + 1) as f64 * width);
            if b > a {
                self.stick[k] += self.m * self.rate * decay(f.lambda, t + (a - x_e) / f.v0, t + (b - x_e) / f.v0);
            }
        }
        self.follow += self.m * (-f.lambda * (t + (hi - x_e) / f.v0)).exp();
        self.entries.push((x_e, self.m * (-f.lambda * t).exp()));
    }

    fn breakaway_slip(&mut self, t: f64, _age: f64) {
        self.follow += self.m * (-self.f.lambda * t).exp();
    }
}

/// One belt state's occupation in its frame: the slip cells, the stick cells, the time outside
/// the cells, and its stick entries (x_e, weight).
struct Occupation {
    slip: Vec<f64>,
    stick: Vec<f64>,
    outside: f64,
    entries: Vec<(f64, f64)>,
}

/// The occupation of the walks of state s from its stationary post-flip measure `nu`, with the
/// continuation of its breakaways.
fn occupy(chain: &Chain, s: usize, nu: &Measure, rate: f64, size: f64, half: (usize, usize)) -> Occupation {
    let mesh = &chain.meshes[s];
    let f = mesh.frame;
    let cells = 2 * half.0 * (2 * half.1 + 1);
    let (mut slip, mut stick, mut outside) = (vec![0.0; cells], vec![0.0; CELLS], 0.0);
    // the breakaway's continuation, once: one pass until the breakaway slip touches the belt
    // line (μ_s = μ_k) or its stick breaks away again (μ_s > μ_k), after the period P; the
    // passes repeat, each e^{−λP} later
    let (mut b_slip, mut b_stick, mut b_out) = (vec![0.0; cells], vec![0.0; CELLS], 0.0);
    let (mut b_entries, mut entries) = (Vec::new(), Vec::new());
    let mut pass = Occupy {
        f,
        spacing: mesh.h,
        rate,
        size,
        half,
        slip: &mut b_slip,
        stick: &mut b_stick,
        outside: &mut b_out,
        m: 1.0,
        follow: 0.0,
        entries: &mut b_entries,
    };
    f.walk(f.breakaway(), 0.0, mesh.h, f64::INFINITY, &mut pass);
    let repeat = 1.0 / (1.0 - pass.follow);
    let mut occ =
        Occupy { f, spacing: mesh.h, rate, size, half, slip: &mut slip, stick: &mut stick, outside: &mut outside, m: 0.0, follow: 0.0, entries: &mut entries };
    // (the Anderson mixing leaves masses of ~1e-60 below zero where the measure vanishes: a
    // density is not negative, so those atoms are left out)
    for (z, age, m) in chain::atoms(chain, s, nu).into_iter().filter(|a| a.2 > 0.0) {
        occ.m = m;
        f.walk(z, age, mesh.h, mesh.horizon, &mut occ);
    }
    let w = occ.follow * repeat;
    slip.iter_mut().zip(&b_slip).for_each(|(a, b)| *a += w * b);
    stick.iter_mut().zip(&b_stick).for_each(|(a, b)| *a += w * b);
    outside += w * b_out;
    entries.extend(b_entries.iter().map(|&(x, e)| (x, w * e)));
    Occupation { slip, stick, outside, entries }
}

/// The stationary density from the stationary post-flip measures `nu` of the chain's states.
pub(crate) fn occupation(chain: &Chain, nu: &[Measure]) -> Density {
    let frames: Vec<Frame> = chain.meshes.iter().map(|m| m.frame).collect();
    let (size, hx, hw) = cells(&frames, chain.meshes[0].h);
    let (nx, nv) = (2 * hx, 2 * hw + 1);
    let symmetric = frames.len() == 1;
    let rate = if symmetric { frames[0].lambda } else { 1.0 / frames.iter().map(|f| 1.0 / f.lambda).sum::<f64>() };
    let occ: Vec<Occupation> = nu.iter().enumerate().map(|(s, m)| occupy(chain, s, m, rate, size, (hx, hw))).collect();
    let entries: Vec<(usize, f64, f64)> = occ.iter().enumerate().flat_map(|(s, o)| o.entries.iter().map(move |&(x, w)| (s, x, w))).collect();
    let stick_survival = survival(&frames, &entries);
    // densities, and the lab frame: the symmetric belt's (x, ẋ) and (−x, −ẋ) each half the
    // time; the telegraph's forward state as it is, its reverse state reflected
    let (first, last) = (&occ[0], &occ[occ.len() - 1]);
    let ds = 2.0 * frames[0].cs / CELLS as f64;
    let (dx, dv) = (size, size * frames[0].omega);
    let lab: Vec<f64> = (0..nx * nv)
        .map(|k| {
            let (i, j) = (k / nv, k % nv);
            let mirror = (nx - 1 - i) * nv + nv - 1 - j;
            if symmetric {
                0.5 * (first.slip[k] + first.slip[mirror]) / (dx * dv)
            } else {
                (first.slip[k] + last.slip[mirror]) / (dx * dv)
            }
        })
        .collect();
    let share = if symmetric { 0.5 } else { 1.0 };
    let plus: Vec<f64> = first.stick.iter().map(|s| share * s / ds).collect();
    let minus: Vec<f64> = last.stick.iter().rev().map(|s| share * s / ds).collect();
    let edges = |lo: f64, d: f64, n: usize| (0..=n).map(|k| lo + k as f64 * d).collect::<Vec<f64>>();
    let back = frames[frames.len() - 1];
    Density {
        x_edges: edges(-(hx as f64) * dx, dx, nx),
        v_edges: edges(-(hw as f64 + 0.5) * dv, dv, nv),
        slip: lab,
        stick_edges: [edges(frames[0].hold_lo(), ds, CELLS), edges(-back.hold_hi(), ds, CELLS)],
        stick: [plus, minus],
        velocities: [frames[0].v0, -back.v0],
        outside: occ.iter().map(|o| o.outside).sum(),
        stick_survival,
    }
}

/// The times of a stick duration's curves: [`SURVIVAL_POINTS`] from 0 to the longest holding
/// time (the stick region's width over the slowest belt speed), with `extra` (finite, ≥ 0)
/// merged in, sorted.
pub(crate) fn survival_times(frames: &[Frame], extra: &[f64]) -> Vec<f64> {
    let top = frames.iter().map(|f| 2.0 * f.cs / f.v0).fold(0.0, f64::max);
    let mut times: Vec<f64> = (0..SURVIVAL_POINTS).map(|j| top * j as f64 / (SURVIVAL_POINTS - 1) as f64).collect();
    times.extend(extra.iter().copied().filter(|t| t.is_finite() && *t >= 0.0));
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// P(D > t) = Σ w e^{−λ_s t} 1{t < d_s(x_e)} / Σ w over the stick entries (s, x_e, w) of the
/// belt states s: a stick entered at x_e ends at the earlier of the next flip (memoryless:
/// Exp(λ_s) from the entry) and the breakaway after d_s(x_e) = (x_b − x_e)/v_s — the
/// conditional estimator of the tails analysis, here on the stationary entry law.
pub(super) fn survival(frames: &[Frame], entries: &[(usize, f64, f64)]) -> Vec<(f64, f64)> {
    let times = survival_times(frames, &[]);
    let s = survival_at(frames, entries, &times);
    times.into_iter().zip(s).collect()
}

/// [`survival`] at the increasing `times`.
fn survival_at(frames: &[Frame], entries: &[(usize, f64, f64)], times: &[f64]) -> Vec<f64> {
    let total: f64 = entries.iter().map(|e| e.2).sum();
    let mut out = vec![0.0; times.len()];
    for (s, f) in frames.iter().enumerate() {
        for (o, w) in out.iter_mut().zip(held_past(*f, entries.iter().filter(|e| e.0 == s).map(|e| (e.1, e.2)), times)) {
            *o += w / total;
        }
    }
    out
}

/// e^{−λt} times the weight of the entries (x_e, w) of one belt state held past each of the
/// increasing `times` (holding time (x_b − x_e)/v0 > t), from the longest down.
fn held_past(f: Frame, entries: impl Iterator<Item = (f64, f64)>, times: &[f64]) -> Vec<f64> {
    let mut held: Vec<(f64, f64)> = entries.map(|(x, w)| ((f.hold_hi() - x) / f.v0, w)).collect();
    held.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut k, mut beyond, mut out) = (held.len(), 0.0, vec![0.0; times.len()]);
    for j in (0..times.len()).rev() {
        let t = times[j];
        while k > 0 && held[k - 1].0 > t {
            k -= 1;
            beyond += held[k].1;
        }
        out[j] = (-f.lambda * t).exp() * beyond;
    }
    out
}

/// The law of a stick's duration D from the law of its entry position held on each belt
/// state's line nodes x_j = x_lo + j h_s, j = 0 … n (`lines[s]`: h_s and the weights w_{s,j},
/// as a passage absorbs them), at the increasing `times`: (t, P(D > t), f(t)), with
/// d_s(x) = (x_b − x)/v_s the holding time and W = Σ w,
///
/// ```text
///     P(D > t) = Σ_s e^{−λ_s t} W_s(d_s > t) / W
///     f(t)     = Σ_s e^{−λ_s t} [λ_s W_s(d_s > t) + v_s g_s(x_b − v_s t)] / W
/// ```
///
/// (a stick held past t ends there by a flip at rate λ_s; one entered at x = x_b − v_s t ends by
/// the breakaway, Jacobian v_s), g_s the piecewise-linear entry density through w_{s,j}/h_s
/// (2 w/h at the two end nodes, which hold half a cell: g_s integrates to W_s). The survival
/// counts each node's weight at its own holding time, the density spreads it over the node's
/// cell: the two agree to O(h), as the entry law itself.
pub(crate) fn stick_law(frames: &[Frame], lines: &[(f64, Vec<f64>)], times: &[f64]) -> Vec<(f64, f64, f64)> {
    let total: f64 = lines.iter().flat_map(|l| l.1.iter()).sum();
    let (mut survival, mut density) = (vec![0.0; times.len()], vec![0.0; times.len()]);
    for (f, (h, w)) in frames.iter().zip(lines) {
        let beyond = held_past(*f, w.iter().enumerate().map(|(j, &w)| (f.hold_lo() + j as f64 * h, w)), times);
        let n = w.len().saturating_sub(1);
        let node = |j: usize| if j == 0 || j == n { 2.0 * w[j] / h } else { w[j] / h };
        for (j, &t) in times.iter().enumerate() {
            // the entry density at x_b − v t (the breakaway at t)
            let u = (f.hold_hi() - f.v0 * t - f.hold_lo()) / h;
            let g = if n == 0 || !(0.0..=n as f64).contains(&u) {
                0.0
            } else {
                let i = (u.floor() as usize).min(n - 1);
                let a = u - i as f64;
                (1.0 - a) * node(i) + a * node(i + 1)
            };
            survival[j] += beyond[j] / total;
            density[j] += (f.lambda * beyond[j] + (-f.lambda * t).exp() * f.v0 * g) / total;
        }
    }
    times.iter().zip(survival.into_iter().zip(density)).map(|(&t, (s, d))| (t, s, d)).collect()
}
