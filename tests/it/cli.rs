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

/// Refused at once with exit 2 and one printable line naming `culprit`, nothing written.
fn refused_in_one_line(args: &[&str], cwd: &std::path::Path, culprit: &str) {
    let o = stickslip(args, cwd);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert!(e.contains(culprit), "{args:?} does not name {culprit:?}: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: one line: {e}");
    assert!(e.len() < 2000 && !e.trim_end().chars().any(char::is_control), "{args:?}: short and printable: {e}");
}

/// Issue 20, items 9, 21 and 22: the smaller doors.
#[test]
fn the_smaller_doors_refuse_in_one_printable_line() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // a swept key in a stage that runs one scene
    refused_in_one_line(&["tradeoff", "--out", "to", "--set", "belt.switch_rate=[1, 10]"], t, "belt.switch_rate");
    refused_in_one_line(
        &["sensitivity", "--out", "so", "--set", "model.damping=[0.5, 5]", "--set", "model.friction_coefficient={dist=\"uniform\", low=0.3, high=0.7}"],
        t,
        "model.damping",
    );
    // a 100,000-character value is shortened, a TOML syntax error is one line
    let long = format!("model.mass={}", "1".repeat(100_000));
    refused_in_one_line(&["simulate", "--out", "o", "--set", &long], t, "characters");
    std::fs::write(t.join("bad.toml"), "[model\nmass = \u{1}\u{2} 2\n").unwrap();
    refused_in_one_line(&["simulate", "bad.toml", "--out", "o"], t, "line 1, column 7");
    // a FIFO is not read (it would block)
    let fifo = t.join("fifo.toml");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    refused_in_one_line(&["simulate", "fifo.toml", "--out", "o"], t, "not a regular file");
    // the key the user set is named
    refused_in_one_line(&["simulate", "--out", "o", "--set", "belt.reverse_switch_rate=2e6", "--set", "belt.reverse_speed=1"], t, "belt.reverse_switch_rate");
    // the shard and a reproduce root
    let o = stickslip(&["reproduce", "--out", "r", "--shard", "0/2"], t);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!t.join("r").exists());
    assert!(stickslip(&["reproduce", "--out", "r", "--realizations", "300", "-q"], t).status.success());
    refused_in_one_line(&["analyze", "r", "--out", "a"], t, "did you mean r/dataset?");
    assert!(!t.join("a").exists() && !t.join("o").exists() && !t.join("to").exists() && !t.join("so").exists());
    // k in digits only
    let o = stickslip(&["simulate", "--out", "o", "--realizations", "100", "--target-se", "T_+1=0.1"], t);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("k must be an integer"), "{}", stderr(&o));
    // sensitivity keeps its samples in memory: bounded, naming the largest N
    refused_in_one_line(
        &["sensitivity", "--out", "so", "--realizations", "100000000", "--set", "model.friction_coefficient={dist=\"uniform\", low=0.3, high=0.7}"],
        t,
        "use N <=",
    );
}

/// Issue 20, item 16: the shipped scenes without a clone.
#[test]
fn scenes_lists_prints_and_writes_the_shipped_scenarios() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let o = stickslip(&["scenes"], t);
    assert!(o.status.success());
    let list = String::from_utf8_lossy(&o.stdout);
    for name in ["paper", "stribeck", "damped", "static_friction", "asymmetric_belt", "uncertain_friction", "stribeck_damped"] {
        assert!(list.lines().any(|l| l.starts_with(name)), "{name} missing: {list}");
    }
    // printed: the repository's file, byte for byte
    let o = stickslip(&["scenes", "damped"], t);
    let repo = std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("pipelines/scenes/damped.toml")).unwrap();
    assert_eq!(o.stdout, repo);
    // written to a new file, which then runs; an existing file is never replaced
    assert!(stickslip(&["scenes", "stribeck", "--out", "my/s.toml"], t).status.success());
    assert!(stickslip(&["simulate", "my/s.toml", "--out", "d", "--realizations", "50", "-q"], t).status.success());
    std::fs::write(t.join("mine.toml"), "mine").unwrap();
    refused_in_one_line(&["scenes", "paper", "--out", "mine.toml"], t, "refusing to replace");
    assert_eq!(std::fs::read_to_string(t.join("mine.toml")).unwrap(), "mine");
    refused_in_one_line(&["scenes", "nope"], t, "stribeck_damped");
}

/// polars reads its hot group-by table size from `POLARS_HOT_TABLE_SIZE` and panics on a
/// malformed one: a value the user gives is kept when it is a positive whole number and refused
/// in one line otherwise (`src/main.rs`), before anything is written.
#[test]
fn a_malformed_polars_hot_table_size_is_refused_before_anything_runs() {
    let tmp = tempfile::tempdir().unwrap();
    for bad in ["abc", "0", "-5", ""] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .args(["simulate", "--out", "d", "--realizations", "20", "-q"])
            .env("POLARS_HOT_TABLE_SIZE", bad)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {e}");
        assert!(e.contains("POLARS_HOT_TABLE_SIZE") && e.trim_end().lines().count() == 1, "{bad:?}: {e}");
        assert!(!tmp.path().join("d").exists(), "{bad:?}: wrote a dataset");
    }
    let ok = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["simulate", "--out", "d", "--realizations", "20", "-q"])
        .env("POLARS_HOT_TABLE_SIZE", "1024")
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(ok.status.success(), "{}", stderr(&ok));
}
