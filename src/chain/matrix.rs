//! The chain's linear system between events: the matrix Ã of ż = Ã z for a mode, the weighted
//! norm that bounds e^{Ãτ}, the Taylor step of the state and the Taylor polynomial of an event
//! function with its proven truncation bound (module docs of [`super`] and [`super::exact`]).

use super::roots::Poly;
use super::Chain;

/// Taylor terms kept: with ‖Ã‖τ ≤ 1/2 the next term is below 0.5¹⁹/19! ≈ 1.6·10⁻²³ of ‖z‖.
pub(crate) const TERMS: usize = 18;

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
            let (mut stiff, mut damp) = (k[i], c[i]);
            if i + 1 < n {
                let (kn, cn) = (k[i + 1] / m[i], c[i + 1] / m[i]);
                a[at(r, x(i))] -= kn;
                a[at(r, x(i + 1))] += kn;
                a[at(r, xd(n, i))] -= cn;
                a[at(r, xd(n, i + 1))] += cn;
                stiff += k[i + 1];
                damp += c[i + 1];
            }
            if let (Mode::Slip(sigma), true) = (mode, i == n - 1) {
                a[at(r, one(n))] += (sigma * ch.kinetic + ch.viscous * v) / m[i];
                a[at(r, xd(n, i))] -= ch.viscous / m[i];
                damp += ch.viscous;
            }
            omega = omega.max((stiff / m[i]).sqrt()).max(damp / m[i]);
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
    fn left(&self, r: &[f64]) -> Vec<f64> {
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

    /// Ã times a vector.
    fn right(&self, z: &[f64]) -> Vec<f64> {
        let d = self.dim;
        (0..d).map(|i| self.a[i * d..(i + 1) * d].iter().zip(z).map(|(a, b)| a * b).sum()).collect()
    }

    /// The rows r_j = c Ã^j, j = 0…TERMS + 1, of the event function c·z.
    pub fn rows(&self, c: Vec<f64>) -> Vec<Vec<f64>> {
        let mut rows = vec![c];
        for _ in 0..=TERMS {
            let next = self.left(rows.last().expect("a row"));
            rows.push(next);
        }
        rows
    }

    /// ‖z‖_D.
    pub fn size(&self, z: &[f64]) -> f64 {
        z.iter().zip(&self.weight).map(|(z, d)| z.abs() / d).fold(0.0, f64::max)
    }

    /// z(s) = e^{Ãs} z by its Taylor series (Horner; s‖Ã‖_D ≤ 1/2).
    pub fn step(&self, z: &[f64], s: f64) -> Vec<f64> {
        let mut y = z.to_vec();
        for j in (1..=TERMS).rev() {
            let ay = self.right(&y);
            for ((yi, zi), ai) in y.iter_mut().zip(z).zip(ay) {
                *yi = zi + s / j as f64 * ai;
            }
        }
        y
    }

    /// The Taylor polynomial in s of g(τ + s) = r₀·z(τ + s) from z = z(τ), valid on [0, h], and
    /// the bound of |g − P| there: the truncation ‖r_{M+1}‖_D* e^{‖Ã‖h} ‖z‖_D h^{M+1}/(M+1)!
    /// and the rounding of the coefficients.
    pub fn taylor(&self, rows: &[Vec<f64>], z: &[f64], h: f64) -> (Poly, f64) {
        let mut c = Vec::with_capacity(TERMS + 1);
        let (mut fact, mut rounding, mut power) = (1.0, 0.0, 1.0);
        for (j, r) in rows.iter().take(TERMS + 1).enumerate() {
            if j > 0 {
                fact *= j as f64;
                power *= h;
            }
            let (dot, abs) = r.iter().zip(z).fold((0.0, 0.0), |(d, a), (ri, zi)| (d + ri * zi, a + (ri * zi).abs()));
            c.push(dot / fact);
            rounding += (self.dim + 4) as f64 * U * abs / fact * power;
        }
        let last = &rows[TERMS + 1];
        let dual: f64 = last.iter().zip(&self.weight).map(|(r, d)| r.abs() * d).sum();
        let truncation = dual * (self.norm * h).exp() * self.size(z) * power * h / (fact * (TERMS + 1) as f64);
        (Poly { c }, truncation + rounding)
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

/// c·z.
pub(crate) fn dot(c: &[f64], z: &[f64]) -> f64 {
    c.iter().zip(z).map(|(a, b)| a * b).sum()
}
