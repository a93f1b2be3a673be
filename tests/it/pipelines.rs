//! Pipelines and scale: sweeps, the make pipeline, real clients (Python polars and DuckDB).

use std::path::{Path, PathBuf};
use std::process::Command;

use stickslip::table::Table;

use crate::common::stickslip;

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}\n{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
}

/// Simulate and analyse a 3 × 2 sweep of (λ, μ) into `tmp/sweep`, `tmp/sweep-a`.
fn sweep(tmp: &Path) -> Table {
    let args = [
        "simulate",
        "--out",
        "sweep",
        "--realizations",
        "1500",
        "--quiet",
        "--set",
        "belt.switch_rate=[2.5, 10, 20.5]",
        "--set",
        "model.friction_coefficient=[0.3, 1.0]",
    ];
    ok(&stickslip(&args, tmp));
    ok(&stickslip(&["analyze", "sweep", "--out", "sweep-a", "--quiet"], tmp));
    Table::read_parquet(&tmp.join("sweep-a/sweep.parquet")).unwrap()
}

#[test]
fn sweep_maps_show_the_expected_trends() {
    let tmp = tempfile::tempdir().unwrap();
    let t = sweep(tmp.path());
    assert_eq!(t.height(), 6);
    let (lam, mu) = (t.floats("switch_rate").unwrap(), t.floats("friction_coefficient").unwrap());
    let (d, frac) = (t.floats("mean_D").unwrap(), t.floats("stick_fraction").unwrap());
    // cells in numeric order (by text, "switch_rate=10" would come before "switch_rate=2.5")
    let order: Vec<(f64, f64)> = (0..t.height()).map(|r| (lam[r].unwrap(), mu[r].unwrap())).collect();
    assert_eq!(order, [(2.5, 0.3), (2.5, 1.0), (10.0, 0.3), (10.0, 1.0), (20.5, 0.3), (20.5, 1.0)]);
    let at = |l: f64, m: f64, v: &[Option<f64>]| (0..t.height()).find(|&r| lam[r] == Some(l) && mu[r] == Some(m)).and_then(|r| v[r]).unwrap();
    for m in [0.3, 1.0] {
        // more switches → shorter sticks
        assert!(at(2.5, m, d) > at(10.0, m, d) && at(10.0, m, d) > at(20.5, m, d), "E[D] at μ = {m}");
    }
    for l in [2.5, 10.0, 20.5] {
        // more friction → more time in stick
        assert!(at(l, 1.0, frac) > at(l, 0.3, frac), "stick fraction at λ = {l}");
    }
    // the tails' columns (issue 22, item 4), each inside its own interval: sticks per second is
    // E[S_T]/t_a (t_a = 10 s); the rarer the belt flips, the more sticks last to breakaway
    let st = t.floats("mean_S_T").unwrap();
    for name in ["sticks_per_second", "longest_stick", "severity", "breakaway_fraction"] {
        let (v, lo, hi) = (t.floats(name).unwrap(), t.floats(&format!("{name}_lo")).unwrap(), t.floats(&format!("{name}_hi")).unwrap());
        for r in 0..t.height() {
            match (v[r].unwrap(), lo[r], hi[r]) {
                (v, Some(lo), Some(hi)) => assert!(lo <= v && v <= hi && v >= 0.0, "{name}, cell {r}: {v} [{lo}, {hi}]"),
                // a fraction of 0 has no band on the log scale (said so by a null)
                (v, None, None) => assert!(name == "breakaway_fraction" && v == 0.0, "{name}, cell {r}: {v} without a band"),
                other => panic!("{name}, cell {r}: {other:?}"),
            }
        }
    }
    let rate = t.floats("sticks_per_second").unwrap();
    for r in 0..t.height() {
        assert!((rate[r].unwrap() - st[r].unwrap() / 10.0).abs() < 1e-12, "sticks_per_second = mean S_T / t_a");
    }
    let b = t.floats("breakaway_fraction").unwrap();
    for m in [0.3, 1.0] {
        assert!(at(2.5, m, b) > at(20.5, m, b), "breakaway fraction at μ = {m}");
    }
    for s in ["1", "1.25"] {
        assert!(t.floats(&format!("p_severity_gt_{s}")).is_some(), "P(severity > {s}) for the default thresholds");
    }
    // each cell is a complete analysis, and has its own, reproducible stream
    assert!(tmp.path().join("sweep-a/switch_rate=10/friction_coefficient=1/moments.parquet").is_file());
    let part = |dir: &str| std::fs::read(tmp.path().join(dir).join("switch_rate=10/friction_coefficient=0.3/part-00000-of-00001.parquet")).unwrap();
    let args = [
        "simulate",
        "--out",
        "again",
        "--realizations",
        "1500",
        "--quiet",
        "--set",
        "belt.switch_rate=[10, 2.5, 20.5]",
        "--set",
        "model.friction_coefficient=[0.3, 1.0]",
    ];
    ok(&stickslip(&args, tmp.path()));
    assert!(part("sweep") == part("again"), "a cell's output must not depend on the grid's order");
    let x0 = |cell: &str| {
        let df = crate::dataset::read_dir(&tmp.path().join("sweep").join(cell));
        df.column("x0").unwrap().f64().unwrap().get(0).unwrap()
    };
    assert_ne!(x0("switch_rate=2.5/friction_coefficient=0.3"), x0("switch_rate=10/friction_coefficient=0.3"));
}

