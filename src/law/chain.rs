//! The chain of post-flip states (module docs of [`super`]): its measure on three supports — a
//! grid of the plane, the belt line's image and the breakaway slip's image — one step of its
//! kernel by walking every atom's flow, and the long-run tallies read off the same walks.

use super::flow::{aged_decay, centroid, decay, Frame, Slip, Visitor};

/// Sums over the walks of one step, per unit mass of the measure walked (module docs of
/// [`super`]): times are ∫ e^{−λt}(…) dt up to the next flip, counts are weighted by e^{−λt}.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Tally {
    /// ∫ e^{−λt} 1{stuck} dt
    pub stick_time: f64,
    /// ∫ e^{−λt} 1{slipping} dt
    pub slip_time: f64,
    /// ∫ e^{−λt} (age of the slip) 1{slipping} dt
    pub slip_age_time: f64,
    /// Σ e^{−λ t_e} over stick entries
    pub entries: f64,
    /// Σ e^{−λ t_b} over breakaways
    pub breakaways: f64,
    /// Σ e^{−λ t_e} E[D | entry], D = min(flip time, holding time)
    pub d1: f64,
    /// Σ e^{−λ t_e} E[D² | entry]
    pub d2: f64,
    /// mass deposited outside the grid (lost to the truncation)
    pub lost: f64,
}

impl Tally {
    pub(super) fn add(&mut self, o: &Tally, f: f64) {
        self.stick_time += f * o.stick_time;
        self.slip_time += f * o.slip_time;
        self.slip_age_time += f * o.slip_age_time;
        self.entries += f * o.entries;
        self.breakaways += f * o.breakaways;
        self.d1 += f * o.d1;
        self.d2 += f * o.d2;
        self.lost += f * o.lost;
    }
}

/// The supports of the measure and how fine they are.
#[derive(Debug, Clone)]
pub(crate) struct Mesh {
    pub frame: Frame,
    /// grid spacing in the plane (X, V/ω) [m]
    pub h: f64,
    /// nodes per axis: node (i, j) is at X = (i − nx/2 + ½) h and, for the `nb` rows j < nb
    /// below belt speed, V/ω = w0 − (nb − 1 − j) h, for the rows above, V/ω = w0 + (j − nb) h.
    /// Each side has its own row on the belt line V = v0: the friction (and so the flow) jumps
    /// there, and an interpolation across it would move mass from one side's flow to the other's
    /// (an error first order in h).
    pub nx: usize,
    pub nw: usize,
    pub nb: usize,
    /// the stick region's nodes y_j = x_lo + j h_line (x_lo = [`Frame::hold_lo`]),
    /// j = 0..=n_line: a flip during a stick at y leaves the mass at (−y, −v0) in the next
    /// state's frame, on that state's line support ([`Chain`])
    pub h_line: f64,
    pub n_line: usize,
    /// walks stop where e^{−λt} < 1e-18
    pub horizon: f64,
}

impl Mesh {
    /// The mesh of spacing h over the box |X|, |V/ω| ≤ `half`.
    pub fn new(frame: Frame, h: f64, half: f64) -> Mesh {
        let n_line = ((2.0 * frame.cs / (h / 4.0)).ceil() as usize).max(2);
        let nb = ((half + frame.w0) / h).ceil() as usize + 2;
        let na = ((half - frame.w0).max(0.0) / h).ceil() as usize + 2;
        Mesh {
            frame,
            h,
            nx: 2 * (half / h).ceil() as usize,
            nw: nb + na,
            nb,
            h_line: 2.0 * frame.cs / n_line as f64,
            n_line,
            horizon: super::flow::HORIZON_DECAYS / frame.lambda,
        }
    }

    /// The slip state of node (i, j).
    pub(super) fn node(&self, i: usize, j: usize) -> Slip {
        let f = self.frame;
        let x = (i as f64 - (self.nx / 2) as f64 + 0.5) * self.h;
        let below = j < self.nb;
        let w = if below { f.w0 - (self.nb - 1 - j) as f64 * self.h } else { f.w0 + (j - self.nb) as f64 * self.h };
        Slip { x, v: w * f.omega, below }
    }

