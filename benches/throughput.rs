//! Throughput benchmark (`cargo bench --bench throughput`): numbers for the README.
//!
//! 1. The exact solver alone on the paper scenario, one thread: realizations per second.
//! 2. The exact solver against `rk45` on the same 200 paper realizations, in the same run: the
//!    paper's ode45 settings, rtol = 1e-6 with the paper's other settings, and rtol = atol = 1e-6
//!    without a step limit.
//! 3. `simulate` end to end to Parquet with all cores, then `analyze` of that dataset, for 10^5
//!    and 10^6 realizations (and 10^7 with `--large`), each stage in a fresh child process so
//!    that its peak RSS (VmHWM) is its own. Events = all list elements in the dataset.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use stickslip::analysis;
use stickslip::scenario::Scenario;
use stickslip::simulation::ensemble::{Ensemble, Outcome};
use stickslip::simulation::simulate::{self, Options, Shard};
use stickslip::solver::SolverKind;

fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn simulate_child(n: u64, dir: &Path) {
    let mut sc = Scenario::paper();
    sc.run.realizations = n;
    let opts = Options { out: dir.to_owned(), shard: Shard::WHOLE, threads: None, progress: false };
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

fn analyze_child(n: u64, dir: &Path) {
    let start = Instant::now();
    let a = analysis::analyze(dir, &analysis::Options::default()).unwrap();
    analysis::output::write(&a, &dir.with_extension("analysis")).unwrap();
    let secs = start.elapsed().as_secs_f64();
    // every list element of the dataset: T, D (S_T each), L, H (S_L each)
    let st = a.stats.iter().find(|s| s.series.to_string() == "S_T").unwrap().moments;
    let sl = a.stats.iter().find(|s| s.series.to_string() == "S_L").unwrap().moments;
    let events = 2.0 * (st.mean + sl.mean) * n as f64;
    println!("analyze             N = {n:>8}: {secs:7.2} s  {:>9.1} M events/s  peak RSS {:6.1} MiB", events / secs / 1e6, peak_rss_mib());
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(pos) = args.iter().position(|a| a == "--simulate" || a == "--analyze") {
        let (n, dir) = (args[pos + 1].parse().unwrap(), Path::new(&args[pos + 2]));
        if args[pos] == "--simulate" {
            simulate_child(n, dir)
        } else {
            analyze_child(n, dir)
        }
        return;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("machine: {cores} cores");

    // The exact solver alone: 5 repetitions of 100,000 realizations (this VM's speed varies by
    // ±20% from run to run; best and median are reported).
    let ens = Ensemble::new(&Scenario::paper()).unwrap();
    let mut out = Outcome::default();
    for i in 0..10_000 {
        ens.realization(i, &mut out).unwrap();
    }
    let n = 100_000u64;
    let mut rates: Vec<f64> = (0..5)
        .map(|rep| {
            let start = Instant::now();
            for i in rep * n..(rep + 1) * n {
                ens.realization(i, &mut out).unwrap();
            }
            n as f64 / start.elapsed().as_secs_f64()
        })
        .collect();
    rates.sort_by(f64::total_cmp);
    println!("exact solver, 1 thread, paper scenario: best {:.0}, median {:.0} realizations/s (5 x {n})", rates[4], rates[2]);

    // The exact solver against rk45, same realizations, same run.
    {
        let per_realization = |set: &dyn Fn(&mut Scenario), n: u64, reps: u64| {
            let mut sc = Scenario::paper();
            set(&mut sc);
            sc.check().unwrap();
            let ens = Ensemble::new(&sc).unwrap();
            let mut out = Outcome::default();
            let start = Instant::now();
            for _ in 0..reps {
                for i in 0..n {
                    ens.realization(i, &mut out).unwrap();
                }
            }
            start.elapsed().as_secs_f64() / (n * reps) as f64
        };
        let exact = per_realization(&|_| {}, 200, 500);
        println!("exact solver: {:.2} us per realization (200 paper realizations x 500)", exact * 1e6);
        let settings: [(&str, &dyn Fn(&mut Scenario), u64); 3] = [
            ("rk45, paper ode45 settings (rtol = atol = 1e-9, max_step = 1e-4)", &|sc| sc.run.solver = SolverKind::Rk45, 1),
            ("rk45, rtol = 1e-6 (atol = 1e-9, max_step = 1e-4 as the paper)", &|sc| (sc.run.solver, sc.numerics.rtol) = (SolverKind::Rk45, 1e-6), 1),
            (
                "rk45, rtol = atol = 1e-6, no max_step",
                &|sc| (sc.run.solver, sc.numerics.rtol, sc.numerics.atol, sc.numerics.max_step) = (SolverKind::Rk45, 1e-6, 1e-6, 10.0),
                50,
            ),
        ];
        for (label, set, reps) in settings {
            let t = per_realization(set, 200, reps);
            println!("{label}: {:.2} us per realization, exact is {:.0}x faster", t * 1e6, t / exact);
        }
        // the Stribeck scene as shipped (pipelines/stribeck.toml: mu_s = 0.6, mu_k = 0.51,
        // v_s = 0.1, δ = 2, rk45 at the setting `tradeoff` recommends for it), and at 1e-6
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("pipelines/stribeck.toml");
        let scene = Scenario::resolve(Some(&file), &[]).unwrap();
        let rtol = scene.numerics.rtol;
        for tol in [rtol, 1e-6] {
            let t = per_realization(
                &|sc| {
                    (sc.model, sc.numerics) = (scene.model.clone(), scene.numerics);
                    (sc.numerics.rtol, sc.numerics.atol) = (tol, tol);
                },
                200,
                50,
            );
            let which = if tol == rtol { "the recommended setting" } else { "tighter" };
            println!("Stribeck scene, rk45 at rtol = atol = {tol:e} ({which}): {:.2} us per realization ({:.0} realizations/s per core)", t * 1e6, 1.0 / t);
        }
    }

    // Figures + report of the paper scenario (18,000 realizations, trajectories and switch times on).
    {
        let dir = tempfile::tempdir().unwrap();
        let (data, top) = (dir.path().join("paper/dataset"), dir.path().join("paper"));
        let mut sc = Scenario::paper();
        (sc.output.trajectories, sc.output.switch_times) = (3, true);
        simulate::run(&sc, &Options { out: data.clone(), shard: Shard::WHOLE, threads: None, progress: false }).unwrap();
        let a = analysis::analyze(&data, &analysis::Options::default()).unwrap();
        analysis::output::write(&a, &top.join("analysis")).unwrap();
        let start = Instant::now();
        let figures = stickslip::figures::run(&top.join("analysis"), &top.join("figures")).unwrap();
        let drawn = start.elapsed().as_secs_f64();
        stickslip::report::run(&data, &top.join("analysis"), &top.join("figures"), None, &top.join("report.html")).unwrap();
        println!(
            "figures + report, paper scenario: {:.2} s ({} figures as PNG + SVG in {drawn:.2} s, report in {:.2} s)",
            start.elapsed().as_secs_f64(),
            figures.len(),
            start.elapsed().as_secs_f64() - drawn
        );
    }

    let exe = std::env::current_exe().unwrap();
    let mut sizes = vec![100_000u64, 1_000_000];
    if args.iter().any(|a| a == "--large") {
        sizes.push(10_000_000);
    }
    for n in sizes {
        let dir = tempfile::tempdir().unwrap();
        for stage in ["--simulate", "--analyze"] {
            let status = Command::new(&exe).args([stage, &n.to_string(), dir.path().to_str().unwrap()]).status().unwrap();
            assert!(status.success());
        }
    }
}
