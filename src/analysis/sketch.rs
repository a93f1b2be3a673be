//! Dyadic histogram sketches: one-pass, fixed-memory, mergeable histograms.
//!
//! A sketch counts values on bins of width `w = 2^e` whose edges are the integer multiples of `w`
//! (bin `i` is `[i w, (i+1) w)`), keeping at most `cap` bins per axis. When a value falls outside
//! the current bins and the range would need more than `cap` bins, the width doubles (`e += 1`)
//! and neighbouring pairs merge: bin `i` goes to `⌊i/2⌋`. Because every edge is a multiple of a
//! power of two, any coarser power-of-two grid is a union of sketch bins: histograms read off a
//! sketch at width `2^E ≥ w` are exact counts, the 1-D grid and the joint grid of a pair agree
//! bin for bin, and sketches of two parts of a dataset combine exactly.
//!
//! The starting width is `2^(⌊log2 scale⌋ − 40)` for the scenario's natural scale (t_a: every
//! time and duration lies in [0, t_a]), so bin indices stay below 2^53 and are exact in f64.

use super::accum::Histogram;

/// Bins per axis of a 1-D sketch and of a joint (2-D) sketch.
pub const CAP_1D: usize = 4096;
pub const CAP_2D: usize = 512;

/// The starting exponent for values of magnitude up to `scale`.
pub fn start_exponent(scale: f64) -> i32 {
    let s = if scale.is_finite() && scale > 0.0 { scale } else { 1.0 };
    // kept where 2^±exp is a finite normal number: a value scaled by 2^-exp must not overflow
    // (run.duration = 1e-300 gave 0 · 2^1037 = 0 · ∞ = NaN)
    (s.log2().floor() as i32 - 40).clamp(-1000, 1000)
}

/// One axis: bins `lo .. lo + len` of width `2^exp`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Axis {
    exp: i32,
    lo: f64,
    len: usize,
}

/// Index of the bin of width `2^exp` holding `x` (exact: scaling by a power of two is exact).
fn index(x: f64, exp: i32) -> f64 {
    (x * (-exp as f64).exp2()).floor()
}

impl Axis {
    /// The smallest shift k ≥ 0 such that indices `a ≤ b` (at `exp`) fit in `cap` bins at `exp + k`.
    fn shift_for(a: f64, b: f64, cap: usize) -> i32 {
        let mut k = 0;
        while ((b * (-k as f64).exp2()).floor() - (a * (-k as f64).exp2()).floor()) as usize + 1 > cap {
            k += 1;
        }
        k
    }
}

/// Where old bin `j` of an axis lands after shifting by `k` and re-basing at `new_lo`.
fn remap(axis: &Axis, j: usize, k: i32, new_lo: f64) -> usize {
    (((axis.lo + j as f64) * (-k as f64).exp2()).floor() - new_lo) as usize
}

/// A 1-D sketch.
#[derive(Debug, Clone, PartialEq)]
pub struct Sketch {
    axis: Axis,
    counts: Vec<u64>,
}

impl Sketch {
    pub fn new(scale: f64) -> Sketch {
        Sketch { axis: Axis { exp: start_exponent(scale), lo: 0.0, len: 0 }, counts: Vec::new() }
    }

    pub fn exponent(&self) -> i32 {
        self.axis.exp
    }

    pub fn add(&mut self, x: f64) {
        let i = index(x, self.axis.exp);
        if self.counts.is_empty() {
            self.axis.lo = i;
            self.axis.len = 1;
            self.counts.push(1);
            return;
        }
        let (a, b) = (i.min(self.axis.lo), i.max(self.axis.lo + self.axis.len as f64 - 1.0));
        let k = Axis::shift_for(a, b, CAP_1D);
        if k > 0 || a < self.axis.lo || b >= self.axis.lo + self.axis.len as f64 {
            let new_lo = (a * (-k as f64).exp2()).floor();
            let new_len = ((b * (-k as f64).exp2()).floor() - new_lo) as usize + 1;
            let mut counts = vec![0u64; new_len];
            for (j, &c) in self.counts.iter().enumerate() {
                counts[remap(&self.axis, j, k, new_lo)] += c;
            }
            self.axis = Axis { exp: self.axis.exp + k, lo: new_lo, len: new_len };
            self.counts = counts;
        }
        let j = (index(x, self.axis.exp) - self.axis.lo) as usize;
        self.counts[j] += 1;
    }

