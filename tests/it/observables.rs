//! The observables home: its value on an in-memory record is what `analyze` reads from the
//! dataset, for every Table 1 quantity (the one censoring rule on both paths).

use stickslip::analysis::{analyze, Options};
use stickslip::observables::Observable;

use crate::common::{outcomes, scenario, stickslip};

#[test]
fn the_record_path_agrees_with_analyze_on_the_same_realizations() {
    let n = 3000;
    let sc = scenario(&[&format!("run.realizations={n}")]);
    let outcomes = outcomes(&sc, n);
    let tmp = tempfile::tempdir().unwrap();
    assert!(stickslip(&["simulate", "--out", "d", "--realizations", &n.to_string(), "-q"], tmp.path()).status.success());
    let a = analyze(&tmp.path().join("d"), &Options::default()).unwrap();
    for q in Observable::table1().into_iter().chain([Observable::Switches, Observable::StickFraction]) {
        let values: Vec<f64> = outcomes.iter().filter_map(|o| q.value(o)).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let m = &a.get(q).unwrap_or_else(|| panic!("analyze has no {q}")).moments;
        assert_eq!(m.n, values.len() as u64, "{q}: realizations with a value");
        assert!((m.mean - mean).abs() <= 1e-12 * mean.abs(), "{q}: analyze {} vs record {mean}", m.mean);
    }
    // the cut stick is censored out of D_k but its time counts in the stick fraction
    let censored = outcomes.iter().filter(|o| o.record.last_truncated && o.record.n_stick() > o.record.n_slip()).count();
    assert!(censored > 100, "the paper scene ends in a stick often ({censored} of {n})");
}

#[test]
fn the_polars_expression_equals_the_record_value_on_every_realization() {
    use polars::prelude::*;
    // a scene with short windows, so that many realizations end in a cut stick or slip, and a
    // few have no stick at all
    let n = 2000;
    let sets = ["run.duration=1.5", "output.switch_times=true"];
    let sc = scenario(&[&format!("run.realizations={n}"), sets[0], sets[1]]);
    let outcomes = outcomes(&sc, n);
    let tmp = tempfile::tempdir().unwrap();
    let args = ["simulate", "--out", "d", "--realizations", &n.to_string(), "--set", sets[0], "--set", sets[1], "-q"];
    assert!(stickslip(&args, tmp.path()).status.success());
    let part = tmp.path().join("d/part-00000-of-00001.parquet");
    let t_a = sc.run.duration;
    // every quantity the home declares, indices past those most realizations reach
    let all = Observable::every(8);
    let exprs: Vec<Expr> = all.iter().map(|q| q.expr(t_a)).collect();
    let df = LazyFrame::scan_parquet(PlRefPath::new(part.to_string_lossy().as_ref()), ScanArgsParquet::default()).unwrap().select(exprs).collect().unwrap();
    assert_eq!(df.height(), n as usize);
    let (mut censored, mut none) = (0, 0);
    for q in &all {
        let column = df.column(&q.name()).unwrap().f64().unwrap().clone();
        for (i, o) in outcomes.iter().enumerate() {
            let (e, v) = (column.get(i), q.value(o));
            let same = match (e, v) {
                (Some(e), Some(v)) => (e - v).abs() <= 1e-12 * v.abs().max(1e-300),
                (None, None) => true,
                _ => false,
            };
            assert!(same, "{q}, realization {i}: expression {e:?}, record {v:?}");
            none += usize::from(v.is_none());
        }
    }
    for o in &outcomes {
        censored += usize::from(o.record.last_truncated);
    }
    assert!(censored > 1000 && none > 1000, "the rule is exercised: {censored} cut, {none} without a value");
}
