//! Scenes beyond the paper: damping, static friction above kinetic, the asymmetric belt and
//! random parameters — closed forms, an independent reference, extremes, determinism, the door.

use stickslip::simulation::ensemble::Outcome;
use stickslip::simulation::simulate::{self, Options, Shard};

use crate::common::{check_invariants, outcomes, params, scenario, stickslip};
use crate::dataset::read_dir;

const N: f64 = 9.8;
const K: f64 = 4.0;

/// Events of the first `n` realizations: (stick starts, slip starts) per realization.
fn events(sets: &[&str], n: u64) -> Vec<(Vec<f64>, Vec<f64>)> {
    outcomes(&scenario(sets), n).into_iter().map(|o| (o.record.stick_start, o.record.slip_start)).collect()
}

/// Two runs' events agree: the same counts, times within `tol` seconds.
fn assert_same_events(a: &[(Vec<f64>, Vec<f64>)], b: &[(Vec<f64>, Vec<f64>)], tol: f64, what: &str) {
    for (i, (a, b)) in a.iter().zip(b).enumerate() {
        assert_eq!((a.0.len(), a.1.len()), (b.0.len(), b.1.len()), "{what}: realization {i}");
        for (x, y) in a.0.iter().chain(&a.1).zip(b.0.iter().chain(&b.1)) {
            assert!((x - y).abs() < tol, "{what}: realization {i}: {x} vs {y}");
        }
    }
}

#[test]
fn stick_duration_and_breakaway_with_damping_and_static_friction() {
    // A constant belt at v0, starting stuck at x0: D_1 = (mu_s n − (k x0 + c v0))/(k v0); with
    // mu_s > mu_k the slip after breakaway leaves belt speed at once and may stick again, with
    // mu_s = mu_k and c > 0 its velocity (an extremum at v0) only decays: never a second stick.
    for &(c, mu_s, x0, v0) in &[(0.5, 0.6, 0.1, 1.0), (2.0, 0.51, -0.3, 0.5), (4.0, 0.9, 0.0, 2.0), (0.5, 0.51, 0.2, 1.0)] {
        let sets = [
            "belt.switch_rate=0".to_string(),
            "run.duration=30".into(),
            format!("model.damping={c}"),
            format!("model.static_friction_coefficient={mu_s}"),
            format!("belt.speed={v0}"),
            format!("initial_conditions.position=[{x0}, {x0}]"),
            format!("initial_conditions.velocity=[{v0}, {v0}]"),
        ];
        let refs: Vec<&str> = sets.iter().map(String::as_str).collect();
        let o = &outcomes(&scenario(&refs), 1)[0];
        let r = &o.record;
        let d = (mu_s * N - (K * x0 + c * v0)) / (K * v0);
        assert_eq!(r.stick_start[0], 0.0);
        assert!((r.stick_duration[0] - d).abs() < 1e-12 * d, "c {c}: D_1 {} vs {d}", r.stick_duration[0]);
        if mu_s == 0.51 {
            assert_eq!(r.stick_start.len(), 1, "c {c}: the damped grazing orbit never returns to belt speed");
        }
    }
}

#[test]
fn a_dashpot_stronger_than_the_friction_never_lets_the_mass_stick() {
    // No spring, c v0 = 10 N > mu n = 5 N: in slip the velocity tends to mu n / c < v0, and a
    // stick would need |c v| <= mu n. No realization ever sticks.
    let sc = scenario(&["model.stiffness=0", "model.damping=10", "run.realizations=500"]);
    let os = outcomes(&sc, 500);
    assert!(os.iter().all(|o| o.record.stick_start.is_empty()));
    // the same scene with a weak dashpot does stick
    let os = outcomes(&scenario(&["model.stiffness=0", "model.damping=1"]), 200);
    assert!(os.iter().filter(|o| !o.record.stick_start.is_empty()).count() > 100);
}

#[test]
fn critical_damping_and_its_neighbours_give_the_same_events() {
    // ζ = 1 exactly (c = 4) against ζ = 1 ± 1e-9: the same counts, times within 1e-7 s
    let crit = events(&["model.damping=4"], 300);
    for c in ["3.999999996", "4.000000004"] {
        assert_same_events(&crit, &events(&[&format!("model.damping={c}")], 300), 1e-7, c);
    }
}

