//! 95 % intervals by the delete-a-group jackknife over realization-index groups.
//!
//! Realization `i` belongs to group `i mod G` (G = [`GROUPS`]): the groups depend on the indices
//! alone, so the intervals are the same for any thread count, file or shard split. The pass keeps
//! one mergeable accumulator per group beside the whole-sample one; for each group g the
//! statistic is recomputed without it, θ₍g₎ (from prefix and suffix merges of the other groups),
//! and (M. H. Quenouille 1956; J. W. Tukey 1958; the grouped form: K. M. Wolter, *Introduction to
//! Variance Estimation*, 2nd ed., Springer 2007, §4.2)
//!
//! ```text
//!     se² = (G − 1)/G · Σ_g (θ₍g₎ − θ̄)²,     θ̄ = mean of the θ₍g₎
//!     95 % interval: θ̂ ± t_{G−1, 0.975} · se   (θ̂ the whole-sample estimate; t_{19} = 2.093)
//! ```
//!
//! It needs nothing but mergeable accumulators, so it fits the one-pass design for every
//! statistic: mean, variance, skewness, kurtosis, the mode (a kernel estimate on each
//! leave-one-group-out sketch), growth slopes and renewal predictions. Its coverage is measured
//! (`tests/it/coverage.rs`, and the book: docs/src/explanation/estimators.md).

/// Realization-index groups.
pub const GROUPS: usize = 20;

/// t_{19, 0.975}: the two-sided 95 % quantile of Student's t with G − 1 = 19 degrees of freedom.
pub const T_QUANTILE: f64 = 2.093_024_054_408_263;

/// A 95 % interval `(lo, hi)`.
pub type Interval = (f64, f64);

/// The interval around `full` from the leave-one-group-out values (None if any is missing or
/// not finite, or there are fewer than two).
pub fn interval(full: Option<f64>, loo: &[Option<f64>]) -> Option<Interval> {
    let s = Spread::of(full, loo)?;
    let g = s.loo.len() as f64;
    s.around(T_QUANTILE * ((g - 1.0) / g * s.squares).sqrt())
}

/// The estimate and its leave-one-group-out values, checked: the ingredients of an interval.
struct Spread {
    full: f64,
    /// the θ₍g₎
    loo: Vec<f64>,
    mean: f64,
    /// Σ (θ₍g₎ − θ̄)²
    squares: f64,
}

impl Spread {
    /// None if the estimate or any leave-one-out value is missing or not finite, or there are
    /// fewer than two.
    fn of(full: Option<f64>, loo: &[Option<f64>]) -> Option<Spread> {
        let full = full.filter(|x| x.is_finite())?;
        let loo: Vec<f64> = loo.iter().map(|x| x.filter(|x| x.is_finite())).collect::<Option<Vec<f64>>>()?;
        if loo.len() < 2 {
            return None;
        }
        let g = loo.len() as f64;
        let mean = loo.iter().sum::<f64>() / g;
        let squares = loo.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>();
        Some(Spread { full, loo, mean, squares })
    }

    /// θ̂ ± `half` (None if it is not finite).
    fn around(&self, half: f64) -> Option<Interval> {
        half.is_finite().then_some((self.full - half, self.full + half))
    }
}

