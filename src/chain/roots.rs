//! Root isolation of a polynomial on an interval that provably misses none.
//!
//! Between events the chain's event functions are g(τ) = c·e^{Ãτ}z₀ ([`super`]); on a step
//! [τₐ, τₐ + h] with ‖Ã‖h ≤ 1 they equal their Taylor polynomial P(s) = Σ_{j≤M} g_j s^j/j! to
//! within a proven bound δ (the truncation, [`super::exact`]). This file finds the zeros of g
//! from P and δ: g has no zero on a sub-interval [l, l + ℓ] where |P| > δ + (rounding), and this
//! is *proven* by the shifted expansion P(l + t) = Σ_m q_m t^m (exact for a polynomial):
//!
//! ```text
//!     σ₀ P(l + t) ≥ |q₀| − Σ_{m ≥ 1, sgn q_m ≠ σ₀} |q_m| ℓ^m        (0 ≤ t ≤ ℓ, σ₀ = sgn q₀)
//! ```
//!
//! (the terms of q₀'s sign only push P away from zero). A sub-interval that cannot be proven
//! free is split in two and the halves searched left to right, so the first zero found is the
//! first zero of g. A half whose ends differ in sign beyond the margin and on which P′ is
//! proven free of zeros (the same bound one order up) holds exactly one simple zero, found by
//! safeguarded Newton to the last bit. A sub-interval shorter than [`RESOLUTION`]·h that is
//! neither is a *touch*: g comes within its error bound of zero without a proven crossing (a
//! tangency, the grazing case), reported as such for the physics to decide.
//!
//! Why no zero is missed: every point of [0, h] lies in a sub-interval that was either proven
//! free, or searched further, or reported; the bound holds for every t in the sub-interval, not
//! at sample points, so a zero between samples cannot hide (as it can from a step-and-check
//! event locator with a fixed step).

/// Sub-intervals shorter than this fraction of the step are not split further (a touch).
pub(crate) const RESOLUTION: f64 = 1e-10;

/// The most sub-intervals one search examines: past it, each sub-interval left is reported as a
/// touch without a further split, so that a search always ends (never reached by the tests'
/// scenes; a polynomial of degree 24 has at most 24 zeros, each costing about 70 sub-intervals).
const MAX_VISITS: usize = 1 << 14;

/// Unit roundoff.
const U: f64 = f64::EPSILON * 0.5;

/// The most terms a polynomial here has (the Taylor polynomials of [`super::matrix`]).
const MAX_TERMS: usize = 32;

/// A polynomial Σ p_j s^j in the power basis.
#[derive(Debug, Clone)]
pub(crate) struct Poly {
    pub c: Vec<f64>,
}

/// A zero found at `s` (from the step's start): a proven simple crossing, or a touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Zero {
    pub s: f64,
    pub touch: bool,
}

impl Poly {
    /// The value at s (Horner).
    pub fn at(&self, s: f64) -> f64 {
        self.c.iter().rev().fold(0.0, |acc, &p| acc * s + p)
    }

    /// The derivative.
    pub fn derivative(&self) -> Poly {
        Poly { c: self.c.iter().enumerate().skip(1).map(|(j, &p)| j as f64 * p).collect() }
    }

    /// Whether P has no zero on [l, l + ℓ] with |P| > `margin` there (see the module docs).
    fn free(&self, l: f64, len: f64, margin: f64) -> bool {
        self.bounds(l, len, margin).0
    }

    /// Whether P has no zero on [l, l + ℓ] with |P| > `margin` there, and whether P lies within
    /// `margin` of zero on all of it (`flat`: g may be zero anywhere there, a touch as long as
    /// the sub-interval): from the coefficients q of P(l + t) = Σ q_m t^m by repeated synthetic
    /// division (O(M²); none at l = 0), with a bound of the rounding of each.
    fn bounds(&self, l: f64, len: f64, margin: f64) -> (bool, bool) {
        let n = self.c.len();
        assert!(n <= MAX_TERMS, "a polynomial of at most {MAX_TERMS} terms");
        let (mut q, mut a) = ([0.0; MAX_TERMS], [0.0; MAX_TERMS]);
        for (j, &c) in self.c.iter().enumerate() {
            (q[j], a[j]) = (c, c.abs());
        }
        if l != 0.0 {
            for i in 0..n {
                for j in (i..n - 1).rev() {
                    q[j] += l * q[j + 1];
                    a[j] += l.abs() * a[j + 1];
                }
            }
        }
        let rounding = 4.0 * (2 * n + 2) as f64 * U;
        let sign = q[0].signum();
        let mut low = q[0].abs() - rounding * a[0];
        let mut high = q[0].abs();
        let mut power = 1.0;
        for m in 1..n {
            power *= len;
            if q[m] * sign < 0.0 {
                low -= q[m].abs() * power;
            }
            low -= rounding * a[m] * power;
            high += q[m].abs() * power;
        }
        (q[0] != 0.0 && low > margin, high <= margin)
    }

