//! Throughput benchmark (`cargo bench --bench throughput`): numbers for the README.
//!
//! 1. The exact solver alone on the paper scenario, one thread: realizations per second.
//! 2. `simulate` end to end to Parquet with all cores, for 10^5 and 10^6 realizations, each in a
//!    fresh child process so that its peak RSS (VmHWM) is its own.

use std::process::Command;
use std::time::Instant;

use stickslip::ensemble::{Ensemble, Outcome};
use stickslip::scenario::Scenario;
use stickslip::simulate::{self, Options, Shard};

fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn child(n: u64) {
    let dir = tempfile::tempdir().unwrap();
    let sc = Scenario::paper().with("run.realizations", &n.to_string()).unwrap();
    let opts = Options { out: dir.path().to_owned(), shard: Shard::WHOLE, threads: None, progress: false };
    let s = simulate::run(&sc, &opts).unwrap();
    let bytes = std::fs::metadata(&s.path).unwrap().len();
    println!(
        "simulate -> Parquet  N = {n:>8}: {:7.2} s  {:>9.0} realizations/s  peak RSS {:6.1} MiB  file {:6.1} MiB  mean S_T {:.3}",
        s.seconds,
        n as f64 / s.seconds,
        peak_rss_mib(),
        bytes as f64 / (1 << 20) as f64,
        s.total_sticks as f64 / n as f64
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(pos) = args.iter().position(|a| a == "--child") {
        child(args[pos + 1].parse().unwrap());
        return;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("machine: {cores} cores");

    let ens = Ensemble::new(&Scenario::paper());
    let mut out = Outcome::default();
    let mut sticks = 0usize;
    for i in 0..10_000 {
        ens.realization(i, &mut out).unwrap();
    }
    let n = 200_000u64;
    let start = Instant::now();
    for i in 0..n {
        ens.realization(i, &mut out).unwrap();
        sticks += out.record.stick_start.len();
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "exact solver, 1 thread, paper scenario: {:.0} realizations/s ({:.2} us each, mean S_T {:.3})",
        n as f64 / secs,
        1e6 * secs / n as f64,
        sticks as f64 / n as f64
    );

    let exe = std::env::current_exe().unwrap();
    for n in [100_000u64, 1_000_000] {
        let status = Command::new(&exe).args(["--child", &n.to_string()]).status().unwrap();
        assert!(status.success());
    }
}
