//! Output safety and input checks (issue 10): no output destroys an input or a file the tool did
//! not write; concurrent writers, symlinks, signals and killed runs leave no corrupt or stale
//! data; every bad value is refused with its culprit named; every table read is checked.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use arrow_array::{Array, ArrayRef, Float64Array, Int64Array, ListArray, RecordBatch};
use arrow_buffer::{NullBuffer, OffsetBuffer};
use arrow_schema::{DataType, Field};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::file::properties::WriterProperties;
use proptest::prelude::*;
use stickslip::scenario::Scenario;

use crate::common::stickslip;

pub(crate) fn err(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub(crate) fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}", err(o));
}

/// Refused as bad input: exit code 2, one message naming `culprit`, no panic.
pub(crate) fn refused(o: &std::process::Output, culprit: &str) {
    let e = err(o);
    assert_eq!(o.status.code(), Some(2), "expected exit 2 (bad input): {e}");
    assert!(e.contains(culprit), "the message does not name {culprit:?}: {e}");
    assert!(!e.contains("panicked"), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "one message: {e}");
}

/// Every file below `dir` with its bytes (hidden files included).
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    crate::common::files_below(dir).into_iter().map(|p| (p.clone(), std::fs::read(&p).unwrap_or_default())).collect()
}

/// The names of everything below `dir` (files and directories).
fn names_below(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            out.push(p.file_name().unwrap().to_string_lossy().into_owned());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out
}

/// Hidden temporaries and locks below `dir` (the marker is not one).
fn hidden_leftovers(dir: &Path) -> Vec<String> {
    names_below(dir).into_iter().filter(|n| n.starts_with('.') && n != ".stickslip-output" && n != ".stickslip-dataset").collect()
}

#[test]
fn an_output_that_is_or_holds_an_input_is_refused_and_the_input_survives() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "top/ds", "--realizations", "200", "-q"], t));
    std::fs::write(t.join("top/notes.txt"), "my notes").unwrap();
    ok(&stickslip(&["analyze", "top/ds", "--out", "an", "-q"], t));
    ok(&stickslip(&["figures", "an", "--out", "fig", "-q"], t));
    let before = snapshot(t);
    let cases: &[&[&str]] = &[
        &["analyze", "top/ds", "--out", "top/ds"],
        &["analyze", "top/ds", "--out", "top"],
        &["analyze", "top/ds", "--out", "top/ds/sub"],
        &["analyze", "top/ds", "--out", "./top/../top/ds/"],
        &["figures", "an", "--out", "an"],
        &["figures", "an", "--out", "."],
        &["report", "top/ds", "an", "fig", "--out", "an/moments.html"],
        &["report", "top/ds", "an", "fig", "--out", "top/ds/r.html"],
    ];
    for args in cases {
        let o = stickslip(args, t);
        refused(&o, "input");
        assert!(snapshot(t) == before, "{args:?} changed files");
    }
    // outputs of another kind, or holding a file the tool did not write, are never replaced
    let cases: &[(&[&str], &str)] = &[
        (&["tradeoff", "--out", "top/ds", "--realizations", "2"], "dataset"),
        (&["analyze", "top/ds", "--out", "fig"], "figures"),
        (&["report", "top/ds", "an", "fig", "--out", "an2.md"], ".html"),
    ];
    for (args, culprit) in cases {
        refused(&stickslip(args, t), culprit);
        assert!(snapshot(t) == before, "{args:?} changed files");
    }
    std::fs::write(t.join("an/mine.txt"), "keep").unwrap();
    refused(&stickslip(&["analyze", "top/ds", "--out", "an"], t), "mine.txt");
    assert_eq!(std::fs::read_to_string(t.join("an/mine.txt")).unwrap(), "keep");
    std::fs::remove_file(t.join("an/mine.txt")).unwrap();
    // a file the report did not write is not replaced; its own output is
    std::fs::write(t.join("r.html"), "<html>someone else's page</html>").unwrap();
    refused(&stickslip(&["report", "top/ds", "an", "fig", "--out", "r.html"], t), "r.html");
    // nor is its Markdown twin, and then the page is not written either
    std::fs::write(t.join("m.md"), "my notes").unwrap();
    refused(&stickslip(&["report", "top/ds", "an", "fig", "--out", "m.html"], t), "m.md");
    assert!(!t.join("m.html").exists(), "a refused report left its page behind");
    assert_eq!(std::fs::read_to_string(t.join("m.md")).unwrap(), "my notes");
    ok(&stickslip(&["report", "top/ds", "an", "fig", "--out", "mine.html", "-q"], t));
    ok(&stickslip(&["report", "top/ds", "an", "fig", "--out", "mine.html", "-q"], t));
    // simulate adds parts only to a dataset directory: never into a directory of other files
    refused(&stickslip(&["simulate", "--out", "top", "--realizations", "10"], t), "top");
    assert_eq!(std::fs::read_to_string(t.join("top/notes.txt")).unwrap(), "my notes");
    // the tool's own analysis is replaced
    ok(&stickslip(&["analyze", "top/ds", "--out", "an", "-q"], t));
    assert!(hidden_leftovers(t).is_empty(), "{:?}", hidden_leftovers(t));
}

