//! `simulate --target-se`: the dataset is the first N rows of a fixed-N run, for any thread count.

use polars::prelude::*;
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::{scenario, stickslip};
use crate::dataset::read_dir;

fn metadata(dir: &std::path::Path, key: &str) -> Option<String> {
    use parquet::file::reader::FileReader;
    let f = std::fs::File::open(dir.join("part-00000-of-00001.parquet")).unwrap();
    let r = parquet::file::reader::SerializedFileReader::new(f).unwrap();
    let kv = r.metadata().file_metadata().key_value_metadata().cloned().unwrap_or_default();
    kv.iter().find(|e| e.key == key).and_then(|e| e.value.clone())
}

#[test]
fn a_target_run_is_a_prefix_of_the_fixed_run() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let targets: [stickslip::observables::Target; 2] = ["S_T=0.06".parse().unwrap(), "H_1=0.005".parse().unwrap()];
    let mut sc = scenario(&[]);
    sc.run.realizations = 40_000;
    for (dir, threads) in [("t1", 1), ("t2", 2)] {
        let opts = Options { out: t.join(dir), shard: Shard::WHOLE, threads: Some(threads) };
        let s = simulate::compute_until(&sc.plan().unwrap(), &opts, &stickslip::observables::Target::tracked(&targets), stickslip::progress::Control::silent())
            .unwrap()
            .commit()
            .unwrap();
        assert!(s.targets.as_ref().is_some_and(|(met, _)| *met), "{:?}", s.targets);
    }
    let one = std::fs::read(t.join("t1/part-00000-of-00001.parquet")).unwrap();
    assert!(one == std::fs::read(t.join("t2/part-00000-of-00001.parquet")).unwrap(), "the thread count changed the stopping point");
    let n: u64 = metadata(&t.join("t1"), "stickslip.realizations").unwrap().parse().unwrap();
    assert!(n > 1000 && n < 40_000, "{n}");
    assert_eq!(metadata(&t.join("t1"), "stickslip.target_se_met").as_deref(), Some("true"));
    // the same seed, a fixed N of 3n: the target run is its first n rows
    sc.run.realizations = 3 * n;
    simulate::run(&sc.plan().unwrap(), &Options { out: t.join("fixed"), shard: Shard::WHOLE, threads: Some(2) }).unwrap();
    let prefix = read_dir(&t.join("fixed")).slice(0, n as usize);
    assert!(read_dir(&t.join("t1")).equals(&prefix));
    // and the SEs it stopped at are below the targets
    let st = prefix.column("n_stick").unwrap().cast(&DataType::Float64).unwrap();
    let st = st.f64().unwrap();
    let se = st.std(1).unwrap() / (n as f64).sqrt();
    assert!(se <= 0.06, "{se}");
    // analyze reads it as a complete run
    let a = stickslip::analysis::analyze(&t.join("t1"), &Default::default()).unwrap();
    assert_eq!(a.dataset.rows, n);
}

#[test]
fn each_shard_stops_at_its_own_target_and_the_union_is_complete() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let args = |shard: &'static str| ["simulate", "--out", "s", "--realizations", "100000", "--shard", shard, "--target-se", "S_T=0.08", "-q"];
    assert!(stickslip(&args("0/2"), t).status.success());
    // one shard alone: the other block is missing
    let o = stickslip(&["analyze", "s", "--out", "a0", "-q"], t);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    // only the missing block is named, not the tail shard 0 left out by design (issue 20, item 12)
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(e.contains("incomplete") && e.contains("lack 50000..100000;"), "{e}");
    assert!(stickslip(&args("1/2"), t).status.success());
    let a = stickslip::analysis::analyze(&t.join("s"), &Default::default()).expect("both shards: complete");
    assert!(a.dataset.missing.is_empty());
    // each shard is the start of its block of the fixed run: realizations 0.. and 50000..
    let d = read_dir(&t.join("s"));
    let idx = d.column("realization").unwrap().i64().unwrap().clone();
    let starts: Vec<i64> = (0..idx.len()).filter(|&r| r == 0 || idx.get(r).unwrap() != idx.get(r - 1).unwrap() + 1).map(|r| idx.get(r).unwrap()).collect();
    assert_eq!(starts, [0, 50_000]);
    assert_eq!(a.dataset.rows as usize, d.height());
    assert!(d.height() < 20_000, "each shard stopped early: {}", d.height());
}

#[test]
fn the_cap_is_reported_and_bad_targets_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["simulate", "--out", "c", "--realizations", "2000", "--target-se", "S_T=0.0001", "-q"], tmp.path());
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("cap of 2000"), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(metadata(&tmp.path().join("c"), "stickslip.target_se_met").as_deref(), Some("false"));
    let o = stickslip(&["simulate", "--out", "s", "--target-se", "Z=0.1", "-q"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(!tmp.path().join("s").exists());
}