#[test]
fn vanishing_damping_tends_to_the_undamped_solver_and_zero_is_the_paper() {
    // c = 0 and mu_s = mu_k given explicitly are the paper: the same rows
    let paper = events(&[], 300);
    assert_eq!(paper, events(&["model.damping=0", "model.static_friction_coefficient=0.51"], 300));
    // c = 1e-12 runs the damped forms; its events differ from c = 0 by O(c)
    assert_same_events(&paper, &events(&["model.damping=1e-12"], 300), 1e-8, "c = 1e-12");
}

#[test]
fn random_scenes_keep_every_invariant_at_the_extremes() {
    let cases: &[&[&str]] = &[
        &["model.damping=1e6"],                      // c huge (ζ = 2.5e5)
        &["model.damping=4", "belt.switch_rate=20"], // ζ = 1
        &["model.static_friction_coefficient=25"],   // mu_s ≫ mu_k
        &["model.static_friction_coefficient=0.6", "model.damping=0.5"],
        &["belt.reverse_speed=1e-6", "belt.reverse_switch_rate=5"],   // v_r ≪ v_f
        &["belt.reverse_speed=0.5", "belt.reverse_switch_rate=1e-9"], // λ_r → 0
        &["belt.reverse_speed=3", "belt.reverse_switch_rate=0", "belt.initial_sign=\"random\""],
        &["model.friction_coefficient={dist = \"uniform\", low = 0.5, high = 0.5}"], // no spread
        &["model.friction_coefficient={dist = \"lognormal\", mean = 0.5, cv = 1e-12}"],
        &["model.friction_coefficient={dist = \"gamma\", mean = 0.5, cv = 30}"], // huge spread
        &["model.mass={dist = \"lognormal\", mean = 1, cv = 20}", "model.damping={dist = \"uniform\", low = 0, high = 8}"],
        &["belt.switch_rate={dist = \"gamma\", mean = 5, cv = 3}", "belt.speed={dist = \"normal\", mean = 0.05, sd = 1}"],
    ];
    for sets in cases {
        let sc = scenario(sets);
        for (i, o) in outcomes(&sc, 60).iter().enumerate() {
            if let Err(e) = check_invariants(&sc, o, false) {
                panic!("{sets:?}, realization {i}: {e}");
            }
        }
    }
}

#[test]
fn a_random_key_draws_its_own_stream_and_is_stored() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let dist = "model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}";
    for (dir, extra) in [
        ("plain", vec![]),
        ("mu", vec!["--set", dist]),
        ("mu_lambda", vec!["--set", dist, "--set", "belt.switch_rate={dist = \"uniform\", low = 2, high = 10}"]),
    ] {
        let mut args = vec!["simulate", "--out", dir, "--realizations", "400", "--set", "output.switch_times=true", "--quiet"];
        args.extend(extra);
        let o = stickslip(&args, t);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (plain, mu, both) = (read_dir(&t.join("plain")), read_dir(&t.join("mu")), read_dir(&t.join("mu_lambda")));
    // the belt and the initial conditions are those of the same seed without the random key
    for col in ["x0", "xdot0", "initial_sign", "n_switches", "switch_times"] {
        assert!(plain.column(col).unwrap().equals(mu.column(col).unwrap()), "{col} shifted by a random mu");
    }
    // a second random key does not shift the first one's draws
    assert!(mu.column("friction_coefficient").unwrap().equals(both.column("friction_coefficient").unwrap()));
    let drawn = mu.column("friction_coefficient").unwrap().f64().unwrap();
    assert!((0..drawn.len()).all(|i| drawn.get(i).is_some_and(|x| (0.3..0.7).contains(&x))));
    assert!(plain.column("friction_coefficient").is_err(), "only keys that vary are stored");
    // each realization is the fixed scene at its drawn value
    let sc = scenario(&[dist]);
    let ens = sc.ensemble().unwrap();
    let mut out = Outcome::default();
    for i in [0u64, 7, 99] {
        ens.realization(i, &mut out).unwrap();
        let fixed = scenario(&[&format!("model.friction_coefficient={:e}", out.drawn[0])]);
        let o = &outcomes(&fixed, i + 1)[i as usize];
        assert_eq!(o.record, out.record, "realization {i}");
    }
}

