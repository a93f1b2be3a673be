//! The belt processes beyond the paper's: the multi-level Markov belt (`belt.process =
//! "markov"`) and the recorded belt (`"recorded"`), each against the independent RK4 reference
//! of `reference.rs` (which takes any belt levels, a belt at rest included), their laws, their
//! refusals, and the stages downstream.

use stickslip::scenario::Scenario;

use crate::common::{check_invariants, outcomes, scenario, stickslip};
use crate::reference::{compare, Params, PAPER};

/// A table that stops between the directions (the example scene `markov_belt.toml`).
const STOPPING: [&str; 3] = ["belt.process=\"markov\"", "belt.velocities=[1.0, 0.0, -1.0]", "belt.rates=[[0, 2, 0], [1, 0, 1], [0, 4, 0]]"];

fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(extra).copied().collect()
}

#[test]
fn exact_solver_on_a_markov_belt_agrees_with_the_reference() {
    compare(&STOPPING, &PAPER, 24);
    // with a dashpot, μ_s > μ_k and viscous friction; four levels of one sign and a fast chain
    compare(
        &with(&STOPPING, &["model.damping=0.5", "model.static_friction_coefficient=0.6", "model.viscous_friction=0.3"]),
        &Params { c: 0.5, fs: 0.6 * 9.8, cv: 0.3, ..PAPER },
        24,
    );
    compare(
        &["belt.process=\"markov\"", "belt.velocities=[0.2, 0.5, 1.0, 2.0]", "belt.rates=[[0, 3, 0, 0], [1, 0, 3, 0], [0, 1, 0, 3], [20, 0, 0, 0]]"],
        &PAPER,
        24,
    );
}

#[test]
fn a_markov_belt_starts_in_its_stationary_law_and_changes_at_its_rates() {
    // the initial level of 20,000 realizations against π = (2, 4, 1)/7, and the mean number of
    // changes in 10 s against the stationary flux Σ_i π_i q_i t_a = (2·2 + 4·2 + 1·4)/7 · 10
    let sc = scenario(&with(&STOPPING, &["run.realizations=20000"]));
    let ens = sc.ensemble().unwrap();
    let mut o = stickslip::simulation::ensemble::Outcome::default();
    let (mut counts, mut changes) = ([0u64; 3], 0.0);
    let n = 20_000;
    for i in 0..n {
        ens.realization(i, &mut o).unwrap();
        counts[[1.0, 0.0, -1.0].iter().position(|v| *v == o.belt.initial_velocity).unwrap()] += 1;
        changes += o.belt.switch_times.len() as f64;
    }
    for (c, p) in counts.iter().zip([2.0 / 7.0, 4.0 / 7.0, 1.0 / 7.0]) {
        let f = *c as f64 / n as f64;
        assert!((f - p).abs() < 5.0 * (p * (1.0 - p) / n as f64).sqrt(), "initial level share {f} vs {p}");
    }
    let mean = changes / n as f64;
    // the count of changes in 10 s has a standard deviation below 6: 5 standard errors < 0.2
    assert!((mean - 160.0 / 7.0).abs() < 0.2, "mean changes {mean} vs {}", 160.0 / 7.0);
}

#[test]
fn a_stick_on_a_belt_at_rest_lasts_until_the_belt_moves() {
    // a belt at rest throughout the stick: the holding force k x stays inside μ_s n, so every
    // stick entered at rest ends at a change of the belt, never by breakaway
    let sc = scenario(&STOPPING);
    let mut at_rest = 0;
    for o in outcomes(&sc, 200) {
        check_invariants(&sc, &o, true).unwrap();
        let r = &o.record;
        for (k, v) in r.stick_entry_velocity.iter().enumerate() {
            if *v == 0.0 {
                at_rest += 1;
                let end = r.stick_start[k] + r.stick_duration[k];
                let at_change = o.switches().iter().any(|t| (t - end).abs() < 1e-12) || (end - 10.0).abs() < 1e-12;
                assert!(
                    at_change && r.stick_end[k] != stickslip::simulation::events::StickEnd::Breakaway,
                    "a stick at rest ended at {end} by {:?}",
                    r.stick_end[k]
                );
            }
        }
    }
    assert!(at_rest > 100, "{at_rest} sticks at rest");
}

