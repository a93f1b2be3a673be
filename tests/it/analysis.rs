//! The analysis stage: moments against independent computations, histogram identities,
//! independence tests, the paper's Table 1, bad input.

use std::path::Path;

use polars::prelude::*;
use stickslip::analysis::{self, output, Options};
use stickslip::observables::Observable;
use stickslip::simulation::dataset::{Layout, PartWriter, Rows};
use stickslip::simulation::ensemble::Outcome;
use stickslip::simulation::simulate::{self, provenance, Shard};

use crate::common::{outcomes, scenario, stickslip};

fn read(path: &Path) -> DataFrame {
    ParquetReader::new(std::fs::File::open(path).unwrap()).finish().unwrap()
}

fn simulate_into(dir: &Path, sets: &[&str]) {
    let opts = simulate::Options { out: dir.to_owned(), shard: Shard::WHOLE, threads: Some(2) };
    simulate::run(&scenario(sets).plan().unwrap(), &opts).unwrap();
}

/// Population skewness / Pearson kurtosis and unbiased variance, two-pass.
fn direct(x: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let c = |p: i32| x.iter().map(|v| (v - m).powi(p)).sum::<f64>() / n;
    (m, c(2) * n / (n - 1.0), c(3) / c(2).powf(1.5), c(4) / (c(2) * c(2)))
}

fn row(df: &DataFrame, var: &str, index: Option<i64>) -> usize {
    let v = df.column("variable").unwrap().str().unwrap();
    let i = df.column("index").unwrap().i64().unwrap();
    (0..df.height()).find(|&r| v.get(r) == Some(var) && i.get(r) == index).unwrap_or_else(|| panic!("{var} {index:?}"))
}

fn get(df: &DataFrame, col: &str, r: usize) -> f64 {
    df.column(col).unwrap().f64().unwrap().get(r).unwrap()
}

#[test]
fn moments_match_a_direct_computation_including_truncation() {
    let tmp = tempfile::tempdir().unwrap();
    let sets = ["run.realizations=4000", "run.seed=3", "run.duration=3"];
    simulate_into(&tmp.path().join("d"), &sets);
    let a = analysis::analyze(&tmp.path().join("d"), &Options::default()).unwrap();
    output::write(&a, &tmp.path().join("a")).unwrap();
    let m = read(&tmp.path().join("a/moments.parquet"));
    let lib = outcomes(&scenario(&sets), 4000);
    for (var, k) in [("T", 1usize), ("T", 4), ("L", 2), ("D", 1), ("D", 3), ("H", 2)] {
        let mut truncated = 0;
        let x: Vec<f64> = lib
            .iter()
            .filter_map(|o| {
                let r = &o.record;
                // (values, whether the last interval of the realization is of this kind)
                let (list, last_is_this) = match var {
                    "T" => (&r.stick_start, false),
                    "L" => (&r.slip_start, false),
                    "D" => (&r.stick_duration, r.stick_start.len() > r.slip_start.len()),
                    _ => (&r.slip_duration, r.stick_start.len() == r.slip_start.len()),
                };
                let v = *list.get(k - 1)?;
                if last_is_this && list.len() == k && r.last_truncated {
                    truncated += 1;
                    return None;
                }
                Some(v)
            })
            .collect();
        let (mean, var_u, skew, kurt) = direct(&x);
        let r = row(&m, var, Some(k as i64));
        let n = m.column("n").unwrap().i64().unwrap().get(r).unwrap();
        assert_eq!(n as usize, x.len(), "{var}_{k}");
        let cut = m.column("n_truncated_excluded").unwrap().i64().unwrap().get(r).unwrap();
        assert_eq!(cut, truncated, "{var}_{k}");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-10 * b.abs().max(1.0);
        assert!(close(get(&m, "mean", r), mean), "{var}_{k} mean");
        assert!(close(get(&m, "variance", r), var_u), "{var}_{k} variance");
        assert!(close(get(&m, "skewness", r), skew), "{var}_{k} skewness");
        assert!(close(get(&m, "kurtosis", r), kurt), "{var}_{k} kurtosis");
        assert!(close(get(&m, "mean_se", r), (var_u / x.len() as f64).sqrt()));
    }
    assert!(a.stats.iter().any(|s| s.truncated > 0), "the short window truncates some intervals");
}