    /// Visit the zeros of g (|g − P| ≤ `margin` on [0, h]) in (`from`, h], left to right, until
    /// `found` says to stop (true). Returns whether it stopped.
    pub fn zeros(&self, from: f64, h: f64, margin: f64, found: &mut impl FnMut(Zero) -> bool) -> bool {
        let slope = self.derivative();
        // the margin of P′ is not needed to the bit: a wrong "no zero of P′" would at worst
        // make Newton bracket a zero it still holds (the ends differ in sign beyond the margin)
        let mut stack = vec![(from, h - from)];
        let min_len = RESOLUTION * h;
        let mut visits = 0;
        while let Some((l, len)) = stack.pop() {
            visits += 1;
            if len <= 0.0 {
                continue;
            }
            let (free, flat) = self.bounds(l, len, margin);
            if free {
                continue;
            }
            if flat {
                // (g within its margin of zero throughout: one touch for the whole sub-interval,
                // not one per leaf of a split that could never prove anything)
                if found(Zero { s: l, touch: true }) {
                    return true;
                }
                continue;
            }
            let (pa, pb) = (self.at(l), self.at(l + len));
            if pa * pb < 0.0 && pa.abs() > margin && pb.abs() > margin && slope.free(l, len, 0.0) {
                if found(Zero { s: self.newton(l, l + len, pa), touch: false }) {
                    return true;
                }
                continue;
            }
            if len <= min_len || visits > MAX_VISITS {
                // the zero within the resolution: where |P| is least of the ends and the middle
                let s = [l, l + 0.5 * len, l + len].into_iter().min_by(|a, b| self.at(*a).abs().total_cmp(&self.at(*b).abs())).unwrap_or(l);
                if found(Zero { s, touch: true }) {
                    return true;
                }
                continue;
            }
            // the left half is searched first
            stack.push((l + 0.5 * len, 0.5 * len));
            stack.push((l, 0.5 * len));
        }
        false
    }

    /// The least and greatest value of P on [0, len], where P is known to `margin`: at its ends
    /// and at its turning points (the zeros of P′, known to about TERMS·margin/len: where P′
    /// is flat within that, P is flat too and its ends hold its extremes).
    pub fn range(&self, len: f64, margin: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (self.at(0.0).min(self.at(len)), self.at(0.0).max(self.at(len)));
        if len > 0.0 {
            let slope_margin = margin * super::matrix::TERMS as f64 / len;
            self.derivative().zeros(0.0, len, slope_margin, &mut |z| {
                let p = self.at(z.s);
                (lo, hi) = (lo.min(p), hi.max(p));
                false
            });
        }
        (lo, hi)
    }

    /// ∫₀^s P.
    pub fn integral(&self, s: f64) -> f64 {
        self.c.iter().enumerate().rev().fold(0.0, |acc, (j, c)| acc * s + c / (j + 1) as f64) * s
    }

    /// The first zero in (`from`, h].
    pub fn first_zero(&self, from: f64, h: f64, margin: f64) -> Option<Zero> {
        let mut first = None;
        self.zeros(from, h, margin, &mut |z| {
            first = Some(z);
            true
        });
        first
    }

