//! Determinism: the same bytes for any thread count; shards add up to the whole run.

use polars::prelude::*;
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::scenario;
use crate::dataset::read_dir;

fn run(dir: &std::path::Path, shard: Shard, threads: usize) -> std::path::PathBuf {
    let sc = scenario(&["run.realizations=3000", "run.seed=42", "output.switch_times=true"]);
    let opts = Options { out: dir.to_owned(), shard, threads: Some(threads) };
    simulate::run(&sc.plan().unwrap(), &opts).expect("simulate").path
}

#[test]
fn same_bytes_for_one_and_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let a = std::fs::read(run(&tmp.path().join("t1"), Shard::WHOLE, 1)).unwrap();
    let b = std::fs::read(run(&tmp.path().join("t2"), Shard::WHOLE, 2)).unwrap();
    assert!(a.len() > 10_000);
    assert!(a == b, "thread count changed the output bytes");
}

#[test]
fn shards_union_equals_the_unsharded_run() {
    let tmp = tempfile::tempdir().unwrap();
    run(&tmp.path().join("whole"), Shard::WHOLE, 2);
    for i in 0..3 {
        run(&tmp.path().join("sharded"), Shard { index: i, count: 3 }, 1 + i as usize % 2);
    }
    let whole = read_dir(&tmp.path().join("whole"));
    let sharded = read_dir(&tmp.path().join("sharded")).sort(["realization"], SortMultipleOptions::default()).unwrap();
    assert_eq!(whole.height(), 3000);
    assert!(whole.equals(&sharded), "sharded rows differ from the whole run");
}