fn log(dir: &std::path::Path, rows: &[(f64, f64)]) -> std::path::PathBuf {
    let path = dir.join("log.csv");
    let text: String = std::iter::once("time,velocity\n".to_string()).chain(rows.iter().map(|(t, v)| format!("{t},{v}\n"))).collect();
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn exact_solver_on_a_recorded_belt_agrees_with_the_reference() {
    let tmp = tempfile::tempdir().unwrap();
    let rows = [(0.0, 1.0), (0.7, 0.0), (1.5, -0.6), (2.2, 0.4), (3.0, 0.0), (3.3, 1.5), (5.0, -1.0), (6.2, 0.8), (8.0, 0.0), (8.5, 2.0), (12.0, -2.0)];
    let path = log(tmp.path(), &rows);
    let file = format!("belt.file={:?}", path.display().to_string());
    compare(&["belt.process=\"recorded\"", &file], &PAPER, 24);
    // the belt is the record: every realization sees the changes inside the window, the last
    // row (at 12 s) is past t_a = 10 s
    let sc = scenario(&["belt.process=\"recorded\"", &file]);
    for o in outcomes(&sc, 5) {
        assert_eq!(o.switches(), &[0.7, 1.5, 2.2, 3.0, 3.3, 5.0, 6.2, 8.0, 8.5]);
        assert_eq!(o.velocities(), &[1.0, 0.0, -0.6, 0.4, 0.0, 1.5, -1.0, 0.8, 0.0, 2.0]);
    }
}

#[test]
fn a_parquet_log_gives_the_same_rows_as_the_csv_log() {
    let tmp = tempfile::tempdir().unwrap();
    let rows = [(0.0, 1.0), (2.0, -0.5), (4.5, 0.0), (6.0, 1.0)];
    let csv = log(tmp.path(), &rows);
    // the Parquet log written with the simulator's own arrow/parquet stack
    let parquet = tmp.path().join("log.parquet");
    {
        use std::sync::Arc;
        let schema = Arc::new(arrow_schema::Schema::new(vec![
            arrow_schema::Field::new("time", arrow_schema::DataType::Float64, false),
            arrow_schema::Field::new("velocity", arrow_schema::DataType::Float64, false),
        ]));
        let cols: Vec<arrow_array::ArrayRef> = vec![
            Arc::new(arrow_array::Float64Array::from(rows.iter().map(|r| r.0).collect::<Vec<_>>())),
            Arc::new(arrow_array::Float64Array::from(rows.iter().map(|r| r.1).collect::<Vec<_>>())),
        ];
        let batch = arrow_array::RecordBatch::try_new(schema.clone(), cols).unwrap();
        let mut w = parquet::arrow::ArrowWriter::try_new(std::fs::File::create(&parquet).unwrap(), schema, None).unwrap();
        w.write(&batch).unwrap();
        w.close().unwrap();
    }
    let run = |p: &std::path::Path| {
        let sc = scenario(&["belt.process=\"recorded\"", &format!("belt.file={:?}", p.display().to_string())]);
        outcomes(&sc, 20).into_iter().map(|o| (o.record.stick_start, o.record.slip_start)).collect::<Vec<_>>()
    };
    assert_eq!(run(&csv), run(&parquet));
}

#[test]
fn bad_belts_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let file = |rows: &str| {
        let p = tmp.path().join(format!("l{}.csv", rows.len()));
        std::fs::write(&p, rows).unwrap();
        format!("belt.file={:?}", p.display().to_string())
    };
    let recorded = "belt.process=\"recorded\"";
    let cases: Vec<(Vec<String>, &str, &str)> = vec![
        (vec!["belt.process=\"markov\"".into(), "belt.velocities=[1, -1]".into()], "belt.rates", "needs"),
        (vec!["belt.process=\"markov\"".into(), "belt.velocities=[1, -1]".into(), "belt.rates=[[0, 1]]".into()], "belt.rates", "2×2"),
        (
            vec!["belt.process=\"markov\"".into(), "belt.velocities=[1, 0, -1]".into(), "belt.rates=[[0, 0, 0], [1, 0, 1], [0, 0, 0]]".into()],
            "belt.rates",
            "two closed classes",
        ),
        (vec!["belt.process=\"markov\"".into(), "belt.velocities=[0, 0]".into(), "belt.rates=[[0, 1], [1, 0]]".into()], "belt.velocities", "nonzero"),
        (vec!["belt.process=\"markov\"".into(), "belt.velocities=[1, -1]".into(), "belt.rates=[[0, 1e7], [1, 0]]".into()], "belt.rates", "at most"),
        (vec![STOPPING[0].into(), STOPPING[1].into(), STOPPING[2].into(), "belt.speed=2".into()], "belt.speed", "only belt.process"),
        (vec![STOPPING[0].into(), STOPPING[1].into(), STOPPING[2].into(), "belt.initial_sign=\"random\"".into()], "belt.initial_sign", "only"),
        (vec!["belt.velocities=[1, -1]".into()], "belt.velocities", "only belt.process = \"markov\""),
        (vec!["belt.process=\"telegraph\"".into()], "belt.reverse_speed", "needs"),
        (vec![recorded.into()], "belt.file", "needs belt.file"),
        (vec![recorded.into(), "belt.file=\"/nonexistent/log.csv\"".into()], "belt.file", "cannot read"),
        (vec![recorded.into(), file("t,v\n0,1\n")], "belt.file", "no column `time`"),
        (vec![recorded.into(), file("time,velocity\n0.5,1\n")], "belt.file", "first time must be 0"),
        (vec![recorded.into(), file("time,velocity\n0,1\n2,1\n1,0\n")], "belt.file", "row 3"),
        (vec![recorded.into(), file("time,velocity\n0,1\n1,x\n")], "belt.file", "line 3"),
        (vec![recorded.into(), file("time,velocity\n0,0\n20,1\n")], "belt.file", "nonzero"),
        (vec!["belt.process=\"brownian\"".into()], "belt.process", ""),
    ];
    for (sets, key, words) in cases {
        let err = Scenario::resolve(None, &sets).expect_err(&format!("{sets:?} must be refused")).to_string();
        assert!(err.contains(key) && err.contains(words) && !err.contains('\n'), "{sets:?}: {err}");
    }
}

