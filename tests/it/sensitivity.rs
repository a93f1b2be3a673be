//! `sensitivity`: Sobol indices by pick-freeze, checked against an independent estimate.

use stickslip::sensitivity;
use stickslip::simulation::ensemble::Outcome;

use crate::common::{scenario, stickslip};

const MU: &str = "model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}";
const LAMBDA: &str = "belt.switch_rate={dist = \"uniform\", low = 2, high = 10}";

#[test]
fn the_first_order_index_of_lambda_agrees_with_binning_a_plain_run() {
    // Var(E[S_T | λ]) / Var(S_T) from 200,000 plain realizations (seed 5), λ in 40 bins
    let plain = scenario(&[MU, LAMBDA, "run.seed=5"]);
    let ens = plain.ensemble().unwrap();
    let lambda_col = ens.scene().columns().iter().position(|c| *c == "switch_rate").unwrap();
    let mut out = Outcome::default();
    let (mut bins, mut all) = (vec![(0.0f64, 0u64); 40], Vec::with_capacity(200_000));
    for i in 0..200_000 {
        ens.realization(i, &mut out).unwrap();
        let (lambda, st) = (out.drawn[lambda_col], out.record.n_stick() as f64);
        let b = (((lambda - 2.0) / 8.0 * 40.0) as usize).min(39);
        bins[b].0 += st;
        bins[b].1 += 1;
        all.push(st);
    }
    let n = all.len() as f64;
    let mean = all.iter().sum::<f64>() / n;
    let var = all.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    let between = bins.iter().map(|(s, c)| *c as f64 * (s / *c as f64 - mean).powi(2)).sum::<f64>() / n;
    let binned = between / var;
    // the pick-freeze estimate (seed 1, independent of the plain run) and its interval
    let rows = sensitivity::compute(&scenario(&[MU, LAMBDA]), 100_000).unwrap();
    let r = rows.iter().find(|r| r.parameter == "switch_rate" && r.output.name() == "S_T").unwrap();
    assert!(r.first_order_ci.0 <= binned && binned <= r.first_order_ci.1, "binned {binned} outside {:?} (estimate {})", r.first_order_ci, r.first_order);
    // first order ≤ total, both within [0, 1] up to their noise, for every row
    for r in &rows {
        assert!(r.first_order <= r.total + 0.05 && r.total <= 1.05 && r.first_order >= -0.1, "{r:?}");
    }
}

#[test]
fn the_command_writes_its_table_and_refuses_a_scene_without_random_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["sensitivity", "--out", "s", "--realizations", "300", "--set", MU, "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = stickslip::table::Table::read_parquet(&tmp.path().join("s/sobol.parquet")).unwrap();
    assert_eq!(t.height(), 2 * sensitivity::OUTPUTS.len());
    for c in ["first_order", "first_order_lo", "first_order_hi", "total", "total_lo", "total_hi"] {
        assert!(t.floats(c).is_some(), "{c}");
    }
    assert!(tmp.path().join("s/sobol.png").is_file() && tmp.path().join("s/sobol.md").is_file());
    let o = stickslip(&["sensitivity", "--out", "p", "-q"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("random key"));
    assert!(!tmp.path().join("p").exists());
}
