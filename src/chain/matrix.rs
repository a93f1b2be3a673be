//! The chain's linear system between events: the matrix Ã of ż = Ã z for a mode, the weighted
//! norm that bounds e^{Ãτ}, the Taylor step of the state and the Taylor polynomial of an event
//! function with its proven truncation bound (module docs of [`super`] and [`super::exact`]).

use super::roots::Poly;
use super::Chain;

/// Taylor terms kept: with ‖Ã‖τ ≤ 1 the next term is below 1/25! ≈ 6·10⁻²⁶ of ‖z‖.
pub(crate) const TERMS: usize = 24;

/// Unit roundoff.
const U: f64 = f64::EPSILON * 0.5;

/// The contact's mode: stuck to the belt, or slipping with friction direction σ = sgn(v − ẋ_N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Mode {
    Stick,
    Slip(f64),
}

/// The linear system of one phase (a mode under belt velocity v and anchor velocity u).
#[derive(Debug, Clone)]
pub(crate) struct System {
    /// the state's dimension 2N + 2
    pub dim: usize,
    /// Ã, row-major
    a: Vec<f64>,
    /// the weights d of the norm ‖z‖_D = max |z_i|/d_i
    weight: Vec<f64>,
    /// ‖Ã‖_D
    pub norm: f64,
}

/// Index helpers of the state z = (x₁…x_N, ẋ₁…ẋ_N, a, 1).
pub(crate) fn x(i: usize) -> usize {
    i
}
pub(crate) fn xd(n: usize, i: usize) -> usize {
    n + i
}
pub(crate) fn anchor(n: usize) -> usize {
    2 * n
}
pub(crate) fn one(n: usize) -> usize {
    2 * n + 1
}

impl System {
    /// Ã of `mode` under belt velocity `v` and anchor velocity `u`; `rate` is a floor of the
    /// norm's unit rate Ω [1/s] (1/t_a: a chain with no spring and no dashpot still gets steps).
    pub fn new(ch: &Chain, mode: Mode, v: f64, u: f64, rate: f64) -> System {
        let n = ch.len();
        let dim = 2 * n + 2;
        let mut a = vec![0.0; dim * dim];
        let at = |r: usize, c: usize| r * dim + c;
        let (m, k, c) = (&ch.masses, &ch.stiffnesses, &ch.dampings);
        let mut omega: f64 = rate;
        for i in 0..n {
            a[at(x(i), xd(n, i))] = 1.0;
            if mode == Mode::Stick && i == n - 1 {
                continue;
            }
            let r = xd(n, i);
            // the spring and dashpot before m_i (to the anchor for i = 0)
            let (prev_x, kk, cc) = (if i == 0 { anchor(n) } else { x(i - 1) }, k[i] / m[i], c[i] / m[i]);
            a[at(r, prev_x)] += kk;
            a[at(r, x(i))] -= kk;
            if i == 0 {
                a[at(r, one(n))] += cc * u;
            } else {
                a[at(r, xd(n, i - 1))] += cc;
            }
            a[at(r, xd(n, i))] -= cc;
            if i + 1 < n {
                let (kn, cn) = (k[i + 1] / m[i], c[i + 1] / m[i]);
                a[at(r, x(i))] -= kn;
                a[at(r, x(i + 1))] += kn;
                a[at(r, xd(n, i))] -= cn;
                a[at(r, xd(n, i + 1))] += cn;
            }
            let mut viscous = 0.0;
            if let (Mode::Slip(sigma), true) = (mode, i == n - 1) {
                a[at(r, one(n))] += (sigma * ch.kinetic + ch.viscous * v) / m[i];
                a[at(r, xd(n, i))] -= ch.viscous / m[i];
                viscous = ch.viscous;
            }
            omega = omega.max(super::mass_rate(m, k, c, viscous, i));
        }
        a[at(anchor(n), one(n))] = u;
        // the constant's weight: its column adds at most Ω to any row's weighted sum
        let mut d_one = f64::INFINITY;
        for r in 0..dim - 1 {
            let b = a[at(r, one(n))].abs();
            if b > 0.0 {
                let d_r = if (n..2 * n).contains(&r) { omega } else { 1.0 };
                d_one = d_one.min(omega * d_r / b);
            }
        }
        if !d_one.is_finite() {
            d_one = 1.0;
        }
        let weight: Vec<f64> = (0..dim)
            .map(|r| {
                if r == one(n) {
                    d_one
                } else if (n..2 * n).contains(&r) {
                    omega
                } else {
                    1.0
                }
            })
            .collect();
        let norm = (0..dim).map(|r| (0..dim).map(|c| a[at(r, c)].abs() * weight[c]).sum::<f64>() / weight[r]).fold(0.0, f64::max);
        System { dim, a, weight, norm }
    }

    /// Row vector times Ã.
    pub fn left(&self, r: &[f64]) -> Vec<f64> {
        let d = self.dim;
        let mut out = vec![0.0; d];
        for (i, &ri) in r.iter().enumerate() {
            if ri != 0.0 {
                for (o, &aij) in out.iter_mut().zip(&self.a[i * d..(i + 1) * d]) {
                    *o += ri * aij;
                }
            }
        }
        out
    }