/// A dataset whose stick starts T_1 are the n quantiles of Exp(1) and T_2 = T_1 + 1.
fn exponential_dataset(dir: &Path, n: usize) -> Vec<f64> {
    // a horizon that holds every value of the sample (quantiles of Exp(1) reach ln(2n) ≈ 10.6)
    let sc = scenario(&[&format!("run.realizations={n}"), "run.duration=100"]);
    let mut w = PartWriter::create(dir, 0, 1, Layout::default(), provenance(&sc.plan().unwrap(), Shard::WHOLE)).unwrap();
    let mut rows = Rows::new((false, false), 0, 0, 0);
    let mut x = Vec::new();
    for i in 0..n {
        let t1 = -(1.0 - (i as f64 + 0.5) / n as f64).ln();
        x.push(t1);
        let mut o = Outcome::default();
        o.belt.initial_velocity = 1.0;
        (o.speed_scale, o.t_a) = (1.0, 100.0);
        let r = &mut o.record;
        (r.min_velocity, r.max_velocity) = (-1.0, 1.0);
        r.stick_start.extend([t1, t1 + 1.0]);
        r.stick_duration.extend([0.5, 0.25]);
        r.stick_end.extend([stickslip::simulation::events::StickEnd::Flip, stickslip::simulation::events::StickEnd::Horizon]);
        r.stick_entry_position.extend([0.0, 0.1]);
        r.stick_entry_velocity.extend([1.0, -1.0]);
        r.slip_start.push(t1 + 0.5);
        r.slip_duration.push(0.5);
        r.last_truncated = true;
        rows.push(i as u64, &o);
    }
    w.write(rows).unwrap();
    w.commit().unwrap();
    x
}

#[test]
fn exponential_sample_has_skewness_two_and_kurtosis_nine() {
    let tmp = tempfile::tempdir().unwrap();
    let x = exponential_dataset(tmp.path(), 20_000);
    let a = analysis::analyze(tmp.path(), &Options::default()).unwrap();
    let s = a.get("T1".parse().unwrap()).unwrap();
    let (mean, var, skew, kurt) = direct(&x);
    assert!((s.moments.mean - mean).abs() < 1e-12 && (s.moments.variance().unwrap() - var).abs() < 1e-12);
    // quantile grid of Exp(1): moments within the grid's tail truncation of 1, 1, 2, 9
    assert!((mean - 1.0).abs() < 1e-3 && (var - 1.0).abs() < 0.01);
    assert!((s.moments.skewness().unwrap() - 2.0).abs() < 0.05, "{:?}", s.moments.skewness());
    assert!((s.moments.kurtosis().unwrap() - 9.0).abs() < 0.5, "{:?}", s.moments.kurtosis());
    assert!((s.moments.skewness().unwrap() - skew).abs() < 1e-10 && (s.moments.kurtosis().unwrap() - kurt).abs() < 1e-9);
    // the KDE mode of an exponential sample sits at 0
    assert!(s.mode.unwrap() < 0.05, "mode {:?}", s.mode);
    // the truncated last stick (D_2) is excluded: none of the 20,000 counted
    let d2 = a.get("D2".parse().unwrap()).unwrap();
    assert_eq!((d2.moments.n, d2.truncated), (0, 20_000));
}

