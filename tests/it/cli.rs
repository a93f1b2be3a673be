//! The command line end to end, and bad input: one clear message, non-zero exit, nothing left.

use crate::common::stickslip;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Everything below `dir`, relative, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(dir).unwrap().display().to_string());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn simulate_writes_a_dataset_and_reports() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["simulate", "--out", "data/paper", "--realizations", "200", "--threads", "2"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("mean S_T"), "{}", stderr(&o));
    assert_eq!(listing(tmp.path()), ["data", "data/paper", "data/paper/.stickslip-dataset", "data/paper/part-00000-of-00001.parquet"]);
    // a second run replaces the part atomically
    let o = stickslip(&["simulate", "--out", "data/paper", "--realizations", "100", "--quiet"], tmp.path());
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
}

#[test]
fn a_scene_left_at_the_slow_default_numerics_gets_a_note() {
    // `auto` on a Stribeck scene without [numerics]: rk45 at the paper's ode45 settings, said
    let tmp = tempfile::tempdir().unwrap();
    let stribeck = ["--set", "model.friction_law=\"stribeck\"", "--set", "model.stribeck_velocity=0.1", "--set", "model.static_friction_coefficient=0.6"];
    let mut args = vec!["simulate", "--out", "a", "--realizations", "20"];
    args.extend(stribeck);
    let o = stickslip(&args, tmp.path());
    assert!(o.status.success() && stderr(&o).contains("note: this scene has no closed form") && stderr(&o).contains("tradeoff"), "{}", stderr(&o));
    // not with -q, not with numerics chosen (the shipped scene), not where auto is exact
    args.push("-q");
    let o = stickslip(&args, tmp.path());
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("pipelines/stribeck.toml");
    let o = stickslip(&["simulate", scene.to_str().unwrap(), "--out", "b", "--realizations", "20"], tmp.path());
    assert!(o.status.success() && !stderr(&o).contains("note:"), "{}", stderr(&o));
    let o = stickslip(&["simulate", "--out", "c", "--realizations", "20"], tmp.path());
    assert!(o.status.success() && !stderr(&o).contains("note:"), "{}", stderr(&o));
}

#[test]
fn a_scenario_file_and_set_overrides_are_applied() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), "[belt]\nswitch_rate = 0.0\n[run]\nrealizations = 50\n").unwrap();
    let o = stickslip(&["simulate", "s.toml", "--out", "d", "--set", "model.stiffness=0", "--quiet"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let df = crate::dataset::read_dir(&tmp.path().join("d"));
    assert_eq!(df.height(), 50);
    // k = 0, constant belt: exactly one stick each, never a slip after it
    let n_slip = df.column("n_slip").unwrap().i64().unwrap();
    assert!(n_slip.into_no_null_iter().all(|n| n == 0));
}

#[test]
fn bad_input_names_the_culprit_and_leaves_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("typo.toml"), "[model]\nmas = 1.0\n").unwrap();
    std::fs::write(tmp.path().join("broken.toml"), "[model\nmass = 1.0\n").unwrap();
    std::fs::write(tmp.path().join("a_file"), "").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["simulate", "typo.toml", "--out", "o"], "model.mas"),
        (&["simulate", "broken.toml", "--out", "o"], "broken.toml"),
        (&["simulate", "missing.toml", "--out", "o"], "missing.toml"),
        (&["simulate", "--out", "o", "--set", "model.mass=-1"], "model.mass"),
        (&["simulate", "--out", "o", "--set", "belt.speed=inf"], "belt.speed"),
        (&["simulate", "--out", "o", "--set", "model.stiffness=nan"], "model.stiffness"),
        (&["simulate", "--out", "o", "--set", "belt.initial_sign=2"], "belt.initial_sign"),
        (&["simulate", "--out", "o", "--set", "initial_conditions.position=[1, -1]"], "initial_conditions.position"),
        (&["simulate", "--out", "o", "--set", "run.solver=ode45"], "run.solver"),
        (&["simulate", "--out", "o", "--set", "belt.switch_rate=1e9"], "belt.switch_rate"),
        (&["simulate", "--out", "o", "--set", "nokey"], "nokey"),
        (&["simulate", "--out", "o", "--realizations", "0"], "run.realizations"),
        (&["simulate", "--out", "o", "--shard", "3/3"], "--shard"),
        (&["simulate", "--out", "o", "--threads", "0"], "--threads"),
        (&["simulate", "--out", "a_file/sub"], "a_file/sub"),
        (&["simulate", "--out", "a_file"], "a_file"),
    ];
    let before = listing(tmp.path());
    for (args, culprit) in cases {
        let o = stickslip(args, tmp.path());
        let err = stderr(&o);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(err.contains(culprit), "{args:?}: message does not name {culprit}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(listing(tmp.path()), before, "{args:?} left files behind");
    }
}

#[test]
fn a_different_shard_layout_in_the_same_directory_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["simulate", "--out", "d", "--realizations", "20", "--shard", "0/2", "--quiet"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = stickslip(&["simulate", "--out", "d", "--realizations", "20", "--quiet"], tmp.path());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("part-00000-of-00002.parquet"), "{}", stderr(&o));
    assert_eq!(listing(&tmp.path().join("d")), [".stickslip-dataset", "part-00000-of-00002.parquet"]);
}