/// The interval of a higher moment (skewness, kurtosis): as [`interval`], but with the
/// degrees of freedom of the jackknife's variance estimate set by how heavy-tailed the
/// leave-one-group-out values are. The t interval assumes normal pseudo-values, whose s² has
/// relative variance 2/(G − 1); pseudo-values of excess kurtosis κ give s² a relative variance
/// of about 2/(G − 1) + κ/G, so the s² of a heavy-tailed statistic (a higher moment of a
/// heavy-tailed variable) is noisier than the t quantile allows, and it is small exactly when the
/// sample misses the tail. The effective degrees of freedom, as Satterthwaite's (F. E.
/// Satterthwaite, *Biometrics Bulletin* 2, 1946), are
///
/// ```text
///     ν = 2 / (2/(G − 1) + κ̂/G),   clamped to [2, G − 1],
/// ```
///
/// with κ̂ the excess kurtosis of the θ₍g₎ (those of the pseudo-values G θ̂ − (G − 1) θ₍g₎: an
/// affine map keeps it). Pseudo-values as light-tailed as a normal sample keep ν = G − 1 and the
/// plain interval; the interval is never narrower than it. The quantile t_ν is Hill's expansion
/// ([`t_quantile`]). Coverage per column: the book's Benchmarks, "Interval coverage".
pub fn moment_interval(full: Option<f64>, loo: &[Option<f64>]) -> Option<Interval> {
    let s = Spread::of(full, loo)?;
    let g = s.loo.len() as f64;
    let m2 = s.squares / g;
    let m4 = s.loo.iter().map(|x| (x - s.mean).powi(4)).sum::<f64>() / g;
    let excess = if m2 > 0.0 { m4 / (m2 * m2) - 3.0 } else { 0.0 };
    let nu = (2.0 / (2.0 / (g - 1.0) + excess / g)).clamp(2.0, g - 1.0);
    s.around(t_quantile(if nu.is_finite() { nu } else { g - 1.0 }) * ((g - 1.0) * m2).sqrt())
}

/// The two-sided 95 % quantile of Student's t with ν ≥ 2 degrees of freedom by the Cornish–Fisher
/// expansion about the normal quantile z = 1.959964 (G. W. Hill, *Comm. ACM* 13, 1970, Algorithm
/// 396), and [`T_QUANTILE`] at ν = G − 1: t = z + (z³ + z)/(4ν) + (5z⁵ + 16z³ + 3z)/(96ν²) + (3z⁷ + 19z⁵ + 17z³ − 15z)/(384ν³) +
/// (79z⁹ + 776z⁷ + 1482z⁵ − 1920z³ − 945z)/(92160ν⁴). It lies below the exact quantile by
/// 0.75 % at ν = 2, 0.12 % at ν = 3, 0.011 % at ν = 5 and less than 4·10⁻⁶ relative from ν = 10
/// (tested against tables): next to the widening it measures (t₂ = 4.27 against t₁₉ = 2.09),
/// a small shortfall at the fewest degrees of freedom.
pub fn t_quantile(nu: f64) -> f64 {
    if nu == (GROUPS - 1) as f64 {
        // (the plain jackknife's quantile, exactly)
        return T_QUANTILE;
    }
    let z: f64 = 1.959_963_984_540_054;
    let (z3, z5, z7, z9) = (z.powi(3), z.powi(5), z.powi(7), z.powi(9));
    z + (z3 + z) / (4.0 * nu)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu.powi(2))
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * nu.powi(3))
        + (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / (92160.0 * nu.powi(4))
}

/// The interval on the scale `to` (mapped back by `back`, the ends in increasing order), centred
/// on the estimate; None where `to` is undefined for the estimate or a leave-one-out value.
pub fn transformed(full: Option<f64>, loo: &[Option<f64>], to: impl Fn(f64) -> Option<f64>, back: impl Fn(f64) -> f64) -> Option<Interval> {
    let t = to(full?)?;
    let l: Vec<Option<f64>> = loo.iter().map(|x| x.and_then(&to)).collect();
    let (a, b) = interval(Some(t), &l)?;
    let (a, b) = (back(a), back(b));
    Some((a.min(b), a.max(b)))
}