    /// Bilinear weights of (x, v) on its side's nodes: the column i and its fraction towards
    /// i + 1, the rows j0 and j1 and the fraction towards j1; None outside.
    fn locate(&self, x: f64, v: f64) -> Option<(usize, f64, usize, usize, f64)> {
        let f = self.frame;
        let fx = x / self.h + (self.nx / 2) as f64 - 0.5;
        let dw = (v / f.omega - f.w0) / self.h;
        if !(fx >= 0.0) || !dw.is_finite() {
            return None;
        }
        let i = fx as usize;
        let (k, frac) = (dw.abs().floor(), dw.abs().fract());
        let k = k as usize;
        let (j0, j1) = if dw <= 0.0 {
            // below: rows nb − 1 (the line), nb − 2, … downwards
            (self.nb.checked_sub(1 + k)?, self.nb.checked_sub(2 + k)?)
        } else {
            (self.nb + k, self.nb + k + 1)
        };
        (i + 1 < self.nx && j1 < self.nw).then_some((i, fx - i as f64, j0, j1, frac))
    }

    /// The grid indices and bilinear weights of (x, v) on its side's nodes; None outside.
    pub(super) fn corners(&self, x: f64, v: f64) -> Option<[(usize, f64); 4]> {
        let (i, fx, j0, j1, fw) = self.locate(x, v)?;
        let nw = self.nw;
        Some([(i * nw + j0, (1.0 - fx) * (1.0 - fw)), ((i + 1) * nw + j0, fx * (1.0 - fw)), (i * nw + j1, (1.0 - fx) * fw), ((i + 1) * nw + j1, fx * fw)])
    }

    /// A stick entered at x_e, cut into the intervals where a flip can end it: (the interval's
    /// start from the entry, its length dt, the position y at its e^{−λτ}-weighted centre, the
    /// belt-line node k below y and the fraction towards k + 1). A flip at y leaves (−y, −v0).
    pub(super) fn stick_intervals(&self, x_e: f64) -> impl Iterator<Item = (f64, f64, f64, usize, f64)> + '_ {
        let f = self.frame;
        let n = ((f.hold_hi() - x_e) / (self.h_line / 2.0)).ceil().max(1.0) as usize;
        let dy = (f.hold_hi() - x_e) / n as f64;
        let dt = dy / f.v0;
        let mid = f.v0 * centroid(f.lambda, dt);
        (0..n).map(move |i| {
            let y = x_e + i as f64 * dy + mid;
            let fy = ((y - f.hold_lo()) / self.h_line).clamp(0.0, self.n_line as f64);
            let k = (fy as usize).min(self.n_line - 1);
            (i as f64 * dt, dt, y, k, fy - k as f64)
        })
    }
}

/// The meshes of the belt's states s = 0 … n − 1, a flip taking state s to s + 1 (mod n): one
/// state for the symmetric belt (its two states are one frame by the point reflection), two for
/// the telegraph belt (forward, reverse: each in its own frame, the belt at +v_s, flips at λ_s).
/// State d's measure lives on its mesh's grid, on the line support of the flips during the
/// sticks of the state before it (that state's stick nodes) and on the images of that state's
/// breakaway slip.
pub(crate) struct Chain {
    pub meshes: Vec<Mesh>,
    /// per state, what follows its breakaway (deposited into the next state's measure)
    pub conts: Vec<Continuation>,
}

impl Chain {
    pub fn new(meshes: Vec<Mesh>) -> Chain {
        let n = meshes.len();
        let conts = (0..n).map(|s| continuation(&meshes[s], &meshes[(s + 1) % n])).collect();
        Chain { meshes, conts }
    }

    /// The state a flip from s leads to.
    pub fn next(&self, s: usize) -> usize {
        (s + 1) % self.meshes.len()
    }

