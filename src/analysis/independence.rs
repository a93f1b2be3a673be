//! Are two variables independent? Tests on a contingency table.
//!
//! The fine joint histogram is first coarsened to at most `g × g` cells by merging adjacent bins
//! into groups of roughly equal marginal mass (g = min(10, ⌊√(n/5)⌋), so that expected counts
//! under independence are about n/g² ≥ 5, the usual validity condition of the χ² approximation).
//! On that table:
//!
//! - Pearson's χ² = Σ (O − E)²/E with E = rᵢ cⱼ / n, df = (R − 1)(C − 1), p = P(χ²_df > χ²);
//! - the G statistic G = 2 Σ O ln(O/E) with the same asymptotic χ² law;
//! - the plug-in mutual information I = G/(2n) nats, with a permutation null: the pairing of the
//!   two variables is shuffled (equivalently, a random table with the observed margins is drawn),
//!   `permutations` times with a ChaCha8 stream, p = (1 + #{I_perm ≥ I}) / (1 + permutations).

use rand::Rng;

use crate::simulation::rng::realization_rng;
use crate::special::chi2_sf;

/// Results of the three tests.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Independence {
    pub n: u64,
    pub rows: usize,
    pub cols: usize,
    pub chi2: f64,
    pub df: f64,
    pub chi2_p_value: f64,
    pub g: f64,
    pub g_p_value: f64,
    pub mutual_information: f64,
    pub mi_null_mean: Option<f64>,
    pub mi_p_value: f64,
    pub permutations: u32,
}

/// Merge adjacent bins (given their marginal counts) into at most `g` groups of similar mass;
/// returns the group of each bin.
fn groups(marginal: &[u64], g: usize) -> Vec<usize> {
    let total: u64 = marginal.iter().sum();
    let mut out = Vec::with_capacity(marginal.len());
    let mut cum = 0u64;
    let mut group = 0usize;
    for &c in marginal {
        out.push(group);
        cum += c;
        // close the group once its share of the mass is reached
        while group + 1 < g && cum as f64 >= (group + 1) as f64 * total as f64 / g as f64 {
            group += 1;
        }
    }
    // drop empty groups (renumber)
    let mut used: Vec<usize> = out.clone();
    used.dedup();
    out.iter().map(|gi| used.binary_search(gi).unwrap()).collect()
}

/// Mutual information (nats) of a table with its margins and total.
fn mutual_information(table: &[Vec<u64>], rows: &[u64], cols: &[u64], n: f64) -> f64 {
    let mut mi = 0.0;
    for (i, row) in table.iter().enumerate() {
        for (j, &o) in row.iter().enumerate() {
            if o > 0 {
                let o = o as f64;
                mi += o / n * (o * n / (rows[i] as f64 * cols[j] as f64)).ln();
            }
        }
    }
    mi.max(0.0)
}