    /// Ã times a vector, into `out`.
    fn right(&self, z: &[f64], out: &mut [f64]) {
        let d = self.dim;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.a[i * d..(i + 1) * d].iter().zip(z).map(|(a, b)| a * b).sum();
        }
    }

    /// The vectors w_j = Ã^j z, j = 0…TERMS, into `w` (flattened): z(τ + s) = Σ_j w_j s^j/j!
    /// and an event function's derivatives g^{(j)} = c·w_j come from them.
    pub fn powers(&self, z: &[f64], w: &mut Vec<f64>) {
        let d = self.dim;
        w.resize((TERMS + 1) * d, 0.0);
        w[..d].copy_from_slice(z);
        for j in 1..=TERMS {
            let (done, next) = w.split_at_mut(j * d);
            self.right(&done[(j - 1) * d..], &mut next[..d]);
        }
    }

    /// The state Σ_j w_j s^j/j! at s from the [`System::powers`] `w` (Horner).
    pub fn at(&self, w: &[f64], s: f64, out: &mut Vec<f64>) {
        let d = self.dim;
        out.clear();
        out.extend_from_slice(&w[TERMS * d..(TERMS + 1) * d]);
        for j in (0..TERMS).rev() {
            let scale = s / (j + 1) as f64;
            for (o, wj) in out.iter_mut().zip(&w[j * d..(j + 1) * d]) {
                *o = wj + scale * *o;
            }
        }
    }

    /// ‖z‖_D.
    pub fn size(&self, z: &[f64]) -> f64 {
        z.iter().zip(&self.weight).map(|(z, d)| z.abs() / d).fold(0.0, f64::max)
    }

    /// z(s) = e^{Ãs} z by its Taylor series (Horner; s‖Ã‖_D ≤ 1).
    pub fn step(&self, z: &[f64], s: f64) -> Vec<f64> {
        let mut y = z.to_vec();
        let mut ay = vec![0.0; self.dim];
        for j in (1..=TERMS).rev() {
            self.right(&y, &mut ay);
            for ((yi, zi), ai) in y.iter_mut().zip(z).zip(&ay) {
                *yi = zi + s / j as f64 * ai;
            }
        }
        y
    }

    /// The Taylor polynomial in s of g(τ + s) = c·z(τ + s) from the [`System::powers`] `w` of
    /// z = z(τ), valid on [0, h], and the bound of |g − P| there: the truncation
    /// ‖c‖_D* ‖Ã‖_D^{M+1} e^{‖Ã‖h} ‖z‖_D h^{M+1}/(M+1)! (|c Ã^{M+1} z(τ + s)| ≤ ‖c‖_D* ‖Ã‖_D^{M+1}
    /// ‖e^{Ãs}‖_D ‖z‖_D) and the rounding of the coefficients (each a dot product and a
    /// chain of TERMS matrix-vector products: (dim + TERMS + 4) u of its absolute terms, the
    /// latter bounded by ‖c‖_D* ‖Ã‖_D^j ‖z‖_D).
    pub fn taylor(&self, c: &[f64], w: &[f64], h: f64) -> (Poly, f64) {
        let d = self.dim;
        let dual: f64 = c.iter().zip(&self.weight).map(|(r, d)| r.abs() * d).sum();
        let size = self.size(&w[..d]);
        let mut coef = Vec::with_capacity(TERMS + 1);
        let (mut fact, mut rounding, mut power, mut growth) = (1.0, 0.0, 1.0, 1.0);
        for j in 0..=TERMS {
            if j > 0 {
                fact *= j as f64;
                power *= h;
                growth *= self.norm;
            }
            coef.push(dot(c, &w[j * d..(j + 1) * d]) / fact);
            rounding += (d + TERMS + 4) as f64 * U * dual * growth * size / fact * power;
        }
        let truncation = dual * growth * self.norm * (self.norm * h).exp() * size * power * h / (fact * (TERMS + 1) as f64);
        (Poly { c: coef }, truncation + rounding)
    }
}

/// The rows of the event functions: w = v − ẋ_N, and F = k_N (x_N − x_{N−1}) + c_N (v − ẋ_{N−1}).
pub(crate) fn relative_velocity(n: usize, v: f64) -> Vec<f64> {
    let mut c = vec![0.0; 2 * n + 2];
    c[one(n)] = v;
    c[xd(n, n - 1)] = -1.0;
    c
}

/// The holding force F of the contact (module docs of [`super`]) as a row.
pub(crate) fn holding(ch: &Chain, v: f64, u: f64) -> Vec<f64> {
    let n = ch.len();
    let (k, c) = (ch.stiffnesses[n - 1], ch.dampings[n - 1]);
    let mut row = vec![0.0; 2 * n + 2];
    row[x(n - 1)] += k;
    row[if n == 1 { anchor(n) } else { x(n - 2) }] -= k;
    row[one(n)] += c * v;
    if n == 1 {
        row[one(n)] -= c * u;
    } else {
        row[xd(n, n - 2)] -= c;
    }
    row
}

/// The anchor's force T = k₁ (a − x₁) + c₁ (u − ẋ₁) as a row.
pub(crate) fn anchor_force(ch: &Chain, u: f64) -> Vec<f64> {
    let n = ch.len();
    let mut row = vec![0.0; 2 * n + 2];
    row[anchor(n)] = ch.stiffnesses[0];
    row[x(0)] = -ch.stiffnesses[0];
    row[one(n)] = ch.dampings[0] * u;
    row[xd(n, 0)] = -ch.dampings[0];
    row
}

/// c·z.
pub(crate) fn dot(c: &[f64], z: &[f64]) -> f64 {
    c.iter().zip(z).map(|(a, b)| a * b).sum()
}
