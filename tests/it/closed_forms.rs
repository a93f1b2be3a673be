//! Closed-form cases: constant belt, no friction, no spring.

use std::f64::consts::PI;

use crate::common::{belt_velocity, outcomes, scenario, solve_scripted};

const FMAX: f64 = 0.51 * 9.8; // paper f_max, N
const K: f64 = 4.0;
const OMEGA: f64 = 2.0; // sqrt(k/m)

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn constant_belt_stick_lasts_until_breakaway_and_grazing_is_not_a_stick() {
    // Start stuck (x'0 = v0) at several positions; λ = 0 over 100 s (≈ 32 natural periods).
    for &(c, v0) in &[(0.0, 1.0), (-FMAX / K, 1.0), (0.9, 0.25), (-1.2, 3.0)] {
        let pos = format!("initial_conditions.position=[{c:e}, {c:e}]");
        let vel = format!("initial_conditions.velocity=[{v0:e}, {v0:e}]");
        let speed = format!("belt.speed={v0:e}");
        let sc = scenario(&["belt.switch_rate=0", "run.duration=100", &pos, &vel, &speed]);
        let o = &outcomes(&sc, 3)[0];
        let r = &o.record;
        let d = (FMAX / K - c) / v0; // breakaway at k x = f_max
        assert_eq!(r.stick_start, [0.0], "c = {c}");
        assert!(close(r.stick_duration[0], d, 1e-12 * d), "D_1 {} vs {d}", r.stick_duration[0]);
        assert!(r.stick_duration[0] <= 2.0 * FMAX / (K * v0) * (1.0 + 1e-15));
        // after breakaway the velocity v0 cos ωτ touches v0 every 2π/ω: never a stick again
        assert_eq!(r.slip_start.len(), 1);
        assert!(close(r.slip_duration[0], 100.0 - d, 1e-12 * 100.0));
        assert!(r.last_truncated);
    }
}

#[test]
fn maximum_stick_duration_is_two_fmax_over_k_v0() {
    let sc = scenario(&["belt.switch_rate=0", "initial_conditions.position=[-1.2495, -1.2495]", "initial_conditions.velocity=[1, 1]"]);
    let d = outcomes(&sc, 1)[0].record.stick_duration[0];
    assert!(close(d, 2.0 * FMAX / K, 1e-12), "{d}");
}

#[test]
fn first_stick_after_an_initial_slip_matches_the_phase_form_solution() {
    // x0 = 0, x'0 = -v0, belt +v0: slip with friction +f_max about x_e = f_max/k:
    // x'(t) = R sin(ωt - φ), R = hypot(x_e ω, v0), φ = atan2(v0, x_e ω); x'(T_1) = v0.
    let sc = scenario(&["belt.switch_rate=0", "initial_conditions.position=[0, 0]", "initial_conditions.velocity=[-1, -1]"]);
    let r = &outcomes(&sc, 1)[0].record;
    let xe = FMAX / K;
    let (rr, phi) = ((xe * OMEGA).hypot(1.0), 1f64.atan2(xe * OMEGA));
    let t1 = (phi + (1.0 / rr).asin()) / OMEGA;
    let x1 = xe * (1.0 - (OMEGA * t1).cos()) - (OMEGA * t1).sin() / OMEGA;
    assert!(close(r.stick_start[0], t1, 1e-13), "{} vs {t1}", r.stick_start[0]);
    assert!((K * x1).abs() <= FMAX);
    assert!(close(r.stick_duration[0], xe - x1, 1e-12));
    assert_eq!(r.stick_start.len(), 1);
}

#[test]
fn slip_after_breakaway_is_periodic_with_the_natural_period() {
    // Stuck at x = 0 from t = 0, breakaway at t_b = x_e / v0; the belt flips at t_b + n·2π/ω + 0.3.
    // The slip orbit repeats every 2π/ω, so everything after the flip shifts by the same amount.
    let sc = scenario(&["belt.switch_rate=0", "run.duration=60"]);
    let tb = FMAX / K;
    let period = 2.0 * PI / OMEGA;
    let after_flip = |n: f64| {
        let flip = tb + n * period + 0.3;
        let r = solve_scripted(&sc, 1.0, &[flip], 0.0, 1.0);
        assert!(r.stick_start.len() >= 2, "a stick after the flip");
        assert!(close(r.slip_start[0], tb, 1e-13));
        (r.stick_start[1] - flip, r.stick_duration[1])
    };
    let (a0, d0) = after_flip(0.0);
    for n in [1.0, 3.0, 10.0] {
        let (a, d) = after_flip(n);
        assert!(close(a, a0, 1e-11), "n = {n}: {a} vs {a0}");
        assert!(close(d, d0, 1e-11), "n = {n}: {d} vs {d0}");
    }
}

#[test]
fn without_friction_the_mass_never_sticks() {
    let sc = scenario(&["model.friction_coefficient=0", "run.realizations=200"]);
    for o in outcomes(&sc, 200) {
        assert_eq!(o.record.stick_start.len(), 0);
        assert_eq!(o.record.slip_start.len(), 0);
        assert!(!o.record.last_truncated);
    }
}

#[test]
fn without_spring_slips_decelerate_uniformly() {
    let af = FMAX; // m = 1
                   // Constant belt: one slip of |u0|/a_f, then stuck for good.
    let sc = scenario(&["model.stiffness=0", "belt.switch_rate=0"]);
    for o in outcomes(&sc, 50) {
        let r = &o.record;
        let t1 = (o.xdot0 - 1.0).abs() / af;
        assert!(close(r.stick_start[0], t1, 1e-14), "{} vs {t1}", r.stick_start[0]);
        assert_eq!((r.stick_start.len(), r.slip_start.len()), (1, 0));
    }
    // Random belt: a flip ends a stick; the slip then lasts 2 v0 / a_f unless another flip comes.
    let sc = scenario(&["model.stiffness=0"]);
    let mut checked = 0;
    for o in outcomes(&sc, 300) {
        let (sw, vel) = (o.switches(), o.velocities());
        let r = &o.record;
        for (i, (&l, &h)) in r.slip_start.iter().zip(&r.slip_duration).enumerate() {
            let flip_inside = sw.iter().any(|&y| y > l && y < l + 2.0 * 1.0 / af + 1e-12);
            let truncated = i + 1 == r.slip_start.len() && r.stick_start.len() == r.slip_start.len();
            assert!(sw.contains(&l), "slips start at belt flips only");
            assert!(belt_velocity(vel, sw, l) != belt_velocity(vel, sw, l - 1e-9));
            if !flip_inside && !truncated {
                assert!(close(h, 2.0 / af, 1e-12), "H = {h}");
                checked += 1;
            }
        }
    }
    assert!(checked > 500, "only {checked} slips checked");
}