#[test]
fn histograms_integrate_to_one_and_joint_marginals_match() {
    let tmp = tempfile::tempdir().unwrap();
    simulate_into(&tmp.path().join("d"), &["run.realizations=3000", "output.switch_times=true"]);
    let a = analysis::analyze(&tmp.path().join("d"), &Options::default()).unwrap();
    output::write(&a, &tmp.path().join("a")).unwrap();
    let h = read(&tmp.path().join("a/histograms.parquet"));
    let (var, idx) = (h.column("variable").unwrap().str().unwrap(), h.column("index").unwrap().i64().unwrap());
    let mut integrals: std::collections::BTreeMap<(String, Option<i64>), f64> = Default::default();
    for r in 0..h.height() {
        let width = get(&h, "hi", r) - get(&h, "lo", r);
        *integrals.entry((var.get(r).unwrap().to_string(), idx.get(r))).or_default() += get(&h, "density", r) * width;
    }
    assert!(integrals.contains_key(&("Y".to_string(), Some(6))), "Y_k histograms with switch times");
    assert!(integrals.contains_key(&("Q".to_string(), None)));
    for (key, integral) in &integrals {
        assert!((integral - 1.0).abs() < 1e-12, "{key:?} integrates to {integral}");
    }
    // joint histogram marginals = 1-D histograms on the same bins (every T_2 has a T_1, every
    // counted D_2 a counted D_1), and the product of marginals integrates to 1
    for j in &a.joints {
        let second = a.get(j.pair.1).unwrap();
        let cols: Vec<u64> = (0..j.y.bins()).map(|c| j.counts.iter().map(|r| r[c]).sum()).collect();
        assert_eq!(cols, second.histogram.counts, "{} marginal", j.pair.1);
        assert_eq!(j.y, second.histogram);
    }
    let jt = read(&tmp.path().join("a/joint_histograms.parquet"));
    let area = |r: usize| (get(&jt, "x_hi", r) - get(&jt, "x_lo", r)) * (get(&jt, "y_hi", r) - get(&jt, "y_lo", r));
    let x = jt.column("x").unwrap().str().unwrap();
    for pair in ["T_1", "D_1"] {
        let rows: Vec<usize> = (0..jt.height()).filter(|&r| x.get(r) == Some(pair)).collect();
        let total: f64 = rows.iter().map(|&r| get(&jt, "density", r) * area(r)).sum();
        let prod: f64 = rows.iter().map(|&r| get(&jt, "product_density", r) * area(r)).sum();
        assert!((total - 1.0).abs() < 1e-12 && (prod - 1.0).abs() < 1e-12, "{pair}: {total} {prod}");
    }
}

#[test]
fn paper_table_1_is_reproduced_within_the_stated_tolerances() {
    // 5,000 realizations (the README reproduction runs the paper's 18,000): means of T_k, L_k, D_k,
    // H_k within 10 % of Table 1, variances within 15 %, E[S_T] within 3 % of 16.71.
    let tmp = tempfile::tempdir().unwrap();
    simulate_into(tmp.path(), &["run.realizations=5000"]);
    let a = analysis::analyze(tmp.path(), &Options::default()).unwrap();
    for &(o, p) in analysis::paper::TABLE1 {
        let s = a.get(o).unwrap();
        let (mean, variance) = (s.moments.mean, s.moments.variance().unwrap());
        assert!((mean / p[0] - 1.0).abs() < 0.10, "{}: mean {mean:.3} vs paper {}", s.series, p[0]);
        assert!((variance / p[1] - 1.0).abs() < 0.15, "{}: variance {variance:.3} vs paper {}", s.series, p[1]);
    }
    let st = a.get(Observable::Sticks).unwrap();
    assert!((st.moments.mean / 16.71 - 1.0).abs() < 0.03, "E[S_T] = {}", st.moments.mean);
    // the paper's Fig. 7: Var T_k linear in k
    let var_t = a.growth.iter().find(|g| g.family == Observable::StickStart(1) && g.statistic == "variance").unwrap();
    assert!(var_t.line.r2 > 0.99, "R² = {}", var_t.line.r2);
    // renewal check within 3 %
    let r = a.renewal.as_ref().unwrap();
    assert!((r.predicted_mean / r.measured_mean - 1.0).abs() < 0.03);
    assert!((r.predicted_variance / r.measured_variance - 1.0).abs() < 0.15);
}

/// Simulate `realizations` whole and as `shards` shards, analyse both, and require equal
/// `tables`.
fn whole_and_sharded_agree(realizations: u64, shards: u64, tables: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let set = format!("run.realizations={realizations}");
    let sc = scenario(&[set.as_str()]);
    for (dir, shards) in [("whole", 1u64), ("sharded", shards)] {
        for i in 0..shards {
            let opts = simulate::Options { out: tmp.path().join(dir), shard: Shard { index: i, count: shards }, threads: Some(1) };
            simulate::run(&sc.plan().unwrap(), &opts).unwrap();
        }
        let a = analysis::analyze(&tmp.path().join(dir), &Options::default()).unwrap();
        output::write(&a, &tmp.path().join(format!("{dir}-a"))).unwrap();
    }
    for table in tables {
        let one = read(&tmp.path().join(format!("whole-a/{table}.parquet")));
        let many = read(&tmp.path().join(format!("sharded-a/{table}.parquet")));
        assert!(one.equals_missing(&many), "{table} differs between the whole and the sharded run ({realizations} realizations)");
    }
}