#[test]
fn concurrent_writers_give_an_error_or_valid_files_never_a_corrupt_one() {
    let tmp = tempfile::tempdir().unwrap();
    let spawn = |seed: &str, n: &str| {
        Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .args(["simulate", "--out", "d", "--threads", "1", "-q", "--seed", seed, "--realizations", n])
            .current_dir(tmp.path())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn("1", "60000"), spawn("2", "40000"));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    for o in [&a, &b] {
        if !o.status.success() {
            let e = err(o);
            assert!(e.contains("in use by"), "{e}");
            assert_eq!(o.status.code(), Some(2));
        }
    }
    assert!(a.status.success() || b.status.success());
    // whatever won is a whole, valid dataset of one run
    ok(&stickslip(&["analyze", "d", "--out", "a", "-q"], tmp.path()));
    assert!(hidden_leftovers(tmp.path()).is_empty(), "{:?}", hidden_leftovers(tmp.path()));
}

#[test]
fn a_planted_symlink_is_never_followed() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "50", "-q"], t));
    std::fs::write(t.join("victim"), "precious").unwrap();
    for name in [".part-00000-of-00001.parquet.tmp", ".part-00000-of-00001.parquet.stickslip-tmp-1-0-0"] {
        std::os::unix::fs::symlink(t.join("victim"), t.join("d").join(name)).unwrap();
    }
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "80", "-q"], t));
    std::os::unix::fs::symlink(t.join("victim"), t.join("d/.part-00000-of-00001.parquet.stickslip-lock")).unwrap();
    let o = stickslip(&["simulate", "--out", "d", "--realizations", "90", "-q"], t);
    assert!(!o.status.success() && !err(&o).contains("panicked"), "a symlinked lock is refused: {}", err(&o));
    assert_eq!(std::fs::read_to_string(t.join("victim")).unwrap(), "precious");
    std::fs::remove_file(t.join("d/.part-00000-of-00001.parquet.stickslip-lock")).unwrap();
    ok(&stickslip(&["analyze", "d", "--out", "a", "-q"], t));
}

/// Start the binary, wait until a hidden temporary appears below `watch`, send `signal`.
fn interrupt(args: &[&str], cwd: &Path, watch: &Path, signal: i32) -> std::process::Output {
    let child = Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).current_dir(cwd).stderr(Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(60) {
        let busy = names_below(watch).iter().any(|n| n.contains(".stickslip-tmp-"));
        if busy {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(100));
    unsafe { libc::kill(child.id() as i32, signal) };
    child.wait_with_output().unwrap()
}

#[test]
fn sigint_sigterm_and_sigkill_leave_nothing_that_is_counted() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let big = ["simulate", "--out", "d", "--realizations", "3000000", "--threads", "1", "-q"];
    let o = interrupt(&big, t, t, libc::SIGINT);
    assert_eq!(o.status.code(), Some(130), "{}", err(&o));
    assert!(hidden_leftovers(t).is_empty(), "after SIGINT: {:?}", hidden_leftovers(t));
    let o = interrupt(&big, t, t, libc::SIGTERM);
    assert_eq!(o.status.code(), Some(143), "{}", err(&o));
    assert!(hidden_leftovers(t).is_empty(), "after SIGTERM: {:?}", hidden_leftovers(t));
    // SIGKILL cannot be caught: the temporaries stay, hidden, never read as data, and the next
    // writer of the same part removes them
    let o = interrupt(&big, t, t, libc::SIGKILL);
    assert_eq!(o.status.code(), None);
    assert!(!hidden_leftovers(t).is_empty(), "a killed run leaves its temporary");
    refused(&stickslip(&["analyze", "d", "--out", "a"], t), "no dataset part files");
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "300", "-q"], t));
    assert!(hidden_leftovers(t).is_empty(), "stale temporaries removed: {:?}", hidden_leftovers(t));
    // an interrupted analyze leaves no staging directory and keeps the previous analysis
    ok(&stickslip(&["simulate", "--out", "big", "--realizations", "400000", "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", "a", "-q"], t));
    let before = snapshot(&t.join("a"));
    let o = interrupt(&["analyze", "big", "--out", "a", "-q"], t, t, libc::SIGINT);
    assert_eq!(o.status.code(), Some(130), "{}", err(&o));
    assert!(hidden_leftovers(t).is_empty(), "after an interrupted analyze: {:?}", hidden_leftovers(t));
    assert!(snapshot(&t.join("a")) == before, "the previous analysis is untouched");
}

#[test]
fn a_failed_sweep_rerun_leaves_the_previous_sweep_untouched() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "s", "--realizations", "300", "-q", "--set", "belt.switch_rate=[1, 5]"], t));
    let before = snapshot(&t.join("s"));
    // the third cell cannot be written (a file stands where its directory goes)
    std::fs::write(t.join("s/switch_rate=20"), "in the way").unwrap();
    let o = stickslip(&["simulate", "--out", "s", "--realizations", "500", "-q", "--set", "belt.switch_rate=[1, 5, 20]"], t);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(err(&o).contains("switch_rate=20"), "{}", err(&o));
    std::fs::remove_file(t.join("s/switch_rate=20")).unwrap();
    assert!(snapshot(&t.join("s")) == before, "a failed sweep changed the previous sweep");
}

