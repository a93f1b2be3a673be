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

impl Axis {
    /// The smallest shift k ≥ 0 such that indices `a ≤ b` (at `exp`) fit in `cap` bins at `exp + k`.
    fn shift_for(a: f64, b: f64, cap: usize) -> i32 {
        let mut k = 0;
        while ((b * (-k as f64).exp2()).floor() - (a * (-k as f64).exp2()).floor()) as usize + 1 > cap {
            k += 1;
        }
        k
    }

    /// The axis of the sketch of values whose bins at `exp` span indices `a ..= b`: the finest
    /// width 2^E, E ≥ `exp`, on which they fit in `cap` bins. (Fitting is monotone in E: if the
    /// span fits in `cap` ≥ 2 bins at E, it fits at E + 1.)
    fn fitting(exp: i32, a: f64, b: f64, cap: usize) -> Axis {
        let k = Axis::shift_for(a, b, cap);
        let lo = (a * (-k as f64).exp2()).floor();
        Axis { exp: exp + k, lo, len: ((b * (-k as f64).exp2()).floor() - lo) as usize + 1 }
    }
}

/// The exponent of the sketch of values spanning `[lo, hi]` (`lo ≤ hi`, both ≥ 0) that starts at
/// `start`: the smallest E ≥ `start` on which they fit in `cap` bins.
pub fn exponent_for(lo: f64, hi: f64, start: i32, cap: usize) -> i32 {
    Axis::fitting(start, (lo * (-start as f64).exp2()).floor(), (hi * (-start as f64).exp2()).floor(), cap).exp
}

/// Where old bin `j` of an axis lands after shifting by `k` and re-basing at `new_lo`.
fn remap(axis: &Axis, j: usize, k: i32, new_lo: f64) -> usize {
    (((axis.lo + j as f64) * (-k as f64).exp2()).floor() - new_lo) as usize
}

/// The range of bin indices in sparse counts (None when there are none).
fn span<'a>(indices: impl Iterator<Item = &'a i64>) -> Option<(f64, f64)> {
    indices.fold(None, |r, &i| Some(r.map_or((i, i), |(a, b): (i64, i64)| (a.min(i), b.max(i))))).map(|(a, b)| (a as f64, b as f64))
}

/// A 1-D sketch: counts on bins of width 2^exp, the finest power of two ≥ the start on which the
/// values fit in [`CAP_1D`] bins. It is what adding the values one at a time, doubling the
/// width whenever the range outgrows the cap, ends with, whatever their order.
#[derive(Debug, Clone, PartialEq)]
pub struct Sketch {
    axis: Axis,
    counts: Vec<u64>,
}

impl Sketch {
    /// The empty sketch for values of magnitude up to `scale`.
    pub fn new(scale: f64) -> Sketch {
        Sketch { axis: Axis { exp: start_exponent(scale), lo: 0.0, len: 0 }, counts: Vec::new() }
    }

    /// The sketch of values given as counts on the grid of width `2^exp` (bin `i` = [i w, (i+1) w)),
    /// `exp` at least the start exponent of `scale`.
    pub fn from_counts(scale: f64, exp: i32, bins: &[(i64, u64)]) -> Sketch {
        let Some((a, b)) = span(bins.iter().filter(|(_, c)| *c > 0).map(|(i, _)| i)) else { return Sketch::new(scale) };
        let axis = Axis::fitting(exp, a, b, CAP_1D);
        let k = axis.exp - exp;
        let mut counts = vec![0u64; axis.len];
        for &(i, c) in bins {
            counts[((i as f64 * (-k as f64).exp2()).floor() - axis.lo) as usize] += c;
        }
        Sketch { axis, counts }
    }

