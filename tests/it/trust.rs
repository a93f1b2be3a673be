//! Trust at the edges (issue 44), one test per class: a key's range is checked together with
//! what it implies, so every arithmetic step stays finite; no writer emits NaN or ±∞; whatever
//! `simulate` accepts every later stage takes; every reader checks the columns and tables it uses.

use std::path::Path;
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float32Array, Float64Array, ListArray, StringArray};
use arrow_buffer::OffsetBuffer;
use arrow_schema::{DataType, Field};
use stickslip::scenario::Scenario;
use stickslip::simulation::ensemble::Outcome;
use stickslip::simulation::keys::Key;

use crate::common::stickslip;
use crate::safety::{err, footer_set, list_with, mutate, ok, refused, rewrite};

fn resolve(sets: &[&str]) -> Result<Scenario, String> {
    Scenario::resolve(None, &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>()).map_err(|e| e.to_string())
}

/// Every value a realization of `sets` writes, as the dataset's columns hold them.
fn all_finite(sc: &Scenario, n: u64) {
    let ens = sc.ensemble().unwrap();
    let mut o = Outcome::default();
    for i in 0..n {
        ens.realization(i, &mut o).unwrap_or_else(|e| panic!("realization {i}: {e}"));
        let r = &o.record;
        let lists = [&r.stick_start, &r.stick_duration, &r.slip_start, &r.slip_duration, &r.stick_entry_position, &r.stick_entry_velocity];
        assert!(lists.iter().all(|l| l.iter().all(|x| x.is_finite())), "realization {i}: a list value is not finite");
        let severity = r.severity(o.speed_scale);
        for x in [r.min_velocity, r.max_velocity, r.max_slip_speed, severity, o.x0, o.xdot0] {
            assert!(x.is_finite(), "realization {i}: {x}");
        }
        assert!(severity <= stickslip::observables::SEVERITY_BOUND, "realization {i}: severity {severity}");
    }
}