/// For each group, the merge of all the others: `out[g] = ⊕_{h ≠ g} parts[h]`, by prefix and
/// suffix merges (3G merges in all).
pub fn leave_one_out<T: Clone>(parts: &[T], empty: &T, merge: impl Fn(&T, &T) -> T) -> Vec<T> {
    let n = parts.len();
    let mut prefix = vec![empty.clone(); n + 1];
    for g in 0..n {
        prefix[g + 1] = merge(&prefix[g], &parts[g]);
    }
    let mut suffix = vec![empty.clone(); n + 1];
    for g in (0..n).rev() {
        suffix[g] = merge(&parts[g], &suffix[g + 1]);
    }
    (0..n).map(|g| merge(&prefix[g], &suffix[g + 1])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jackknife_of_a_mean_is_the_usual_standard_error() {
        // for the mean of equal-size groups, the grouped jackknife se equals sd(group means)/√G
        let groups: Vec<Vec<f64>> = (0..GROUPS).map(|g| (0..10).map(|i| ((g * 10 + i) as f64).sin()).collect()).collect();
        let sums: Vec<f64> = groups.iter().map(|v| v.iter().sum()).collect();
        let total: f64 = sums.iter().sum();
        let n = 10.0 * GROUPS as f64;
        let loo: Vec<Option<f64>> = sums.iter().map(|s| Some((total - s) / (n - 10.0))).collect();
        let (lo, hi) = interval(Some(total / n), &loo).unwrap();
        let gm: Vec<f64> = sums.iter().map(|s| s / 10.0).collect();
        let m = gm.iter().sum::<f64>() / GROUPS as f64;
        let sd = (gm.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (GROUPS as f64 - 1.0)).sqrt();
        let se = sd / (GROUPS as f64).sqrt();
        assert!(((hi - lo) / 2.0 - T_QUANTILE * se).abs() < 1e-12, "{} vs {}", (hi - lo) / 2.0, T_QUANTILE * se);
    }

    #[test]
    fn hills_t_quantile_is_within_its_stated_accuracy() {
        // two-sided 95 % quantiles of Student's t (tables, e.g. Abramowitz & Stegun 26.10)
        for (nu, exact, relative) in [
            (2.0, 4.302_652_73, 7.5e-3),
            (3.0, 3.182_446_31, 1.3e-3),
            (4.0, 2.776_445_11, 3.2e-4),
            (5.0, 2.570_581_84, 1.1e-4),
            (10.0, 2.228_138_85, 4e-6),
            (19.0, 2.093_024_05, 1e-8),
            (30.0, 2.042_272_46, 4e-6),
        ] {
            let t = t_quantile(nu);
            assert!((t - exact).abs() <= relative * exact, "nu = {nu}: {t} vs {exact}");
        }
        assert_eq!(t_quantile((GROUPS - 1) as f64), T_QUANTILE);
    }

    #[test]
    fn the_moment_interval_is_the_plain_one_for_light_tails_and_wider_for_heavy_ones() {
        // leave-one-out values with no excess kurtosis to speak of (a uniform spread: −1.2) keep
        // ν = G − 1; one far value among equal ones (excess kurtosis ≈ G) widens the interval
        let light: Vec<Option<f64>> = (0..GROUPS).map(|g| Some(1.0 + 0.01 * g as f64)).collect();
        assert_eq!(moment_interval(Some(1.1), &light), interval(Some(1.1), &light));
        let mut heavy = vec![Some(1.0); GROUPS];
        heavy[3] = Some(2.0);
        let (plain, wide) = (interval(Some(1.0), &heavy).unwrap(), moment_interval(Some(1.0), &heavy).unwrap());
        // one value of G apart: mean 1 + 1/G, m2 = (G − 1)/G², m4 = (G − 1)((G − 1)³ + 1)/G⁵,
        // so the excess kurtosis is ((G − 1)³ + 1)/(G (G − 1)) − 3 (15.05 for G = 20)
        let g = GROUPS as f64;
        let k = ((g - 1.0).powi(3) + 1.0) / (g * (g - 1.0)) - 3.0;
        assert!((k - 15.052_631_578_947_368).abs() < 1e-12);
        let nu = 2.0 / (2.0 / (g - 1.0) + k / g);
        assert!((((wide.1 - wide.0) / (plain.1 - plain.0)) - t_quantile(nu) / T_QUANTILE).abs() < 1e-9, "{wide:?} vs {plain:?}");
        assert!(wide.1 - wide.0 > 1.1 * (plain.1 - plain.0));
        // missing or non-finite values: no interval, as the plain one
        let mut gap = light.clone();
        gap[0] = None;
        assert_eq!(moment_interval(Some(1.0), &gap), None);
    }

    #[test]
    fn leave_one_out_merges_all_others() {
        let parts: Vec<u64> = (1..=5).collect();
        assert_eq!(leave_one_out(&parts, &0, |a, b| a + b), vec![14, 13, 12, 11, 10]);
    }
}
