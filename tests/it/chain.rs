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
        eprintln!("{sets:?}: {} events, worst {worst:e}", errors.len());
        assert_eq!((missed, spurious), (0, 0), "{sets:?}");
        assert!(worst < 1e-9, "{sets:?}: worst event-time difference {worst:e} s over {} events", errors.len());
        for (a, b) in closed.iter().zip(&chain) {
            assert_eq!(a.stick_end, b.stick_end, "{sets:?}");
            assert!((a.min_velocity - b.min_velocity).abs() < 1e-9 && (a.max_velocity - b.max_velocity).abs() < 1e-9, "{sets:?}");
        }
    }
}
