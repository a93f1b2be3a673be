//! The exact chain solver: against the closed forms (N = 1), against an independent RK4
//! reference (N = 2, 3), in the stiff limit, and by its energy balance.

use stickslip::chain::{Anchor, Chain, ChainExact};
use stickslip::simulation::events::Record;
use stickslip::solver::{drive, Drive};

use crate::common::{event_errors, outcomes, scenario};

fn solve_chain(ch: &Chain, anchor: &Anchor, velocities: &[f64], switches: &[f64], x0: &[f64], xd0: &[f64], t_a: f64) -> Record {
    let mut m = ChainExact::new(ch, anchor, x0, xd0, t_a);
    let d = Drive { velocities, switches, t_end: t_a };
    let mut rec = Record::default();
    let n = ch.len();
    drive(&mut m, &d, x0[n - 1], xd0[n - 1], u64::MAX, &mut rec).expect("solves");
    rec.finish(t_a);
    rec
}

#[test]
fn one_mass_on_a_fixed_anchor_is_the_closed_forms() {
    // the paper scene, and a damped one with μ_s > μ_k and a viscous term
    for sets in [vec![], vec!["model.damping=0.3", "model.static_friction_coefficient=0.6", "model.viscous_friction=0.2"]] {
        let sc = scenario(&sets);
        let p = crate::common::params(&sc);
        let ch = Chain {
            masses: vec![p.mass],
            stiffnesses: vec![p.stiffness],
            dampings: vec![p.damping],
            kinetic: p.kinetic * p.normal_force,
            breakaway: p.static_ * p.normal_force,
            viscous: p.viscous,
        };
        let outs = outcomes(&sc, 200);
        let chain: Vec<Record> =
            outs.iter().map(|o| solve_chain(&ch, &Anchor::constant(0.0), o.velocities(), o.switches(), &[o.x0], &[o.xdot0], o.t_a)).collect();
        let closed: Vec<Record> = outs.iter().map(|o| o.record.clone()).collect();
        let (errors, missed, spurious) = event_errors(&closed, &chain);
        let worst = errors.last().copied().unwrap_or(0.0);
        // (printed for the book: cargo test --release --test it chain -- --nocapture)
        eprintln!("one mass {sets:?}: {} events, worst difference {worst:e} s", errors.len());
        assert_eq!((missed, spurious), (0, 0), "{sets:?}");
        assert!(worst < 1e-9, "{sets:?}: worst event-time difference {worst:e} s over {} events", errors.len());
        for (a, b) in closed.iter().zip(&chain) {
            assert_eq!(a.stick_end, b.stick_end, "{sets:?}");
            assert!((a.min_velocity - b.min_velocity).abs() < 1e-9 && (a.max_velocity - b.max_velocity).abs() < 1e-9, "{sets:?}");
        }
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1], 8 points.
const GAUSS: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

#[test]
fn energy_balance_along_a_trajectory() {
    // dE/dt = u T − Σ c_i (ẋ_i − ẋ_{i−1})² + f ẋ_N, with T = k₁(a − x₁) + c₁(u − ẋ₁) the
    // anchor's force and f the contact's (σ f_k + σ_v (v − ẋ_N) slipping, F stuck), integrated
    // by 8-point Gauss–Legendre on every piece the solver advances over (each smooth; their
    // length ≤ 1/(2‖Ã‖) makes the rule exact to rounding) against E(t_a) − E(0)
    use stickslip::solver::{Event, Method, Stop};
    let ch =
        Chain { masses: vec![1.0, 0.7, 1.3], stiffnesses: vec![3.0, 6.0, 4.0], dampings: vec![0.2, 0.1, 0.3], kinetic: 3.0, breakaway: 4.0, viscous: 0.25 };
    let anchor = Anchor { velocities: vec![0.8, 2.0, 0.4], switches: vec![3.0, 7.5] };
    let (velocities, switches) = ([1.0, -0.5, 0.0, 1.5], [2.0, 5.0, 9.0]);
    let t_a = 12.0;
    let (x0, xd0) = ([0.3, -0.2, 0.5], [0.1, 0.4, -0.3]);
    let n = ch.len();
    let mut m = ChainExact::new(&ch, &anchor, &x0, &xd0, t_a);
    m.keep_pieces();
    let e0 = ch.energy(&m.state_of_all_at(0.0));
    let u_at = |t: f64| anchor.velocities[anchor.switches.partition_point(|&s| s <= t)];
    let power = |z: &[f64], t: f64, v: f64, stuck: bool| {
        let u = u_at(t);
        let (x, xd, a) = (&z[..n], &z[n..2 * n], z[2 * n]);
        let tension = ch.stiffnesses[0] * (a - x[0]) + ch.dampings[0] * (u - xd[0]);
        let mut p = u * tension;
        for i in 0..n {
            let prev = if i == 0 { u } else { xd[i - 1] };
            p -= ch.dampings[i] * (xd[i] - prev) * (xd[i] - prev);
        }
        let f = if stuck {
            let (xp, vp) = if n == 1 { (a, u) } else { (x[n - 2], xd[n - 2]) };
            ch.stiffnesses[n - 1] * (x[n - 1] - xp) + ch.dampings[n - 1] * (v - vp)
        } else {
            let w = v - xd[n - 1];
            ch.kinetic * w.signum() + ch.viscous * w
        };
        p + f * xd[n - 1]
    };
    let mut v = velocities[0];
    let _ = m.start(x0[n - 1], xd0[n - 1], v);
    let (mut work, mut scale, mut events) = (0.0, 0.0, 0);
    // the anchor's force T integrated the same way, and seen at every node: the solver's
    // summary must hold the integral, and a range that holds every node's value
    let (mut tension, mut seen) = (0.0, (f64::INFINITY, f64::NEG_INFINITY));
    for (k, &t1) in switches.iter().chain([t_a].iter()).enumerate() {
        loop {
            let (t0, stuck) = (m.time(), m.stuck());
            let stop = m.advance(t1, v);
            let t = m.time();
            for (node, weight) in GAUSS {
                let s = t0 + 0.5 * (t - t0) * (node + 1.0);
                let z = m.state_of_all_at(s);
                let p = power(&z, s, v, stuck) * 0.5 * (t - t0) * weight;
                work += p;
                scale += p.abs();
                let f = ch.stiffnesses[0] * (z[2 * n] - z[0]) + ch.dampings[0] * (u_at(s) - z[n]);
                tension += f * 0.5 * (t - t0) * weight;
                seen = (seen.0.min(f), seen.1.max(f));
            }
            match stop {
                Stop::SegmentEnd => break,
                Stop::Event(Event::Stick { .. } | Event::Slip { .. }) => events += 1,
                Stop::Advanced => {}
            }
        }
        if let Some(&v_new) = velocities.get(k + 1) {
            let _ = m.switch(t1, v, v_new);
            v = v_new;
        }
    }
    let e1 = ch.energy(m.state());
    assert!(events >= 5, "{events} events");
    let gap = (e1 - e0 - work).abs() / scale;
    let summary = m.summary();
    let mean = tension / t_a;
    assert!((summary.anchor_force_mean - mean).abs() < 1e-12 * mean.abs(), "anchor force mean {} vs {mean}", summary.anchor_force_mean);
    let (lo, hi) = (summary.anchor_force_min, summary.anchor_force_max);
    assert!(lo <= seen.0 && seen.1 <= hi && seen.0 - lo < 1e-2 * (hi - lo) && hi - seen.1 < 1e-2 * (hi - lo), "range [{lo}, {hi}], seen {seen:?}");
    let drift = (m.state()[n - 1] - x0[n - 1]) / t_a;
    assert!((summary.mean_velocity - drift).abs() < 1e-15 * drift.abs().max(1.0), "mean velocity {} vs {drift}", summary.mean_velocity);
    eprintln!("energy balance: {events} events, relative gap {gap:e}");
    assert!(gap < 1e-9, "E(t_a) − E(0) = {:e}, work {work:e}: relative gap {gap:e}", e1 - e0);
}

#[test]
fn a_stiff_damped_spring_makes_two_masses_one() {
    // m₁ —k₂→∞— m₂ on the contact tends to one mass m₁ + m₂ on k₁ (the closed forms); the
    // event times approach it as the stiff mode's deflection, O(1/k₂)
    let sc = scenario(&["model.static_friction_coefficient=0.6"]);
    let p = crate::common::params(&sc);
    let outs = outcomes(&sc, 20);
    let closed: Vec<Record> = outs.iter().map(|o| o.record.clone()).collect();
    let mut worst = Vec::new();
    for k2 in [1e3, 1e4, 1e5] {
        let (m1, m2) = (0.4 * p.mass, 0.6 * p.mass);
        // the internal mode critically damped
        let c2 = 2.0 * (k2 * m1 * m2 / (m1 + m2)).sqrt();
        let ch = Chain {
            masses: vec![m1, m2],
            stiffnesses: vec![p.stiffness, k2],
            dampings: vec![0.0, c2],
            kinetic: p.kinetic * p.normal_force,
            breakaway: p.static_ * p.normal_force,
            viscous: 0.0,
        };
        let chain: Vec<Record> = outs
            .iter()
            .map(|o| {
                // both masses start together (the rigid body's state)
                solve_chain(&ch, &Anchor::constant(0.0), o.velocities(), o.switches(), &[o.x0, o.x0], &[o.xdot0, o.xdot0], o.t_a)
            })
            .collect();
        let (errors, missed, spurious) = event_errors(&closed, &chain);
        let mid = errors[errors.len() / 2];
        eprintln!("stiff limit k2 = {k2:e}: median difference {mid:e} s, {} unmatched of {}", missed + spurious, errors.len());
        worst.push((mid, missed + spurious));
    }
    // the median difference falls with k₂ (measured 1.4e-5, 2.6e-6, 1.7e-7 s), and the sticks
    // the stiff mode adds or removes (an event near a threshold) vanish: 2, 1, 0 of 671
    assert!(worst.windows(2).all(|w| w[1].0 < w[0].0 / 4.0) && worst[2].0 < 1e-6, "median event-time differences {worst:?}");
    assert!(worst[0].1 <= 4 && worst[2].1 == 0, "unmatched events {worst:?}");
}

#[test]
fn chain_scenarios_are_refused_with_the_culprit() {
    use stickslip::scenario::Scenario;
    let refused = |sets: &[&str], key: &str, why: &str| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let e = Scenario::resolve(None, &sets).expect_err(&format!("{sets:?} is refused")).to_string();
        assert!(e.contains(key) && e.contains(why), "{sets:?}: {e}");
    };
    let two = ["chain.masses=[1, 1]", "chain.stiffnesses=[4, 8]"];
    refused(&[two[0], "chain.stiffnesses=[4]"], "chain.stiffnesses", "one value per mass");
    refused(&[two[0], two[1], "model.mass=2"], "model.mass", "[chain] gives the masses");
    refused(&[two[0], two[1], "model.damping=0.1"], "model.damping", "[chain] gives the masses");
    refused(&["chain.masses=[1, 0]", "chain.stiffnesses=[4, 8]"], "chain.masses", "the range the solvers are proven on");
    refused(&[two[0], two[1], "run.solver=\"rk45\""], "run.solver", "exact chain solver only");
    refused(&[two[0], two[1], "model.friction_law=\"stribeck\"", "model.stribeck_velocity=0.1"], "model.friction_law", "Coulomb");
    refused(&[two[0], "chain.stiffnesses=[4, 1e9]", "run.duration=100"], "chain.stiffnesses", "radians");
    refused(&["anchor.speed=1", "belt.process=\"constant\"", "belt.velocity=1"], "anchor.speed", "nothing slides");
    refused(&["belt.process=\"constant\"", "belt.velocity=0"], "belt.velocity", "moves nothing");
    refused(&["belt.process=\"constant\""], "belt.velocity", "needs belt.velocity");
    refused(&["anchor.process=\"markov\"", "anchor.speed=1"], "anchor.speed", "only anchor.process = \"constant\"");
    refused(&["anchor.process=\"markov\"", "anchor.velocities=[1, 2]"], "anchor.rates", "needs anchor.velocities");
    // a one-mass chain on a fixed anchor is the paper's oscillator, run by its closed forms
    let one = Scenario::resolve(None, &["chain.masses=[1]".into(), "chain.stiffnesses=[4]".into()]).unwrap();
    assert!(one.scene().unwrap().chain.is_none());
    assert_eq!(one.scene().unwrap().params, Scenario::paper().scene().unwrap().params);
}