    /// The sketch of the union of both samples (parts of a dataset reduced independently): both
    /// are re-binned to the coarser width, doubled further if the union needs more than the cap.
    pub fn merge(&self, other: &Sketch) -> Sketch {
        if other.counts.is_empty() {
            return self.clone();
        }
        if self.counts.is_empty() {
            return other.clone();
        }
        let mut exp = self.axis.exp.max(other.axis.exp);
        let span = |s: &Sketch, e: i32| {
            let k = (e - s.axis.exp) as f64;
            ((s.axis.lo * (-k).exp2()).floor(), ((s.axis.lo + s.axis.len as f64 - 1.0) * (-k).exp2()).floor())
        };
        let (mut lo, mut hi);
        loop {
            let (a, b) = (span(self, exp), span(other, exp));
            (lo, hi) = (a.0.min(b.0), a.1.max(b.1));
            if (hi - lo) as usize + 1 <= CAP_1D {
                break;
            }
            exp += 1;
        }
        let mut counts = vec![0u64; (hi - lo) as usize + 1];
        for s in [self, other] {
            let k = exp - s.axis.exp;
            for (j, &c) in s.counts.iter().enumerate() {
                counts[remap(&s.axis, j, k, lo)] += c;
            }
        }
        Sketch { axis: Axis { exp, lo, len: counts.len() }, counts }
    }

    /// The sketch's own bins as a histogram (the fine grid of the mode estimator).
    pub fn fine(&self) -> Histogram {
        let w = (self.axis.exp as f64).exp2();
        Histogram { lo: self.axis.lo * w, hi: (self.axis.lo + self.axis.len as f64) * w, counts: self.counts.clone() }
    }

    /// Counts on the grid of width `2^exp` (≥ the sketch's width), spanning the occupied range.
    pub fn histogram(&self, exp: i32) -> Histogram {
        let k = (exp - self.axis.exp).max(0);
        if self.counts.is_empty() {
            return Histogram::new(0.0, 1.0, 1);
        }
        let new_lo = (self.axis.lo * (-k as f64).exp2()).floor();
        let last = ((self.axis.lo + self.axis.len as f64 - 1.0) * (-k as f64).exp2()).floor();
        let mut counts = vec![0u64; (last - new_lo) as usize + 1];
        for (j, &c) in self.counts.iter().enumerate() {
            counts[remap(&self.axis, j, k, new_lo)] += c;
        }
        let w = ((self.axis.exp + k) as f64).exp2();
        Histogram { lo: new_lo * w, hi: (last + 1.0) * w, counts }
    }
}

/// A 2-D sketch of pairs (x, y).
#[derive(Debug, Clone, PartialEq)]
pub struct Sketch2 {
    x: Axis,
    y: Axis,
    /// row-major: `counts[i * y.len + j]`
    counts: Vec<u64>,
}

impl Sketch2 {
    pub fn new(scale: f64) -> Sketch2 {
        let axis = Axis { exp: start_exponent(scale), lo: 0.0, len: 0 };
        Sketch2 { x: axis, y: axis, counts: Vec::new() }
    }

    pub fn exponents(&self) -> (i32, i32) {
        (self.x.exp, self.y.exp)
    }

    /// The axis covering the current one and index `i`, with some room to grow, and its shift.
    fn grown(axis: &Axis, i: f64) -> (Axis, i32) {
        if axis.len == 0 {
            return (Axis { exp: axis.exp, lo: i, len: 1 }, 0);
        }
        let (a, b) = (i.min(axis.lo), i.max(axis.lo + axis.len as f64 - 1.0));
        // leave a margin of 1/8 of the span on the side that grew, to avoid re-layouts per value
        let margin = ((b - a + 1.0) / 8.0).floor();
        let (a, b) = (if i < axis.lo { a - margin } else { a }, if i > axis.lo { b + margin } else { b });
        let k = Axis::shift_for(a, b, CAP_2D);
        let new_lo = (a * (-k as f64).exp2()).floor();
        let new_len = ((b * (-k as f64).exp2()).floor() - new_lo) as usize + 1;
        (Axis { exp: axis.exp + k, lo: new_lo, len: new_len }, k)
    }

