//! The tails' state in each record (schema v3): how each stick ended, where it was entered, and
//! the extremes of the motion — checked against the physics and an independent trajectory.

use stickslip::ensemble::Ensemble;
use stickslip::events::StickEnd;
use stickslip::physics::Params;

use crate::common::{belt_velocity, outcomes, scenario};

/// Every stick's end is what its record says: a breakaway stick lasts exactly the closed-form
/// holding time from its entry position, a flip stick ends at a belt switch, a horizon stick at
/// t_a; the longest stick and the stick fraction are those of the durations.
#[test]
fn stick_ends_and_entries_agree_with_the_belt_and_the_holding_time() {
    for sets in [
        &["model.static_friction_coefficient=0.7", "belt.switch_rate=0.5"][..],
        &["model.damping=0.8", "belt.switch_rate=0.5"][..],
        &["belt.reverse_speed=0.4", "belt.reverse_switch_rate=3.0"][..],
    ] {
        let sc = scenario(sets);
        let p = Params::per_unit_mass(&crate::common::params(&sc));
        let ta = sc.run.duration;
        let (mut seen, mut sticks) = ([0usize; 3], 0);
        for o in outcomes(&sc, 400) {
            let r = &o.record;
            assert_eq!(r.stick_end.len(), r.n_stick());
            assert_eq!(r.stick_entry_position.len(), r.n_stick());
            for (i, end) in r.stick_end.iter().enumerate() {
                let (t, d, x, v) = (r.stick_start[i], r.stick_duration[i], r.stick_entry_position[i], r.stick_entry_velocity[i]);
                assert_eq!(v, belt_velocity(o.velocities(), o.switches(), t), "entry velocity is the belt's");
                let e = t + d;
                match end {
                    StickEnd::Breakaway => {
                        let hold = p.stick_duration(x, v);
                        assert!((d - hold).abs() <= 1e-9 * (1.0 + hold), "breakaway after {d} s, holding time {hold} s");
                    }
                    StickEnd::Flip => assert!(o.switches().iter().any(|&y| (y - e).abs() <= 1e-12 * ta), "flip stick ends at {e}, no switch there"),
                    StickEnd::Horizon => {
                        assert_eq!(i + 1, r.n_stick(), "only the last stick reaches the horizon");
                        assert!(r.last_truncated && (e - ta).abs() <= 1e-12 * ta);
                    }
                }
                seen[*end as usize] += 1;
            }
            sticks += r.n_stick();
            let longest = r.stick_duration.iter().copied().fold(0.0, f64::max);
            assert_eq!(r.longest_stick(), longest);
            assert!((r.stick_fraction(ta) - r.stick_duration.iter().sum::<f64>() / ta).abs() <= 1e-15);
        }
        assert!(seen.iter().all(|&n| n > 0), "{sets:?}: every kind of end occurs ({seen:?} of {sticks})");
    }
}

/// The extremes of ẋ and of |v − ẋ| enclose those of a trajectory sampled every millisecond and
/// lie within what the motion can move between samples — for the closed forms (undamped and
/// damped) and for the located extrema of rk45.
#[test]
fn velocity_extremes_enclose_a_fine_trajectory_and_are_reached() {
    for sets in [
        &["belt.switch_rate=0.3"][..],
        &["model.damping=0.6", "belt.switch_rate=0.3"][..],
        &["run.solver=rk45", "belt.switch_rate=0.3"][..],
        &["model.static_friction_coefficient=0.8", "model.damping=3.0", "belt.switch_rate=0.3"][..],
    ] {
        let sc = scenario(sets);
        let ens = Ensemble::new(&sc).unwrap();
        let step = 1e-3;
        for i in 0..30 {
            let mut o = Default::default();
            let samples = ens.trajectory(i, step, &mut o).unwrap().samples;
            let r = &o.record;
            let (mut lo, mut hi, mut slip) = (f64::INFINITY, f64::NEG_INFINITY, 0f64);
            for &[_, _, xd, v] in &samples {
                (lo, hi, slip) = (lo.min(xd), hi.max(xd), slip.max((v - xd).abs()));
            }
            // ẍ is bounded by ω² |x| + γ |ẋ| + a_s: a few m/s² here, so 1 ms moves ẋ by < 0.05 m/s
            let tol = 0.05;
            let tight = if sets.contains(&"run.solver=rk45") { 1e-6 } else { 1e-12 };
            assert!(r.min_velocity <= lo + tight && r.max_velocity >= hi - tight, "{sets:?} #{i}: [{}, {}] vs samples [{lo}, {hi}]", r.min_velocity, r.max_velocity);
            assert!(lo - r.min_velocity <= tol && r.max_velocity - hi <= tol, "{sets:?} #{i}: [{}, {}] vs samples [{lo}, {hi}]", r.min_velocity, r.max_velocity);
            assert!(r.max_slip_speed >= slip - tight && r.max_slip_speed - slip <= 2.0 * tol, "{sets:?} #{i}: {} vs {slip}", r.max_slip_speed);
        }
    }
}

/// A motion stuck from t = 0 to t_a (started at belt speed, a holding limit never reached, no
/// flips) has ẋ = v throughout, no slip speed, and one stick cut at the horizon.
#[test]
fn a_motion_stuck_throughout_has_the_belt_speed_as_its_only_velocity() {
    let sc = scenario(&[
        "belt.switch_rate=0",
        "belt.initial_sign=1",
        "model.static_friction_coefficient=50",
        "model.friction_coefficient=40",
        "initial_conditions.position=[0, 0]",
        "initial_conditions.velocity=[1, 1]",
    ]);
    let r = &outcomes(&sc, 1)[0].record;
    assert_eq!((r.min_velocity, r.max_velocity, r.max_slip_speed), (1.0, 1.0, 0.0));
    assert_eq!((r.stick_start.as_slice(), r.stick_end.as_slice()), (&[0.0][..], &[StickEnd::Horizon][..]));
    assert_eq!(r.longest_stick(), sc.run.duration);
}