#[test]
fn degenerate_chains_finish() {
    // an anchor at the belt's speed (the anchor force constant through a stick), a first link
    // with neither spring nor dashpot (the anchor force zero), a free mass: each realization
    // ends, with finite rows (the probe that hung on them: a search for the turning points of a
    // polynomial that is zero)
    for sets in [
        vec!["anchor.speed=1"],
        vec!["chain.masses=[1]", "chain.stiffnesses=[4]", "anchor.speed=-1"],
        vec!["chain.masses=[1, 1]", "chain.stiffnesses=[0, 4]"],
        vec!["chain.masses=[1, 1]", "chain.stiffnesses=[0, 0]"],
        vec!["chain.masses=[1]", "chain.stiffnesses=[0]", "anchor.speed=-0.001"],
    ] {
        let sc = scenario(&sets);
        for o in outcomes(&sc, 20) {
            let c = o.chain.expect("a chain's summary");
            assert!([c.anchor_force_mean, c.anchor_force_min, c.anchor_force_max, c.mean_velocity].iter().all(|x| x.is_finite()), "{sets:?}");
        }
    }
}

#[test]
fn chattering_sticks_end_with_an_error_naming_the_instant() {
    // an undamped stiff internal mode under μ_s = μ_k: the sticks of realization 101 accumulate
    // near t = 9.05 s; the run stops there with one line instead of running on
    let sc = scenario(&["chain.masses=[0.5, 0.5]", "chain.stiffnesses=[4, 1e6]"]);
    let ens = sc.ensemble().unwrap();
    let mut o = stickslip::simulation::ensemble::Outcome::default();
    let e = ens.realization(101, &mut o).expect_err("chatters").to_string();
    assert!(e.contains("realization 101") && e.contains("accumulate at t = 9.0"), "{e}");
}