/// Test independence on the fine joint count table `joint[x_bin][y_bin]`.
pub fn test(joint: &[Vec<u64>], permutations: u32, seed: u64) -> Option<Independence> {
    let nx = joint.len();
    let ny = joint.first()?.len();
    let row_m: Vec<u64> = joint.iter().map(|r| r.iter().sum()).collect();
    let col_m: Vec<u64> = (0..ny).map(|j| joint.iter().map(|r| r[j]).sum()).collect();
    let n: u64 = row_m.iter().sum();
    let g = (((n as f64) / 5.0).sqrt().floor() as usize).clamp(2, 10);
    let (gx, gy) = (groups(&row_m, g), groups(&col_m, g));
    let (r, c) = (gx.last()? + 1, gy.last()? + 1);
    let mut table = vec![vec![0u64; c]; r];
    for i in 0..nx {
        for j in 0..ny {
            table[gx[i]][gy[j]] += joint[i][j];
        }
    }
    let rows: Vec<u64> = table.iter().map(|t| t.iter().sum()).collect();
    let cols: Vec<u64> = (0..c).map(|j| table.iter().map(|t| t[j]).sum()).collect();
    if r < 2 || c < 2 || n == 0 {
        return None;
    }
    let nf = n as f64;
    let (mut chi2, mut gstat) = (0.0, 0.0);
    for i in 0..r {
        for j in 0..c {
            let e = rows[i] as f64 * cols[j] as f64 / nf;
            let o = table[i][j] as f64;
            chi2 += (o - e) * (o - e) / e;
            if o > 0.0 {
                gstat += 2.0 * o * (o / e).ln();
            }
        }
    }
    let df = ((r - 1) * (c - 1)) as f64;
    let mi = mutual_information(&table, &rows, &cols, nf);

    // Permutation null: column labels in a random order, dealt to the rows by their margins.
    let mut labels: Vec<u16> = cols.iter().enumerate().flat_map(|(j, &cj)| std::iter::repeat_n(j as u16, cj as usize)).collect();
    let mut rng = realization_rng(seed, u64::MAX);
    let (mut exceed, mut null_sum) = (0u32, 0.0);
    let mut perm = vec![vec![0u64; c]; r];
    for _ in 0..permutations {
        for k in (1..labels.len()).rev() {
            let m = (rng.next_u64() % (k as u64 + 1)) as usize;
            labels.swap(k, m);
        }
        perm.iter_mut().for_each(|row| row.fill(0));
        let mut at = 0usize;
        for (i, &ri) in rows.iter().enumerate() {
            for &l in &labels[at..at + ri as usize] {
                perm[i][l as usize] += 1;
            }
            at += ri as usize;
        }
        let mi_p = mutual_information(&perm, &rows, &cols, nf);
        null_sum += mi_p;
        if mi_p >= mi {
            exceed += 1;
        }
    }
    Some(Independence {
        n,
        rows: r,
        cols: c,
        chi2,
        df,
        chi2_p_value: chi2_sf(chi2, df),
        g: gstat,
        g_p_value: chi2_sf(gstat, df),
        mutual_information: mi,
        mi_null_mean: (permutations > 0).then(|| null_sum / permutations as f64),
        mi_p_value: (1.0 + exceed as f64) / (1.0 + permutations as f64),
        permutations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Joint counts of pairs on a 20 × 20 grid over [0, 1)².
    fn table(pairs: impl Iterator<Item = (f64, f64)>) -> Vec<Vec<u64>> {
        let mut t = vec![vec![0u64; 20]; 20];
        for (x, y) in pairs {
            t[((x * 20.0) as usize).min(19)][((y * 20.0) as usize).min(19)] += 1;
        }
        t
    }

    fn uniforms(seed: u64) -> impl Iterator<Item = f64> {
        let mut rng = realization_rng(seed, 0);
        std::iter::repeat_with(move || crate::simulation::rng::unit_f64(&mut rng))
    }

    #[test]
    fn rejects_a_dependent_pair() {
        // y = (x + 0.2 u) / 1.2: strongly dependent
        let t = table(uniforms(1).zip(uniforms(2)).take(5000).map(|(x, u)| (x, (x + 0.2 * u) / 1.2)));
        let r = test(&t, 99, 7).unwrap();
        assert!(r.chi2_p_value < 1e-6 && r.g_p_value < 1e-6 && r.mi_p_value <= 0.01 + 1e-12, "{r:?}");
        assert_eq!((r.rows, r.cols), (10, 10));
    }

    #[test]
    fn does_not_reject_an_independent_pair_at_the_five_percent_level() {
        let t = table(uniforms(3).zip(uniforms(4)).take(5000));
        let r = test(&t, 99, 7).unwrap();
        assert!(r.chi2_p_value > 0.05 && r.g_p_value > 0.05 && r.mi_p_value > 0.05, "{r:?}");
        // the permutation null's mean MI is close to the asymptotic (R−1)(C−1)/(2n)
        let asymptotic = r.df / (2.0 * r.n as f64);
        assert!((r.mi_null_mean.unwrap() / asymptotic - 1.0).abs() < 0.25, "{r:?}");
    }
}