#[test]
fn derived_ranges_are_refused_at_the_door_and_every_step_stays_finite_inside() {
    let tmp = tempfile::tempdir().unwrap();
    let log = tmp.path().join("log.csv");
    std::fs::write(&log, "time,velocity\n0,0\n1,1e-320\n").unwrap();
    let file = format!("belt.file={:?}", log.display().to_string());
    let markov = ["belt.process=\"markov\"", "belt.rates=[[0,1],[1,0]]"];
    // (sets, the key the refusal names)
    let refusals: Vec<(Vec<&str>, &str)> = vec![
        // a level in the subnormals: the severity's unit 1e-320 m/s made every severity ∞
        ([&markov[..], &["belt.velocities=[0, 1e-320]"]].concat(), "belt.velocities"),
        ([&markov[..], &["belt.velocities=[1e-320, -1e-320]"]].concat(), "belt.velocities"),
        (vec!["belt.process=\"recorded\"", &file], "belt.file"),
        // an initial state whose square overflows (v² in the arrival test, k·x)
        (vec!["initial_conditions.velocity=[1e150, 1e150]"], "initial_conditions.velocity"),
        (vec!["initial_conditions.velocity=[-1e300, 1e300]"], "initial_conditions.velocity"),
        (vec!["initial_conditions.position=[1e308, 1e308]"], "initial_conditions.position"),
        (vec!["initial_conditions.position=[1e10, 1e10]"], "initial_conditions.position"),
        // a chain at rest but for a level it visits a billionth of the time: its scale 1e-9 m/s
        ([&markov[..], &["belt.velocities=[0, 1]", "belt.rates=[[0, 1e-9], [1, 0]]"]].concat(), "belt.velocities"),
        // a severity the analysis cannot take: swings of 3 m/s on a belt of 1e-9 m/s
        (vec!["belt.speed=1e-9"], "initial_conditions"),
        // the swing a breakaway releases: a stick held to μ_s n and let go slips about μ_k n
        // (the probe's scene: a severity of 2.05e7 written by realization 0 before the door knew)
        (
            vec![
                "model.stiffness=100",
                "run.duration=1e6",
                "belt.switch_rate=0",
                "belt.speed=0.0625",
                "model.friction_coefficient=0",
                "model.static_friction_coefficient=1",
                "model.normal_force=1.5625e7",
                "initial_conditions.position=[0, 0]",
                "initial_conditions.velocity=[1e6, 1e6]",
            ],
            "initial_conditions",
        ),
    ];
    for (sets, key) in refusals {
        let e = resolve(&sets).expect_err(&format!("{sets:?} is refused"));
        assert!(e.contains(key), "{sets:?}: the refusal names {key}: {e}");
    }
    // just inside: every value finite, every severity within the bound
    for sets in [
        vec!["initial_conditions.velocity=[1e6, 1e6]"],
        vec!["initial_conditions.velocity=[-1e6, 1e6]", "initial_conditions.position=[-2e5, 2e5]"],
        vec!["initial_conditions.position=[-1e6, 1e6]"],
        vec!["belt.speed=1e-4"],
        vec!["belt.speed=1e-9", "initial_conditions.position=[-1e-9, 1e-9]", "initial_conditions.velocity=[-1e-9, 1e-9]"],
        [&markov[..], &["belt.velocities=[1e-9, -1e-9]", "initial_conditions.position=[-1e-9, 1e-9]", "initial_conditions.velocity=[-1e-9, 1e-9]"]].concat(),
        // a drawn belt speed down to 1e-9 m/s with the mass at rest: the belt's part of the
        // severity is 1 for every draw (its top speed is its scale)
        vec!["belt.speed={dist = \"uniform\", low = 1e-9, high = 1}", "initial_conditions.position=[0, 0]", "initial_conditions.velocity=[0, 0]"],
    ] {
        let sc = resolve(&sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
        all_finite(&sc, 50);
    }
    // the exact law: a flip rate far below ω lost every digit (NaN densities); refused naming the key
    for (sets, key) in
        [(vec!["belt.switch_rate=1e-20"], "belt.switch_rate"), (vec!["belt.reverse_speed=0.5", "belt.reverse_switch_rate=1e-20"], "belt.reverse_switch_rate")]
    {
        let mut args = vec!["exact-law", "--resolution", "8", "--out", "L"];
        for s in &sets {
            args.extend(["--set", s]);
        }
        refused(&stickslip(&args, tmp.path()), key);
        assert!(!tmp.path().join("L").exists());
    }
}

#[test]
fn the_severity_scale_is_what_the_belt_does_in_the_window() {
    // a level the chain never enters, and a row after t_a, do not set the scale
    let chain = resolve(&["belt.process=\"markov\"", "belt.velocities=[1, -1, 1e6]", "belt.rates=[[0,5,0],[5,0,0],[0,5,0]]"]).unwrap();
    assert_eq!(chain.scene().unwrap().belt.scale(), 1.0);
    let tmp = tempfile::tempdir().unwrap();
    let log = tmp.path().join("log.csv");
    std::fs::write(&log, "time,velocity\n0,1\n4,-3\n20,1e6\n").unwrap();
    let record = resolve(&["belt.process=\"recorded\"", &format!("belt.file={:?}", log.display().to_string())]).unwrap();
    // the time average of |v| over [0, 10]: (4·1 + 6·3)/10
    assert!((record.scene().unwrap().belt.scale() - 2.2).abs() < 1e-15);
    // a chain with a level at rest: Σ π_i |v_i| (π = (1/2, 1/2) for equal rates)
    let rest = resolve(&["belt.process=\"markov\"", "belt.velocities=[0, 2]", "belt.rates=[[0,3],[3,0]]"]).unwrap();
    assert!((rest.scene().unwrap().belt.scale() - 1.0).abs() < 1e-15);
    // the paper's belt: its speed, exactly
    assert_eq!(Scenario::paper().scene().unwrap().belt.scale(), 1.0);
}

#[test]
fn no_writer_emits_a_non_finite_value() {
    use stickslip::table::{Col, Table};
    let tmp = tempfile::tempdir().unwrap();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut t = Table::default();
        t.push("variable", Col::Str(vec!["a".into(), "b".into()])).push("mean", Col::Float(vec![Some(1.0), Some(bad)]));
        let path = tmp.path().join("t.parquet");
        let e = t.write_parquet(&path).unwrap_err().to_string();
        assert!(e.contains("`mean` row 1"), "{e}");
        assert!(!path.exists(), "nothing is written");
    }
    let mut t = Table::default();
    t.push("variance", Col::Float(vec![Some(-1.0)]));
    assert!(t.write_parquet(&tmp.path().join("v.parquet")).unwrap_err().to_string().contains("negative"));
    // a record with a non-finite value is refused by its row's guard
    let mut r = stickslip::simulation::events::Record::default();
    use stickslip::simulation::events::Observer;
    r.slip(0.0, 0.0, 0.0, stickslip::solver::Release::Start);
    r.motion(-1.0, f64::INFINITY, 1.0);
    r.finish(10.0);
    assert_eq!(r.outside(10.0, 1.0).map(|o| o.0), Some("max_velocity"));
    (r.max_velocity, r.max_slip_speed) = (2.0, 3.0);
    assert_eq!(r.outside(10.0, 1.0), None);
    assert_eq!(r.outside(10.0, 1e9).map(|o| o.0), Some("severity"));
}