    /// The state whose flips lead to d.
    pub fn prev(&self, d: usize) -> usize {
        (d + self.meshes.len() - 1) % self.meshes.len()
    }

    /// The zero measure of every state.
    pub fn zero(&self) -> Vec<Measure> {
        (0..self.meshes.len())
            .map(|d| {
                let p = self.prev(d);
                Measure::zero(&self.meshes[d], &self.meshes[p], self.conts[p].samples.len())
            })
            .collect()
    }
}

/// The measure of the post-flip state: mass and age-mass (mass × the slip's age) per grid node
/// and per sample of the breakaway slip; mass per belt-line node (age 0: the slip just began).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Measure {
    pub grid: Vec<[f64; 2]>,
    pub line: Vec<f64>,
    pub graze: Vec<[f64; 2]>,
}

impl Measure {
    /// The zero measure of a state on `mesh`, whose flips come from the state on `from` (its
    /// line support is `from`'s stick nodes) with `graze` samples of that state's breakaway slip.
    pub fn zero(mesh: &Mesh, from: &Mesh, graze: usize) -> Measure {
        Measure { grid: vec![[0.0; 2]; mesh.nx * mesh.nw], line: vec![0.0; from.n_line + 1], graze: vec![[0.0; 2]; graze] }
    }

    pub fn total(&self) -> f64 {
        self.grid.iter().map(|g| g[0]).sum::<f64>() + self.line.iter().sum::<f64>() + self.graze.iter().map(|g| g[0]).sum::<f64>()
    }

    fn add(&mut self, o: &Measure) {
        self.grid.iter_mut().zip(&o.grid).for_each(|(a, b)| *a = [a[0] + b[0], a[1] + b[1]]);
        self.line.iter_mut().zip(&o.line).for_each(|(a, b)| *a += b);
        self.graze.iter_mut().zip(&o.graze).for_each(|(a, b)| *a = [a[0] + b[0], a[1] + b[1]]);
    }

    /// Every number of the measure in one vector (grid, line, graze).
    pub fn flat(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.grid.iter().flatten().copied().collect();
        v.extend(&self.line);
        v.extend(self.graze.iter().flatten());
        v
    }

    /// The length of [`Measure::flat`]'s vector.
    pub fn flat_len(&self) -> usize {
        2 * self.grid.len() + self.line.len() + 2 * self.graze.len()
    }

    /// The measure from [`Measure::flat`]'s vector.
    pub fn set_flat(&mut self, v: &[f64]) {
        let (g, rest) = v.split_at(2 * self.grid.len());
        let (l, z) = rest.split_at(self.line.len());
        self.grid.iter_mut().zip(g.chunks(2)).for_each(|(a, b)| *a = [b[0], b[1]]);
        self.line.copy_from_slice(l);
        self.graze.iter_mut().zip(z.chunks(2)).for_each(|(a, b)| *a = [b[0], b[1]]);
    }

    pub fn scale(&mut self, f: f64) {
        self.grid.iter_mut().for_each(|a| *a = [a[0] * f, a[1] * f]);
        self.line.iter_mut().for_each(|a| *a *= f);
        self.graze.iter_mut().for_each(|a| *a = [a[0] * f, a[1] * f]);
    }

    /// Σ |mass difference|.
    pub fn distance(&self, o: &Measure) -> f64 {
        let g: f64 = self.grid.iter().zip(&o.grid).map(|(a, b)| (a[0] - b[0]).abs()).sum();
        let l: f64 = self.line.iter().zip(&o.line).map(|(a, b)| (a - b).abs()).sum();
        let z: f64 = self.graze.iter().zip(&o.graze).map(|(a, b)| (a[0] - b[0]).abs()).sum();
        g + l + z
    }
}

