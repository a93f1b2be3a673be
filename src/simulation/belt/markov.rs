//! The multi-level Markov belt ([`Markov`]): a continuous-time chain on velocity levels, its
//! stationary law and its draws (the parent module's docs give the process).

use rand::Rng;

use super::BeltPath;
use crate::simulation::rng::unit_f64;

/// A multi-level Markov belt (module docs), with the tables its draws use.
#[derive(Debug, Clone, PartialEq)]
pub struct Markov {
    /// v_1 … v_n, m/s
    pub(super) velocities: Vec<f64>,
    /// r_ij, 1/s (the diagonal is 0)
    pub(super) rates: Vec<Vec<f64>>,
    /// π, the stationary law
    pub(super) stationary: Vec<f64>,
    /// q_i = Σ_{j≠i} r_ij
    pub(super) leave: Vec<f64>,
    /// per level, the cumulative jump probabilities Σ_{l≤j} r_il/q_i
    jumps: Vec<Vec<f64>>,
}

/// Most levels of a Markov belt.
pub const MAX_LEVELS: usize = 64;

impl Markov {
    /// The rate q_i at which each level is left [1/s].
    pub fn leave_rates(&self) -> &[f64] {
        &self.leave
    }

    /// The chain with `velocities` [m/s] and `rates[i][j]` [1/s] (the diagonal ignored). `Err`
    /// says what is wrong: a non-square or non-finite table, a negative rate, no unique
    /// stationary law (more than one closed class of levels).
    pub fn new(velocities: Vec<f64>, rates: Vec<Vec<f64>>) -> Result<Markov, String> {
        let n = velocities.len();
        if n == 0 || n > MAX_LEVELS {
            return Err(format!("needs 1 to {MAX_LEVELS} levels, has {n}"));
        }
        if rates.len() != n || rates.iter().any(|row| row.len() != n) {
            return Err(format!("belt.rates must be an {n}×{n} matrix (one row per velocity in belt.velocities)"));
        }
        let mut rates = rates;
        for (i, row) in rates.iter_mut().enumerate() {
            row[i] = 0.0;
            if let Some(r) = row.iter().find(|r| !(r.is_finite() && **r >= 0.0)) {
                return Err(format!("belt.rates: row {} holds {r}; rates must be finite and >= 0 (1/s)", i + 1));
            }
        }
        let leave: Vec<f64> = rates.iter().map(|row| row.iter().sum()).collect();
        let stationary = stationary_law(&rates, &leave)?;
        let jumps = rates
            .iter()
            .zip(&leave)
            .map(|(row, &q)| {
                let mut acc = 0.0;
                row.iter()
                    .map(|r| {
                        acc += r / q;
                        acc
                    })
                    .collect()
            })
            .collect();
        Ok(Markov { velocities, rates, stationary, leave, jumps })
    }

    /// v_1 … v_n, m/s.
    pub fn velocities(&self) -> &[f64] {
        &self.velocities
    }

    /// r_ij, 1/s (diagonal 0).
    pub fn rates(&self) -> &[Vec<f64>] {
        &self.rates
    }

    /// π, the stationary law of the levels (the law of the initial level).
    pub fn stationary(&self) -> &[f64] {
        &self.stationary
    }

    /// The level whose cumulative probability first exceeds `u` (the last one for rounding).
    fn pick(cdf: impl Iterator<Item = f64>, u: f64, n: usize) -> usize {
        cdf.enumerate().find(|&(_, c)| u < c).map_or(n - 1, |(i, _)| i)
    }

    pub(super) fn draw_into<R: Rng + ?Sized>(&self, rng: &mut R, duration: f64, path: &mut BeltPath) {
        let n = self.velocities.len();
        let mut acc = 0.0;
        let mut level = Self::pick(
            self.stationary.iter().map(|p| {
                acc += p;
                acc
            }),
            unit_f64(rng),
            n,
        );
        // a transient level has π = 0 and is never picked: the cumulative sum does not rise there
        path.initial_velocity = self.velocities[level];
        let mut t = 0.0;
        loop {
            let q = self.leave[level];
            if !(q > 0.0) {
                return;
            }
            t += -(-unit_f64(rng)).ln_1p() / q;
            if !(t < duration) {
                return;
            }
            let next = Self::pick(self.jumps[level].iter().copied(), unit_f64(rng), n);
            // (a jump to the level itself has probability 0; rounding may pick the last level)
            if self.velocities[next] != self.velocities[level] {
                path.switch_times.push(t);
                path.velocities.push(self.velocities[next]);
            }
            level = next;
        }
    }
}

/// The stationary law of a chain with rates `r` and exit rates `q`: π Q = 0, Σ π = 1 (Gaussian
/// elimination with partial pivoting on Qᵀ with one equation replaced by the normalization),
/// after checking that it is unique — exactly one closed class of levels (a class no rate
/// leaves); the levels outside it are transient and get π = 0.
fn stationary_law(r: &[Vec<f64>], q: &[f64]) -> Result<Vec<f64>, String> {
    let n = q.len();
    // reach[i][j]: level j can be reached from level i (transitive closure, Warshall)
    let mut reach: Vec<Vec<bool>> = (0..n).map(|i| (0..n).map(|j| i == j || r[i][j] > 0.0).collect()).collect();
    for k in 0..n {
        for i in 0..n {
            if reach[i][k] {
                for j in 0..n {
                    if reach[k][j] {
                        reach[i][j] = true;
                    }
                }
            }
        }
    }
    // a level is recurrent when every level it reaches reaches it back
    let recurrent: Vec<bool> = (0..n).map(|i| (0..n).all(|j| !reach[i][j] || reach[j][i])).collect();
    let first = recurrent.iter().position(|&x| x).expect("a finite chain has a closed class");
    if let Some(other) = (0..n).find(|&j| recurrent[j] && !reach[first][j]) {
        return Err(format!(
            "levels {} and {} lie in two closed classes (no rate leads from one to the other), so the chain has no unique stationary law to draw the initial level from",
            first + 1,
            other + 1
        ));
    }
    // A π = b: rows 0..n−1 of Qᵀ π = 0 (Q_ji = r_ji, Q_ii = −q_i), the last row Σ π = 1
    let mut a: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| if i == j { -q[i] } else { r[j][i] }).collect()).collect();
    let mut b = vec![0.0; n];
    a[n - 1] = vec![1.0; n];
    b[n - 1] = 1.0;
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs())).expect("rows left");
        a.swap(col, pivot);
        b.swap(col, pivot);
        let p = a[col][col];
        if p == 0.0 {
            return Err("the stationary law of the rate matrix could not be solved".into());
        }
        for row in col + 1..n {
            let f = a[row][col] / p;
            if f != 0.0 {
                for k in col..n {
                    a[row][k] -= f * a[col][k];
                }
                b[row] -= f * b[col];
            }
        }
    }
    let mut pi = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| a[i][k] * pi[k]).sum();
        pi[i] = (b[i] - s) / a[i][i];
    }
    // rounding leaves transient levels at ±1e-17: clamp, and renormalize
    for (p, rec) in pi.iter_mut().zip(&recurrent) {
        if !*rec || *p < 0.0 {
            *p = 0.0;
        }
    }
    let total: f64 = pi.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err("the stationary law of the rate matrix could not be solved".into());
    }
    Ok(pi.into_iter().map(|p| p / total).collect())
}
