//! The tails' state in each record (schema v3): how each stick ended, where it was entered, and
//! the extremes of the motion — checked against the physics and an independent trajectory.

use stickslip::physics::Params;
use stickslip::simulation::events::StickEnd;

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
        &["run.solver=dop853", "belt.switch_rate=0.3"][..],
        &["model.static_friction_coefficient=0.8", "model.damping=3.0", "belt.switch_rate=0.3"][..],
    ] {
        let sc = scenario(sets);
        let ens = sc.ensemble().unwrap();
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
            let tight = if sets.iter().any(|s| s.starts_with("run.solver=")) { 1e-6 } else { 1e-12 };
            assert!(
                r.min_velocity <= lo + tight && r.max_velocity >= hi - tight,
                "{sets:?} #{i}: [{}, {}] vs samples [{lo}, {hi}]",
                r.min_velocity,
                r.max_velocity
            );
            assert!(
                lo - r.min_velocity <= tol && r.max_velocity - hi <= tol,
                "{sets:?} #{i}: [{}, {}] vs samples [{lo}, {hi}]",
                r.min_velocity,
                r.max_velocity
            );
            assert!(r.max_slip_speed >= slip - tight && r.max_slip_speed - slip <= 2.0 * tol, "{sets:?} #{i}: {} vs {slip}", r.max_slip_speed);
        }
    }
}