    pub fn exponent(&self) -> i32 {
        self.axis.exp
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
            if ((hi - lo) as usize) < CAP_1D {
                break;
            }
            exp += 1;
        }
        let mut counts = vec![0u64; (hi - lo) as usize + 1];
        for s in [self, other] {
            // `remap` in integers: the bin indices are integers below 2^42 (in f64 exactly), and
            // ⌊i / 2^k⌋ is i >> k (an arithmetic shift floors negative ones too); k ≥ 0
            let (k, first, to) = (exp - s.axis.exp, s.axis.lo as i64, lo as i64);
            for (j, &c) in s.counts.iter().enumerate() {
                if c != 0 {
                    counts[(((first + j as i64) >> k) - to) as usize] += c;
                }
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

/// A 2-D sketch of pairs (x, y): per axis the finest power-of-two width ≥ the start on which the
/// pairs' range fits in [`CAP_2D`] bins.
#[derive(Debug, Clone, PartialEq)]
pub struct Sketch2 {
    x: Axis,
    y: Axis,
    /// row-major: `counts[i * y.len + j]`
    counts: Vec<u64>,
}

impl Sketch2 {
    /// The sketch of pairs given as counts on the grid of widths `2^ex` × `2^ey`.
    pub fn from_counts(scale: f64, (ex, ey): (i32, i32), bins: &[((i64, i64), u64)]) -> Sketch2 {
        let occupied = || bins.iter().filter(|(_, c)| *c > 0);
        let (Some((ax, bx)), Some((ay, by))) = (span(occupied().map(|((i, _), _)| i)), span(occupied().map(|((_, j), _)| j))) else {
            let axis = Axis { exp: start_exponent(scale), lo: 0.0, len: 0 };
            return Sketch2 { x: axis, y: axis, counts: Vec::new() };
        };
        let (x, y) = (Axis::fitting(ex, ax, bx, CAP_2D), Axis::fitting(ey, ay, by, CAP_2D));
        let (kx, ky) = (x.exp - ex, y.exp - ey);
        let mut counts = vec![0u64; x.len * y.len];
        for &((i, j), c) in bins {
            let bi = ((i as f64 * (-kx as f64).exp2()).floor() - x.lo) as usize;
            let bj = ((j as f64 * (-ky as f64).exp2()).floor() - y.lo) as usize;
            counts[bi * y.len + bj] += c;
        }
        Sketch2 { x, y, counts }
    }

    pub fn exponents(&self) -> (i32, i32) {
        (self.x.exp, self.y.exp)
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

    /// The bin of `x` on the grid of width 2^`exp` (what the analysis query computes).
    fn index(x: f64, exp: i32) -> f64 {
        (x * (-exp as f64).exp2()).floor()
    }

    /// The sketch of values, from their counts on the start grid of `scale`.
    fn of(x: &[f64], scale: f64) -> Sketch {
        of_at(x, scale, start_exponent(scale))
    }

    /// The sketch of values from their counts on the grid of width 2^`exp`.
    fn of_at(x: &[f64], scale: f64, exp: i32) -> Sketch {
        let mut bins = std::collections::BTreeMap::new();
        x.iter().for_each(|&v| *bins.entry(index(v, exp) as i64).or_insert(0u64) += 1);
        Sketch::from_counts(scale, exp, &bins.into_iter().collect::<Vec<_>>())
    }

    #[test]
    fn sketch_histograms_are_exact_counts_on_dyadic_grids() {
        let mut u = lcg(1);
        let x: Vec<f64> = (0..50_000).map(|_| 3.0 * u() * u()).collect();
        let s = of(&x, 10.0);
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
    fn the_sketch_is_the_finest_fitting_grid_whatever_grid_its_counts_come_on() {
        // the pilot's promise (`query`): counts on any grid at least as fine give the same sketch
        let mut u = lcg(4);
        let x: Vec<f64> = (0..20_000).map(|_| 7.0 * u() * u() * u()).collect();
        let whole = of(&x, 10.0);
        let (lo, hi) = x.iter().fold((f64::INFINITY, 0f64), |(a, b), &v| (a.min(v), b.max(v)));
        assert_eq!(whole.exponent(), exponent_for(lo, hi, start_exponent(10.0), CAP_1D));
        let span = |e: i32| (index(hi, e) - index(lo, e)) as usize + 1;
        assert!(span(whole.exponent()) <= CAP_1D && span(whole.exponent() - 1) > CAP_1D, "the finest grid that fits");
        for e in [start_exponent(10.0) + 7, whole.exponent() - 3, whole.exponent()] {
            assert_eq!(of_at(&x, 10.0, e), whole, "counts on 2^{e}");
        }
    }

    #[test]
    fn merged_parts_equal_the_whole_on_every_common_grid() {
        let mut u = lcg(3);
        let x: Vec<f64> = (0..30_000).map(|i| if i < 20_000 { 2.0 * u() } else { 5.0 + 40.0 * u() * u() }).collect();
        let (whole, a, b) = (of(&x, 50.0), of(&x[..20_000], 50.0), of(&x[20_000..], 50.0));
        let merged = a.merge(&b);
        assert_eq!(merged, whole, "the merge of the parts' sketches is the whole's");
        for exp in [merged.exponent(), -2, 0, 3] {
            assert_eq!(merged.histogram(exp), whole.histogram(exp), "exp {exp}");
        }
    }

    #[test]
    fn joint_table_marginals_equal_the_one_dimensional_histograms() {
        let mut u = lcg(2);
        let pairs: Vec<(f64, f64)> = (0..20_000)
            .map(|_| {
                let a = u();
                (a, a + u())
            })
            .collect();
        let (xs, ys): (Vec<f64>, Vec<f64>) = pairs.iter().copied().unzip();
        let (sx, sy) = (of(&xs, 10.0), of(&ys, 10.0));
        let e = start_exponent(10.0);
        let mut bins = std::collections::BTreeMap::new();
        pairs.iter().for_each(|&(a, b)| *bins.entry((index(a, e) as i64, index(b, e) as i64)).or_insert(0u64) += 1);
        let sj = Sketch2::from_counts(10.0, (e, e), &bins.into_iter().collect::<Vec<_>>());
        let (ex, ey) = sj.exponents();
        let (hx, hy) = (sx.histogram(ex.max(-5)), sy.histogram(ey.max(-5)));
        let t = sj.table(&hx, &hy);
        let rows: Vec<u64> = t.iter().map(|r| r.iter().sum()).collect();
        let cols: Vec<u64> = (0..hy.bins()).map(|j| t.iter().map(|r| r[j]).sum()).collect();
        assert_eq!(rows, hx.counts);
        assert_eq!(cols, hy.counts);
    }
}
