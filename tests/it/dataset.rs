//! The dataset as users read it: through polars, with the contract's columns and metadata.

use polars::prelude::*;
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::{files_below, outcomes, scenario};

/// Read every part file below `dir` (recursively, in path order) with polars' Parquet reader and
/// stack them: the rows a `DIR/**/*.parquet` scan gives, without hive columns.
pub fn read_dir(dir: &std::path::Path) -> DataFrame {
    let files: Vec<_> = files_below(dir).into_iter().filter(|p| p.extension().is_some_and(|x| x == "parquet")).collect();
    let mut frames = files.iter().map(|p| ParquetReader::new(std::fs::File::open(p).unwrap()).finish().unwrap());
    let mut df = frames.next().expect("no part file");
    for f in frames {
        df.vstack_mut(&f).unwrap();
    }
    df
}

fn write(dir: &std::path::Path, sets: &[&str]) -> std::path::PathBuf {
    let opts = Options { out: dir.to_owned(), shard: Shard::WHOLE, threads: Some(2) };
    simulate::run(&scenario(sets).plan().unwrap(), &opts).expect("simulate").path
}

#[test]
fn polars_reads_the_contract_columns_and_values() {
    let tmp = tempfile::tempdir().unwrap();
    write(tmp.path(), &["run.realizations=500"]);
    let df = read_dir(tmp.path());
    let list = DataType::List(Box::new(DataType::Float64));
    let expected = [
        ("realization", DataType::Int64),
        ("x0", DataType::Float64),
        ("xdot0", DataType::Float64),
        ("n_switches", DataType::Int64),
        ("n_stick", DataType::Int64),
        ("n_slip", DataType::Int64),
        ("stick_start", list.clone()),
        ("stick_duration", list.clone()),
        ("slip_start", list.clone()),
        ("slip_duration", list.clone()),
        ("last_truncated", DataType::Boolean),
    ];
    for (name, dtype) in &expected {
        assert_eq!(df.column(name).unwrap().dtype(), dtype, "column {name}");
    }
    assert!(df.column("switch_times").is_err(), "switch_times only when asked");
    // the values are those of the library, row by row
    let sc = scenario(&["run.realizations=500"]);
    let lib = outcomes(&sc, 500);
    let n_stick = df.column("n_stick").unwrap().i64().unwrap();
    let starts = df.column("stick_start").unwrap().list().unwrap();
    for (i, o) in lib.iter().enumerate() {
        assert_eq!(n_stick.get(i), Some(o.record.stick_start.len() as i64));
        let s = starts.get_as_series(i).unwrap();
        let v: Vec<f64> = s.f64().unwrap().into_no_null_iter().collect();
        assert_eq!(v, o.record.stick_start);
    }
}

#[test]
fn switch_times_are_stored_when_asked_and_match_q() {
    let tmp = tempfile::tempdir().unwrap();
    write(tmp.path(), &["run.realizations=300", "output.switch_times=true"]);
    let df = read_dir(tmp.path());
    let q = df.column("n_switches").unwrap().i64().unwrap();
    let y = df.column("switch_times").unwrap().list().unwrap();
    for i in 0..df.height() {
        let s = y.get_as_series(i).unwrap();
        let v: Vec<f64> = s.f64().unwrap().into_no_null_iter().collect();
        assert_eq!(v.len() as i64, q.get(i).unwrap());
        assert!(v.windows(2).all(|w| w[0] <= w[1]) && v.iter().all(|&t| (0.0..10.0).contains(&t)));
    }
    // Q ~ Poisson(λ t_a = 50): mean and variance within 5 standard errors
    let n = df.height() as f64;
    let mean = q.into_no_null_iter().map(|c| c as f64).sum::<f64>() / n;
    assert!((mean - 50.0).abs() < 5.0 * (50.0 / n).sqrt(), "mean Q = {mean}");
}

#[test]
fn provenance_is_in_the_key_value_metadata() {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    let tmp = tempfile::tempdir().unwrap();
    let path = write(tmp.path(), &["run.realizations=10", "run.seed=7"]);
    let reader = SerializedFileReader::new(std::fs::File::open(path).unwrap()).unwrap();
    let kv = reader.metadata().file_metadata().key_value_metadata().unwrap().clone();
    let get = |k: &str| kv.iter().find(|e| e.key == k).and_then(|e| e.value.clone()).unwrap_or_default();
    assert_eq!(get("stickslip.seed"), "7");
    assert_eq!(get("stickslip.solver"), "exact");
    assert_eq!(get("stickslip.schema_version"), "4");
    assert_eq!(get("stickslip.version"), env!("CARGO_PKG_VERSION"));
    // every row group declares its sort by realization (column 0, ascending)
    for rg in reader.metadata().row_groups() {
        let sorting = rg.sorting_columns().expect("sorting_columns declared");
        assert_eq!((sorting[0].column_idx, sorting[0].descending), (0, false));
    }
    let toml: toml::Table = get("stickslip.scenario").parse().unwrap();
    assert_eq!(toml["run"]["realizations"].as_integer(), Some(10));
    assert_eq!(toml["model"]["friction_coefficient"].as_float(), Some(0.51));
}