/// Two sweeps of different keys, or a plain run and a sweep, written into one directory are not
/// summarised as one sweep (the second's cells were labelled by the first's keys).
#[test]
fn two_different_runs_in_one_directory_are_not_analysed_as_one_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // simulate refuses to add a run of another shape (issue 44, item 19)
    ok(&stickslip(&["simulate", "--out", "m", "--realizations", "20", "-q", "--set", "model.damping=[0, 1]"], t));
    refused(&stickslip(&["simulate", "--out", "m", "--realizations", "20", "-q", "--set", "belt.switch_rate=[1, 2]"], t), "a sweep of switch_rate");
    ok(&stickslip(&["simulate", "--out", "p", "--realizations", "20", "-q"], t));
    refused(&stickslip(&["simulate", "--out", "p", "--realizations", "20", "-q", "--set", "model.damping=[0, 1]"], t), "a plain run");
    refused(&stickslip(&["simulate", "--out", "m", "--realizations", "20", "-q"], t), "a plain run");
    // and analyze refuses such a directory put together by hand
    ok(&stickslip(&["simulate", "--out", "s", "--realizations", "20", "-q", "--set", "belt.switch_rate=[1, 2]"], t));
    std::fs::rename(t.join("s/switch_rate=1"), t.join("m/switch_rate=1")).unwrap();
    refused(&stickslip(&["analyze", "m", "--out", "a"], t), "sweep different keys");
    assert!(!t.join("a").exists());
    std::fs::rename(t.join("m/damping=0"), t.join("p/damping=0")).unwrap();
    refused(&stickslip(&["analyze", "p", "--out", "a"], t), "a plain dataset at the top");
    // one sweep of two keys is one sweep
    ok(&stickslip(&["simulate", "--out", "two", "--realizations", "20", "-q", "--set", "model.damping=[0, 1]", "--set", "belt.switch_rate=[1, 2]"], t));
    ok(&stickslip(&["analyze", "two", "--out", "a", "-q"], t));
}

#[test]
fn values_that_used_to_slip_through_are_refused_or_made_safe() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    // signed zeros are zeros: k = -0 is k = 0 (one stick, never -inf)
    let sc = Scenario::resolve(None, &["model.stiffness=-0.0".into()]).unwrap();
    let k = crate::common::params(&sc).stiffness;
    assert!(k == 0.0 && k.is_sign_positive());
    assert!(!sc.to_toml().contains("-0.0"));
    let cases: &[(&[&str], &str)] = &[
        (&["simulate", "--out", "o", "--set", "initial_conditions.position=[-1e308, 1e308]"], "initial_conditions.position"),
        (&["simulate", "--out", "o", "--realizations", "9223372036854775807"], "run.realizations"),
        (&["simulate", "--out", "o", "--realizations", "4294967296000"], "run.realizations"),
        (&["simulate", "--out", "o", "--set", "output.trajectories=1", "--set", "output.trajectory_step=1e-7"], "output.trajectories"),
        (&["simulate", "--out", "o", "--threads", "100000"], "--threads"),
        (&["simulate", "/dev/urandom", "--out", "o"], "/dev/urandom"),
        (&["simulate", "--out", "o", "--set", "belt.switch_rate=[1, 1.0]"], "belt.switch_rate"),
        (&["simulate", "--out", "o", "--set", "model.mass=1\nstiffness=5"], "model.mass=1"),
        (&["simulate", "--out", "o", "--set", "run.seed=[1, 2]"], "run.seed"),
        (&["simulate", "--out", "o", "--set", "model.mass=[1, 2]", "--set", "model.stiffness=-1"], "model.stiffness"),
        (&["analyze", "o", "--out", "a", "--max-index", "100000"], "--max-index"),
    ];
    for (args, culprit) in cases {
        let start = Instant::now();
        refused(&stickslip(args, t), culprit);
        assert!(start.elapsed() < Duration::from_secs(5), "{args:?} took {:?}", start.elapsed());
        assert!(snapshot(t).is_empty(), "{args:?} left files");
    }
    // 16 keys x 16 values: refused before anything is written, naming the size
    let mut args: Vec<String> = ["simulate", "--out", "o"].map(String::from).to_vec();
    for key in ["mass", "stiffness", "normal_force", "friction_coefficient"] {
        args.extend(["--set".into(), format!("model.{key}=[{}]", (1..=16).map(|i| i.to_string()).collect::<Vec<_>>().join(","))]);
    }
    for key in ["speed", "switch_rate"] {
        args.extend(["--set".into(), format!("belt.{key}=[{}]", (1..=16).map(|i| i.to_string()).collect::<Vec<_>>().join(","))]);
    }
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(&stickslip(&refs, t), "cells");
    // hive names of the largest and smallest values are short, and an analysis of the shortest
    // window has no NaN
    ok(&stickslip(&["simulate", "--out", "w", "--realizations", "20", "-q", "--set", "model.mass=[1e6, 1e-9]", "--set", "run.duration=1e-9"], t));
    assert!(t.join("w/mass=1000000/part-00000-of-00001.parquet").is_file());
    assert!(t.join("w/mass=0.000000001/part-00000-of-00001.parquet").is_file());
    ok(&stickslip(&["analyze", "w", "--out", "wa", "-q"], t));
    for (path, _) in snapshot(&t.join("wa")).iter().filter(|(p, _)| p.extension().is_some_and(|x| x == "parquet")) {
        let table = stickslip::table::Table::read_parquet(path).unwrap();
        for (name, col) in &table.columns {
            if let stickslip::table::Col::Float(v) = col {
                assert!(v.iter().flatten().all(|x| x.is_finite()), "{}: column {name} has a non-finite value", path.display());
            }
        }
    }
}

