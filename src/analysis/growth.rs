//! Growth of the start instants with their index: OLS lines and the renewal check.
//!
//! The paper (Fig. 7) finds Var T_k and Var L_k linear in k. We fit `y_k = a + b k` by ordinary
//! least squares for the mean and the variance of T_k and L_k, k = 1..K, with
//! `R² = 1 − SSE/SST` and the slope's standard error `√(SSE/(K−2) / Σ(k − k̄)²)`.
//!
//! If sticks recur as a renewal process with cycle length C (E C = slope of E T_k,
//! Var C = slope of Var T_k), the renewal central limit theorem (e.g. Cox, *Renewal Theory*, 1962,
//! §6.3) predicts for the number of sticks in [0, t_a]:
//!
//! ```text
//!     E[S_T] ≈ t_a / E C,        Var[S_T] ≈ t_a Var C / (E C)³.
//! ```

/// An OLS line through `(k, y_k)`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Line {
    pub slope: f64,
    pub intercept: f64,
    pub r2: f64,
    pub slope_se: Option<f64>,
    pub points: usize,
}

/// Fit `y = a + b x`; `None` with fewer than two points or no spread in x.
pub fn ols(points: &[(f64, f64)]) -> Option<Line> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let sse: f64 = points.iter().map(|p| (p.1 - intercept - slope * p.0).powi(2)).sum();
    Some(Line {
        slope,
        intercept,
        r2: if syy > 0.0 { 1.0 - sse / syy } else { 1.0 },
        slope_se: (points.len() > 2).then(|| (sse / (n - 2.0) / sxx).sqrt()),
        points: points.len(),
    })
}

/// Renewal prediction of E[S_T] and Var[S_T] from the slopes of E T_k and Var T_k.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Renewal {
    pub predicted_mean: f64,
    pub measured_mean: f64,
    pub predicted_variance: f64,
    pub measured_variance: f64,
    /// 95 % jackknife intervals of the two predictions (see `super::jackknife`)
    pub predicted_mean_interval: Option<(f64, f64)>,
    pub predicted_variance_interval: Option<(f64, f64)>,
}

pub fn renewal(duration: f64, mean_line: &Line, var_line: &Line, measured_mean: f64, measured_variance: f64) -> Option<Renewal> {
    let c = mean_line.slope;
    (c > 0.0).then(|| Renewal {
        predicted_mean: duration / c,
        measured_mean,
        predicted_variance: duration * var_line.slope / (c * c * c),
        measured_variance,
        predicted_mean_interval: None,
        predicted_variance_interval: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_line_and_noisy_line() {
        let l = ols(&[(1.0, 3.0), (2.0, 5.0), (3.0, 7.0), (4.0, 9.0)]).unwrap();
        assert!((l.slope - 2.0).abs() < 1e-14 && (l.intercept - 1.0).abs() < 1e-14 && (l.r2 - 1.0).abs() < 1e-14);
        assert!(l.slope_se.unwrap() < 1e-7);
        // y = x + (+1, -1, -1, +1): slope 1 exactly, SSE = 4 - (Σ(k-k̄)e)²/Sxx = 4, Sxx = 5
        let l = ols(&[(1.0, 2.0), (2.0, 1.0), (3.0, 2.0), (4.0, 5.0)]).unwrap();
        assert!((l.slope - 1.0).abs() < 1e-14);
        assert!((l.slope_se.unwrap() - (4.0f64 / 2.0 / 5.0).sqrt()).abs() < 1e-14);
    }
}