/// `make -f pipelines/Makefile ARGS` as a user runs it: the binary found through
/// CARGO_TARGET_DIR (as `.ci/run` sets it); returns make's stdout.
fn make(args: &[String]) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = Path::new(env!("CARGO_BIN_EXE_stickslip")).parent().and_then(Path::parent).expect("<target>/release/stickslip");
    let o = Command::new("make").current_dir(root).env("CARGO_TARGET_DIR", target).args(["-f", "pipelines/Makefile"]).args(args).output().expect("make runs");
    ok(&o);
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `make paper` on `scenario` in a fresh OUT.
fn make_paper(jobs: &str, scenario: &Path, out: &Path) -> String {
    make(&[jobs.into(), "paper".into(), format!("SCENARIO={}", scenario.display()), format!("OUT={}", out.display())])
}

#[test]
fn make_paper_is_incremental() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = tmp.path().join("small.toml");
    std::fs::write(&scenario, "[run]\nrealizations = 400\n").unwrap();
    let out = tmp.path().join("paper");
    let first = make_paper("-j2", &scenario, &out);
    for stage in [" simulate ", " analyze ", " figures ", " report "] {
        assert!(first.contains(stage), "first run misses{stage}: {first}");
    }
    assert!(out.join("report.html").is_file() && out.join("figures/fig04_trajectories.png").is_file());
    let second = make_paper("-j2", &scenario, &out);
    assert!(second.contains("Nothing to be done"), "second run: {second}");
    // editing the scenario re-runs the four stages, and compiles nothing
    std::thread::sleep(std::time::Duration::from_millis(1100));
    std::fs::write(&scenario, "[run]\nrealizations = 500\n").unwrap();
    let third = make_paper("-j1", &scenario, &out);
    for stage in [" simulate ", " analyze ", " figures ", " report "] {
        assert!(third.contains(stage), "after editing the scenario, no{stage}: {third}");
    }
    assert!(!third.contains("cargo build"), "editing a scenario recompiled: {third}");
    // the dataset directory holds part files only
    let names: Vec<String> = std::fs::read_dir(out.join("dataset")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| n.starts_with('.') || (n.starts_with("part-") && n.ends_with(".parquet"))), "{names:?}");
}

#[test]
fn make_law_is_incremental() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = tmp.path().join("law.toml");
    std::fs::write(&scenario, "[belt]\nswitch_rate = 2.0\n").unwrap();
    let out = tmp.path().join("law");
    let make = || make(&["law".into(), "LAW_RESOLUTION=16".into(), format!("SCENARIO={}", scenario.display()), format!("LAW_OUT={}", out.display())]);
    assert!(make().contains(" exact-law "));
    assert!(out.join("stationary.parquet").is_file() && out.join("density.parquet").is_file());
    assert!(make().contains("Nothing to be done"));
}

