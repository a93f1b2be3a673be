//! Coverage of the 95 % jackknife intervals: 60 independent small datasets of the paper scene
//! against a 200,000-realization reference (`cargo test` keeps this small version; the README
//! gives 100 runs of 1,000).

use stickslip::analysis::accum::Moments;
use stickslip::analysis::{self, SeriesStats};
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::scenario;

fn analysed(dir: &std::path::Path, seed: u64, n: u64) -> analysis::Analysis {
    let mut sc = scenario(&[]);
    (sc.run.seed, sc.run.realizations) = (seed, n);
    simulate::run(&sc.plan().unwrap(), &Options { out: dir.to_owned(), shard: Shard::WHOLE, threads: None }).unwrap();
    analysis::analyze(dir, &analysis::Options::default()).unwrap()
}

#[test]
fn intervals_cover_a_large_sample_reference() {
    let tmp = tempfile::tempdir().unwrap();
    let reference = analysed(&tmp.path().join("ref"), 999_999, 200_000);
    let names = ["T_1", "T_2", "D_1", "H_1", "L_1", "S_T", "stick_fraction"];
    let pick = |a: &analysis::Analysis| -> Vec<SeriesStats> {
        names.iter().map(|n| a.stats.iter().find(|s| s.series.to_string() == *n).unwrap_or_else(|| panic!("{n}")).clone()).collect()
    };
    let truth = pick(&reference);
    let stat: [(&str, fn(&Moments) -> Option<f64>); 4] =
        [("mean", |m| Some(m.mean)), ("variance", Moments::variance), ("skewness", Moments::skewness), ("kurtosis", Moments::kurtosis)];
    let (mut hits, mut total) = ([0usize; 5], [0usize; 5]);
    for run in 0..60 {
        let dir = tmp.path().join(format!("r{run}"));
        let a = analysed(&dir, run + 1, 1000);
        for (s, t) in pick(&a).iter().zip(&truth) {
            for (k, (_, f)) in stat.iter().enumerate() {
                let interval = if stat[k].0 == "kurtosis" { s.kurtosis_interval() } else { s.interval(f) };
                if let (Some((lo, hi)), Some(x)) = (interval, f(&t.moments)) {
                    total[k] += 1;
                    hits[k] += usize::from(lo <= x && x <= hi);
                }
            }
            if let (Some((lo, hi)), Some(x)) = (s.mode_interval(), t.mode) {
                total[4] += 1;
                hits[4] += usize::from(lo <= x && x <= hi);
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
    for (k, name) in stat.iter().map(|s| s.0).chain(["mode"]).enumerate() {
        let coverage = hits[k] as f64 / total[k] as f64;
        // 95 % nominal; 60 runs × 7 series: a binomial standard error of about 0.01, but the runs
        // of one dataset share realizations, so the bound leaves room (the mode, a non-smooth
        // statistic, is the hardest; the plain jackknife of the kurtosis covered 0.75–0.86 and
        // failed this floor before it moved to the log scale, widened)
        let floor = if name == "mode" { 0.8 } else { 0.85 };
        assert!(total[k] >= 400 && coverage >= floor, "{name}: coverage {coverage:.3} over {} intervals", total[k]);
    }
}

#[test]
fn the_convergence_table_ends_at_the_whole_sample_and_narrows_as_one_over_root_n() {
    let tmp = tempfile::tempdir().unwrap();
    let a = analysed(&tmp.path().join("d"), 7, 50_000);
    assert_eq!(a.convergence.len(), 4);
    for c in &a.convergence {
        let whole = a.stats.iter().find(|s| s.series == c.series).unwrap().moments;
        let last = c.points.last().unwrap();
        assert_eq!((last.0, last.1, last.2), (50_000, whole.n, whole.mean), "{}", c.series);
        // realization counts grow geometrically, 10 per decade
        assert!(c.points.windows(2).all(|w| w[1].0 > w[0].0));
        let at = |n: u64| c.points.iter().find(|p| p.0 >= n).unwrap().3.unwrap();
        let ratio = at(500) / last.3.unwrap();
        assert!((5.0..=20.0).contains(&ratio), "{}: se ratio {ratio} for 100x the realizations (1/√N: 10)", c.series);
    }
}