#[test]
fn sharded_and_unsharded_datasets_give_identical_tables() {
    // (the tails' counts are made per batch of rows, and summed over the batches)
    whole_and_sharded_agree(2500, 4, &["moments", "histograms", "joint_histograms", "independence", "growth", "survival", "tails"]);
}

#[test]
fn the_tails_counted_in_dense_arrays_and_in_the_map_agree() {
    // The tails' keys of a batch are counted in dense arrays when the batch has at least a
    // quarter as many keys as the array has cells, in a map otherwise (`tail_counts::Space`).
    // 40,000 paper realizations are one row group, which polars hands over in batches of about
    // 20,000 rows: 3.3·10^5 durations each, dense on the fine cells (1.05·10^6 cells). Eight
    // shards of 5,000 give batches of at most 5,000 rows: 8·10^4 durations, counted in the map.
    whole_and_sharded_agree(40_000, 8, &["survival", "tails"]);
}

#[test]
fn bad_datasets_name_the_file_and_leave_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    simulate_into(&tmp.path().join("good"), &["run.realizations=300"]);
    let part = tmp.path().join("good/part-00000-of-00001.parquet");
    let bytes = std::fs::read(&part).unwrap();
    let make = |name: &str, content: &[u8]| {
        let dir = tmp.path().join(name);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("part-00000-of-00001.parquet"), content).unwrap();
    };
    make("truncated", &bytes[..bytes.len() / 2]);
    make("garbage", b"this is not parquet at all");
    // a valid Parquet file with the wrong columns
    let wrong = tmp.path().join("wrong");
    std::fs::create_dir_all(&wrong).unwrap();
    let mut df = df!("realization" => [1i64, 2], "x0" => [0.1, 0.2]).unwrap();
    ParquetWriter::new(std::fs::File::create(wrong.join("part-00000-of-00001.parquet")).unwrap()).finish(&mut df).unwrap();
    std::fs::create_dir_all(tmp.path().join("empty")).unwrap();
    for (dir, culprit) in [
        ("truncated", "part-00000-of-00001.parquet"),
        ("garbage", "part-00000-of-00001.parquet"),
        ("wrong", "part-00000-of-00001.parquet"),
        ("empty", "empty"),
        ("missing", "missing"),
    ] {
        let out = format!("{dir}-analysis");
        let o = stickslip(&["analyze", dir, "--out", &out], tmp.path());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{dir}");
        assert!(err.contains(culprit) && err.contains(dir), "{dir}: {err}");
        assert!(!tmp.path().join(&out).exists(), "{dir}: output left behind");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn count_modes_and_their_intervals_are_integers() {
    // issue 20, item 19: a count's mode is a most frequent integer, and so are its interval's ends
    let tmp = tempfile::tempdir().unwrap();
    let o = crate::common::stickslip(&["simulate", "--out", "d", "--realizations", "3000", "-q"], tmp.path());
    assert!(o.status.success());
    let a = analysis::analyze(&tmp.path().join("d"), &Options::default()).unwrap();
    for (name, o) in [("S_T", Observable::Sticks), ("S_L", Observable::Slips)] {
        let s = a.get(o).unwrap();
        let (lo, hi) = s.mode_interval().expect("an interval");
        let mode = s.mode.unwrap();
        assert!([mode, lo, hi].iter().all(|x| x.fract() == 0.0) && lo <= mode && mode <= hi, "{name}: {mode} [{lo} – {hi}]");
    }
}

#[test]
fn the_tables_are_the_same_bytes_for_any_thread_count_and_morsel_size() {
    // polars sums in whatever order its threads meet the rows; the analysis' sums are exact
    // (integers), so its tables must not change in a single bit
    let tmp = tempfile::tempdir().unwrap();
    simulate_into(&tmp.path().join("d"), &["run.realizations=4000"]);
    let run = |out: &str, env: &[(&str, &str)]| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"));
        cmd.args(["analyze", "d", "--out", out, "-q"]).current_dir(tmp.path());
        for (k, v) in env {
            cmd.env(k, v);
        }
        assert!(cmd.status().unwrap().success(), "{out}");
    };
    run("a", &[]);
    run("b", &[("POLARS_MAX_THREADS", "1"), ("RAYON_NUM_THREADS", "1"), ("POLARS_IDEAL_MORSEL_SIZE", "300")]);
    run("c", &[("POLARS_IDEAL_MORSEL_SIZE", "777")]);
    // (the tails' counts are made per batch of rows, and summed over the batches)
    for table in ["moments", "histograms", "joint_histograms", "independence", "growth", "convergence", "survival", "tails"] {
        let a = std::fs::read(tmp.path().join(format!("a/{table}.parquet"))).unwrap();
        for other in ["b", "c"] {
            assert!(a == std::fs::read(tmp.path().join(format!("{other}/{table}.parquet"))).unwrap(), "{table}: {other} differs");
        }
    }
}