#[test]
fn a_reproduce_dataset_directory_reads_as_one_table_in_every_client() {
    // issue 20, item 13: the dataset directory of `reproduce` (trajectories sampled) holds part
    // files only, so directory readers take it whole; the trajectories sit beside it
    let tmp = tempfile::tempdir().unwrap();
    ok(&stickslip(&["reproduce", "--out", "r", "--realizations", "700", "-q"], tmp.path()));
    let d = tmp.path().join("r/dataset");
    let got = python(&format!(
        r#"
import polars as pl, pyarrow.dataset as ds, duckdb
print("polars_rows", pl.read_parquet("{d}/").height)
print("pyarrow_rows", ds.dataset("{d}", format="parquet").count_rows())
print("duckdb_rows", duckdb.sql("SELECT count(*) FROM read_parquet('{d}/*.parquet')").fetchall()[0][0])
s = pl.read_parquet("{d}.trajectories/samples.parquet")
e = pl.read_parquet("{d}.trajectories/events.parquet")
print("samples_realizations", s["realization"].n_unique())
print("samples_columns_ok", float(s.columns == ["realization", "t", "x", "xdot", "belt_velocity"] and s.null_count().sum_horizontal()[0] == 0))
print("events_kinds_ok", float(set(e["event"]) <= {{"belt_switch", "stick_start", "stick_end"}} and e.null_count().sum_horizontal()[0] == 0))
"#,
        d = d.display()
    ));
    for (name, value) in got {
        let want = match name.as_str() {
            "polars_rows" | "pyarrow_rows" | "duckdb_rows" => 700.0,
            "samples_realizations" => 3.0,
            _ => 1.0,
        };
        assert_eq!(value, want, "{name}");
    }
}

#[test]
fn make_paper_runs_a_sweep_once() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = tmp.path().join("sweep.toml");
    std::fs::write(&scenario, "[belt]\nswitch_rate = [2.5, 5]\n[run]\nrealizations = 300\n").unwrap();
    let out = tmp.path().join("sweep");
    let first = make_paper("-j2", &scenario, &out);
    for cell in ["switch_rate=2.5", "switch_rate=5"] {
        assert!(out.join("reports").join(cell).join("report.html").is_file(), "no report for {cell}: {first}");
    }
    let second = make_paper("-j2", &scenario, &out);
    assert!(second.contains("Nothing to be done"), "a sweep is simulated again: {second}");
}

