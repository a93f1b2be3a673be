//! T_k and L_k within the window: the law conditioned on X ≤ t_a — what a Monte Carlo table of
//! [0, t_a] estimates — from Table 1's moments and the part of the densities' series beyond t_a
//! ([`super::densities`]).

use super::densities::{Transform, Transforms};

/// (P(X ≤ a), E[X; X ≤ a], E[X²; X ≤ a]) of transform `x` from its cosine series integrated
/// term by term, and its point masses up to a:
///
/// ```text
///     ∫_0^a cos ωt dt = sin ωa / ω,   ∫_0^a t cos ωt dt = a sin ωa / ω + (cos ωa − 1)/ω²,
///     ∫_0^a t² cos ωt dt = a² sin ωa / ω + 2a cos ωa / ω² − 2 sin ωa / ω³
/// ```
fn window_sums(x: &Transform, half_period: f64, a: f64) -> [f64; 3] {
    let mut m = [x.phi[0].re * a, x.phi[0].re * a * a / 2.0, x.phi[0].re * a * a * a / 3.0];
    for (j, f) in x.phi.iter().enumerate().skip(1) {
        let w = std::f64::consts::PI * j as f64 / half_period;
        let (sin, cos) = (w * a).sin_cos();
        m[0] += 2.0 * f.re * sin / w;
        m[1] += 2.0 * f.re * (a * sin / w + (cos - 1.0) / (w * w));
        m[2] += 2.0 * f.re * (a * a * sin / w + 2.0 * a * cos / (w * w) - 2.0 * sin / (w * w * w));
    }
    let mut out = m.map(|v| v / half_period);
    for &(t, mass) in x.points.iter().filter(|p| p.0 <= a) {
        out[0] += mass;
        out[1] += mass * t;
        out[2] += mass * t * t;
    }
    out
}

