//! Richardson extrapolation of values solved at several resolutions, with an error estimate the
//! resolutions' changes support (the exact law solves at [`LEVELS`] resolutions N/4, N/2, N).

/// The resolutions `exact-law` solves at: a quarter of the finest, a half, itself.
pub const LEVELS: u32 = 3;

/// What the resolutions' changes show of the order ([`guarded`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    /// The laws from a box of starts (split along its fates: module docs of
    /// [`super::sticks`]): their changes fall at a steady order (on the paper scene the Table 1
    /// ratios lie in 2.9–6.2 from n = 20 to 160 and 3.0–4.3 from 80 to 320, D_1's mean apart),
    /// so a ratio in the asymptotic range is evidence.
    Regular,
    /// The laws after a point start: its mass meets the grid's nodes and the fates' curves
    /// all at once, and the changes are erratic — from rest at x = 0.5 on the paper scene the
    /// breakaway probability's changes from h = 0.17 to 0.01 are +4.9e-4, +1.2e-4, +6.0e-5,
    /// +9.8e-6 (ratios 4.1, 2.0, 6.1), so the first ratio, in range, would have trusted an
    /// extrapolation whose change (3e-6) understates its error (about 4e-5) tenfold; stuck at
    /// 0.3: +5.4e-4, −4.9e-4, −1.4e-5, +1.7e-6. One ratio is no evidence there. The laws of
    /// the counts (`--counts`), whose resolutions are coarse, are taken as irregular too.
    Irregular,
}

/// [`extrapolate`]'s value, with an error that the changes support.
///
/// If v_h = V + a h^p, Richardson's R_h = v_h + (v_h − v_{2h})/3 = V + a h^p (4 − 2^p)/3, so
/// the change of R between the pairs is |R_h − R_{2h}| = |R_h − V| (2^p − 1): it bounds R's
/// error whenever p > 1 (by 1.8× at p = 1.5). The order shows in the ratio of the changes,
/// (v_{2h} − v_{4h}) / (v_h − v_{2h}) = 2^p: for [`Order::Regular`] levels whose ratio lies in
/// [2^1.5, 2^3] the change of R is the error (Roache's asymptotic range, *Verification and
/// Validation in Computational Science and Engineering*, 1998, ch. 5). Otherwise — another
/// ratio, or [`Order::Irregular`] levels — the finest change, the size of the finest level's
/// own error, is its floor.
pub(crate) fn guarded(points: &[(f64, f64)], order: Order) -> (f64, f64) {
    let (value, error) = extrapolate(points);
    let change = |w: &[(f64, f64)]| w[1].1 - w[0].1;
    let changes: Vec<f64> = points.windows(2).map(change).collect();
    let finest = changes.last().map_or(0.0, |c| c.abs());
    let ratio = match changes[..] {
        [.., coarse, fine] => coarse / fine,
        _ => f64::NAN,
    };
    if order == Order::Regular && (2f64.powf(1.5)..=8.0).contains(&ratio) {
        (value, error)
    } else {
        (value, error.max(finest))
    }
}

/// (value, error) from the values at spacings h (coarsest first), as [`estimates`].
pub(crate) fn extrapolate(points: &[(f64, f64)]) -> (f64, f64) {
    let k = points.len();
    let v = |i: usize| points[i].1;
    let richardson = |i: usize| v(i) + (v(i) - v(i - 1)) / ((points[i - 1].0 / points[i].0).powi(2) - 1.0);
    match k {
        0 => (f64::NAN, f64::NAN),
        1 => (v(0), f64::NAN),
        2 => (v(1), (v(1) - v(0)).abs()),
        _ => (richardson(k - 1), (richardson(k - 1) - richardson(k - 2)).abs()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The guard's two regimes: a power law v_h = V + a h^p (+ a smaller h^{p+1} term) in the
    /// asymptotic range gets the change of the extrapolation, which bounds the error; first
    /// order (p = 1, ratio 2) and sign changes get the finest change, which bounds it there.
    #[test]
    fn the_guard_trusts_the_extrapolation_only_in_the_asymptotic_range() {
        let (big, h) = (0.3f64, [0.04f64, 0.02, 0.01]);
        for p in [1.0, 1.5, 2.0, 2.5, 3.0] {
            let pts: Vec<(f64, f64)> = h.iter().map(|&h| (h, big + 2.0 * h.powf(p) + 0.5 * h.powf(p + 1.0))).collect();
            let (value, error) = guarded(&pts, Order::Regular);
            let finest = (pts[2].1 - pts[1].1).abs();
            assert!((value - big).abs() <= error, "p = {p}: {value} ± {error}");
            if (1.5..=2.5).contains(&p) {
                assert!(error < 0.9 * finest, "p = {p}: {error} against the finest change {finest}");
            } else if p == 1.0 {
                assert_eq!(error, finest, "p = {p}");
            }
        }
        // changes 1.2e-4, 1e-4 (ratio 1.2, no power law): the finest change is the floor over
        // the extrapolation's change, 9.3e-5
        let (_, error) = guarded(&[(0.04, 0.3), (0.02, 0.30012), (0.01, 0.30022)], Order::Regular);
        assert!((error - 1e-4).abs() < 1e-12, "{error}");
        // the breakaway probability after a point start (Order::Irregular's docs): changes
        // +4.9e-4, +1.2e-4 (ratio 4.1) trusted would say 3e-6; the floor is the finest change
        let pts = [(0.17, 0.0), (0.085, 4.9e-4), (0.0425, 6.1e-4)];
        assert!(guarded(&pts, Order::Regular).1 < 1e-5);
        assert!((guarded(&pts, Order::Irregular).1 - 1.2e-4).abs() < 1e-12);
    }
}