#[test]
fn causes_are_printed_once() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["simulate", "missing.toml", "--out", "o"], tmp.path());
    refused(&o, "missing.toml");
    assert_eq!(err(&o).matches("No such file").count(), 1, "{}", err(&o));
    let o = stickslip(&["analyze", "nothing", "--out", "a"], tmp.path());
    refused(&o, "nothing");
    assert_eq!(err(&o).matches("No such file").count(), 1, "{}", err(&o));
}

#[test]
fn incomplete_overlapping_and_duplicated_parts_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "half", "--realizations", "1000", "--shard", "0/2", "-q"], t));
    refused(&stickslip(&["analyze", "half", "--out", "a"], t), "500..1000");
    ok(&stickslip(&["analyze", "half", "--out", "a", "--allow-partial", "-q"], t));
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(t.join("a/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["dataset"]["complete"], false);
    assert_eq!(summary["dataset"]["missing_ranges"][0], "500..1000");
    assert_eq!(summary["dataset"]["realizations"], 500);
    ok(&stickslip(&["figures", "a", "--out", "f", "-q"], t));
    ok(&stickslip(&["report", "half", "a", "f", "--out", "r.html", "-q"], t));
    assert!(std::fs::read_to_string(t.join("r.html")).unwrap().contains("PARTIAL"));
    // a copied part overlaps its original
    ok(&stickslip(&["simulate", "--out", "dup", "--realizations", "300", "-q"], t));
    std::fs::copy(t.join("dup/part-00000-of-00001.parquet"), t.join("dup/part-00000-of-00001 (copy).parquet")).unwrap();
    refused(&stickslip(&["analyze", "dup", "--out", "a2"], t), "overlap");
    // shards of two different splits raced into one directory
    ok(&stickslip(&["simulate", "--out", "mix", "--realizations", "300", "--shard", "0/2", "-q"], t));
    std::fs::create_dir(t.join("other")).unwrap();
    ok(&stickslip(&["simulate", "--out", "other", "--realizations", "300", "--shard", "0/3", "-q"], t));
    std::fs::copy(t.join("other/part-00000-of-00003.parquet"), t.join("mix/part-00000-of-00003.parquet")).unwrap();
    ok(&stickslip(&["simulate", "--out", "other", "--realizations", "300", "--shard", "1/3", "-q"], t));
    refused(&stickslip(&["analyze", "mix", "--out", "a3"], t), "overlap");
    assert!(!t.join("a2").exists() && !t.join("a3").exists());
}

/// Rewrite the part file in `dir` with `column` replaced by `f(column)` (metadata kept).
pub(crate) fn mutate(dir: &Path, column: &str, f: impl Fn(&ArrayRef) -> ArrayRef) {
    rewrite(dir, &[column], f, |kv| kv)
}

/// Rewrite the part file in `dir` with each of `columns` replaced by `f(column)` and its
/// key-value metadata by `meta(metadata)`.
pub(crate) fn rewrite(
    dir: &Path,
    columns: &[&str],
    f: impl Fn(&ArrayRef) -> ArrayRef,
    meta: impl Fn(Option<Vec<parquet::file::metadata::KeyValue>>) -> Option<Vec<parquet::file::metadata::KeyValue>>,
) {
    let path = dir.join("part-00000-of-00001.parquet");
    let builder = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&path).unwrap()).unwrap();
    let kv = meta(builder.metadata().file_metadata().key_value_metadata().cloned());
    let batches: Vec<RecordBatch> = builder.build().unwrap().map(Result::unwrap).collect();
    let schema = batches[0].schema();
    let at: Vec<usize> = columns.iter().map(|c| schema.index_of(c).unwrap()).collect();
    let mutated: Vec<Vec<ArrayRef>> = batches
        .iter()
        .map(|b| {
            let mut cols = b.columns().to_vec();
            for &i in &at {
                cols[i] = f(&cols[i]);
            }
            cols
        })
        .collect();
    let fields: Vec<Field> =
        schema.fields().iter().enumerate().map(|(j, fl)| Field::new(fl.name(), mutated[0][j].data_type().clone(), fl.is_nullable())).collect();
    let schema = Arc::new(arrow_schema::Schema::new(fields));
    let props = WriterProperties::builder().set_key_value_metadata(kv).build();
    let mut w = ArrowWriter::try_new(std::fs::File::create(&path).unwrap(), schema.clone(), Some(props)).unwrap();
    for cols in mutated {
        w.write(&RecordBatch::try_new(schema.clone(), cols).unwrap()).unwrap();
    }
    w.close().unwrap();
}

