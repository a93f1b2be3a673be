//! Bin rules and the mode estimator.
//!
//! **Bins** (1-D histograms and the grids of joint histograms): equal width over the sample's
//! range, the width a power of two (so that every grid is a union of the dyadic sketch bins of
//! [`super::sketch`] — exact counts, identical 1-D and joint grids, mergeable across parts) nearest
//! to Scott's rule `h = 3.49 σ n^{-1/3}` (D. W. Scott, "On optimal and data-based histograms",
//! Biometrika 66, 1979), then halved or doubled to keep 10..200 bins; `--bins N` asks for the
//! power-of-two width nearest to range/N. Never finer than the sketches' own resolution.
//!
//! **Mode**: the maximum of a Gaussian kernel density estimate, evaluated on a fine grid of
//! bins from binned counts (binned KDE; M. P. Wand, "Fast computation of multivariate
//! kernel density estimates", J. Comput. Graph. Stat. 3, 1994), bandwidth by Silverman's rule of
//! thumb `0.9 σ n^{-1/5}` (never below one grid bin). All analysed quantities are ≥ 0 and the
//! durations pile up at 0, so the kernel is reflected at 0 (the density estimate of a variable on
//! [0, ∞) without the boundary's deficit). A histogram's highest bin would jump between
//! neighbouring bins from one seed to the next; the smoothed maximum is stable to well within a
//! bandwidth.

use super::accum::{Histogram, Moments};

/// Number of bins of the power-of-two grid `2^exp` over [min, max].
fn bins_at(m: &Moments, exp: i32) -> i64 {
    let w = (exp as f64).exp2();
    (m.max / w).floor() as i64 - (m.min / w).floor() as i64 + 1
}

/// The histogram grid exponent (bin width `2^exp`) for a sample summarized by `m`, no finer than
/// `finest`; `fixed` asks for about that many bins instead of Scott's rule.
pub fn grid_exponent(m: &Moments, fixed: Option<usize>, finest: i32) -> i32 {
    let range = m.max - m.min;
    let target = match fixed {
        Some(n) => range / n.max(1) as f64,
        None => 3.49 * m.std() * (m.n.max(1) as f64).powf(-1.0 / 3.0),
    };
    if !(target > 0.0) || !(range > 0.0) {
        return finest.max(0);
    }
    let mut exp = (target.log2().round() as i32).max(finest);
    if fixed.is_none() {
        while bins_at(m, exp) > 200 {
            exp += 1;
        }
        while exp > finest && bins_at(m, exp) < 10 {
            exp -= 1;
        }
    }
    exp
}

/// Mode of the reflected Gaussian KDE evaluated on the fine histogram `fine` of a sample with
/// moments `m` (exactly 0 when the estimate peaks in the first cell at the boundary 0).
pub fn kde_mode(fine: &Histogram, m: &Moments) -> Option<f64> {
    if m.n == 0 {
        return None;
    }
    let bw = (0.9 * m.std() * (m.n as f64).powf(-0.2)).max(fine.width());
    if !(bw.is_finite() && bw > 0.0 && fine.width() > 0.0) {
        return None; // a spread too wide for f64 (validated data never has one): no mode
    }
    // No finer than an eighth of the bandwidth: merge neighbouring bins (the estimate's own
    // resolution is the bandwidth; this bounds the work at ~100 kernel terms per grid point).
    let merge = ((bw / fine.width()) / 8.0).floor().max(1.0) as usize;
    let merged;
    let fine = if merge > 1 {
        let counts: Vec<u64> = fine.counts.chunks(merge).map(|c| c.iter().sum()).collect();
        let hi = fine.lo + fine.width() * (merge * counts.len()) as f64;
        merged = Histogram { lo: fine.lo, hi, counts };
        &merged
    } else {
        fine
    };
    let w = fine.width();
    let reach = ((6.0 * bw / w).ceil() as usize).min(fine.bins());
    // equal-width bins: the kernel between bin centres depends only on their offset d − reach
    let kernel_about: Vec<f64> = (0..=2 * reach).map(|d| (-0.5 * (d.abs_diff(reach) as f64 * w / bw).powi(2)).exp()).collect();
    let bins = fine.bins();
    let center = |i: usize| fine.lo + w * (i as f64 + 0.5);
    // mirror images about 0 of the mass near it (only when the grid starts at or above 0)
    let mirrored = if fine.lo >= 0.0 { (0..bins).take_while(|&i| center(i) < 6.0 * bw).count() } else { 0 };
    // f_j = Σ_i c_i K(|i − j|) over |i − j| ≤ reach, each f_j summed over i in increasing order:
    // bin by bin, every occupied bin i adds its terms to the f_j it reaches (the same terms in
    // the same order as summing f_j alone, so the same bits; an empty bin adds exactly 0 and is
    // left out; the inner loop runs over consecutive j, which vectorises)
    let mut sums = vec![0.0f64; bins];
    for (i, &c) in fine.counts.iter().enumerate().filter(|(_, &c)| c != 0) {
        let (lo, hi) = (i.saturating_sub(reach), (i + reach).min(bins - 1));
        let c = c as f64;
        let ks = &kernel_about[lo + reach - i..=hi + reach - i];
        for (f, k) in sums[lo..=hi].iter_mut().zip(ks) {
            *f += c * k;
        }
    }
    let mut best = (f64::NEG_INFINITY, None);
    for (j, &f) in sums.iter().enumerate() {
        let mut f = f;
        for i in 0..if j < mirrored { mirrored } else { 0 } {
            let d = (center(j) + center(i)) / bw;
            f += fine.counts[i] as f64 * (-0.5 * d * d).exp();
        }
        if f > best.0 {
            best = (f, Some(center(j)));
        }
    }
    // A maximum in the first cell of a grid that starts at the boundary 0 is the boundary: the
    // reflected estimate has zero slope there and falls from it (a density peaking at 0, as the
    // first stick start, stick and slip durations do). Its cell centre would move with the
    // sample's grid resolution, not with the density.
    if mirrored > 0 && fine.lo < w && best.1 == Some(center(0)) {
        return Some(0.0);
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_keeps_between_10_and_200_bins() {
        let mut m = Moments::default();
        (0..100_000).for_each(|i| m.add((i % 1000) as f64 / 100.0));
        let e = grid_exponent(&m, None, -60);
        assert!((10..=200).contains(&bins_at(&m, e)), "{}", bins_at(&m, e));
        let e = grid_exponent(&m, Some(40), -60);
        assert!((20..=80).contains(&bins_at(&m, e)), "{}", bins_at(&m, e));
    }

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
        let mut h = Histogram::new(m.min, m.max, 2048);
        x.iter().for_each(|&v| h.add(v));
        let mode = kde_mode(&h, &m).unwrap();
        assert!((mode - 5.0).abs() < 0.1, "{mode}");
    }

    #[test]
    fn kde_mode_of_an_exponential_sample_is_at_zero() {
        let x: Vec<f64> = (0..20000).map(|i| -((i as f64 + 0.5) / 20000.0).ln()).collect();
        let mut m = Moments::default();
        x.iter().for_each(|&v| m.add(v));
        let mut h = Histogram::new(m.min, m.max, 2048);
        x.iter().for_each(|&v| h.add(v));
        let mode = kde_mode(&h, &m).unwrap();
        assert!(mode < 0.02, "{mode}");
    }
}