/// Without a trajectory, dop853 completes its dense output only for the steps it looks inside
/// (a crossing, a dip, a velocity turning point): its located extremes still match the exact
/// solver's closed-form extremes on the same realizations.
#[test]
fn dop853_extremes_match_the_closed_forms_without_a_trajectory() {
    let exact = scenario(&[]).ensemble().unwrap();
    let dop = scenario(&["run.solver=dop853", "numerics.rtol=1e-11", "numerics.atol=1e-11", "numerics.max_step=10"]).ensemble().unwrap();
    for i in 0..40 {
        let (mut a, mut b) = (Default::default(), Default::default());
        exact.realization(i, &mut a).unwrap();
        dop.realization(i, &mut b).unwrap();
        let (a, b): (&stickslip::simulation::events::Record, _) = (&a.record, &b.record);
        for (name, x, y) in [("min", a.min_velocity, b.min_velocity), ("max", a.max_velocity, b.max_velocity), ("slip", a.max_slip_speed, b.max_slip_speed)] {
            assert!((x - y).abs() < 1e-7, "#{i} {name}: exact {x}, dop853 {y}");
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

// --- the survival curves of `analyze` -------------------------------------------------------

use stickslip::analysis::tails::{Curve, TailOptions};
use stickslip::analysis::{self, Options};
use stickslip::simulation::simulate::{self, Shard};

/// Simulate `sets` into a temporary directory and analyse it with the tails at `times`.
fn tails_of(sets: &[&str], times: &[f64]) -> analysis::tails::Tails {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("d");
    let opts = simulate::Options { out: dir.clone(), shard: Shard::WHOLE, threads: Some(2) };
    simulate::run(&scenario(sets).plan().unwrap(), &opts).unwrap();
    let opts = Options { tail: TailOptions { times: times.to_vec(), severity: vec![1.0] }, ..Options::default() };
    analysis::analyze(&dir, &opts).unwrap().tails.expect("tails are on by default")
}

fn pooled<'a>(t: &'a analysis::tails::Tails, variable: &str, method: &str) -> &'a Curve {
    t.curves.iter().find(|c| c.variable == variable && c.method == method && c.index.is_none()).unwrap_or_else(|| panic!("no {method} curve of {variable}"))
}

/// (P, lo, hi) of a curve at t.
fn at(c: &Curve, t: f64) -> (f64, f64, f64) {
    let p = c.points.iter().find(|p| p.0 == t).expect("the asked time is on the curve");
    let (lo, hi) = p.2.expect("a band");
    (p.1, lo, hi)
}

/// Without a spring a stick never breaks away: it ends at the belt's next flip, so
/// P(D > t) = exp(−λ t) exactly. The conditional estimator must give it to rounding; the product
/// limit must cover it with its band, and no stick may end by breakaway.
#[test]
fn without_a_spring_the_stick_tail_is_the_flip_clock() {
    let lambda = 1.5;
    let times = [0.25, 0.5, 1.0, 2.0];
    let t = tails_of(&["model.stiffness=0", &format!("belt.switch_rate={lambda}"), "run.realizations=3000", "run.duration=10"], &times);
    assert!(t.conditional_refused.is_none());
    let (km, cond) = (pooled(&t, "D", "kaplan_meier"), pooled(&t, "D", "conditional"));
    for &time in &times {
        let exact = (-lambda * time).exp();
        let (c, _, _) = at(cond, time);
        assert!((c - exact).abs() <= 1e-12 * exact, "conditional at {time}: {c} vs {exact}");
        let (s, lo, hi) = at(km, time);
        assert!(lo <= exact && exact <= hi, "Kaplan-Meier at {time}: {s} [{lo}, {hi}] vs exp(-λt) = {exact}");
    }
    let breakaway = t.exceedances.iter().find(|e| e.statistic == "breakaway_fraction").unwrap();
    assert_eq!(breakaway.value, 0.0);
}

/// Where counting resolves the tail, the product limit (counting, censoring handled) and the
/// conditional estimator (no counting at all) agree within the product limit's band — on the
/// paper scene, pooled and for the first stick.
#[test]
fn counting_and_conditioning_agree_where_both_resolve() {
    let times = [0.25, 0.5, 1.0];
    let t = tails_of(&["run.realizations=4000"], &times);
    for index in [None, Some(1)] {
        let pick = |m: &str| t.curves.iter().find(|c| c.variable == "D" && c.method == m && c.index == index).unwrap();
        let (km, cond) = (pick("kaplan_meier"), pick("conditional"));
        for &time in &times {
            let (s, lo, hi) = at(km, time);
            let (c, clo, chi) = at(cond, time);
            assert!(clo <= c && c <= chi && chi - clo < hi - lo, "the conditional band is the narrower one");
            assert!(lo <= c && c <= hi, "index {index:?}, t = {time}: Kaplan-Meier {s} [{lo}, {hi}], conditional {c}");
        }
    }
}

/// A short window cuts many sticks: dropping them (naive) biases the tail low, visibly outside
/// the product limit's band, while the product limit stays near the conditional estimator
/// (which does not depend on the window at all): at least three times nearer than the naive
/// curve (it need not be inside the band: early sticks, the only ones observed long here, are
/// entered in a state whose law still changes with time).
#[test]
fn censoring_at_a_short_horizon_biases_the_naive_tail_and_not_the_product_limit() {
    let times = [0.5, 1.0];
    let t = tails_of(&["run.realizations=6000", "run.duration=1.5", "belt.switch_rate=0.5"], &times);
    let (km, naive, cond) = (pooled(&t, "D", "kaplan_meier"), pooled(&t, "D", "naive"), pooled(&t, "D", "conditional"));
    assert!(km.censored as f64 > 0.2 * km.n as f64, "the window cuts many sticks: {} of {}", km.censored, km.n);
    for &time in &times {
        let (s, lo, hi) = at(km, time);
        let (c, _, _) = at(cond, time);
        let (nv, _, _) = at(naive, time);
        assert!(3.0 * (s - c).abs() < (nv - c).abs(), "t = {time}: Kaplan-Meier {s}, naive {nv}, conditional {c}");
        assert!(nv < lo, "t = {time}: naive {nv} inside the product limit's band [{lo}, {hi}]");
    }
}

/// A curve read at a user time τ counts exactly the durations below τ: every stick lasts a hair
/// less than τ = 0.5 s, inside the same time cell of width t_a/65,536 as τ (read at the cell's
/// lower edge, as before the cells were split at τ, S(τ) would be 1).
#[test]
fn a_curve_at_a_user_time_counts_the_durations_just_below_it() {
    use stickslip::simulation::dataset::{Layout, PartWriter, Rows};
    use stickslip::simulation::ensemble::Outcome;
    let tmp = tempfile::tempdir().unwrap();
    let (n, tau, d): (u64, f64, f64) = (400, 0.5, 0.5 - 2e-5);
    let rho = 10.0 / 65_536.0;
    assert_eq!((tau / rho).floor(), (d / rho).floor(), "d and τ share a cell");
    let sc = scenario(&[&format!("run.realizations={n}")]);
    let mut w = PartWriter::create(tmp.path(), 0, 1, Layout::default(), simulate::provenance(&sc.plan().unwrap(), Shard::WHOLE)).unwrap();
    let mut rows = Rows::new((false, false), 0, 0, 0);
    for i in 0..n {
        let mut o = Outcome::default();
        o.belt.initial_velocity = 1.0;
        (o.speed_scale, o.t_a) = (1.0, 10.0);
        let r = &mut o.record;
        (r.min_velocity, r.max_velocity) = (-1.0, 1.0);
        r.stick_start.extend([1.0, 3.0]);
        r.stick_duration.extend([d, d]);
        r.stick_end.extend([StickEnd::Flip, StickEnd::Flip]);
        r.stick_entry_position.extend([0.0, 0.0]);
        r.stick_entry_velocity.extend([1.0, 1.0]);
        r.slip_start.extend([1.0 + d, 3.0 + d]);
        r.slip_duration.extend([3.0 - 1.0 - d, 10.0 - 3.0 - d]);
        r.last_truncated = true;
        rows.push(i, &o);
    }
    w.write(rows).unwrap();
    w.commit().unwrap();
    let opts = Options { tail: TailOptions { times: vec![tau, d / 2.0], severity: vec![] }, ..Options::default() };
    let a = analysis::analyze(tmp.path(), &opts).unwrap();
    let t = a.tails.expect("tails");
    for method in ["kaplan_meier", "naive"] {
        let c = pooled(&t, "D", method);
        let value = |t: f64| c.points.iter().find(|p| p.0 == t).expect("the asked time is on the curve").1;
        assert_eq!(value(tau), 0.0, "{method}: no stick lasts τ");
        assert_eq!(value(d / 2.0), 1.0, "{method}: every stick lasts d/2");
    }
}
