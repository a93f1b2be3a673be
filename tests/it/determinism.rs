//! Determinism: the same bytes for any thread count; shards add up to the whole run.

use polars::prelude::*;
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::scenario;
use crate::dataset::read_dir;

fn run(dir: &std::path::Path, shard: Shard, threads: usize) -> std::path::PathBuf {
    run_with(dir, shard, threads, &[])
}

fn run_with(dir: &std::path::Path, shard: Shard, threads: usize, extra: &[&str]) -> std::path::PathBuf {
    let mut sets = vec!["run.realizations=3000", "run.seed=42", "output.switch_times=true"];
    sets.extend_from_slice(extra);
    let sc = scenario(&sets);
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

/// A chain with a Markov anchor and a drawn normal force: its other masses' initial state and
/// the anchor's path come from their own sub-streams, so threads and shards change nothing.
const CHAIN: [&str; 6] = [
    "chain.masses=[0.5, 0.5]",
    "chain.stiffnesses=[4.0, 16.0]",
    "chain.dampings=[0.1, 0.2]",
    "anchor.process=\"markov\"",
    "anchor.velocities=[0.5, 1.5]",
    "anchor.rates=[[0, 1], [2, 0]]",
];

#[test]
fn a_chain_is_the_same_for_any_threads_and_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let mut sets = CHAIN.to_vec();
    sets.push("model.normal_force={ dist = \"uniform\", low = 8.0, high = 11.0 }");
    let sets = sets.as_slice();
    let a = std::fs::read(run_with(&tmp.path().join("t1"), Shard::WHOLE, 1, sets)).unwrap();
    let b = std::fs::read(run_with(&tmp.path().join("t2"), Shard::WHOLE, 2, sets)).unwrap();
    assert!(a == b, "thread count changed a chain's output bytes");
    for i in 0..2 {
        run_with(&tmp.path().join("sharded"), Shard { index: i, count: 2 }, 1, sets);
    }
    let whole = read_dir(&tmp.path().join("t2"));
    let sharded = read_dir(&tmp.path().join("sharded")).sort(["realization"], SortMultipleOptions::default()).unwrap();
    assert!(whole.equals(&sharded), "sharded chain rows differ from the whole run");
}