/// What follows a breakaway, per unit mass at the breakaway instant (the same for every walk
/// that reaches one): its deposits and tallies, the repetitions of its cycle summed.
#[derive(Debug, Clone)]
pub(crate) struct Continuation {
    /// the breakaway slip's samples (x, v) before the flip: the graze support's atoms are their
    /// images (−x, −v)
    pub samples: Vec<(f64, f64)>,
    /// its deposits on the belt line's nodes and the graze support
    pub line: Vec<f64>,
    pub graze: Vec<[f64; 2]>,
    pub tally: Tally,
}

/// A walk's visitor: deposits the post-flip states of a flip at each moment into `out` (the next
/// state's measure, on `dst`) and adds the tallies, for a walk of mass `m` on `src`.
struct Deposit<'a> {
    src: &'a Mesh,
    dst: &'a Mesh,
    out: &'a mut Measure,
    tally: &'a mut Tally,
    m: f64,
    /// slip samples go to the graze support in order (building the continuation) instead of
    /// the grid
    to_graze: Option<usize>,
    /// the weights of the continuation to add (`add_continuation`)
    follow: [f64; 2],
}

impl Deposit<'_> {
    fn slip_at(&mut self, x: f64, v: f64, mass: f64, age_mass: f64) {
        if let Some(k) = self.to_graze.as_mut() {
            self.out.graze[*k][0] += mass;
            self.out.graze[*k][1] += age_mass;
            *k += 1;
            return;
        }
        // the flip reverses the frame: (x, v) → (−x, −v)
        match self.dst.corners(-x, -v) {
            Some(corners) => {
                for (k, w) in corners {
                    let g = &mut self.out.grid[k];
                    g[0] += w * mass;
                    g[1] += w * age_mass;
                }
            }
            None => self.tally.lost += mass,
        }
    }
}

impl Visitor for Deposit<'_> {
    fn slip(&mut self, x: f64, v: f64, t: f64, dt: f64, age: f64) {
        let lambda = self.src.frame.lambda;
        let w = self.m * lambda * decay(lambda, t, t + dt);
        self.slip_at(x, v, w, w * (age + centroid(lambda, dt)));
        self.tally.slip_time += self.m * decay(lambda, t, t + dt);
        self.tally.slip_age_time += self.m * aged_decay(lambda, t, t + dt, age);
    }

    fn periodic(&mut self, start: Slip, t: f64, age: f64, period: f64) {
        // every sample repeats at t + kP, k ≥ 0: mass Σ_k e^{−λkP} = 1/(1 − q), age-mass
        // Σ_k e^{−λkP}(a + kP) = a/(1 − q) + P q/(1 − q)², q = e^{−λP}
        let f = self.src.frame;
        let lambda = f.lambda;
        let q = (-lambda * period).exp();
        let (one, extra) = (1.0 / -(-lambda * period).exp_m1(), period * q / (1.0 - q).powi(2));
        for (offset, dt, (x, v)) in f.period_samples(start, period, self.src.h) {
            let s = t + offset;
            let w = self.m * lambda * decay(lambda, s, s + dt);
            let a = age + offset + centroid(lambda, dt);
            self.slip_at(x, v, w * one, w * (a * one + extra));
        }
        let e = (-lambda * t).exp();
        self.tally.slip_time += self.m * e / lambda;
        self.tally.slip_age_time += self.m * e * (age / lambda + 1.0 / (lambda * lambda));
    }

    fn stick(&mut self, x_e: f64, t: f64) {
        let (mesh, f) = (self.src, self.src.frame);
        let lambda = f.lambda;
        let e = (-lambda * t).exp();
        let d = (f.hold_hi() - x_e) / f.v0;
        let x = lambda * d;
        self.tally.entries += self.m * e;
        self.tally.stick_time += self.m * decay(lambda, t, t + d);
        self.tally.d1 += self.m * e * -(-x).exp_m1() / lambda;
        self.tally.d2 += self.m * e * 2.0 * super::flow::one_minus_exp_poly(x) / (lambda * lambda);
        // a flip at y ∈ [x_e, x_b) leaves (−y, −v0): the next state's line support, linearly
        for (offset, dt, _, k, frac) in mesh.stick_intervals(x_e) {
            let s = t + offset;
            let w = self.m * lambda * decay(lambda, s, s + dt);
            self.out.line[k] += w * (1.0 - frac);
            self.out.line[k + 1] += w * frac;
        }
        let tb = t + d;
        self.tally.breakaways += self.m * (-lambda * tb).exp();
        self.follow(tb, 0.0);
    }

    fn breakaway_slip(&mut self, t: f64, age: f64) {
        self.follow(t, age);
    }
}