/// `d` (300 paper realizations), its analysis `a` and figures `f` in `t`.
fn dataset_analysis_figures(t: &Path) {
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "300", "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", "a", "-q"], t));
    ok(&stickslip(&["figures", "a", "--out", "f", "-q"], t));
}

/// The parts of `dir` through analyze, figures and report (exit 0 each).
fn all_stages(t: &Path, data: &str) {
    ok(&stickslip(&["analyze", data, "--out", &format!("{data}.a"), "-q"], t));
    ok(&stickslip(&["figures", &format!("{data}.a"), "--out", &format!("{data}.f"), "-q"], t));
    ok(&stickslip(&["report", data, &format!("{data}.a"), &format!("{data}.f"), "--out", &format!("{data}.html"), "-q"], t));
}

#[test]
fn every_shipped_scene_and_both_ends_of_every_key_pass_all_four_stages() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // the shipped scenes, as a user gets them (`scenes NAME --out FILE`: the log beside it)
    for s in stickslip::scenes::SHIPPED.iter() {
        let file = format!("{}.toml", s.name);
        ok(&stickslip(&["scenes", s.name, "--out", &file], t));
        let mut args = vec!["simulate", &file, "--out", s.name, "--realizations", "60", "-q"];
        // (numerical scenes at tradeoff-like settings: a test is not minutes of Monte Carlo)
        let fast = ["--set", "numerics.rtol=1e-5", "--set", "numerics.atol=1e-5", "--set", "numerics.max_step=0.1"];
        if !Scenario::resolve(Some(&t.join(&file)), &[]).unwrap().has_closed_forms() {
            args.extend(fast);
        }
        ok(&stickslip(&args, t));
        all_stages(t, s.name);
    }
    // every key at both ends of its range (and its companions, as tests/it/extremes.rs sets
    // them): refused at the door with one line naming a key, or through all four stages
    for key in Key::ALL {
        let (lo, hi) = key.range();
        for (end, x) in [("lo", lo), ("hi", hi)] {
            let mut sets: Vec<String> = match key {
                Key::Static if x < 0.51 => vec!["model.friction_coefficient=0".into()],
                Key::ReverseSpeed => vec!["belt.reverse_switch_rate=5".into()],
                Key::ReverseSwitchRate => vec!["belt.reverse_speed=1".into(), "run.duration=0.1".into()],
                Key::SwitchRate if x > 1e3 => vec!["run.duration=0.1".into()],
                Key::StribeckVelocity | Key::StribeckExponent => vec![
                    "model.friction_law=\"stribeck\"".into(),
                    "model.stribeck_velocity=0.1".into(),
                    "model.static_friction_coefficient=0.6".into(),
                    "numerics.rtol=1e-5".into(),
                    "numerics.atol=1e-5".into(),
                    "numerics.max_step=0.1".into(),
                    "numerics.step_budget=100000000".into(),
                ],
                _ => vec![],
            };
            sets.push(format!("{}={x:e}", key.dotted()));
            let name = format!("{}-{end}", key.name());
            let mut args: Vec<String> = ["simulate", "--out", &name, "--realizations", "8", "-q"].map(String::from).to_vec();
            for s in &sets {
                args.extend(["--set".to_string(), s.clone()]);
            }
            let refs: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = stickslip(&refs, t);
            if o.status.code() == Some(2) {
                let e = err(&o);
                assert!(e.contains("scenario key") && e.trim_end().lines().count() == 1, "{sets:?}: {e}");
                assert!(!t.join(&name).exists(), "{sets:?}: a refusal leaves nothing");
                continue;
            }
            ok(&o);
            all_stages(t, &name);
        }
    }
}

