//! `predict`: the next stick from a given state — exact (the first passage of the law module)
//! against conditional Monte Carlo computed here from the simulated records, the Monte Carlo
//! path against a closed form (no spring: a stuck mass waits for the next flip), and the states
//! and options it refuses.

use stickslip::predict::{run, Options, Prediction, State};
use stickslip::simulation::events::StickEnd;

use crate::common::{outcomes, scenario, stickslip};

/// Mean, variance and their standard errors (the variance's from the fourth central moment).
fn summary(xs: &[f64]) -> [f64; 4] {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let m2 = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    let m4 = xs.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
    [mean, m2 * n / (n - 1.0), (m2 / n).sqrt(), ((m4 - m2 * m2) / n).sqrt()]
}

fn exact(p: &Prediction, variable: &str) -> (f64, f64, f64) {
    let r = p.rows.iter().find(|r| r.variable == variable && r.method == "exact").unwrap_or_else(|| panic!("an exact {variable} row"));
    (r.mean, r.variance, r.error)
}

/// From a slipping and from a stuck state on the paper scene, on μ_s = 0.6, stuck on the damped
/// scene (c = 0.5 N·s/m) and on the asymmetric belt (stuck on the reverse belt, slipping on the
/// forward one): every exact mean
/// and variance within 4.5 standard errors (plus its own error estimate) of 30,000 futures
/// simulated from the state, their τ, D, H and breakaway read off the records here.
#[test]
fn exact_agrees_with_futures_from_the_same_state() {
    let asymmetric = vec!["belt.reverse_speed=0.5", "belt.reverse_switch_rate=2"];
    for (sets, (x, v, belt, stuck)) in [
        (vec![], (0.5, 0.0, 1.0, false)),
        (vec![], (0.3, 1.0, 1.0, true)),
        (vec!["model.static_friction_coefficient=0.6"], (-1.0, 2.5, 1.0, false)),
        (vec!["model.damping=0.5"], (0.2, 1.0, 1.0, true)),
        (asymmetric.clone(), (0.4, -0.5, -0.5, true)),
        (asymmetric.clone(), (-0.8, 0.3, 1.0, false)),
    ] {
        let mut all: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let sc = scenario(&sets);
        let p = run(
            &sc,
            State { x, velocity: v, belt, stuck },
            Options { resolution: 24, futures: None, horizon: None, densities: None },
            None,
            stickslip::progress::Control::silent(),
        )
        .unwrap();
        assert!(p.exact_refused.is_none() && p.rows.iter().all(|r| r.method == "exact"));
        all.extend([format!("initial_conditions.position=[{x:?}, {x:?}]"), format!("initial_conditions.velocity=[{v:?}, {v:?}]"), "run.duration=15".into()]);
        all.push(format!("belt.initial_sign={}", if belt > 0.0 { 1 } else { -1 }));
        let futures = crate::common::scenario(&all.iter().map(String::as_str).collect::<Vec<_>>());
        let k = usize::from(stuck);
        let (mut remaining, mut tau, mut d, mut h, mut b) = (vec![], vec![], vec![], vec![], vec![]);
        for o in outcomes(&futures, 30_000) {
            let r = &o.record;
            assert_eq!(r.stick_start.first() == Some(&0.0), stuck);
            assert!(r.stick_start.len() > k + 1 && r.stick_end[k] != StickEnd::Horizon, "a future unfinished at 15 s");
            if stuck {
                remaining.push(r.stick_duration[0]);
            }
            tau.push(r.stick_start[k]);
            d.push(r.stick_duration[k]);
            h.push(r.slip_duration[k]);
            b.push(if r.stick_end[k] == StickEnd::Breakaway { 1.0 } else { 0.0 });
        }
        let mut pairs = vec![("time_to_stick", tau), ("stick_duration", d), ("slip_duration", h), ("breakaway", b)];
        if stuck {
            pairs.push(("remaining_stick", remaining));
        }
        for (name, xs) in pairs {
            let [mean, var, se_mean, se_var] = summary(&xs);
            let (m, s2, err) = exact(&p, name);
            assert!((m - mean).abs() <= 4.5 * se_mean + err, "{sets:?} {name}: exact mean {m} ± {err}, futures {mean} ± {se_mean}");
            assert!((s2 - var).abs() <= 4.5 * se_var + 2.0 * err * m.abs(), "{sets:?} {name}: exact variance {s2}, futures {var} ± {se_var}");
        }
    }
}

/// Without a spring a stick ends only by a flip: from a stuck state the remaining stick is
/// Exp(λ), mean 1/λ, variance 1/λ² (the exact method refuses the scene and says why, and the
/// command simulates futures instead).
#[test]
fn without_a_spring_a_stuck_mass_waits_for_the_next_flip() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["predict", "--set", "model.stiffness=0", "--state=-0.3,1,1", "--stuck", "--futures", "40000", "--out", "p"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("exact: not available here (model.stiffness is 0"));
    let t = stickslip::table::Table::read_checked(
        &tmp.path().join("p/prediction.parquet"),
        &[("variable", 's'), ("method", 's'), ("mean", 'f'), ("variance", 'f'), ("error", 'f'), ("futures", 'i')],
    )
    .unwrap();
    let at = t.strings("variable").unwrap().iter().position(|v| v == "remaining_stick").unwrap();
    let get = |c: &str| t.floats(c).unwrap()[at].unwrap();
    let (mean, var, se) = (get("mean"), get("variance"), get("error"));
    let lambda = 5.0;
    assert!((mean - 1.0 / lambda).abs() < 4.5 * se, "{mean} ± {se}");
    // the sample variance of Exp(λ) has standard error σ² √(8/n) (fourth central moment 9σ⁴)
    assert!((var - 1.0 / (lambda * lambda)).abs() < 4.5 * (8.0f64 / 40_000.0).sqrt() / (lambda * lambda), "{var}");
    assert_eq!(t.strings("method").unwrap()[at], "monte_carlo");
}