/// The footer edit of [`rewrite`] that sets `key` to `value`.
pub(crate) fn footer_set(
    key: &'static str,
    value: &'static str,
) -> impl Fn(Option<Vec<parquet::file::metadata::KeyValue>>) -> Option<Vec<parquet::file::metadata::KeyValue>> {
    move |kv| {
        kv.map(|kv| {
            kv.into_iter()
                .map(|mut e| {
                    if e.key == key {
                        e.value = Some(value.into());
                    }
                    e
                })
                .collect()
        })
    }
}

/// A list<f64> column with element `at` of the flattened values replaced by `value` (None: null).
pub(crate) fn list_with(col: &ArrayRef, at: usize, value: Option<f64>) -> ArrayRef {
    let l = col.as_any().downcast_ref::<ListArray>().unwrap();
    let vals = l.values().as_any().downcast_ref::<Float64Array>().unwrap();
    let mut v: Vec<Option<f64>> = vals.iter().collect();
    v[at] = value;
    let field = Arc::new(Field::new("element", DataType::Float64, true));
    Arc::new(ListArray::new(field, OffsetBuffer::new(l.offsets().inner().clone()), Arc::new(Float64Array::from(v)), None))
}

/// A list<f64> column with the last element of row `row`'s list removed.
fn list_shortened(col: &ArrayRef, row: usize) -> ArrayRef {
    let l = col.as_any().downcast_ref::<ListArray>().unwrap();
    let vals = l.values().as_any().downcast_ref::<Float64Array>().unwrap();
    let o = l.offsets();
    let cut = o[row + 1] as usize - 1;
    let v: Vec<f64> = vals.values().iter().enumerate().filter(|(i, _)| *i != cut).map(|(_, x)| *x).collect();
    let offsets: Vec<i32> = o.iter().enumerate().map(|(i, &x)| if i > row { x - 1 } else { x }).collect();
    let field = Arc::new(Field::new("element", DataType::Float64, true));
    Arc::new(ListArray::new(field, OffsetBuffer::new(offsets.into()), Arc::new(Float64Array::from(v)), None))
}

fn ints_with(col: &ArrayRef, f: impl Fn(usize, i64) -> i64) -> ArrayRef {
    let a = col.as_any().downcast_ref::<Int64Array>().unwrap();
    Arc::new(Int64Array::new(a.values().iter().enumerate().map(|(i, &x)| f(i, x)).collect(), None::<NullBuffer>))
}

#[test]
fn bad_values_in_a_schema_valid_file_are_refused_with_row_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let cases: Vec<(&str, &str, Box<dyn Fn(&ArrayRef) -> ArrayRef>, &str)> = vec![
        ("nan", "stick_start", Box::new(|c| list_with(c, 3, Some(f64::NAN))), "NaN"),
        ("inf", "slip_start", Box::new(|c| list_with(c, 3, Some(f64::INFINITY))), "inf"),
        ("null", "stick_start", Box::new(|c| list_with(c, 0, None)), "null"),
        ("negative", "stick_duration", Box::new(|c| list_with(c, 5, Some(-0.25))), "-0.25"),
        // finite, positive, in order, but beyond the horizon (issue 20, item 6: it crashed a sketch)
        ("beyond", "stick_duration", Box::new(|c| list_with(c, 40, Some(1.4e306))), "t_a = 10"),
        ("count", "n_stick", Box::new(|c| ints_with(c, |i, x| if i == 7 { x + 1 } else { x })), "n_stick"),
        ("huge", "n_stick", Box::new(|c| ints_with(c, |i, x| if i == 0 { 1 << 31 } else { x })), "2147483648"),
        ("ids", "realization", Box::new(|c| ints_with(c, |_, _| 0)), "realization 1"),
        // issue 21 review: Q without its list, and durations that overlap, break no per-value rule
        ("q", "n_switches", Box::new(|c| ints_with(c, |i, x| if i == 3 { -1 } else { x })), "-1"),
        ("overlap", "stick_duration", Box::new(|c| list_with(c, 0, Some(9.99))), "more than t_a"),
        // issue 22: one entry state per stick (the tails explode them beside the durations)
        ("entries", "stick_entry_position", Box::new(|c| list_shortened(c, 4)), "one per stick"),
    ];
    for (name, column, f, culprit) in cases {
        let dir = t.join(name);
        ok(&stickslip(&["simulate", "--out", name, "--realizations", "200", "-q"], t));
        mutate(&dir, column, f);
        let o = stickslip(&["analyze", name, "--out", "a"], t);
        refused(&o, culprit);
        let e = err(&o);
        assert!(e.contains("part-00000-of-00001.parquet") && e.contains(column) && e.contains("row"), "{name}: {e}");
        assert!(!t.join("a").exists());
    }
}

#[test]
fn a_file_replaced_during_analysis_is_detected() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "300", "-q"], t));
    let data = stickslip::analysis::input::open(&t.join("d")).unwrap();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "300", "--seed", "9", "-q"], t));
    let e = stickslip::analysis::analyze_dataset(data, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("changed while it was being analysed"), "{e}");
}