/// A list<utf8> column with element `at` replaced by `value`.
fn strings_with(col: &ArrayRef, at: usize, value: &str) -> ArrayRef {
    let l = col.as_any().downcast_ref::<ListArray>().unwrap();
    let vals = l.values().as_any().downcast_ref::<StringArray>().unwrap();
    let mut v: Vec<&str> = vals.iter().map(|s| s.unwrap_or("")).collect();
    v[at] = value;
    let field = Arc::new(Field::new("element", DataType::Utf8, false));
    Arc::new(ListArray::new(field, OffsetBuffer::new(l.offsets().inner().clone()), Arc::new(StringArray::from(v)), None))
}

fn floats_with(col: &ArrayRef, at: usize, x: f64) -> ArrayRef {
    let a = col.as_any().downcast_ref::<Float64Array>().unwrap();
    let mut v: Vec<f64> = a.values().to_vec();
    v[at] = x;
    Arc::new(Float64Array::from(v))
}

#[test]
fn analyze_checks_every_column_it_uses_and_the_parts_provenance() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    type Edit = Box<dyn Fn(&ArrayRef) -> ArrayRef>;
    let cases: Vec<(&str, &str, Edit, &str)> = vec![
        ("ls-inf", "longest_stick", Box::new(|c| floats_with(c, 3, f64::INFINITY)), "inf"),
        ("ls-big", "longest_stick", Box::new(|c| floats_with(c, 3, 1e300)), "1e300"),
        ("ls-nan", "longest_stick", Box::new(|c| floats_with(c, 3, f64::NAN)), "NaN"),
        ("ls-neg", "longest_stick", Box::new(|c| floats_with(c, 3, -1.0)), "-1"),
        ("sev-zero", "severity", Box::new(|c| floats_with(c, 3, -0.0)), "-0"),
        ("fraction", "stick_fraction", Box::new(|c| floats_with(c, 3, 1.5)), "1.5"),
        ("slip", "max_slip_speed", Box::new(|c| floats_with(c, 3, f64::NAN)), "NaN"),
        ("vmin", "min_velocity", Box::new(|c| floats_with(c, 3, 1e9)), "max_velocity"),
        ("entry", "stick_entry_position", Box::new(|c| list_with(c, 2, Some(f64::NAN))), "NaN"),
        ("entry-inf", "stick_entry_velocity", Box::new(|c| list_with(c, 2, Some(f64::INFINITY))), "inf"),
        ("entry-level", "stick_entry_velocity", Box::new(|c| list_with(c, 2, Some(0.5))), "one of 1, -1"),
        ("end", "stick_end", Box::new(|c| strings_with(c, 2, "frobnicated")), "frobnicated"),
        ("end-empty", "stick_end", Box::new(|c| strings_with(c, 2, "")), "a stick ends by"),
    ];
    for (name, column, f, culprit) in cases {
        ok(&stickslip(&["simulate", "--out", name, "--realizations", "200", "-q"], t));
        mutate(&t.join(name), column, f);
        let o = stickslip(&["analyze", name, "--out", "a"], t);
        refused(&o, culprit);
        let e = err(&o);
        assert!(e.contains("part-00000-of-00001.parquet") && e.contains(column) && e.contains("row"), "{name}: {e}");
        assert!(!t.join("a").exists());
    }
    // a severity stored as float32, a v3 part without one of its columns
    ok(&stickslip(&["simulate", "--out", "f32", "--realizations", "100", "-q"], t));
    mutate(&t.join("f32"), "severity", |c| {
        let a = c.as_any().downcast_ref::<Float64Array>().unwrap();
        Arc::new(Float32Array::from(a.values().iter().map(|x| *x as f32).collect::<Vec<_>>())) as ArrayRef
    });
    refused(&stickslip(&["analyze", "f32", "--out", "a"], t), "column `severity` is float32, expected float64");
    // parts whose footers disagree: another seed (the scenario text aside), another schema version
    ok(&stickslip(&["simulate", "--out", "two", "--realizations", "400", "--shard", "0/2", "-q"], t));
    ok(&stickslip(&["simulate", "--out", "two", "--realizations", "400", "--shard", "1/2", "-q"], t));
    let part = |i: u32| t.join(format!("two/part-0000{i}-of-00002.parquet"));
    let keep = std::fs::read(part(1)).unwrap();
    std::fs::copy(part(1), t.join("p1.parquet")).unwrap();
    let edit_part = |key: &'static str, value: &'static str| {
        // (rewrite works on part-00000-of-00001: stage the part there)
        let stage = t.join("stage");
        std::fs::create_dir_all(&stage).unwrap();
        std::fs::write(stage.join("part-00000-of-00001.parquet"), &keep).unwrap();
        rewrite(&stage, &[], |c| c.clone(), footer_set(key, value));
        std::fs::copy(stage.join("part-00000-of-00001.parquet"), part(1)).unwrap();
    };
    for (key, value) in [("stickslip.seed", "99"), ("stickslip.solver", "rk45"), ("stickslip.schema_version", "2")] {
        edit_part(key, value);
        let o = stickslip(&["analyze", "two", "--out", "a"], t);
        let e = err(&o);
        assert_eq!(o.status.code(), Some(2), "{key}: {e}");
        assert!(e.contains(key) && e.contains("part-00001-of-00002"), "{key}: the message names the key and the odd part: {e}");
    }
    // simulate refuses to add a shard of another run (another seed or size)
    refused(&stickslip(&["simulate", "--out", "two", "--realizations", "400", "--shard", "1/2", "--seed", "5", "-q"], t), "stickslip.seed is 1");
    refused(&stickslip(&["simulate", "--out", "two", "--realizations", "500", "--shard", "1/2", "-q"], t), "its scenario differs");
    // a footer's shard that is not the file's
    edit_part("stickslip.shard", "0/3");
    refused(&stickslip(&["analyze", "two", "--out", "a"], t), "stickslip.shard = 0/3");
    std::fs::write(part(1), &keep).unwrap();
    ok(&stickslip(&["analyze", "two", "--out", "a", "-q"], t));
}

