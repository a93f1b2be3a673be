//! Anderson mixing of a fixed-point iteration (the stationary measure of [`super::stationary::solve`]).

/// Anderson mixing (type II) of a fixed-point iteration x ← G(x): with the residuals
/// f_i = G(x_i) − x_i of the last steps, the next iterate is G(x_k) − Σ γ_j ΔG_j where γ minimises
/// |f_k − Σ γ_j Δf_j|₂ (Walker & Ni, SIAM J. Numer. Anal. 49, 2011).
pub(super) struct Anderson {
    depth: usize,
    last: Option<(Vec<f64>, Vec<f64>)>,
    /// (ΔG, Δf) of the remembered steps
    history: std::collections::VecDeque<(Vec<f64>, Vec<f64>)>,
    /// Δf_i · Δf_j of the remembered steps (kept as steps come and go: one new row per step)
    gram: std::collections::VecDeque<std::collections::VecDeque<f64>>,
}

/// Values per parallel chunk of a dot product (fixed: the sum's order, and so its bits, do not
/// depend on the threads).
const DOT_CHUNK: usize = 1 << 15;

/// a · b, in fixed chunks summed in order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    use rayon::prelude::*;
    let parts: Vec<f64> = a.par_chunks(DOT_CHUNK).zip(b.par_chunks(DOT_CHUNK)).map(|(x, y)| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>()).collect();
    parts.iter().sum()
}

impl Anderson {
    pub(super) fn new(depth: usize) -> Anderson {
        Anderson { depth, last: None, history: std::collections::VecDeque::new(), gram: std::collections::VecDeque::new() }
    }

    /// The next iterate from x_k and G(x_k).
    pub(super) fn mix(&mut self, x: Vec<f64>, g: Vec<f64>) -> Vec<f64> {
        let f: Vec<f64> = g.iter().zip(&x).map(|(a, b)| a - b).collect();
        if let Some((g0, f0)) = self.last.take() {
            let dg: Vec<f64> = g.iter().zip(&g0).map(|(a, b)| a - b).collect();
            let df: Vec<f64> = f.iter().zip(&f0).map(|(a, b)| a - b).collect();
            if self.history.len() == self.depth {
                self.history.pop_front();
                self.gram.pop_front();
                self.gram.iter_mut().for_each(|row| {
                    row.pop_front();
                });
            }
            let row: std::collections::VecDeque<f64> = self.history.iter().map(|(_, d)| dot(d, &df)).chain([dot(&df, &df)]).collect();
            for (r, &v) in self.gram.iter_mut().zip(&row) {
                r.push_back(v);
            }
            self.gram.push_back(row);
            self.history.push_back((dg, df));
        }
        self.last = Some((g.clone(), f.clone()));
        let m = self.history.len();
        if m == 0 {
            return g;
        }
        // normal equations (DfᵀDf + εI) γ = Dfᵀ f, by Gaussian elimination with pivoting
        let mut a = vec![vec![0.0; m + 1]; m];
        for i in 0..m {
            for j in 0..m {
                a[i][j] = self.gram[i][j];
            }
            a[i][i] *= 1.0 + 1e-10;
            a[i][m] = dot(&self.history[i].1, &f);
        }
        let Some(gamma) = solve_dense(a) else {
            self.history.clear();
            self.gram.clear();
            return g;
        };
        let mut out = g;
        for (gam, (dg, _)) in gamma.iter().zip(&self.history) {
            out.iter_mut().zip(dg).for_each(|(o, d)| *o -= gam * d);
        }
        out
    }
}

/// The solution of the augmented system `a` (n rows of n + 1), or None if singular.
fn solve_dense(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let n = a.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if !(a[p][c].abs() > 1e-300) {
            return None;
        }
        a.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            for k in c..=n {
                a[r][k] -= f * a[c][k];
            }
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        x[r] = (a[r][n] - (r + 1..n).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_system() {
        // 2x + y = 5, x − y = 1 → x = 2, y = 1
        let x = solve_dense(vec![vec![2.0, 1.0, 5.0], vec![1.0, -1.0, 1.0]]).unwrap();
        assert!((x[0] - 2.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
        assert!(solve_dense(vec![vec![1.0, 2.0, 1.0], vec![2.0, 4.0, 2.0]]).is_none());
    }

    #[test]
    fn removes_a_slow_rotating_mode() {
        // x ← A x + b, A a rotation by 0.3 rad scaled by 0.97 on the first two coordinates and
        // 0.5 on the third (plain iteration: 0.97^k, ~800 steps to 1e-10); fixed point x* = (I − A)⁻¹ b
        let (r, th) = (0.97f64, 0.3f64);
        let a = [[r * th.cos(), -r * th.sin(), 0.0], [r * th.sin(), r * th.cos(), 0.0], [0.0, 0.0, 0.5]];
        let b = [1.0, 2.0, 3.0];
        let g = |x: &[f64]| -> Vec<f64> { (0..3).map(|i| (0..3).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i]).collect() };
        // (I − A) x* = b, solved directly
        let m: Vec<Vec<f64>> = (0..3).map(|i| (0..3).map(|j| f64::from(u8::from(i == j)) - a[i][j]).chain([b[i]]).collect()).collect();
        let exact = solve_dense(m).unwrap();
        let mut mix = Anderson::new(8);
        let mut x = vec![0.0; 3];
        let mut steps = 0;
        while (0..3).map(|i| (x[i] - exact[i]).abs()).fold(0.0, f64::max) > 1e-10 {
            let gx = g(&x);
            x = mix.mix(x, gx);
            steps += 1;
            assert!(steps < 30, "Anderson mixing did not converge: {x:?} against {exact:?}");
        }
    }
}
