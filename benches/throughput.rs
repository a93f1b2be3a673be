//! In-process speed benchmark (`cargo bench --bench throughput`): numbers for the book's Benchmarks.
//!
//! Per-realization cost of the solvers on the same realizations, measured side by side: every
//! round runs each setting once, in turn (so a slower moment of the machine falls on all alike);
//! printed are the medians over the rounds and, for each setting, the median of its per-round
//! ratio to the exact solver on the paper scene.
//!
//! - the exact solver on the paper scene, on 200 realizations (repeated) and on 100,000 fresh ones
//!   (realizations per second, one thread);
//! - the exact solver on the damped scene (`pipelines/scenes/damped.toml`);
//! - `rk45` on the paper scene at the paper's ode45 settings, at rtol = 1e-6 with the paper's other
//!   settings, and at rtol = atol = 1e-6 without a step limit;
//! - `rk45` on the Stribeck scene (`pipelines/stribeck.toml`) at its recommended tolerance and at
//!   1e-6.
//!
//! Then the figures and report of the paper scenario, once. Whole-process figures (`simulate` and
//! `analyze` of 10^6 and 10^7 realizations, peak memory) come from `benches/speed.py`.

use std::path::Path;
use std::time::Instant;

use stickslip::analysis;
use stickslip::scenario::Scenario;
use stickslip::simulation::ensemble::{Ensemble, Outcome};
use stickslip::simulation::simulate::{self, Options, Shard};
use stickslip::solver::SolverKind;

const ROUNDS: usize = 5;

/// One setting: a label, the scene, how many realizations (from index `first`) and repetitions.
struct Setting {
    label: String,
    ensemble: Ensemble,
    first: u64,
    n: u64,
    reps: u64,
}

impl Setting {
    fn new(label: &str, scene: Scenario, (first, n, reps): (u64, u64, u64)) -> Setting {
        scene.check().unwrap();
        Setting { label: label.into(), ensemble: scene.ensemble().unwrap(), first, n, reps }
    }

    /// Seconds per realization, one pass.
    fn time(&self, out: &mut Outcome) -> f64 {
        let start = Instant::now();
        for _ in 0..self.reps {
            for i in self.first..self.first + self.n {
                self.ensemble.realization(i, out).unwrap();
            }
        }
        start.elapsed().as_secs_f64() / (self.n * self.reps) as f64
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn scene(file: &str) -> Scenario {
    Scenario::resolve(Some(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file)), &[]).unwrap()
}

fn main() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("machine: {cores} cores; {ROUNDS} interleaved rounds, medians");
    let paper = Scenario::paper;
    let with = |mut sc: Scenario, f: &dyn Fn(&mut Scenario)| {
        f(&mut sc);
        sc
    };
    let stribeck = scene("pipelines/stribeck.toml");
    let (rtol, atol) = (stribeck.numerics.rtol, stribeck.numerics.atol);
    let settings = [
        Setting::new("exact, paper scene (200 realizations x 500)", paper(), (0, 200, 500)),
        Setting::new("exact, paper scene (100,000 fresh realizations)", paper(), (10_000, 100_000, 1)),
        Setting::new("exact, damped scene (200 x 50)", scene("pipelines/scenes/damped.toml"), (0, 200, 50)),
        Setting::new("rk45, paper's ode45 settings (rtol = atol = 1e-9, max_step = 1e-4)", with(paper(), &|sc| sc.run.solver = SolverKind::Rk45), (0, 200, 1)),
        Setting::new(
            "rk45, rtol = 1e-6 (atol = 1e-9, max_step = 1e-4 as the paper)",
            with(paper(), &|sc| (sc.run.solver, sc.numerics.rtol) = (SolverKind::Rk45, 1e-6)),
            (0, 200, 1),
        ),
        Setting::new(
            "rk45, rtol = atol = 1e-6, no max_step",
            with(paper(), &|sc| (sc.run.solver, sc.numerics.rtol, sc.numerics.atol, sc.numerics.max_step) = (SolverKind::Rk45, 1e-6, 1e-6, 10.0)),
            (0, 200, 50),
        ),
        Setting::new(&format!("Stribeck scene, rk45 at rtol = {rtol:e}, atol = {atol:e} (recommended)"), stribeck.clone(), (0, 200, 50)),
        Setting::new(
            "Stribeck scene, rk45 at rtol = atol = 1e-6",
            with(stribeck.clone(), &|sc| (sc.numerics.rtol, sc.numerics.atol) = (1e-6, 1e-6)),
            (0, 200, 50),
        ),
    ];
    let mut out = Outcome::default();
    // warm up (page in the code, grow the buffers)
    for s in &settings {
        s.ensemble.realization(0, &mut out).unwrap();
    }
    let mut times = vec![Vec::new(); settings.len()];
    for _ in 0..ROUNDS {
        for (s, t) in settings.iter().zip(&mut times) {
            t.push(s.time(&mut out));
        }
    }
    for (s, t) in settings.iter().zip(&times) {
        let ratio = median(t.iter().zip(&times[0]).map(|(a, b)| a / b).collect());
        let per_s = 1.0 / median(t.clone());
        println!("{:<78} {:10.2} us per realization {:10.0} realizations/s  x{ratio:.1} the first", s.label, median(t.clone()) * 1e6, per_s);
    }

    // Figures + report of the paper scenario (18,000 realizations, trajectories and switch times on).
    {
        let dir = tempfile::tempdir().unwrap();
        let (data, top) = (dir.path().join("paper/dataset"), dir.path().join("paper"));
        let mut sc = Scenario::paper();
        (sc.output.trajectories, sc.output.switch_times) = (3, true);
        simulate::run(&sc.plan().unwrap(), &Options { out: data.clone(), shard: Shard::WHOLE, threads: None }).unwrap();
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
}