#[test]
fn figures_report_and_their_tables_refuse_impossible_values() {
    use polars::prelude::*;
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    dataset_analysis_figures(t);
    let p = t.join("a/moments.parquet");
    let original = std::fs::read(&p).unwrap();
    for (column, value, culprit) in [
        ("mean", f64::INFINITY, "inf"),
        ("mean", f64::NAN, "NaN"),
        ("variance", -1.0, "negative"),
        ("kurtosis", f64::INFINITY, "inf"),
        ("mean_se", -1.0, "negative"),
    ] {
        let mut df = ParquetReader::new(std::fs::File::open(&p).unwrap()).finish().unwrap();
        let mut v: Vec<Option<f64>> = df.column(column).unwrap().f64().unwrap().iter().collect();
        v[0] = Some(value);
        df.with_column(Column::new(column.into(), v)).unwrap();
        ParquetWriter::new(std::fs::File::create(&p).unwrap()).finish(&mut df).unwrap();
        for args in [vec!["figures", "a", "--out", "f2"], vec!["report", "d", "a", "f", "--out", "r.html"]] {
            let o = stickslip(&args, t);
            refused(&o, culprit);
            assert!(err(&o).contains(column), "{args:?}: {}", err(&o));
        }
        std::fs::write(&p, &original).unwrap();
    }
    assert!(!t.join("f2").exists() && !t.join("r.html").exists());
}