    /// The one simple zero in [a, b] (P(a) = `pa`, P(b) of the other sign): Newton steps kept
    /// inside the bracket, bisection when one leaves it, to adjacent floats.
    fn newton(&self, mut a: f64, mut b: f64, pa: f64) -> f64 {
        let slope = self.derivative();
        let sa = pa.signum();
        let mut s = 0.5 * (a + b);
        for _ in 0..200 {
            let p = self.at(s);
            if p == 0.0 {
                return s;
            }
            if p.signum() == sa {
                a = s;
            } else {
                b = s;
            }
            let d = slope.at(s);
            let next = s - p / d;
            let mid = 0.5 * (a + b);
            s = if next > a && next < b && d != 0.0 { next } else { mid };
            if mid <= a || mid >= b || (b - a) <= 2.0 * U * b.abs().max(a.abs()) {
                break;
            }
        }
        s
    }

    /// Where, from the start of an interval at which g = 0 and leaves with sign `sign`, the
    /// search for its next zero may begin: the first ℓ ≤ h (halving) on which the first
    /// derivative of P not zero within rounding at 0 has sign `sign` throughout — then P
    /// (with the lower derivatives ≈ 0 at 0) moves away from zero on (0, ℓ], and a zero in the
    /// rounding band before is the start's own (the grazing rule of [`super::exact`]).
    pub fn leaves(&self, sign: f64, h: f64) -> f64 {
        let mut d = self.derivative();
        let scale = self.c.iter().enumerate().map(|(j, p)| p.abs() * h.powi(j as i32)).fold(0.0, f64::max);
        for order in 1..self.c.len() {
            let lead = d.c.first().copied().unwrap_or(0.0);
            if lead.abs() * h.powi(order as i32) > 1e-9 * scale {
                if lead.signum() != sign {
                    return 0.0;
                }
                let mut len = h;
                while len > RESOLUTION * h {
                    if d.free(0.0, len, 0.0) {
                        return len;
                    }
                    len *= 0.5;
                }
                return 0.0;
            }
            d = d.derivative();
        }
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(roots: &[f64], scale: f64) -> Poly {
        let mut c = vec![scale];
        for &r in roots {
            let mut next = vec![0.0; c.len() + 1];
            for (j, &p) in c.iter().enumerate() {
                next[j + 1] += p;
                next[j] -= r * p;
            }
            c = next;
        }
        Poly { c }
    }

    #[test]
    fn finds_every_simple_zero_in_order() {
        let roots = [0.1, 0.1 + 1e-7, 0.37, 0.9];
        let p = from_roots(&roots, 1.0);
        let mut seen = Vec::new();
        p.zeros(0.0, 1.0, 0.0, &mut |z| {
            seen.push(z);
            false
        });
        assert_eq!(seen.len(), 4, "{seen:?}");
        // (a zero of a pair 1e-7 apart is conditioned as |P| rounding / |P′| ≈ 1e-17 / 2e-8)
        for (z, r) in seen.iter().zip(roots) {
            let tolerance = if r < 0.2 { 1e-9 } else { 1e-14 };
            assert!(!z.touch && (z.s - r).abs() < tolerance, "{z:?} vs {r}");
        }
    }

    #[test]
    fn a_double_zero_is_a_touch_and_a_near_miss_beyond_the_margin_is_nothing() {
        // (s − 0.5)² touches zero
        let p = from_roots(&[0.5, 0.5], 1.0);
        // (a double zero is found to about the square root of the rounding of P: its band
        // |s − 0.5| ≲ √(1e-16))
        let z = p.first_zero(0.0, 1.0, 1e-18).expect("the touch");
        assert!(z.touch && (z.s - 0.5).abs() < 1e-7, "{z:?}");
        // (s − 0.5)² + 1e-6 never reaches zero
        let mut q = p.clone();
        q.c[0] += 1e-6;
        assert_eq!(q.first_zero(0.0, 1.0, 1e-18), None);
    }

    #[test]
    fn leaving_a_zero_skips_it() {
        // s² (s − 0.6): a double zero at the start (the grazing departure), then a crossing
        let p = from_roots(&[0.0, 0.0, 0.6], -1.0);
        let from = p.leaves(1.0, 1.0);
        assert!(from > 0.0 && from < 0.6);
        let z = p.first_zero(from, 1.0, 1e-18).expect("the crossing");
        assert!(!z.touch && (z.s - 0.6).abs() < 1e-14, "{z:?}");
        // leaving with the wrong sign: no room
        assert_eq!(p.leaves(-1.0, 1.0), 0.0);
    }
}
