//! Power sums that do not depend on the order of addition: the integer parts of (x − c)^p that
//! the analysis' fold sums (see [`quanta`]), and the central moments from them.

/// Power sums that do not depend on the order of addition.
///
/// The batches of rows come in whatever order polars' threads finish them, and floating-point
/// addition is not associative: summed as floats, Σd^p would change in its last bits with the
/// thread count or the shard split. So each term t = d^p (|d| ≤ B, n rows) is cut into two
/// integers, summed exactly as int64 — the sums, being exact, are the same for any order:
///
/// ```text
///     q = B^p / R,  R = 2^61 / n,   v = t / q  (|v| ≤ R),
///     hi = trunc(v),   lo = round((v − hi)·R)  (|lo| ≤ R),     Σt = q (Σhi + Σlo / R)
/// ```
///
/// Each sum stays within n R = 2^61 in magnitude (< 2^63). A term loses at most q/(2R) = B^p n²/2^123
/// (a relative 2^-70 of B^p for n ≤ 10^8) or the rounding of v, whichever is larger; rounded to
/// nearest, these errors do not pile up one way. B is the bound of |d| the pilot sets near the
/// data's spread (`query::pilots`), so that values small against their window keep their digits
/// (tested: a spread 10^-6 of the scale).
pub(crate) fn quanta(bound: f64, rows: u64) -> [(f64, f64); 4] {
    let r = 2f64.powi(61) / rows.max(1) as f64;
    [1, 2, 3, 4].map(|p| (bound.powi(p) / r, r))
}

/// Σt from the two integer sums (see [`quanta`]).
pub(crate) fn exact(hi: i64, lo: i64, (q, r): (f64, f64)) -> f64 {
    q * (hi as f64 + lo as f64 / r)
}

/// The integer parts [hi, lo] of d^p for p = 1..4 (see [`quanta`]).
pub(crate) fn split(d: f64, q: &[(f64, f64); 4]) -> [[i64; 2]; 4] {
    let d2 = d * d;
    let mut out = [[0; 2]; 4];
    for (p, t) in [d, d2, d2 * d, d2 * d2].into_iter().enumerate() {
        let (qp, r) = q[p];
        let v = t / qp;
        // |v| ≤ R ≤ 2^61 by the bound (`as` saturates beyond: that pass is run again). hi is v
        // truncated (any integer within 1 of v keeps |lo| ≤ R and the sums exact; `as` truncates
        // in one instruction, libm's `round` is a call); lo is rounded to nearest, so the only loss,
        // lo's rounding, does not pile up one way
        let hi = v as i64; // truncation: one instruction (`f64::trunc` is a libm call here)
        out[p] = [hi, nearest((v - hi as f64) * r) as i64];
    }
    out
}

/// x rounded to the nearest integer (ties to even) by the 2^52 shift: adding 2^52 to |x| < 2^52
/// leaves no fraction bits, so the addition rounds (in the default rounding mode); |x| ≥ 2^52 is
/// already an integer.
#[inline]
fn nearest(x: f64) -> f64 {
    const SHIFT: f64 = 4_503_599_627_370_496.0; // 2^52
    if x.abs() < SHIFT {
        let s = SHIFT.copysign(x);
        (x + s) - s
    } else {
        x
    }
}

/// The power sums of one observable in one jackknife group: n, Σ(x−c)^p for p = 1..4, range,
/// and how many values were censored.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sums {
    pub n: u64,
    /// the integer sums (Σhi, Σlo) of (x − c)^p, p = 1..4 ([`quanta`])
    pub parts: [[i64; 2]; 4],
    pub min: f64,
    pub max: f64,
    pub cut: u64,
}

impl Default for Sums {
    fn default() -> Self {
        Sums { n: 0, parts: [[0; 2]; 4], min: f64::INFINITY, max: f64::NEG_INFINITY, cut: 0 }
    }
}

impl Sums {
    /// Add the sums of more realizations (exact: integer sums).
    #[inline]
    pub(crate) fn add(&mut self, o: &Sums) {
        self.n += o.n;
        for p in 0..4 {
            for k in 0..2 {
                // (wrapping: a pass whose values exceeded the bound saturates its parts, and is
                // thrown away and run again; see `query::aggregate`)
                self.parts[p][k] = self.parts[p][k].wrapping_add(o.parts[p][k]);
            }
        }
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
        self.cut += o.cut;
    }

    /// Add one value x with the parts of (x − c)^p ([`split`]).
    #[inline]
    pub(crate) fn add_value(&mut self, x: f64, parts: [[i64; 2]; 4]) {
        self.add(&Sums { n: 1, parts, min: x, max: x, cut: 0 });
    }

