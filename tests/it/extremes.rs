//! The extremes matrix: no panic, no NaN, invariants hold; long horizons do not drift.

use std::f64::consts::PI;

use crate::common::{check_invariants, outcomes, scenario, solve_scripted};

/// (overrides, realizations, strictly increasing event times expected)
const MATRIX: &[(&[&str], u64, bool)] = &[
    (&["model.stiffness=0"], 8, true),
    (&["model.stiffness=1e-12"], 8, true),
    (&["model.stiffness=1e8"], 4, true),
    (&["model.mass=1e-6"], 4, true),
    (&["model.mass=1e6"], 8, true),
    (&["belt.speed=1e-9"], 8, true),
    (&["belt.speed=1e6"], 8, true),
    (&["belt.switch_rate=0"], 8, true),
    (&["belt.switch_rate=1e-6"], 8, true),
    (&["belt.switch_rate=1e4"], 2, true),
    (&["model.friction_coefficient=0"], 8, true),
    (&["model.friction_coefficient=1e-9"], 8, true),
    (&["model.friction_coefficient=1e6"], 8, true),
    // slips shorter than the resolution of t (2 v0 m / f_max ≈ 2e-21 s): times may coincide
    (&["model.friction_coefficient=1e20"], 8, false),
    (&["model.stiffness=1e8", "model.friction_coefficient=1e-9"], 2, true),
    (&["model.mass=1e-9", "model.stiffness=1e-9"], 8, true),
    (&["run.duration=1e6", "belt.switch_rate=1e-3"], 4, true),
    (&["run.duration=1e6", "belt.switch_rate=0"], 4, true),
    (&["run.duration=1e6"], 1, true),
    (&["run.duration=1e-9"], 8, true),
];

#[test]
fn extremes_keep_the_invariants() {
    for (sets, n, strict) in MATRIX {
        let sc = scenario(sets);
        for (i, o) in outcomes(&sc, *n).iter().enumerate() {
            if let Err(e) = check_invariants(&sc, o, *strict) {
                panic!("{sets:?}, realization {i}: {e}");
            }
        }
    }
}

#[test]
fn stick_counts_follow_the_physics_at_the_extremes() {
    // Huge friction: stuck almost always, one stick per belt segment.
    let sc = scenario(&["model.friction_coefficient=1e6"]);
    for o in outcomes(&sc, 8) {
        let q = o.belt.switch_times.len();
        assert!(o.record.stick_start.len() == q + 1, "S_T = {} with Q = {q}", o.record.stick_start.len());
    }
    // Very fast switching averages the friction out: a mass released at x = 0 with a velocity
    // amplitude below v0 oscillates almost freely and never reaches belt speed.
    let sc = scenario(&["belt.switch_rate=1e4", "initial_conditions.position=[0, 0]", "initial_conditions.velocity=[-0.3, 0.3]"]);
    for o in outcomes(&sc, 2) {
        assert_eq!(o.record.stick_start.len(), 0);
        assert!(o.belt.switch_times.len() > 90_000);
    }
}

#[test]
fn no_drift_over_a_million_seconds_without_spring() {
    // k = 0: every flip ends a stick and the mass re-sticks exactly 2 v0 m / f_max later.
    let sc = scenario(&["model.stiffness=0", "run.duration=1e6"]);
    let flips: Vec<f64> = (1..1000).map(|i| i as f64 * 1000.0 + 0.123_456_789 * i as f64).collect();
    let r = solve_scripted(&sc, 1.0, &flips, 0.0, 1.0).record;
    assert_eq!(r.stick_start.len(), flips.len() + 1);
    let dt = 2.0 / (0.51 * 9.8);
    for (f, t) in flips.iter().zip(&r.stick_start[1..]) {
        assert!((t - (f + dt)).abs() <= 4.0 * f64::EPSILON * f, "stick at {t}, expected {}", f + dt);
    }
}

#[test]
fn no_drift_over_a_hundred_thousand_periods() {
    // Breakaway at t_b, then the grazing orbit for n periods before a flip: what follows the flip
    // must not depend on n (see closed_forms::slip_after_breakaway_is_periodic...).
    let sc = scenario(&["belt.switch_rate=0", "run.duration=1e6"]);
    let tb = 0.51 * 9.8 / 4.0;
    let offset = |n: f64| {
        let flip = tb + n * PI + 0.3;
        let r = solve_scripted(&sc, 1.0, &[flip], 0.0, 1.0).record;
        r.stick_start[1] - flip
    };
    let (a, b) = (offset(0.0), offset(1e5));
    assert!((a - b).abs() < 1e-8, "{a} vs {b}");
}