#[test]
fn random_scenes_are_the_same_for_any_threads_and_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let sc = scenario(&[
        "run.realizations=2000",
        "model.friction_coefficient={dist = \"normal\", mean = 0.5, sd = 0.1}",
        "model.damping={dist = \"gamma\", mean = 0.5, cv = 0.5}",
        "belt.reverse_speed=0.5",
        "belt.reverse_switch_rate={dist = \"uniform\", low = 1, high = 3}",
    ]);
    let run = |dir: &str, shard: Shard, threads: usize| {
        let opts = Options { out: tmp.path().join(dir), shard, threads: Some(threads) };
        simulate::run(&sc.plan().unwrap(), &opts).expect("simulate").path
    };
    let (a, b) = (run("t1", Shard::WHOLE, 1), run("t2", Shard::WHOLE, 2));
    assert!(std::fs::read(a).unwrap() == std::fs::read(b).unwrap(), "thread count changed the bytes");
    for i in 0..3 {
        run("sh", Shard { index: i, count: 3 }, 2);
    }
    let whole = read_dir(&tmp.path().join("t1"));
    let sharded = read_dir(&tmp.path().join("sh")).sort(["realization"], Default::default()).unwrap();
    assert!(whole.equals(&sharded));
}

#[test]
fn the_door_refuses_impossible_scenes_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: &[(&[&str], &str, &str)] = &[
        (
            &["model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}", "model.static_friction_coefficient=0.6"],
            "model.static_friction_coefficient",
            "every draw",
        ),
        (&["model.static_friction_coefficient=0.4"], "model.static_friction_coefficient", "friction_coefficient"),
        (
            &["model.friction_coefficient={dist = \"normal\", mean = 0.5, sd = 0.1}", "model.static_friction_coefficient=0.9"],
            "model.static_friction_coefficient",
            "every draw",
        ),
        (&["model.mass={dist = \"uniform\", low = 0, high = 1}"], "model.mass", "between 1e-9 and 1e6"),
        (&["model.damping={dist = \"uniform\", low = -1, high = 1}"], "model.damping", "between 0 and 1e9"),
        (&["model.friction_coefficient=[{dist = \"uniform\", low = 0.3, high = 0.7}]"], "model.friction_coefficient", "both swept and random"),
        (&["model.friction_coefficient={dist = \"beta\", a = 1}"], "model.friction_coefficient", "beta"),
        (&["model.friction_coefficient={dist = \"uniform\", low = 0.3}"], "model.friction_coefficient", "high"),
        (&["model.damping=-0.5"], "model.damping", "between 0 and 1e9"),
        (&["belt.reverse_speed=0.5"], "belt.reverse_speed", "reverse_switch_rate"),
        (&["belt.reverse_speed=0"], "belt.reverse_speed", "between 1e-9 and 1e6"),
        (&["run.solver=\"ode45\""], "run.solver", "rk45"),
        (&["model.friction_law=\"dahl\""], "model.friction_law", "stribeck"),
        (&["model.friction_law=\"stribeck\""], "model.stribeck_velocity", "v_s"),
        (&["model.stribeck_velocity=0.1"], "model.stribeck_velocity", "friction_law"),
        (
            &["model.friction_law=\"stribeck\"", "model.stribeck_velocity=0.1", "model.static_friction_coefficient=0.6", "run.solver=\"exact\""],
            "model.friction_law",
            "exact",
        ),
        (
            &["model.friction_law=\"stribeck\"", "model.stribeck_velocity=0", "model.static_friction_coefficient=0.6"],
            "model.stribeck_velocity",
            "between 1e-9 and 1e6",
        ),
        (&["model.dampin=1"], "model.dampin", "damping"),
    ];
    for (sets, key, words) in cases {
        let mut args = vec!["simulate", "--out", "o", "--quiet"];
        for s in *sets {
            args.extend(["--set", s]);
        }
        let o = stickslip(&args, tmp.path());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{sets:?}: {err}");
        assert!(err.contains(key) && err.contains(words), "{sets:?}: {err}");
        assert!(!tmp.path().join("o").exists(), "{sets:?} left an output behind");
    }
}

#[test]
fn every_numerical_solver_runs_damped_and_static_friction_scenes() {
    // rk45 at tight tolerances reproduces the exact events; the others run and count sticks
    // within a few percent (their own trade-offs are measured by `tradeoff`)
    let scene = ["model.damping=0.5", "model.static_friction_coefficient=0.6"];
    let exact = events(&scene, 40);
    let with = |extra: &[&str]| events(&scene.iter().chain(extra).copied().collect::<Vec<_>>(), 40);
    let rk45 = with(&["run.solver=rk45", "numerics.rtol=1e-11", "numerics.atol=1e-11", "numerics.max_step=1e-2"]);
    assert_same_events(&exact, &rk45, 1e-7, "rk45");
    let sticks = |e: &[(Vec<f64>, Vec<f64>)]| e.iter().map(|r| r.0.len()).sum::<usize>() as f64;
    for extra in [
        &["run.solver=rk4", "numerics.step=1e-3"][..],
        &["run.solver=moreau", "numerics.step=1e-4"],
        &["run.solver=smooth", "numerics.epsilon=1e-4", "numerics.stick_velocity=1e-4", "numerics.rtol=1e-8", "numerics.atol=1e-8", "numerics.max_step=1"],
    ] {
        let n = sticks(&with(extra));
        assert!((n / sticks(&exact) - 1.0).abs() < 0.05, "{extra:?}: {n} sticks vs exact {}", sticks(&exact));
    }
}