#[test]
fn figures_and_report_check_every_table_they_read() {
    use polars::prelude::*;
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "300", "-q"], t));
    ok(&stickslip(&["simulate", "--out", "d2", "--realizations", "300", "--seed", "5", "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", "a", "-q"], t));
    ok(&stickslip(&["figures", "a", "--out", "f", "-q"], t));
    let rewrite = |file: &str, f: &dyn Fn(DataFrame) -> DataFrame| {
        let p = t.join("a").join(file);
        let df = ParquetReader::new(std::fs::File::open(&p).unwrap()).finish().unwrap();
        let mut df = f(df);
        ParquetWriter::new(std::fs::File::create(&p).unwrap()).finish(&mut df).unwrap();
    };
    // the analysis of another dataset
    refused(&stickslip(&["report", "d2", "a", "f", "--out", "r.html"], t), "another dataset");
    rewrite("histograms.parquet", &|df| df.drop("density").unwrap());
    refused(&stickslip(&["figures", "a", "--out", "f2"], t), "density");
    rewrite("moments.parquet", &|mut df| {
        let s = df.column("mean").unwrap().cast(&DataType::String).unwrap();
        df.with_column(s).unwrap();
        df
    });
    refused(&stickslip(&["report", "d", "a", "f", "--out", "r.html"], t), "mean");
    assert!(!t.join("f2").exists() && !t.join("r.html").exists());
}

#[test]
fn exit_codes_tell_bad_input_from_failures() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    assert_eq!(stickslip(&["simulate", "--no-such-flag"], t).status.code(), Some(2));
    assert_eq!(stickslip(&["simulate", "--out", "o", "--set", "model.mass=-1"], t).status.code(), Some(2));
    // a failure while running: the output directory cannot be written
    std::fs::create_dir(t.join("ro")).unwrap();
    std::fs::set_permissions(t.join("ro"), std::os::unix::fs::PermissionsExt::from_mode(0o555)).unwrap();
    let o = stickslip(&["simulate", "--out", "ro/d", "--realizations", "10"], t);
    let root = unsafe { libc::geteuid() } == 0; // root writes anywhere
    if !root {
        assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    }
    for sub in ["simulate", "analyze", "figures", "report", "reproduce", "tradeoff", "completions"] {
        let o = stickslip(&[sub, "--help"], t);
        assert!(String::from_utf8_lossy(&o.stdout).contains("--quiet"), "{sub} has no -q/--quiet");
    }
}

/// Random TOML-ish text and `--set` strings: the loader never panics, and every rejection
/// names a key, the file or the --set argument.
fn names_a_culprit(e: &str, keys: &[&str]) -> bool {
    e.contains("scenario key") || e.contains("<scenario>") || e.contains("--set") || keys.iter().any(|k| e.contains(k))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn the_scenario_loader_never_panics(
        text in "(\\[(model|belt|run|numerics|output|initial_conditions|x)\\]\n)?([a-z_]{1,12} = (-?[0-9.e+-]{1,8}|\"[a-z]{0,5}\"|\\[[0-9, .-]{0,10}\\]|true|\\{ dist = \"uniform\" \\})\n){0,4}",
        set in "[a-z_.]{0,24}=?[ -~]{0,16}",
    ) {
        let paper: toml::Table = stickslip::scenario::PAPER_TOML.parse().unwrap();
        let keys: Vec<String> = paper.iter().flat_map(|(s, t)| t.as_table().unwrap().keys().map(move |k| format!("{s}.{k}"))).collect();
        let refs: Vec<&str> = keys.iter().map(String::as_str).collect();
        // a panic fails the property (proptest catches it and shrinks the input)
        if let Err(e) = Scenario::from_text(Some(&text), Path::new("<scenario>"), std::slice::from_ref(&set)) {
            let e = e.to_string();
            prop_assert!(names_a_culprit(&e, &refs), "{e}");
        }
        if let Err(e) = Scenario::resolve_sweep(None, std::slice::from_ref(&set), Default::default()) {
            let e = e.to_string();
            prop_assert!(names_a_culprit(&e, &refs), "{e}");
        }
    }

    #[test]
    fn mutated_paper_scenarios_are_loaded_or_refused_by_name(pos in 0usize..2000, byte in 0u8..128) {
        let mut text = stickslip::scenario::PAPER_TOML.as_bytes().to_vec();
        let at = pos % text.len();
        text[at] = byte;
        let Ok(text) = String::from_utf8(text) else { return Ok(()) };
        if let Err(e) = Scenario::from_text(Some(&text), Path::new("<scenario>"), &[]) {
            prop_assert!(names_a_culprit(&e.to_string(), &[]), "{e}");
        }
    }
}