    pub fn add(&mut self, x: f64, y: f64) {
        let (ix, iy) = (index(x, self.x.exp), index(y, self.y.exp));
        let inside = |a: &Axis, i: f64| a.len > 0 && i >= a.lo && i < a.lo + a.len as f64;
        if !inside(&self.x, ix) || !inside(&self.y, iy) {
            let (nx, kx) = if inside(&self.x, ix) { (self.x, 0) } else { Self::grown(&self.x, ix) };
            let (ny, ky) = if inside(&self.y, iy) { (self.y, 0) } else { Self::grown(&self.y, iy) };
            let mut counts = vec![0u64; nx.len * ny.len];
            for i in 0..self.x.len {
                let ri = remap(&self.x, i, kx, nx.lo);
                for j in 0..self.y.len {
                    let c = self.counts[i * self.y.len + j];
                    if c > 0 {
                        counts[ri * ny.len + remap(&self.y, j, ky, ny.lo)] += c;
                    }
                }
            }
            self.x = nx;
            self.y = ny;
            self.counts = counts;
        }
        let i = (index(x, self.x.exp) - self.x.lo) as usize;
        let j = (index(y, self.y.exp) - self.y.lo) as usize;
        self.counts[i * self.y.len + j] += 1;
    }

    /// Counts on the grids of the given 1-D histograms, whose widths are powers of two at least
    /// as coarse as this sketch's and whose ranges cover its values.
    pub fn table(&self, hx: &Histogram, hy: &Histogram) -> Vec<Vec<u64>> {
        let mut out = vec![vec![0u64; hy.bins()]; hx.bins()];
        let (wx, wy) = ((self.x.exp as f64).exp2(), (self.y.exp as f64).exp2());
        for i in 0..self.x.len {
            // the bin's midpoint lies strictly inside one coarse bin
            let bx = hx.bin((self.x.lo + i as f64 + 0.5) * wx);
            for j in 0..self.y.len {
                let c = self.counts[i * self.y.len + j];
                if c > 0 {
                    out[bx][hy.bin((self.y.lo + j as f64 + 0.5) * wy)] += c;
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn sketch_histograms_are_exact_counts_on_dyadic_grids() {
        let mut u = lcg(1);
        let x: Vec<f64> = (0..50_000).map(|_| 3.0 * u() * u()).collect();
        let mut s = Sketch::new(10.0);
        x.iter().for_each(|&v| s.add(v));
        assert!(s.counts.len() <= CAP_1D && s.counts.len() > CAP_1D / 2);
        for exp in [s.exponent(), s.exponent() + 3, -3] {
            let h = s.histogram(exp);
            let w = (exp as f64).exp2();
            // direct count on the grid [i w, (i+1) w)
            for (b, &c) in h.counts.iter().enumerate() {
                let (lo, hi) = (h.lo + b as f64 * w, h.lo + (b + 1) as f64 * w);
                let direct = x.iter().filter(|&&v| v >= lo && v < hi).count() as u64;
                assert_eq!(c, direct, "exp {exp} bin {b}");
            }
            assert_eq!(h.total(), x.len() as u64);
        }
    }

    #[test]
    fn merged_parts_equal_the_whole_on_every_common_grid() {
        let mut u = lcg(3);
        let x: Vec<f64> = (0..30_000).map(|i| if i < 20_000 { 2.0 * u() } else { 5.0 + 40.0 * u() * u() }).collect();
        let (mut whole, mut a, mut b) = (Sketch::new(50.0), Sketch::new(50.0), Sketch::new(50.0));
        x.iter().for_each(|&v| whole.add(v));
        x[..20_000].iter().for_each(|&v| a.add(v));
        x[20_000..].iter().for_each(|&v| b.add(v));
        let merged = a.merge(&b);
        assert!(merged.counts.len() <= CAP_1D);
        for exp in [merged.exponent().max(whole.exponent()), -2, 0, 3] {
            assert_eq!(merged.histogram(exp), whole.histogram(exp), "exp {exp}");
        }
    }

    #[test]
    fn joint_table_marginals_equal_the_one_dimensional_histograms() {
        let mut u = lcg(2);
        let pairs: Vec<(f64, f64)> = (0..20_000).map(|_| { let a = u(); (a, a + u()) }).collect();
        let (mut sx, mut sy, mut sj) = (Sketch::new(10.0), Sketch::new(10.0), Sketch2::new(10.0));
        for &(a, b) in &pairs {
            sx.add(a);
            sy.add(b);
            sj.add(a, b);
        }
        let (ex, ey) = sj.exponents();
        let (hx, hy) = (sx.histogram(ex.max(-5)), sy.histogram(ey.max(-5)));
        let t = sj.table(&hx, &hy);
        let rows: Vec<u64> = t.iter().map(|r| r.iter().sum()).collect();
        let cols: Vec<u64> = (0..hy.bins()).map(|j| t.iter().map(|r| r[j]).sum()).collect();
        assert_eq!(rows, hx.counts);
        assert_eq!(cols, hy.counts);
    }
}
