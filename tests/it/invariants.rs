//! Property tests: the counting invariants over random scenarios and seeds.

use proptest::prelude::*;

use crate::common::{check_invariants, outcomes, scenario};

#[allow(clippy::too_many_arguments)] // one argument per drawn scene key
fn sets(m: f64, k: f64, mu: f64, v0: f64, lambda: f64, ta: f64, sign: &str, seed: u64) -> Vec<String> {
    vec![
        format!("model.mass={m:e}"),
        format!("model.stiffness={k:e}"),
        format!("model.friction_coefficient={mu:e}"),
        format!("belt.speed={v0:e}"),
        format!("belt.switch_rate={lambda:e}"),
        format!("run.duration={ta:e}"),
        format!("belt.initial_sign={sign}"),
        format!("run.seed={seed}"),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn invariants_hold_over_random_scenarios(
        m in 0.05f64..20.0,
        k in prop_oneof![Just(0.0), 0.01f64..100.0],
        mu in prop_oneof![Just(0.0), 0.01f64..3.0],
        v0 in 0.05f64..20.0,
        lambda in prop_oneof![Just(0.0), 0.05f64..50.0],
        ta in 0.5f64..40.0,
        sign in prop_oneof![Just("1"), Just("-1"), Just("\"random\"")],
        seed in 0u64..1_000_000,
    ) {
        let s = sets(m, k, mu, v0, lambda, ta, sign, seed);
        let refs: Vec<&str> = s.iter().map(String::as_str).collect();
        let sc = scenario(&refs);
        let p = crate::common::params(&sc);
        let dmax = 2.0 * p.static_ * p.normal_force / (k * v0);
        for (i, o) in outcomes(&sc, 8).iter().enumerate() {
            if let Err(e) = check_invariants(&sc, o, true) {
                return Err(TestCaseError::fail(format!("realization {i}: {e}")));
            }
            for &d in &o.record.stick_duration {
                prop_assert!(d <= dmax * (1.0 + 1e-12), "stick of {d} s > 2 f_max/(k v0) = {dmax}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Damping (under-, critically and over-damped), static friction above kinetic and the
    /// asymmetric belt: every invariant, and no stick longer than the holding force's full swing
    /// 2 mu_s n / (k v) at the slower belt speed.
    #[test]
    fn invariants_hold_over_random_scenes(
        c in prop_oneof![Just(0.0), Just(4.0), 0.0f64..12.0],
        excess in prop_oneof![Just(0.0), 0.0f64..2.0],
        mu in 0.05f64..1.5,
        vr in prop_oneof![Just(None), (0.01f64..5.0).prop_map(Some)],
        lr in 0.0f64..20.0,
        seed in 0u64..1_000_000,
    ) {
        let mut s = sets(1.0, 4.0, mu, 1.0, 5.0, 10.0, "\"random\"", seed);
        s.push(format!("model.damping={c:e}"));
        s.push(format!("model.static_friction_coefficient={:e}", mu + excess));
        if let Some(vr) = vr {
            s.push(format!("belt.reverse_speed={vr:e}"));
            s.push(format!("belt.reverse_switch_rate={lr:e}"));
        }
        let refs: Vec<&str> = s.iter().map(String::as_str).collect();
        let sc = scenario(&refs);
        let dmax = 2.0 * (mu + excess) * 9.8 / (4.0 * vr.unwrap_or(1.0).min(1.0));
        for (i, o) in outcomes(&sc, 8).iter().enumerate() {
            if let Err(e) = check_invariants(&sc, o, true) {
                return Err(TestCaseError::fail(format!("realization {i}: {e}")));
            }
            for &d in &o.record.stick_duration {
                prop_assert!(d <= dmax * (1.0 + 1e-12), "stick of {d} s > {dmax}");
            }
        }
    }
}