#[test]
fn schema_v1_datasets_still_analyse() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    for d in ["v2", "v1"] {
        ok(&stickslip(&["simulate", "--out", d, "--realizations", "2000", "-q"], t));
    }
    // v1: int32 counts and schema_version 1
    let to_i32 = |c: &ArrayRef| -> ArrayRef {
        let a = c.as_any().downcast_ref::<Int64Array>().unwrap();
        Arc::new(arrow_array::Int32Array::from(a.values().iter().map(|&x| x as i32).collect::<Vec<_>>()))
    };
    rewrite(&t.join("v1"), &["n_switches", "n_stick", "n_slip"], to_i32, footer_set("stickslip.schema_version", "1"));
    // v2: the same columns labelled version 2 (the tails' columns of v3 are then not read: a part's
    // version, not the columns it happens to hold, says what it has)
    rewrite(&t.join("v2"), &[], |c| c.clone(), footer_set("stickslip.schema_version", "2"));
    let file = t.join("v1/part-00000-of-00001.parquet");
    let schema = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&file).unwrap()).unwrap().schema().clone();
    assert_eq!(schema.field_with_name("n_stick").unwrap().data_type(), &DataType::Int32);
    // the same v1 part as another Parquet writer leaves it: no embedded Arrow schema (DuckDB,
    // parquet-mr), the counts plain INT32 (issue 20, item 22)
    std::fs::create_dir(t.join("v1-plain")).unwrap();
    std::fs::copy(t.join("v1/.stickslip-dataset"), t.join("v1-plain/.stickslip-dataset")).unwrap();
    {
        let builder = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&file).unwrap()).unwrap();
        let kv = builder.metadata().file_metadata().key_value_metadata().cloned();
        let kv: Option<Vec<_>> = kv.map(|kv| kv.into_iter().filter(|e| e.key.starts_with("stickslip.")).collect());
        let schema = builder.schema().clone();
        let props = WriterProperties::builder().set_key_value_metadata(kv).build();
        let options = parquet::arrow::arrow_writer::ArrowWriterOptions::new().with_properties(props).with_skip_arrow_metadata(true);
        let out = std::fs::File::create(t.join("v1-plain/part-00000-of-00001.parquet")).unwrap();
        let mut w = ArrowWriter::try_new_with_options(out, schema, options).unwrap();
        for b in builder.build().unwrap() {
            w.write(&b.unwrap()).unwrap();
        }
        w.close().unwrap();
    }
    for d in ["v2", "v1", "v1-plain"] {
        ok(&stickslip(&["analyze", d, "--out", &format!("{d}-a"), "-q"], t));
    }
    for table in ["moments", "histograms", "growth"] {
        let read = |d: &str| stickslip::table::Table::read_parquet(&t.join(format!("{d}-a/{table}.parquet"))).unwrap();
        let (a, b, c) = (read("v1"), read("v2"), read("v1-plain"));
        assert_eq!(format!("{:?}", a.columns), format!("{:?}", b.columns), "{table}: v1 and v2 analyses differ");
        assert_eq!(format!("{:?}", c.columns), format!("{:?}", b.columns), "{table}: v1 without an Arrow schema and v2 analyses differ");
    }
}

/// Issue 20, item 1: stale-entry cleanup removes only entries the tool can prove it wrote.
#[test]
fn only_entries_the_tool_provably_wrote_are_ever_deleted() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "200", "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", "uan", "-q"], t));
    ok(&stickslip(&["figures", "uan", "--out", "fig", "-q"], t));
    // the user's entries with names like the tool's hidden ones
    let users = [
        ".uan.old-backup/keep.txt",
        ".uan.tmp-notes",
        ".uan.stickslip-tmp-notes",
        ".rep.html.old",
        "d/.part-00000-of-00001.parquet.old",
        "d/.part-00000-of-00001.parquet.tmp",
    ];
    for u in users {
        let p = t.join(u);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, "mine").unwrap();
    }
    // a directory with the tool's exact temporary name but none of its tags: not provably ours
    std::fs::create_dir(t.join(".uan.stickslip-tmp-1-2-ab")).unwrap();
    std::fs::write(t.join(".uan.stickslip-tmp-1-2-ab/mine.txt"), "mine").unwrap();
    // what a SIGKILLed analyze leaves: a staging directory with its tag, and an old copy with its
    // marker, which lists every file in it
    let marker = r#"{"kind": "analysis", "stickslip": "0.1.0", "files": ["moments.parquet"]}"#;
    for (dir, tag, text) in [(".uan.stickslip-tmp-7-0-1f", ".stickslip-staging", ""), (".uan.stickslip-old-7-1-2e", ".stickslip-output", marker)] {
        std::fs::create_dir(t.join(dir)).unwrap();
        std::fs::write(t.join(dir).join(tag), text).unwrap();
        std::fs::write(t.join(dir).join("moments.parquet"), "").unwrap();
    }
    // a directory of that exact form with a marker, holding a file the marker does not list: the
    // user's (issue 44, item 18)
    std::fs::create_dir(t.join(".uan.stickslip-old-1-2-ab")).unwrap();
    std::fs::write(t.join(".uan.stickslip-old-1-2-ab/.stickslip-output"), marker).unwrap();
    std::fs::write(t.join(".uan.stickslip-old-1-2-ab/mine.txt"), "mine").unwrap();
    std::fs::write(t.join("d/.part-00000-of-00001.parquet.stickslip-tmp-7-2-3d"), "stale").unwrap();
    ok(&stickslip(&["analyze", "d", "--out", "uan", "-q"], t));
    ok(&stickslip(&["report", "d", "uan", "fig", "--out", "rep.html", "-q"], t));
    ok(&stickslip(&["report", "d", "uan", "fig", "--out", "rep.html", "-q"], t));
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "200", "-q"], t));
    for u in users {
        assert_eq!(std::fs::read_to_string(t.join(u)).unwrap(), "mine", "{u} was touched");
    }
    assert!(t.join(".uan.stickslip-tmp-1-2-ab/mine.txt").is_file());
    assert!(t.join(".uan.stickslip-old-1-2-ab/mine.txt").is_file());
    for gone in [".uan.stickslip-tmp-7-0-1f", ".uan.stickslip-old-7-1-2e", "d/.part-00000-of-00001.parquet.stickslip-tmp-7-2-3d"] {
        assert!(!t.join(gone).exists(), "the stale {gone} stays");
    }
}