#[test]
fn markov_and_recorded_belts_run_through_every_stage() {
    // simulate → analyze → figures → report on the two example scenes, and tradeoff on one:
    // each stage exits 0; the tails' conditional estimator is refused with its reason
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    for scene in ["markov_belt", "recorded_belt"] {
        let path = root.join(format!("pipelines/scenes/{scene}.toml"));
        let data = tmp.path().join(scene);
        let d = data.to_str().unwrap();
        let run = |args: &[&str]| {
            let out = stickslip(args, root);
            assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
            // (what it prints, notes on stderr included)
            format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
        };
        run(&["simulate", path.to_str().unwrap(), "--out", &format!("{d}/dataset"), "--realizations", "2000", "--set", "output.switch_times=true"]);
        let printed = run(&["analyze", &format!("{d}/dataset"), "--out", &format!("{d}/analysis")]);
        assert!(printed.contains("S_T"), "{printed}");
        run(&["figures", &format!("{d}/analysis"), "--out", &format!("{d}/figures")]);
        run(&["report", &format!("{d}/dataset"), &format!("{d}/analysis"), &format!("{d}/figures"), "--out", &format!("{d}/report.html")]);
        assert!(printed.contains("not a two-state flip process"), "{scene}: the conditional estimator's refusal is said: {printed}");
    }
    let out = stickslip(
        &[
            "tradeoff",
            root.join("pipelines/scenes/markov_belt.toml").to_str().unwrap(),
            "--out",
            tmp.path().join("tradeoff").to_str().unwrap(),
            "--realizations",
            "20",
        ],
        root,
    );
    assert!(out.status.success(), "tradeoff: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn markov_and_recorded_belts_at_the_extremes() {
    // levels at both ends of the speed range and at rest, rates at 1e4 /s (1e5 changes in 10 s),
    // through exact and rk45; a record of 20,000 rows alternating between 1e6 and -1e-9 m/s
    let rk45 = ["run.solver=\"rk45\"", "numerics.rtol=1e-6", "numerics.atol=1e-6", "numerics.max_step=10", "numerics.step_budget=100000000"];
    let chain = ["belt.process=\"markov\"", "belt.velocities=[1e6, 0, -1e-9]", "belt.rates=[[0, 1e4, 0], [1e4, 0, 1e4], [0, 1e4, 0]]"];
    let tmp = tempfile::tempdir().unwrap();
    let rows: Vec<(f64, f64)> = (0..20_000).map(|i| (i as f64 * 5e-4, if i % 2 == 0 { 1e6 } else { -1e-9 })).collect();
    let record = ["belt.process=\"recorded\"".to_string(), format!("belt.file={:?}", log(tmp.path(), &rows).display().to_string())];
    let record: Vec<&str> = record.iter().map(String::as_str).collect();
    for base in [&chain[..], &record[..]] {
        for solver in [&[][..], &rk45[..]] {
            let sc = scenario(&with(base, solver));
            for o in outcomes(&sc, 2) {
                check_invariants(&sc, &o, false).unwrap_or_else(|e| panic!("{base:?} {solver:?}: {e}"));
            }
        }
    }
}