/// The windowed means and variances of T_k and L_k into Table 1's `rows`: the law conditioned
/// on X ≤ t_a, from Table 1's moments of the whole law less the part beyond t_a, which the series
/// gives ([`window_sums`] over [t_a, P], as shares of the law's mass; extrapolated over the
/// levels, coarsest first):
///
/// ```text
///     p = P(X > t_a),  q1 = E[X; X > t_a],  q2 = E[X²; X > t_a],
///     E[X | X ≤ t_a] = (E X − q1)/(1 − p),   E[X² | X ≤ t_a] = (E X² − q2)/(1 − p)
/// ```
///
/// (Table 1's moments come from finer resolutions than the densities', and the part beyond the
/// window is small where the window matters little.) P(X ≤ t_a) goes to `reached` where the
/// counts did not give it (T_k's for D_k, L_k's for H_k).
pub(crate) fn windowed(levels: &[(f64, Transforms)], half_period: f64, t_a: f64, rows: &mut [super::sticks::Row]) {
    for r in rows.iter_mut().filter(|r| matches!(r.variable, "T" | "L")) {
        let per: Vec<(f64, [f64; 3])> = levels
            .iter()
            .filter_map(|(h, l)| {
                let x = l.iter().find(|x| x.variable == r.variable && x.index == r.index)?;
                let (all, inside) = (window_sums(x, half_period, half_period), window_sums(x, half_period, t_a));
                Some((*h, std::array::from_fn(|i| (all[i] - inside[i]) / all[0])))
            })
            .collect();
        if per.len() != levels.len() || per.iter().any(|(_, q)| !q.iter().all(|v| v.is_finite())) {
            continue;
        }
        let [(p, pe), (q1, e1), (q2, e2)] =
            std::array::from_fn(|i| super::richardson::guarded(&per.iter().map(|(h, q)| (*h, q[i])).collect::<Vec<_>>(), super::richardson::Order::Regular));
        let inside = 1.0 - p.clamp(0.0, 1.0);
        if !(inside > 0.0) {
            continue;
        }
        let second = r.variance + r.mean * r.mean;
        let mean = (r.mean - q1) / inside;
        let second_in = (second - q2) / inside;
        let me = (r.error + e1 + mean.abs() * pe) / inside;
        let ve = (r.variance_error + 2.0 * r.mean.abs() * r.error + e2 + second_in.abs() * pe) / inside + 2.0 * mean.abs() * me;
        r.windowed = Some([mean, me, (second_in - mean * mean).max(0.0), ve]);
        if r.reached.is_none() {
            r.reached = Some((inside, pe));
        }
    }
    // D_k needs stick k to start (T_k's share), H_k to end (L_k's), as the counts' `reach`
    let shares: Vec<(&str, u32, Option<(f64, f64)>)> =
        rows.iter().filter(|r| matches!(r.variable, "T" | "L")).map(|r| (r.variable, r.index, r.reached)).collect();
    for r in rows.iter_mut().filter(|r| r.reached.is_none() && matches!(r.variable, "D" | "H")) {
        let from = if r.variable == "D" { "T" } else { "L" };
        r.reached = shares.iter().find(|s| s.0 == from && s.1 == r.index).and_then(|s| s.2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::clock::{Points, C64};
    use crate::law::densities::tests::div;
    use crate::law::densities::N;

    #[test]
    fn the_window_conditions_the_law_as_its_closed_form() {
        // Exp(2) cut at a = 1 (and at 3): P(T ≤ a) = 1 − e^{−λa}, E[T | T ≤ a] = 1/λ −
        // a e^{−λa}/(1 − e^{−λa}), E[T² | T ≤ a] = (2/λ² − e^{−λa}(a² + 2a/λ + 2/λ²))/(1 − e^{−λa}),
        // from Table 1's E T = 1/2, Var T = 1/4 and the series' part beyond a; a point mass of 0.1
        // at 0.5 added to 0.9 Exp(2) moves the window's sums by 0.1 (1, 0.5, 0.25)
        let (lambda, p) = (2.0, Points::<N>::cosine(20.0, &[], false));
        let phi: Box<[C64; N]> = Box::new(std::array::from_fn(|j| div(C64::new(lambda, 0.0), C64::new(lambda + p.z[j].re, p.z[j].im))));
        let levels = vec![(0.1, vec![Transform { variable: "T", index: 1, phi: phi.clone(), points: vec![] }])];
        for a in [1.0, 3.0] {
            let mut rows = vec![super::super::sticks::Row {
                variable: "T",
                index: 1,
                mean: 0.5,
                variance: 0.25,
                error: 0.0,
                variance_error: 0.0,
                reached: None,
                windowed: None,
            }];
            windowed(&levels, p.t, a, &mut rows);
            let [mean, _, var, _] = rows[0].windowed.unwrap();
            let e = (-lambda * a).exp();
            let (p0, w1, w2) =
                (1.0 - e, 1.0 / lambda - a * e / (1.0 - e), (2.0 / (lambda * lambda) - e * (a * a + 2.0 * a / lambda + 2.0 / (lambda * lambda))) / (1.0 - e));
            let got = (rows[0].reached.unwrap().0, mean, var + mean * mean);
            assert!((got.0 - p0).abs() < 1e-4 && (got.1 - w1).abs() < 1e-4 && (got.2 - w2).abs() < 1e-4, "a = {a}: {got:?} against {p0} {w1} {w2}");
            let x = Transform { variable: "T", index: 1, phi: phi.clone(), points: vec![] };
            let scaled = Transform { variable: "T", index: 1, phi: Box::new(phi.map(|c| C64::new(0.9 * c.re, 0.9 * c.im))), points: vec![(0.5, 0.1)] };
            let (m, n) = (window_sums(&x, p.t, a), window_sums(&scaled, p.t, a));
            assert!((n[0] - (0.9 * m[0] + 0.1)).abs() < 1e-12 && (n[1] - (0.9 * m[1] + 0.05)).abs() < 1e-12 && (n[2] - (0.9 * m[2] + 0.025)).abs() < 1e-12);
        }
    }
}