#[test]
fn observables_split_over_several_queries_give_the_same_tables() {
    // `--max-index 70` analyses 354 observables, in several queries over the same rows (one does
    // the row counts, rules, pairs and convergence): the rows for k ≤ 6 must be those of the
    // default analysis, bit for bit
    let tmp = tempfile::tempdir().unwrap();
    simulate_into(&tmp.path().join("d"), &["run.realizations=2000"]);
    for (out, k) in [("a", "6"), ("b", "70")] {
        assert!(stickslip(&["analyze", "d", "--out", out, "--max-index", k, "-q"], tmp.path()).status.success(), "{out}");
    }
    let small = read(&tmp.path().join("a/moments.parquet"));
    let large = read(&tmp.path().join("b/moments.parquet"));
    let kept = large.lazy().filter(col("index").is_null().or(col("index").lt_eq(lit(6)))).collect().unwrap();
    assert_eq!(kept.height(), small.height());
    assert!(kept.equals_missing(&small), "moments of k <= 6 differ when more observables are analysed");
    for table in ["convergence", "joint_histograms", "independence"] {
        let (a, b) = (read(&tmp.path().join(format!("a/{table}.parquet"))), read(&tmp.path().join(format!("b/{table}.parquet"))));
        assert!(a.equals_missing(&b), "{table} differs");
    }
}

#[test]
fn every_row_says_how_many_realizations_reach_it_and_growth_fits_only_what_most_reach() {
    // issue 22, item 5: lower friction (μ = 0.2) gives fewer sticks; T_5, T_6 are reached by
    // fewer realizations, and a slope through them would describe those few (at μ = 0.1 no index
    // past 1 is reached by 90 %: no fit at all)
    let set = "model.friction_coefficient=0.2";
    let n = 3000;
    let sc = scenario(&[&format!("run.realizations={n}"), set]);
    let outcomes = outcomes(&sc, n);
    let tmp = tempfile::tempdir().unwrap();
    let args = ["simulate", "--out", "d", "--realizations", &n.to_string(), "--set", set, "-q"];
    assert!(stickslip(&args, tmp.path()).status.success());
    let a = analysis::analyze(&tmp.path().join("d"), &Options::default()).unwrap();
    let mut k_max = 0;
    for k in 1..=6u32 {
        // counted directly: realizations with at least k sticks (slips)
        let sticks = outcomes.iter().filter(|o| o.record.n_stick() >= k as usize).count() as u64;
        let slips = outcomes.iter().filter(|o| o.record.n_slip() >= k as usize).count() as u64;
        for (o, direct) in [(Observable::StickStart(k), sticks), (Observable::StickDuration(k), sticks), (Observable::SlipStart(k), slips)] {
            assert_eq!(a.get(o).unwrap().reached, direct, "{o}");
        }
        if sticks as f64 >= 0.9 * n as f64 {
            k_max = k;
        }
    }
    assert!((2..6).contains(&k_max), "the scene must leave T_6 to fewer realizations (k_max {k_max})");
    let fit = a.growth.iter().find(|g| g.family == Observable::StickStart(1) && g.statistic == "variance").unwrap();
    assert_eq!((fit.k_max, fit.line.points as u32), (k_max, k_max), "only the indices 90 % reach are fitted");
}
