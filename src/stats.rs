//! Mergeable one-pass moments of a sample (shared by `analyze` and `simulate --target-se`).
//!
//! Moments use the single-value update and the pairwise merge of
//! P. Pébay, "Formulas for robust, one-pass parallel computation of covariances and arbitrary-order
//! statistical moments", Sandia report SAND2008-6212 (2008), with T. Chan, G. Golub, R. LeVeque,
//! "Updating formulae and a pairwise algorithm for computing sample variances" (1979):
//!
//! ```text
//! add x:   n ← n+1, δ = x − mean, δₙ = δ/n, t = δ δₙ (n−1)
//!          mean ← mean + δₙ
//!          M4 ← M4 + t δₙ² (n² − 3n + 3) + 6 δₙ² M2 − 4 δₙ M3
//!          M3 ← M3 + t δₙ (n − 2) − 3 δₙ M2
//!          M2 ← M2 + t
//! merge:   n = a+b, δ = mean_b − mean_a
//!          M2 = M2a + M2b + δ² a b/n
//!          M3 = M3a + M3b + δ³ a b (a−b)/n² + 3δ (a M2b − b M2a)/n
//!          M4 = M4a + M4b + δ⁴ a b (a² − ab + b²)/n³ + 6δ² (a² M2b + b² M2a)/n² + 4δ (a M3b − b M3a)/n
//! ```
//!
//! Values are added in realization order, so the result does not depend on how the dataset is
//! split into files, shards or batches. `M_p = Σ (x − mean)^p`.

/// Count, mean, central power sums M2..M4, and the range of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    /// number of values
    pub n: u64,
    /// their mean
    pub mean: f64,
    /// M2 = Σ (x − mean)²
    pub m2: f64,
    /// M3 = Σ (x − mean)³
    pub m3: f64,
    /// M4 = Σ (x − mean)⁴
    pub m4: f64,
    /// the least value (+∞ when empty)
    pub min: f64,
    /// the greatest value (−∞ when empty)
    pub max: f64,
}

impl Default for Moments {
    fn default() -> Self {
        Moments { n: 0, mean: 0.0, m2: 0.0, m3: 0.0, m4: 0.0, min: f64::INFINITY, max: f64::NEG_INFINITY }
    }
}

impl Moments {
    /// Add one value.
    pub fn add(&mut self, x: f64) {
        let n1 = self.n as f64;
        self.n += 1;
        let n = self.n as f64;
        let delta = x - self.mean;
        let dn = delta / n;
        let dn2 = dn * dn;
        let t = delta * dn * n1;
        self.mean += dn;
        self.m4 += t * dn2 * (n * n - 3.0 * n + 3.0) + 6.0 * dn2 * self.m2 - 4.0 * dn * self.m3;
        self.m3 += t * dn * (n - 2.0) - 3.0 * dn * self.m2;
        self.m2 += t;
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// The moments of both samples together (pairwise merge).
    pub fn merge(&self, o: &Moments) -> Moments {
        if self.n == 0 {
            return *o;
        }
        if o.n == 0 {
            return *self;
        }
        let (a, b) = (self.n as f64, o.n as f64);
        let n = a + b;
        let d = o.mean - self.mean;
        let (d2, d3, d4) = (d * d, d * d * d, d * d * d * d);
        Moments {
            n: self.n + o.n,
            mean: self.mean + d * b / n,
            m2: self.m2 + o.m2 + d2 * a * b / n,
            m3: self.m3 + o.m3 + d3 * a * b * (a - b) / (n * n) + 3.0 * d * (a * o.m2 - b * self.m2) / n,
            m4: self.m4
                + o.m4
                + d4 * a * b * (a * a - a * b + b * b) / (n * n * n)
                + 6.0 * d2 * (a * a * o.m2 + b * b * self.m2) / (n * n)
                + 4.0 * d * (a * o.m3 - b * self.m3) / n,
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Unbiased variance `M2/(n−1)`.
    pub fn variance(&self) -> Option<f64> {
        (self.n >= 2).then(|| self.m2 / (self.n as f64 - 1.0))
    }

    /// Skewness `g1 = m3/m2^{3/2}` with population moments `m_p = M_p/n` (MATLAB's `skewness`).
    pub fn skewness(&self) -> Option<f64> {
        (self.n >= 2 && self.m2 > 0.0).then(|| (self.n as f64).sqrt() * self.m3 / self.m2.powf(1.5))
    }

    /// Pearson kurtosis `b2 = m4/m2²` (3 for a normal; MATLAB's `kurtosis`, as the paper).
    pub fn kurtosis(&self) -> Option<f64> {
        (self.n >= 2 && self.m2 > 0.0).then(|| self.n as f64 * self.m4 / (self.m2 * self.m2))
    }

    /// Standard error of the mean, `√(s²/n)`.
    pub fn mean_se(&self) -> Option<f64> {
        self.variance().map(|v| (v / self.n as f64).sqrt())
    }

    /// Standard error of the unbiased variance, `√((m4 − (n−3)/(n−1) s⁴)/n)`.
    pub fn variance_se(&self) -> Option<f64> {
        let s2 = self.variance()?;
        let n = self.n as f64;
        (self.n >= 4).then(|| ((self.m4 / n - (n - 3.0) / (n - 1.0) * s2 * s2).max(0.0) / n).sqrt())
    }

    /// Sample standard deviation (0 when undefined).
    pub fn std(&self) -> f64 {
        self.variance().unwrap_or(0.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn direct(x: &[f64]) -> (f64, f64, f64, f64) {
        let n = x.len() as f64;
        let m = x.iter().sum::<f64>() / n;
        let c = |p: i32| x.iter().map(|v| (v - m).powi(p)).sum::<f64>();
        (m, c(2), c(3), c(4))
    }

    #[test]
    fn online_and_merged_moments_match_two_pass_sums() {
        let x: Vec<f64> = (0..1000).map(|i| ((i * 7919) % 1000) as f64 / 37.0 + (i as f64).sqrt()).collect();
        let mut all = Moments::default();
        x.iter().for_each(|&v| all.add(v));
        let (mut a, mut b) = (Moments::default(), Moments::default());
        x[..313].iter().for_each(|&v| a.add(v));
        x[313..].iter().for_each(|&v| b.add(v));
        let merged = a.merge(&b);
        let (m, c2, c3, c4) = direct(&x);
        for s in [all, merged] {
            assert_eq!(s.n, 1000);
            assert!((s.mean - m).abs() < 1e-12 * m.abs());
            assert!((s.m2 - c2).abs() < 1e-10 * c2);
            assert!((s.m3 - c3).abs() < 1e-8 * c2.powf(1.5));
            assert!((s.m4 - c4).abs() < 1e-10 * c4);
        }
    }
}