#[test]
fn a_report_refuses_an_exact_law_of_another_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    dataset_analysis_figures(t);
    ok(&stickslip(&["exact-law", "--out", "other", "--resolution", "8", "--set", "belt.switch_rate=2", "-q"], t));
    refused(&stickslip(&["report", "d", "a", "f", "--exact", "other", "--out", "r.html"], t), "another scene");
    assert!(!t.join("r.html").exists());
    // the same scene with another seed and size is the same law, and so is the default belt
    // spelled out
    ok(&stickslip(&["exact-law", "--out", "same", "--resolution", "8", "--set", "run.seed=7", "--set", "belt.process=\"symmetric\"", "-q"], t));
    ok(&stickslip(&["report", "d", "a", "f", "--exact", "same", "--out", "r.html", "-q"], t));
}

#[test]
fn predict_checks_its_flags_and_state_before_it_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    for (args, culprit) in [
        (vec!["predict", "--state=0,1e300,1", "--futures", "200", "--out", "P"], "--state"),
        (vec!["predict", "--state=1e308,0,1", "--out", "P"], "--state"),
        (vec!["predict", "--state=0,0.5,1", "--futures", "18446744073709551615", "--out", "P"], "--futures"),
        (vec!["predict", "--state=0,0.5,1", "--horizon", "1e-10", "--out", "P"], "--horizon"),
        (vec!["predict", "--state=0,0.5,1", "--horizon", "1e308", "--out", "P"], "--horizon"),
    ] {
        let start = std::time::Instant::now();
        let o = stickslip(&args, t);
        refused(&o, culprit);
        // (before the exact part's seconds)
        assert!(start.elapsed() < std::time::Duration::from_secs(2), "{args:?}: {:?}", start.elapsed());
        assert!(!t.join("P").exists());
    }
}

#[test]
fn a_velocity_log_is_a_regular_file_of_bounded_size_in_any_parquet_codec() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let set = |f: &str| format!("belt.file={f:?}");
    for (file, culprit) in [("/dev/zero", "not a regular file"), ("/dev/urandom", "not a regular file")] {
        let e = resolve(&["belt.process=\"recorded\"", &set(file)]).unwrap_err();
        assert!(e.contains("belt.file") && e.contains(culprit), "{e}");
    }
    // a FIFO without a writer: refused at once, not a hang
    let fifo = t.join("fifo");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let e = resolve(&["belt.process=\"recorded\"", &set(fifo.to_str().unwrap())]).unwrap_err();
    assert!(e.contains("not a regular file"), "{e}");
    // the codecs pyarrow and pandas write (snappy by default), written here by polars' writer
    use polars::prelude::{df, ParquetCompression, ParquetWriter};
    let codecs = [
        ParquetCompression::Snappy,
        ParquetCompression::Gzip(None),
        ParquetCompression::Lz4Raw,
        ParquetCompression::Brotli(None),
        ParquetCompression::Zstd(None),
    ];
    for (i, codec) in codecs.into_iter().enumerate() {
        let path = t.join(format!("log-{i}.parquet"));
        let mut frame = df!("time" => [0.0, 2.0, 5.0], "velocity" => [1.0, -1.0, 1.0]).unwrap();
        ParquetWriter::new(std::fs::File::create(&path).unwrap()).with_compression(codec).finish(&mut frame).unwrap();
        let sc = resolve(&["belt.process=\"recorded\"", &set(path.to_str().unwrap())]).unwrap_or_else(|e| panic!("{codec:?}: {e}"));
        all_finite(&sc, 5);
    }
}

