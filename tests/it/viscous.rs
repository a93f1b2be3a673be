//! The viscous term of the friction law, f = f_dry(u) sgn(u) + σ_v u (`model.viscous_friction`):
//! the exact solver against the independent RK4 reference is in `reference.rs`; here the
//! numerical solvers against exact, the law's force against the formula written out, the
//! Stribeck law with it, the door and the extremes.

use stickslip::physics::{Law, Params, Stribeck};

use crate::common::{check_invariants, event_errors as errors, outcomes, scenario};

fn records(sets: &[&str], n: u64) -> Vec<stickslip::simulation::events::Record> {
    outcomes(&scenario(sets), n).into_iter().map(|o| o.record).collect()
}

#[test]
fn the_slip_force_is_the_dry_law_plus_the_viscous_term() {
    // per unit mass: ẍ = [σ f_dry(|u|) + σ_v u − k x − c ẋ]/m, written out here from the law's
    // definition (Stribeck: f_dry = n [μ_k + (μ_s − μ_k) exp(−(|u|/v_s)^δ)])
    let (m, k, c, n, mk, ms, sv, vs, d) = (2.0, 3.0, 0.4, 9.8, 0.4, 0.55, 1.7, 0.2, 1.5);
    let stribeck = Law::Stribeck(Stribeck { velocity: vs, exponent: d });
    for law in [Law::Coulomb, stribeck] {
        let p = Params { mass: m, stiffness: k, damping: c, normal_force: n, kinetic: mk, static_: ms, viscous: sv, law }.per_unit_mass();
        for (x, xd, v) in [(0.3, -0.2, 1.0), (-1.0, 2.5, 1.0), (0.1, 0.05, -0.5), (0.0, 0.3, 0.0)] {
            let u: f64 = v - xd;
            let dry = match law {
                Law::Coulomb => n * mk,
                Law::Stribeck(_) => n * (mk + (ms - mk) * (-(u.abs() / vs).powf(d)).exp()),
            };
            let want = (u.signum() * dry + sv * u - k * x - c * xd) / m;
            let got = p.slip_accel(x, xd, v, u.signum());
            assert!((got - want).abs() < 1e-12 * want.abs().max(1.0), "{law:?} at ({x}, {xd}, {v}): {got} vs {want}");
            // in a stick (u = 0) the viscous term vanishes: the holding force is k x + c v
            assert!((p.holding(x, v) - (k * x + c * v) / m).abs() < 1e-12);
        }
    }
}

#[test]
fn numerical_solvers_converge_to_exact_with_viscous_friction() {
    for viscous in ["model.viscous_friction=0.8", "model.viscous_friction=10"] {
        let exact = records(&[viscous], 20);
        let run = |extra: &[&str]| errors(&exact, &records(&[&[viscous][..], extra].concat(), 20));
        let tight = run(&["run.solver=\"rk45\"", "numerics.rtol=1e-10", "numerics.atol=1e-10", "numerics.max_step=1e-2"]);
        assert_eq!((tight.1, tight.2), (0, 0), "{viscous}: rk45 missed or added sticks");
        assert!(tight.0.len() > 100 && *tight.0.last().unwrap() < 1e-6, "{viscous}: rk45 largest error {:e}", tight.0.last().unwrap());
        // moreau is first order: the median error falls about tenfold with the step
        let med = |e: &(Vec<f64>, u64, u64)| e.0[e.0.len() / 2];
        let (coarse, fine) = (run(&["run.solver=\"moreau\"", "numerics.step=1e-2"]), run(&["run.solver=\"moreau\"", "numerics.step=1e-3"]));
        let ratio = med(&coarse) / med(&fine);
        assert!((4.0..=25.0).contains(&ratio), "{viscous}: moreau's median error ratio for h/10: {ratio}");
    }
}

#[test]
fn stribeck_with_equal_coefficients_and_viscous_friction_is_coulomb_with_it() {
    let viscous = "model.viscous_friction=0.8";
    let exact = records(&[viscous], 20);
    let stribeck = records(
        &[
            viscous,
            "model.friction_law=\"stribeck\"",
            "model.stribeck_velocity=0.1",
            "model.static_friction_coefficient=0.51",
            "run.solver=\"rk45\"",
            "numerics.rtol=1e-11",
            "numerics.atol=1e-11",
            "numerics.max_step=1e-2",
        ],
        20,
    );
    let (errs, missed, spurious) = errors(&exact, &stribeck);
    assert_eq!((missed, spurious), (0, 0));
    assert!(*errs.last().unwrap() < 1e-7, "largest event-time error {:e}", errs.last().unwrap());
}

#[test]
fn stribeck_with_viscous_friction_runs_and_keeps_the_invariants() {
    let sets = [
        "model.viscous_friction=2",
        "model.friction_law=\"stribeck\"",
        "model.stribeck_velocity=0.1",
        "model.static_friction_coefficient=0.6",
        "run.solver=\"rk45\"",
    ];
    let sc = scenario(&sets);
    for o in outcomes(&sc, 50) {
        check_invariants(&sc, &o, true).unwrap();
    }
}

#[test]
fn the_door_refuses_a_negative_or_too_large_viscous_term() {
    for (value, words) in [("-0.1", "must be"), ("1e12", "must be"), ("\"x\"", "must be a number")] {
        let err = stickslip::scenario::Scenario::resolve(None, &[format!("model.viscous_friction={value}")]).unwrap_err().to_string();
        assert!(err.contains("model.viscous_friction") && err.contains(words), "{value}: {err}");
    }
    // the numerical solvers' rate rule counts it: (c + σ_v)/m · t_a ≤ 1e6 radians
    let err = stickslip::scenario::Scenario::resolve(None, &["model.viscous_friction=1e6".into(), "run.solver=\"rk45\"".into()]).unwrap_err().to_string();
    assert!(err.contains("model.viscous_friction") && err.contains("(c + sigma_v)/m"), "{err}");
}