    /// The central moments from the power sums about the pilot's centre c (exact algebra: with
    /// δ = S1/n the offset of the mean from c, M2 = S2 − n δ², M3 = S3 − 3δ S2 + 2n δ³,
    /// M4 = S4 − 4δ S3 + 6δ² S2 − 3n δ⁴).
    pub(crate) fn moments(&self, c: f64, q: &[(f64, f64); 4]) -> crate::stats::Moments {
        if self.n == 0 {
            return crate::stats::Moments::default();
        }
        let n = self.n as f64;
        let [s1, s2, s3, s4] = [0, 1, 2, 3].map(|p| exact(self.parts[p][0], self.parts[p][1], q[p]));
        let d = s1 / n;
        let (d2, d3, d4) = (d * d, d * d * d, d * d * d * d);
        crate::stats::Moments {
            n: self.n,
            mean: c + d,
            m2: (s2 - n * d2).max(0.0),
            m3: s3 - 3.0 * d * s2 + 2.0 * n * d3,
            m4: (s4 - 4.0 * d * s3 + 6.0 * d2 * s2 - 3.0 * n * d4).max(0.0),
            min: self.min,
            max: self.max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ d^p of `d` in the order given, through the integer parts.
    fn sums(d: &[f64], bound: f64) -> [f64; 4] {
        let q = quanta(bound, d.len() as u64);
        let mut acc = [[0i64; 2]; 4];
        for &x in d {
            for (p, [hi, lo]) in split(x, &q).into_iter().enumerate() {
                acc[p][0] += hi;
                acc[p][1] += lo;
            }
        }
        [0, 1, 2, 3].map(|p| exact(acc[p][0], acc[p][1], q[p]))
    }

    #[test]
    fn nearest_is_round_half_to_even() {
        let mut xs =
            vec![0.5, 1.5, 2.5, -0.5, -1.5, -2.5, 0.49999999999999994, 2f64.powi(51) + 0.5, 2f64.powi(52) - 0.5, 2f64.powi(52), -2f64.powi(60), 1e-300, -0.0];
        xs.extend((0..10_000).map(|i| ((i as f64) * 0.7123).sin() * 10f64.powi(i % 19)));
        for x in xs {
            assert_eq!(nearest(x), x.round_ties_even(), "{x:e}");
        }
    }

    #[test]
    fn exact_power_sums_do_not_depend_on_the_order_and_keep_double_precision() {
        let mut s = 88172645463325252u64;
        let mut u = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        // deviations spanning magnitudes, as durations about a centre do
        let d: Vec<f64> = (0..100_000).map(|_| (u() - 0.3) * 10f64.powf(-4.0 * u())).collect();
        let forward = sums(&d, 1.0);
        let mut shuffled = d.clone();
        shuffled.reverse();
        shuffled.rotate_left(31_337);
        assert_eq!(forward, sums(&shuffled, 1.0), "the same bits in any order");
        // an independent reference: the powers summed in a compensated (Neumaier) sum
        for p in 0..4 {
            let (mut sum, mut c) = (0f64, 0f64);
            for &x in &d {
                let t = x.powi(p as i32 + 1);
                let y = sum + t;
                c += if sum.abs() >= t.abs() { (sum - y) + t } else { (t - y) + sum };
                sum = y;
            }
            let reference = sum + c;
            let scale: f64 = d.iter().map(|x| x.abs().powi(p as i32 + 1)).sum();
            assert!((forward[p] - reference).abs() <= 1e-15 * scale, "p = {}: {} vs {reference}", p + 1, forward[p]);
        }
    }

    #[test]
    fn a_spread_far_below_the_window_keeps_its_digits() {
        // durations of about 1 ms ± 0.1 ms in a window of 1000 s: the bound is the spread's
        let d: Vec<f64> = (0..1_000_000).map(|i| 1e-4 * ((i as f64 * 0.618_033_988_7).fract() - 0.5)).collect();
        let reach = d.iter().fold(0f64, |r, x| r.max(x.abs()));
        let got = sums(&d, 3.0 * reach + 1000.0 * 2f64.powi(-40));
        for p in 0..4 {
            let direct: f64 = d.iter().map(|x| x.powi(p as i32 + 1)).sum();
            let scale: f64 = d.iter().map(|x| x.abs().powi(p as i32 + 1)).sum();
            assert!((got[p] - direct).abs() <= 1e-12 * scale, "p = {}: {} vs {direct}", p + 1, got[p]);
        }
    }
}
