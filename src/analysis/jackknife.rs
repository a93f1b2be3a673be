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
    let full = full.filter(|x| x.is_finite())?;
    let v: Vec<f64> = loo.iter().map(|x| x.filter(|x| x.is_finite())).collect::<Option<Vec<f64>>>()?;
    if v.len() < 2 {
        return None;
    }
    let g = v.len() as f64;
    let mean = v.iter().sum::<f64>() / g;
    let se = ((g - 1.0) / g * v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>()).sqrt();
    let half = T_QUANTILE * se;
    (half.is_finite()).then_some((full - half, full + half))
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
    fn leave_one_out_merges_all_others() {
        let parts: Vec<u64> = (1..=5).collect();
        assert_eq!(leave_one_out(&parts, &0, |a, b| a + b), vec![14, 13, 12, 11, 10]);
    }
}