#[test]
fn the_asymmetric_belt_spends_the_expected_time_forward() {
    // v_f = 1, λ_f = 5; v_r = 0.5, λ_r = 2: stationary forward fraction 2/7; from the forward
    // state the mean time to the first switch is 1/λ_f
    let sc = scenario(&["belt.reverse_speed=0.5", "belt.reverse_switch_rate=2", "run.duration=50"]);
    let os = outcomes(&sc, 400);
    let (mut forward, mut first) = (0.0, 0.0);
    for o in &os {
        let (sw, vel) = (o.switches(), o.velocities());
        let mut edges = vec![0.0];
        edges.extend(sw);
        edges.push(50.0);
        forward += edges.windows(2).zip(vel).filter(|(_, &v)| v > 0.0).map(|(w, _)| w[1] - w[0]).sum::<f64>();
        first += sw.first().copied().unwrap_or(50.0);
        assert!(vel.iter().all(|&v| v == 1.0 || v == -0.5));
    }
    let frac = forward / (400.0 * 50.0);
    // starts forward: the transient adds (1/λ_f)(λ_f/(λ_f+λ_r))... ≈ 0.0041 over 50 s
    assert!((frac - 2.0 / 7.0).abs() < 0.02, "forward fraction {frac}");
    assert!((first / 400.0 - 0.2).abs() < 0.03, "mean first holding time {}", first / 400.0);
    let p = params(&sc);
    assert_eq!(p.damping, 0.0);
}

#[test]
fn trajectories_are_sampled_for_every_method() {
    // the driver samples each method's own pieces: closed forms, dense output, Moreau's grid
    let sample = |extra: &[&str]| {
        let sets: Vec<&str> = ["model.damping=0.5", "model.static_friction_coefficient=0.6"].iter().chain(extra).copied().collect();
        let ens = scenario(&sets).ensemble().unwrap();
        ens.trajectory(3, 1e-2, &mut Outcome::default()).unwrap().samples
    };
    let exact = sample(&[]);
    assert_eq!(exact.len(), 1000);
    for (extra, tol) in [
        (&["run.solver=rk45", "numerics.rtol=1e-10", "numerics.atol=1e-10", "numerics.max_step=1e-2"][..], 1e-6),
        (&["run.solver=rk4", "numerics.step=1e-3"], 1e-6),
        (&["run.solver=moreau", "numerics.step=1e-4"], 2e-2),
        (
            &[
                "run.solver=smooth",
                "numerics.epsilon=1e-4",
                "numerics.stick_velocity=1e-4",
                "numerics.max_step=1e-2",
                "numerics.rtol=1e-8",
                "numerics.atol=1e-8",
            ],
            2e-2,
        ),
    ] {
        let other = sample(extra);
        assert_eq!(other.len(), exact.len(), "{extra:?}");
        for (a, b) in exact.iter().zip(&other) {
            assert_eq!((a[0], a[3]), (b[0], b[3]), "{extra:?}: grid instants and belt velocity");
            assert!((a[1] - b[1]).abs() < tol, "{extra:?} at t = {}: x {} vs {}", a[0], b[1], a[1]);
        }
    }
}

#[test]
fn the_example_scene_files_run() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    let scenes = std::fs::read_dir(root.join("pipelines/scenes")).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml"));
    for path in scenes.chain([root.join("pipelines/stribeck.toml")]) {
        let sc = stickslip::scenario::Scenario::resolve(Some(&path), &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for (i, o) in outcomes(&sc, 50).iter().enumerate() {
            check_invariants(&sc, o, true).unwrap_or_else(|e| panic!("{}, realization {i}: {e}", path.display()));
        }
        n += 1;
    }
    assert!(n >= 5, "one example file per scene feature, and the Stribeck scene");
}