impl Deposit<'_> {
    /// The continuation from time t (of a slip `age` old going on through a touch): added per
    /// step, by its total weight (`Deposit::follow`).
    fn follow(&mut self, t: f64, age: f64) {
        let f = self.m * (-self.src.frame.lambda * t).exp();
        self.follow[0] += f;
        self.follow[1] += f * age;
    }
}

/// Add the continuation with weight `w` = [Σ mass, Σ mass × age] to a step's measure and tallies:
/// every walk's breakaway adds the same deposits, so they are added once, scaled by the sum.
fn add_continuation(cont: &Continuation, [w, wa]: [f64; 2], out: &mut Measure, tally: &mut Tally) {
    out.line.iter_mut().zip(&cont.line).for_each(|(a, b)| *a += w * b);
    // (an age only through a touch, where the continuation is one slip going on: older by it)
    out.graze.iter_mut().zip(&cont.graze).for_each(|(a, b)| *a = [a[0] + w * b[0], a[1] + w * b[1] + wa * b[0]]);
    tally.add(&cont.tally, w);
    tally.slip_age_time += wa * cont.tally.slip_time;
}

/// The continuation of a breakaway on `src` (module docs of [`super`]), its flips deposited on
/// `dst` (the next state's mesh): walk the breakaway slip once; it ends in a touch after a period
/// P (μ_s = μ_k: the slip grazes the belt line and goes on, older) or in a stick, whose breakaway
/// after the holding time closes a cycle of length P (μ_s > μ_k); the cycle's repetitions are
/// summed in closed form. (With a dashpot it may instead spiral down for good: walked to the
/// horizon, nothing repeats.)
pub(crate) fn continuation(src: &Mesh, dst: &Mesh) -> Continuation {
    let f = src.frame;
    let lambda = f.lambda;
    // the samples of one pass, with their unrepeated deposits and tallies
    struct Record {
        samples: Vec<(f64, f64, f64, f64, f64)>,
        end: Option<(bool, f64, f64)>,
    }
    impl Visitor for Record {
        fn slip(&mut self, x: f64, v: f64, t: f64, dt: f64, age: f64) {
            self.samples.push((x, v, t, dt, age));
        }
        fn periodic(&mut self, _: Slip, _: f64, _: f64, _: f64) {
            unreachable!("the breakaway slip reaches belt speed")
        }
        fn stick(&mut self, x_e: f64, t: f64) {
            self.end = Some((true, x_e, t));
        }
        fn breakaway_slip(&mut self, t: f64, _age: f64) {
            self.end = Some((false, 0.0, t));
        }
    }
    let mut rec = Record { samples: Vec::new(), end: None };
    f.walk(f.breakaway(), 0.0, src.h, f64::INFINITY, &mut rec);
    let samples: Vec<(f64, f64)> = rec.samples.iter().map(|s| (s.0, s.1)).collect();
    let mut deposit = Measure::zero(dst, src, samples.len());
    let mut tally = Tally::default();
    {
        let mut d = Deposit { src, dst, out: &mut deposit, tally: &mut tally, m: 1.0, to_graze: Some(0), follow: [0.0; 2] };
        for &(x, v, t, dt, age) in &rec.samples {
            d.slip(x, v, t, dt, age);
        }
        if let Some((true, x_e, t_end)) = rec.end {
            d.stick(x_e, t_end);
        }
    }
    let Some((stuck, x_e, t_end)) = rec.end else {
        // (damped: the breakaway slip spirals down without coming back to belt speed, walked
        // to the horizon — nothing repeats)
        return Continuation { samples, line: deposit.line, graze: deposit.graze, tally };
    };
    let period = if stuck { t_end + (f.hold_hi() - x_e) / f.v0 } else { t_end };
    let q = (-lambda * period).exp();
    let one = 1.0 / -(-lambda * period).exp_m1();
    if stuck {
        // the ages restart at every stick: every part repeats unchanged, e^{−λP} later
        deposit.scale(one);
        let unit = tally;
        tally = Tally::default();
        tally.add(&unit, one);
    } else {
        // one slip going on forever: the k-th pass is kP older
        let extra = period * q / (1.0 - q).powi(2);
        deposit.graze.iter_mut().for_each(|g| *g = [g[0] * one, g[1] * one + g[0] * extra]);
        tally.slip_time = 1.0 / lambda;
        tally.slip_age_time = 1.0 / (lambda * lambda);
    }
    Continuation { samples, line: deposit.line, graze: deposit.graze, tally }
}

