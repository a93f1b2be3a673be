//! Bin rules and the mode estimator.
//!
//! **Bins** (1-D histograms and the grids of joint histograms): equal width over the sample's
//! range, Scott's rule `h = 3.49 σ n^{-1/3}` (D. W. Scott, "On optimal and data-based
//! histograms", Biometrika 66, 1979), clamped to 10..200 bins; `--bins N` fixes the count.
//! Both inputs (σ, range) come from the first, mergeable pass, so bins never need a sort.
//!
//! **Mode**: the maximum of a Gaussian kernel density estimate, evaluated on a fine grid of
//! [`MODE_GRID`] bins from binned counts (binned KDE; M. P. Wand, "Fast computation of multivariate
//! kernel density estimates", J. Comput. Graph. Stat. 3, 1994), bandwidth by Silverman's rule of
//! thumb `0.9 σ n^{-1/5}` (never below one grid bin). All analysed quantities are ≥ 0 and the
//! durations pile up at 0, so the kernel is reflected at 0 (the density estimate of a variable on
//! [0, ∞) without the boundary's deficit). A histogram's highest bin would jump between
//! neighbouring bins from one seed to the next; the smoothed maximum is stable to well within a
//! bandwidth.

use super::accum::{Histogram, Moments};

/// Fine grid bins for the mode.
pub const MODE_GRID: usize = 1024;

/// Number of bins by Scott's rule (or `fixed`), for a sample summarized by `m`.
pub fn bins(m: &Moments, fixed: Option<usize>) -> usize {
    if let Some(b) = fixed {
        return b.max(1);
    }
    let h = 3.49 * m.std() * (m.n.max(1) as f64).powf(-1.0 / 3.0);
    let range = m.max - m.min;
    if !(h > 0.0) || !(range > 0.0) {
        return 10;
    }
    ((range / h).ceil() as usize).clamp(10, 200)
}

/// Mode of the reflected Gaussian KDE evaluated on the fine histogram `fine` of a sample with
/// moments `m`.
pub fn kde_mode(fine: &Histogram, m: &Moments) -> Option<f64> {
    if m.n == 0 {
        return None;
    }
    let w = fine.width();
    let bw = (0.9 * m.std() * (m.n as f64).powf(-0.2)).max(w);
    let reach = (6.0 * bw / w).ceil() as isize;
    let centers: Vec<f64> = (0..fine.bins()).map(|i| fine.lo + w * (i as f64 + 0.5)).collect();
    let kernel = |d: f64| (-0.5 * (d / bw) * (d / bw)).exp();
    let mut best = (f64::NEG_INFINITY, None);
    for (j, &cj) in centers.iter().enumerate() {
        let lo = (j as isize - reach).max(0) as usize;
        let hi = ((j as isize + reach) as usize).min(fine.bins() - 1);
        let mut f = 0.0;
        for i in lo..=hi {
            let c = fine.counts[i] as f64;
            if c > 0.0 {
                f += c * kernel(cj - centers[i]);
            }
        }
        if cj < 6.0 * bw && fine.lo >= 0.0 {
            // mirror images of the mass near 0
            for (i, &ci) in centers.iter().enumerate().take_while(|(_, &ci)| ci < 6.0 * bw) {
                f += fine.counts[i] as f64 * kernel(cj + ci);
            }
        }
        if f > best.0 {
            best = (f, Some(cj));
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kde_mode_of_a_normal_sample_is_near_its_center() {
        // deterministic normal-like sample: sum of 12 uniforms from a LCG, centered at 5
        let mut s = 12345u64;
        let mut u = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let x: Vec<f64> = (0..20000).map(|_| 5.0 + (0..12).map(|_| u()).sum::<f64>() - 6.0).collect();
        let mut m = Moments::default();
        x.iter().for_each(|&v| m.add(v));
        let mut h = Histogram::new(m.min, m.max, MODE_GRID);
        x.iter().for_each(|&v| h.add(v));
        let mode = kde_mode(&h, &m).unwrap();
        assert!((mode - 5.0).abs() < 0.1, "{mode}");
    }

    #[test]
    fn kde_mode_of_an_exponential_sample_is_at_zero() {
        let x: Vec<f64> = (0..20000).map(|i| -((i as f64 + 0.5) / 20000.0).ln()).collect();
        let mut m = Moments::default();
        x.iter().for_each(|&v| m.add(v));
        let mut h = Histogram::new(m.min, m.max, MODE_GRID);
        x.iter().for_each(|&v| h.add(v));
        let mode = kde_mode(&h, &m).unwrap();
        assert!(mode < 0.02, "{mode}");
    }
}