/// The same printed table for 1 and 3 threads (exact and futures), and one clear line for each
/// state or option the command cannot take, with nothing written.
#[test]
fn refusals_are_one_line_and_the_output_does_not_depend_on_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let args = ["predict", "--state", "0.5,0,1", "--resolution", "16", "--futures", "3000"];
    let with = |threads: &str| {
        let o =
            std::process::Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).env("RAYON_NUM_THREADS", threads).current_dir(tmp.path()).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        o.stdout
    };
    assert_eq!(with("1"), with("3"));
    // a belt too fast for the exact method's coarsest grid: the futures answer instead
    let o = stickslip(&["predict", "--set", "belt.switch_rate=30", "--state", "0.5,0,1", "--futures", "2000"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("exact: not available here (the mass moves about v0/lambda"));
    assert!(String::from_utf8_lossy(&o.stdout).contains("| time_to_stick | monte carlo |"));
    // a mass velocity within rounding of the belt's is the belt's: stuck, not refused
    let o = stickslip(&["predict", "--state", "0.3,1.0000000001,1", "--stuck", "--futures", "100", "--resolution", "8", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let markov = format!("{}/pipelines/scenes/markov_belt.toml", env!("CARGO_MANIFEST_DIR"));
    for (args, says) in [
        (vec!["--state", "0.5,0,2"], "not a state of this belt"),
        (vec!["--state", "0.3,0.5,1", "--stuck"], "must equal the belt velocity"),
        (vec!["--state", "2,1,1", "--stuck"], "holding limit"),
        (vec!["--state", "0.3,1,1"], "add --stuck"),
        (vec!["--state", "1,2"], "expected three numbers"),
        (vec!["--state", "nan,0,1"], "finite"),
        (vec!["--state", "0.5,0,1", "--futures", "0"], "--futures must be at least 1"),
        (vec!["--state", "0.5,0,1", "--horizon=-1"], "--horizon -1: must be a positive number"),
        (vec!["--state", "0.5,0,1", "--horizon", "nan"], "--horizon NaN: must be a positive number"),
        (vec!["--state", "0.5,0,1", "--resolution", "4"], "--resolution 4"),
        (vec![markov.as_str(), "--state", "0.5,0,1"], "two-state belt"),
    ] {
        let mut all = vec!["predict", "--out", "o", "-q"];
        all.extend(args.iter().copied());
        let o = stickslip(&all, tmp.path());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        // (clap's own errors add a line pointing to --help)
        let lines = err.trim_end().lines().filter(|l| !l.is_empty() && !l.starts_with("For more information")).count();
        assert!(err.contains(says) && lines == 1, "{args:?}: {err}");
        assert!(!tmp.path().join("o").exists(), "{args:?} left an output");
    }
}

/// `predict --out`'s `stick_survival.parquet` is `exact-law`'s D law for the next stick: P(D > 0)
/// = 1, non-increasing, 0 past the longest holding time, and its integral — between the right
/// and the left Riemann sums of a non-increasing curve, widened by the points' error estimates —
/// is the exact mean of the stick's duration in `prediction.parquet` (E[D] = ∫ P(D > t) dt).
#[test]
fn the_next_sticks_survival_curve_integrates_to_its_mean_duration() {
    let tmp = tempfile::tempdir().unwrap();
    let o = stickslip(&["predict", "--state", "0.5,0,1", "--resolution", "16", "--futures", "100", "--out", "p", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let sv = stickslip::table::Table::read_checked(
        &tmp.path().join("p/stick_survival.parquet"),
        &[("variable", 's'), ("index", 'i'), ("method", 's'), ("t", 'f'), ("survival", 'f'), ("error", 'f'), ("density", 'f')],
    )
    .unwrap();
    let (t, s, e): (Vec<f64>, Vec<f64>, Vec<f64>) = (
        sv.floats("t").unwrap().iter().map(|x| x.unwrap()).collect(),
        sv.floats("survival").unwrap().iter().map(|x| x.unwrap()).collect(),
        sv.floats("error").unwrap().iter().map(|x| x.unwrap()).collect(),
    );
    assert!((s[0] - 1.0).abs() < 1e-9 && *s.last().unwrap() == 0.0, "{} … {}", s[0], s.last().unwrap());
    assert!(s.windows(2).zip(e.windows(2)).all(|(w, d)| w[1] <= w[0] + d[0] + d[1] + 1e-12));
    let dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let right: f64 = s[1..].iter().zip(&dt).map(|(x, d)| x * d).sum();
    let left: f64 = s[..s.len() - 1].iter().zip(&dt).map(|(x, d)| x * d).sum();
    let slack: f64 = e.iter().zip(dt.iter().chain([&0.0])).map(|(x, d)| x * d).sum();
    let p =
        stickslip::table::Table::read_checked(&tmp.path().join("p/prediction.parquet"), &[("variable", 's'), ("method", 's'), ("mean", 'f'), ("error", 'f')])
            .unwrap();
    let r = (0..p.height()).find(|&r| p.strings("variable").unwrap()[r] == "stick_duration" && p.strings("method").unwrap()[r] == "exact").unwrap();
    let (mean, err) = (p.floats("mean").unwrap()[r].unwrap(), p.floats("error").unwrap()[r].unwrap());
    assert!(right - slack - err <= mean && mean <= left + slack + err, "E[D] = {mean} ± {err} outside [{right}, {left}] ± {slack}");
}