/// Issue 20, item 22: an output name near NAME_MAX works (hidden names are shortened, distinct).
#[test]
fn an_output_name_near_name_max_works() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "100", "-q"], t));
    let (a, b) = ("a".repeat(240), format!("{}b", "a".repeat(239)));
    ok(&stickslip(&["analyze", "d", "--out", &a, "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", &b, "-q"], t));
    ok(&stickslip(&["analyze", "d", "--out", &a, "-q"], t));
    assert!(t.join(&a).join("summary.json").is_file() && t.join(&b).join("summary.json").is_file());
    assert!(hidden_leftovers(t).is_empty(), "{:?}", hidden_leftovers(t));
}

/// Issue 20, item 22: an interrupted run removes the directories it created (and its lone marker).
#[test]
fn an_interrupted_run_removes_the_directories_it_created() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    for signal in [libc::SIGINT, libc::SIGTERM] {
        let o = interrupt(&["simulate", "--out", "new/deeper/d", "--realizations", "3000000", "--threads", "1", "-q"], t, t, signal);
        assert_eq!(o.status.code(), Some(128 + signal), "{}", err(&o));
        assert!(!t.join("new").exists(), "left {:?}", names_below(t));
        let o = interrupt(&["reproduce", "--out", "top/r", "--realizations", "3000000", "--threads", "1", "-q"], t, t, signal);
        assert_eq!(o.status.code(), Some(128 + signal), "{}", err(&o));
        assert!(!t.join("top").exists(), "left {:?}", names_below(t));
    }
}

/// Issue 20, item 1 (review): a user's file with the lock's name is neither emptied nor removed.
#[test]
fn a_users_file_with_the_locks_name_is_left_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "100", "-q"], t));
    std::fs::write(t.join(".an.stickslip-lock"), "user notes").unwrap();
    refused(&stickslip(&["analyze", "d", "--out", "an"], t), "not a stickslip lock file");
    assert_eq!(std::fs::read_to_string(t.join(".an.stickslip-lock")).unwrap(), "user notes");
    assert!(!t.join("an").exists());
}

/// Trajectory tables another run left beside a dataset are not taken for its realizations.
#[test]
fn trajectories_of_another_run_are_not_used() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    ok(&stickslip(&["simulate", "--out", "ds", "--realizations", "100", "-q", "--set", "output.trajectories=2"], t));
    ok(&stickslip(&["analyze", "ds", "--out", "a1", "-q"], t));
    assert!(t.join("a1/trajectory_samples.parquet").is_file(), "this run's trajectories are used");
    std::fs::remove_dir_all(t.join("ds")).unwrap();
    ok(&stickslip(&["simulate", "--out", "ds", "--realizations", "100", "--seed", "99", "-q", "--set", "belt.speed=3"], t));
    assert!(t.join("ds.trajectories/samples.parquet").is_file(), "the earlier run's tables are still there");
    ok(&stickslip(&["analyze", "ds", "--out", "a2", "-q"], t));
    assert!(!t.join("a2/trajectory_samples.parquet").exists() && !t.join("a2/trajectory_events.parquet").exists());
}

/// A dataset recorded before a range tightened stays readable: its scenario is provenance, not
/// re-validated (issue 21, item 3) — but the window the analysis computes with is still bounded.
#[test]
fn a_recorded_scenario_is_read_as_provenance() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let with_scenario = |edit: &'static str, by: &'static str| {
        move |kv: Option<Vec<parquet::file::metadata::KeyValue>>| {
            kv.map(|kv| {
                kv.into_iter()
                    .map(|mut e| {
                        if e.key == "stickslip.scenario" {
                            e.value = e.value.map(|v| v.replacen(edit, by, 1));
                        }
                        e
                    })
                    .collect()
            })
        }
    };
    let same = |c: &ArrayRef| c.clone();
    // mass 1e-12 kg: below today's range, written by an earlier version
    ok(&stickslip(&["simulate", "--out", "old", "--realizations", "200", "-q"], t));
    rewrite(&t.join("old"), &["n_stick"], same, with_scenario("mass = 1.0", "mass = 1e-12"));
    ok(&stickslip(&["analyze", "old", "--out", "a", "-q"], t));
    ok(&stickslip(&["figures", "a", "--out", "f", "-q"], t));
    // a recorded window past what the analysis is proven on is refused, naming it
    ok(&stickslip(&["simulate", "--out", "wide", "--realizations", "200", "-q"], t));
    rewrite(&t.join("wide"), &["n_stick"], same, with_scenario("duration = 10.0", "duration = 1e200"));
    refused(&stickslip(&["analyze", "wide", "--out", "b"], t), "run.duration");
}
