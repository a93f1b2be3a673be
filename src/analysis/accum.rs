//! Fixed-edge histograms (and, re-exported, the one-pass moments of [`crate::stats`]).

pub use crate::stats::Moments;

/// Counts on `bins` equal-width bins spanning `[lo, hi]` (the last bin includes `hi`).
#[derive(Debug, Clone, PartialEq)]
pub struct Histogram {
    /// lower edge of the first bin
    pub lo: f64,
    /// upper edge of the last bin
    pub hi: f64,
    /// count in each bin
    pub counts: Vec<u64>,
}

impl Histogram {
    /// Bins over the range of a sample; a degenerate range is widened by ±0.5.
    pub fn new(lo: f64, hi: f64, bins: usize) -> Histogram {
        let (lo, hi) = if hi > lo { (lo, hi) } else { (lo - 0.5, lo + 0.5) };
        Histogram { lo, hi, counts: vec![0; bins.max(1)] }
    }

    /// Number of bins.
    pub fn bins(&self) -> usize {
        self.counts.len()
    }

    /// Width of each bin.
    pub fn width(&self) -> f64 {
        (self.hi - self.lo) / self.bins() as f64
    }

    /// The bin of `x` (values outside the range go to the end bins).
    pub fn bin(&self, x: f64) -> usize {
        let i = (x - self.lo) / self.width();
        // `as usize` truncates toward zero (= floor for i ≥ 0) and saturates NaN and negatives to 0.
        (i as usize).min(self.bins() - 1)
    }

    /// Count `x` in its bin (out-of-range values in the end bins).
    pub fn add(&mut self, x: f64) {
        let i = self.bin(x);
        self.counts[i] += 1;
    }

    /// Sum of the counts.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Edges of bin `i`.
    pub fn edges(&self, i: usize) -> (f64, f64) {
        let w = self.width();
        (self.lo + w * i as f64, if i + 1 == self.bins() { self.hi } else { self.lo + w * (i + 1) as f64 })
    }

    /// Density of bin `i`: count / (total · width), integrating to 1.
    pub fn density(&self, i: usize) -> f64 {
        let total = self.total();
        if total == 0 {
            0.0
        } else {
            self.counts[i] as f64 / (total as f64 * self.width())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_bins_and_density() {
        let mut h = Histogram::new(0.0, 1.0, 4);
        for x in [0.0, 0.1, 0.25, 0.5, 0.99, 1.0] {
            h.add(x);
        }
        assert_eq!(h.counts, [2, 1, 1, 2]);
        let integral: f64 = (0..4).map(|i| h.density(i) * h.width()).sum();
        assert!((integral - 1.0).abs() < 1e-15);
    }
}