/// The atoms of state d's measure: (start, age, mass), in d's frame.
pub(crate) fn atoms(chain: &Chain, d: usize, nu: &Measure) -> Vec<(Slip, f64, f64)> {
    let (mesh, p) = (&chain.meshes[d], chain.prev(d));
    let (f, from) = (mesh.frame, &chain.meshes[p]);
    let mut out = Vec::new();
    for i in 0..mesh.nx {
        for j in 0..mesh.nw {
            let [m, a] = nu.grid[i * mesh.nw + j];
            if m.abs() > 1e-300 {
                out.push((mesh.node(i, j), a / m, m));
            }
        }
    }
    for (k, &m) in nu.line.iter().enumerate() {
        if m.abs() > 1e-300 {
            let y = from.frame.hold_lo() + k as f64 * from.h_line;
            out.push((Slip::at(-y, -from.frame.v0, f.v0), 0.0, m));
        }
    }
    for (&(x, v), &[m, a]) in chain.conts[p].samples.iter().zip(&nu.graze) {
        if m.abs() > 1e-300 {
            out.push((Slip::at(-x, -v, f.v0), a / m, m));
        }
    }
    out
}

/// Chunks of a step's atoms, fixed in number so that the sums do not depend on the threads.
pub(super) const CHUNKS: usize = 16;

/// One step of the chain: the measure of every state's next post-flip state (state s's walks
/// land in state s + 1), and the tallies of each state's walks (per unit of its mass).
pub(crate) fn step(chain: &Chain, nu: &[Measure]) -> (Vec<Measure>, Vec<Tally>) {
    use rayon::prelude::*;
    let mut outs = chain.zero();
    let mut tallies = vec![Tally::default(); nu.len()];
    for (s, measure) in nu.iter().enumerate() {
        let (src, d) = (&chain.meshes[s], chain.next(s));
        let (dst, cont) = (&chain.meshes[d], &chain.conts[s]);
        let atoms = atoms(chain, s, measure);
        let size = atoms.len().div_ceil(CHUNKS).max(1);
        let zero = chain.zero().swap_remove(d);
        let parts: Vec<(Measure, Tally)> = atoms
            .par_chunks(size)
            .map(|chunk| {
                let mut out = zero.clone();
                let mut tally = Tally::default();
                let mut dep = Deposit { src, dst, out: &mut out, tally: &mut tally, m: 0.0, to_graze: None, follow: [0.0; 2] };
                for &(z, age, m) in chunk {
                    dep.m = m;
                    src.frame.walk(z, age, src.h, src.horizon, &mut dep);
                }
                let follow = dep.follow;
                add_continuation(cont, follow, &mut out, &mut tally);
                (out, tally)
            })
            .collect();
        for (m, t) in &parts {
            outs[d].add(m);
            tallies[s].add(t, 1.0);
        }
    }
    (outs, tallies)
}