/// Run a Python script (polars and duckdb must be installed: `.ci/run` does it) and parse
/// `name value` lines.
fn python(script: &str) -> Vec<(String, f64)> {
    let o = Command::new("python3").arg("-c").arg(script).output().expect("python3 runs");
    assert!(
        o.status.success(),
        "python failed (are polars, duckdb and pyarrow installed? `pip install polars duckdb pyarrow`, see .ci/run):\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).lines().filter_map(|l| l.rsplit_once(' ').map(|(k, v)| (k.to_string(), v.parse().unwrap()))).collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

#[test]
fn polars_and_duckdb_clients_agree_with_analyze() {
    let tmp = tempfile::tempdir().unwrap();
    ok(&stickslip(&["simulate", "--out", "d", "--realizations", "3000", "--quiet"], tmp.path()));
    ok(&stickslip(&["analyze", "d", "--out", "a", "--quiet"], tmp.path()));
    let dir: PathBuf = tmp.path().join("d");
    let script = format!(
        r#"
import polars as pl, duckdb
g = "{d}/part-*.parquet"
df = pl.scan_parquet(g).select(pl.col("n_stick").mean().alias("st"), pl.col("stick_start").list.get(1, null_on_oob=True).var().alias("v")).collect()
print("polars_mean_S_T", df["st"][0]); print("polars_var_T_2", df["v"][0])
st, v = duckdb.sql(f"SELECT avg(n_stick), var_samp(stick_start[2]) FROM read_parquet('{{g}}')").fetchall()[0]
print("duckdb_mean_S_T", st); print("duckdb_var_T_2", v)
# schema v2 as the clients see it: int64 counts, rows declared sorted by realization
full = pl.read_parquet(g)
print("polars_int64_counts", float(all(full.schema[c] == pl.Int64 for c in ["realization", "n_switches", "n_stick", "n_slip"])))
print("polars_sorted_flag", float(full["realization"].flags["SORTED_ASC"]))
types = duckdb.sql(f"SELECT typeof(n_switches), typeof(n_stick), typeof(n_slip) FROM read_parquet('{{g}}') LIMIT 1").fetchall()[0]
print("duckdb_bigint_counts", float(all(t == "BIGINT" for t in types)))
"#,
        d = dir.display()
    );
    let got = python(&script);
    let m = Table::read_parquet(&tmp.path().join("a/moments.parquet")).unwrap();
    let (var, idx) = (m.strings("variable").unwrap(), m.ints("index").unwrap());
    let row = |v: &str, i: Option<i64>| (0..m.height()).find(|&r| var[r] == v && idx[r] == i).unwrap();
    let ours_st = m.floats("mean").unwrap()[row("S_T", None)].unwrap();
    let ours_v = m.floats("variance").unwrap()[row("T", Some(2))].unwrap();
    let (stats, flags): (Vec<_>, Vec<_>) = got.iter().partition(|(n, _)| n.ends_with("S_T") || n.ends_with("T_2"));
    for (name, value) in &stats {
        let ours = if name.ends_with("S_T") { ours_st } else { ours_v };
        assert!(close(*value, ours), "{name} = {value}, analyze says {ours}");
    }
    assert_eq!(stats.len(), 4);
    assert_eq!(flags.len(), 3);
    for (name, value) in flags {
        assert_eq!(*value, 1.0, "{name}");
    }
}

/// The code block of the book's how-to "Query datasets with polars and DuckDB" that contains
/// `marker`.
fn book_block(marker: &str) -> String {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/how-to/query.md")).unwrap();
    let at = readme.find(marker).unwrap_or_else(|| panic!("the query how-to has no block with {marker:?}"));
    let start = readme[..at].rfind("```").and_then(|i| readme[i..].find('\n').map(|j| i + j + 1)).unwrap();
    let end = at + readme[at..].find("```").unwrap();
    readme[start..end].to_string()
}

#[test]
fn clients_read_a_hive_partitioned_sweep() {
    // the book's DuckDB and polars sweep queries, as written, on a sweep of non-integer keys:
    // typed keys in numeric order, values as analyze's (issue 20, item 15)
    let tmp = tempfile::tempdir().unwrap();
    let t = sweep(tmp.path());
    let dir = tmp.path().join("sweep");
    let sql = book_block("FROM read_parquet('data/sweep/").replace("data/sweep/", &format!("{}/", dir.display()));
    let polars = book_block("pl.scan_parquet(\"data/sweep/").replace("data/sweep/", &format!("{}/", dir.display()));
    let script = format!(
        r#"
import duckdb
{polars}
assert all(cells.schema[k] == pl.Float64 for k in keys), cells.schema
for r in cells.iter_rows(named=True):
    print(f"polars {{r['switch_rate']}}/{{r['friction_coefficient']}}", r["mean_S_T"])
print("polars_order", float(cells["switch_rate"].to_list() == sorted(cells["switch_rate"].to_list())))
rel = duckdb.sql("""{sql}""".rstrip().rstrip(";"))
assert [str(t) for t in rel.types[:2]] == ["DOUBLE", "DOUBLE"], rel.types
rows = rel.fetchall()
print("duckdb_order", float([r[0] for r in rows] == sorted(r[0] for r in rows)))
for a, b, n, st, v, f in rows:
    print(f"duckdb {{a}}/{{b}}", st)
    print(f"fraction {{a}}/{{b}}", f)
"#
    );
    let got = python(&script);
    assert_eq!(got.len(), 20, "{got:?}");
    let (lam, mu) = (t.floats("switch_rate").unwrap(), t.floats("friction_coefficient").unwrap());
    let (st, frac) = (t.floats("mean_S_T").unwrap(), t.floats("stick_fraction").unwrap());
    for (name, value) in &got {
        if name.ends_with("_order") {
            assert_eq!(*value, 1.0, "{name}: keys not in numeric order");
            continue;
        }
        let (client, cell) = name.split_once(' ').unwrap();
        let (l, m) = cell.split_once('/').unwrap();
        let (l, m): (f64, f64) = (l.parse().unwrap(), m.parse().unwrap());
        let r = (0..t.height()).find(|&r| lam[r] == Some(l) && mu[r] == Some(m)).unwrap_or_else(|| panic!("no cell {l}/{m}"));
        let ours = if client == "fraction" { frac[r] } else { st[r] }.unwrap();
        assert!(close(*value, ours), "{name} = {value}, sweep.parquet says {ours}");
    }
}