#[test]
fn a_scenario_reads_its_log_beside_it_from_any_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    std::fs::create_dir(t.join("elsewhere")).unwrap();
    ok(&stickslip(&["scenes", "recorded_belt", "--out", "recorded.toml"], t));
    assert!(t.join("rotary_log.csv").is_file());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shipped = root.join("pipelines/scenes/recorded_belt.toml");
    for (scenario, cwd) in [(t.join("recorded.toml"), t.join("elsewhere")), (shipped.clone(), t.join("elsewhere")), (shipped, root.to_path_buf())] {
        let out = t.join("elsewhere").join(format!("d{}", scenario.to_string_lossy().len()));
        let o = stickslip(&["simulate", scenario.to_str().unwrap(), "--out", out.to_str().unwrap(), "--realizations", "20", "-q"], &cwd);
        ok(&o);
        std::fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn analyze_checks_the_trajectories_it_copies() {
    use polars::prelude::*;
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    for (file, column) in [("samples.parquet", "x"), ("events.parquet", "t"), ("events.parquet", "event")] {
        let _ = std::fs::remove_dir_all(t.join("d"));
        let _ = std::fs::remove_dir_all(t.join("d.trajectories"));
        ok(&stickslip(&["simulate", "--out", "d", "--realizations", "20", "--set", "output.trajectories=2", "-q"], t));
        let p = t.join("d.trajectories").join(file);
        let mut df = ParquetReader::new(std::fs::File::open(&p).unwrap()).finish().unwrap();
        let edited = if column == "event" {
            let mut v: Vec<String> = df.column(column).unwrap().str().unwrap().iter().map(|s| s.unwrap().to_string()).collect();
            v[1] = "frobnicated".into();
            Column::new(column.into(), v)
        } else {
            let mut v: Vec<Option<f64>> = df.column(column).unwrap().f64().unwrap().iter().collect();
            v[1] = Some(f64::NAN);
            Column::new(column.into(), v)
        };
        df.with_column(edited).unwrap();
        // (the file's key-value metadata says which run sampled it: kept)
        let meta = stickslip_metadata(&p);
        let mut w = ParquetWriter::new(std::fs::File::create(&p).unwrap());
        w = w.with_key_value_metadata(Some(KeyValueMetadata::from_static(meta)));
        w.finish(&mut df).unwrap();
        let o = stickslip(&["analyze", "d", "--out", "a"], t);
        refused(&o, file);
        assert!(err(&o).contains(column), "{}", err(&o));
        assert!(!t.join("a").exists());
    }
}

/// The key-value metadata of a Parquet file.
fn stickslip_metadata(p: &Path) -> Vec<(String, String)> {
    let r = parquet::file::reader::SerializedFileReader::new(std::fs::File::open(p).unwrap()).unwrap();
    use parquet::file::reader::FileReader;
    let kv = r.metadata().file_metadata().key_value_metadata().cloned().unwrap_or_default();
    kv.into_iter().filter(|e| e.key != "ARROW:schema").map(|e| (e.key, e.value.unwrap_or_default())).collect()
}

#[test]
fn reproduce_checks_every_output_before_its_first_stage() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["reproduce", "--out", "R", "--realizations", "50", "-q"], t));
    std::fs::write(t.join("R/figures/mine.txt"), "mine").unwrap();
    let part = t.join("R/dataset/part-00000-of-00001.parquet");
    let before = std::fs::read(&part).unwrap();
    refused(&stickslip(&["reproduce", "--out", "R", "--realizations", "50", "--seed", "2"], t), "mine.txt");
    assert_eq!(std::fs::read(&part).unwrap(), before, "the earlier dataset stays");
    assert_eq!(std::fs::read_to_string(t.join("R/figures/mine.txt")).unwrap(), "mine");
}
