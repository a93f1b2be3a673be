//! The law without sampling (`exact-law`): against a closed form (the deterministic stick-slip
//! cycle that μ_s > μ_k leaves when flips are rare), against long Monte Carlo runs of the exact
//! solver, and its refusals.

use std::f64::consts::PI;

use stickslip::law::{stationary, Level, QUANTITIES};
use stickslip::simulation::ensemble::Outcome;
use stickslip::simulation::events::StickEnd;

use crate::common::{outcomes, scenario};

fn value(level: &Level, name: &str) -> f64 {
    level.values[QUANTITIES.iter().position(|q| *q == name).expect("a quantity")]
}

/// With μ_s > μ_k the breakaway slip falls behind the belt and sticks again: without flips the
/// motion is a cycle — a stick from 2c_k − c_s to c_s (holding time 2(c_s − c_k)/v0), then the
/// slip on the circle about c_k through (c_s, v0), which takes (2π − 2φ0)/ω with
/// φ0 = atan((c_s − c_k)ω/v0). With a flip every 10^4 s on average the long run is that cycle
/// but for the transients after flips (relative share ~ λ × a few seconds). (Not so the
/// variances: a flip can leave the mass on a circle that never reaches belt speed, and that slip
/// lasts ~1/λ.)
#[test]
fn rare_flips_leave_the_deterministic_cycle() {
    let sc = scenario(&["model.static_friction_coefficient=0.6", "belt.switch_rate=1e-4"]);
    let levels = stationary(&sc.scene().unwrap(), 16, 1).unwrap();
    let l = &levels[0];
    let (omega, v0): (f64, f64) = (2.0, 1.0);
    let (ck, cs) = (0.51 * 9.8 / 4.0, 0.6 * 9.8 / 4.0);
    let hold = 2.0 * (cs - ck) / v0;
    let phi0 = ((cs - ck) * omega / v0).atan();
    let slip = (2.0 * PI - 2.0 * phi0) / omega;
    let period = hold + slip;
    let close = |got: f64, want: f64, what: &str| assert!((got - want).abs() <= 2e-3 * want, "{what}: {got} against the cycle's {want}");
    close(value(l, "stick_fraction"), hold / period, "stick fraction");
    close(value(l, "sticks_per_second"), 1.0 / period, "sticks per second");
    close(value(l, "mean_stick_duration"), hold, "mean stick duration");
    close(value(l, "mean_slip_duration"), slip, "mean slip duration");
    close(value(l, "breakaway_fraction"), 1.0, "breakaway fraction");
    assert!((l.covered - 1.0).abs() < 1e-12, "the walks account for the whole time to the next flip: {}", l.covered);
}

/// Long-run estimates from Monte Carlo (realizations independent): the time stuck and the sticks
/// begun within [burn, horizon] per second; the durations of the sticks and slips begun within
/// [burn, horizon − 30 s], all of which end before the horizon (dropping the ones cut there would
/// bias the mean slip duration low: the cut ones are the long ones). Each a ratio Σa/Σb of
/// per-realization sums, with its delta-method standard error.
struct LongRun {
    /// (estimate, standard error) per quantity of [`QUANTITIES`]
    values: Vec<(f64, f64)>,
}

fn long_run(sets: &[&str], realizations: u64, horizon: f64, burn: f64) -> LongRun {
    let mut all: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    all.push(format!("run.duration={horizon}"));
    let sc = stickslip::scenario::Scenario::resolve(None, &all).unwrap();
    let last = horizon - 30.0;
    // per realization: [window, stuck time, sticks, sticks timed, ΣD, ΣD², breakaways, slips
    // timed, ΣH, ΣH²]
    let rows: Vec<[f64; 10]> = outcomes(&sc, realizations)
        .iter()
        .map(|o| {
            let r = &o.record;
            let mut a = [horizon - burn, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            for (i, (&s, &d)) in r.stick_start.iter().zip(&r.stick_duration).enumerate() {
                a[1] += ((s + d).min(horizon) - s.max(burn)).max(0.0);
                a[2] += f64::from(u8::from(s >= burn));
                if (burn..last).contains(&s) {
                    assert!(r.stick_end[i] != StickEnd::Horizon, "a stick begun before {last} s was cut");
                    a[3] += 1.0;
                    a[4] += d;
                    a[5] += d * d;
                    a[6] += f64::from(u8::from(r.stick_end[i] == StickEnd::Breakaway));
                }
            }
            for (&s, &h) in r.slip_start.iter().zip(&r.slip_duration) {
                if (burn..last).contains(&s) {
                    assert!(s + h < horizon, "a slip begun before {last} s was cut");
                    a[7] += 1.0;
                    a[8] += h;
                    a[9] += h * h;
                }
            }
            a
        })
        .collect();
    let ratio = |num: &dyn Fn(&[f64; 10]) -> f64, den: &dyn Fn(&[f64; 10]) -> f64| {
        let (sn, sd): (f64, f64) = (rows.iter().map(num).sum(), rows.iter().map(den).sum());
        let r = sn / sd;
        let var: f64 = rows.iter().map(|a| (num(a) - r * den(a)).powi(2)).sum();
        (r, var.sqrt() / sd)
    };
    let (d, d_se) = ratio(&|a| a[4], &|a| a[3]);
    let (d2, d2_se) = ratio(&|a| a[5], &|a| a[3]);
    let (h, h_se) = ratio(&|a| a[8], &|a| a[7]);
    let (h2, h2_se) = ratio(&|a| a[9], &|a| a[7]);
    LongRun {
        values: vec![
            ratio(&|a| a[1], &|a| a[0]),
            (d, d_se),
            (h, h_se),
            (d2 - d * d, d2_se + 2.0 * d * d_se),
            (h2 - h * h, h2_se + 2.0 * h * h_se),
            ratio(&|a| a[2], &|a| a[0]),
            ratio(&|a| a[6], &|a| a[3]),
            (d + h, d_se + h_se),
        ],
    }
}

/// Every long-run quantity of the exact law inside the Monte Carlo estimate's 4.5 standard
/// errors widened by the law's own error estimate.
fn agrees(sets: &[&str], realizations: u64, horizon: f64, finest: u32) -> Vec<Level> {
    let sc = scenario(sets);
    let levels = stationary(&sc.scene().unwrap(), finest, stickslip::law::LEVELS).unwrap();
    let mc = long_run(sets, realizations, horizon, 20.0);
    for (q, (name, (exact, error))) in QUANTITIES.iter().zip(stickslip::law::estimates(&levels)).enumerate() {
        let (m, se) = mc.values[q];
        assert!((exact - m).abs() <= 4.5 * se + error, "{sets:?} {name}: exact {exact} (error {error:.1e}) against Monte Carlo {m} ± {se:.1e}");
    }
    levels
}

/// The asymmetric telegraph belt (forward 1 m/s left at 5/s, reverse 0.5 m/s left at 2/s): two
/// frames, the chain alternating between them.
#[test]
fn the_asymmetric_belt_agrees_with_a_long_monte_carlo_run() {
    agrees(&["belt.reverse_speed=0.5", "belt.reverse_switch_rate=2"], 2000, 400.0, 32);
}

#[test]
fn the_paper_scene_agrees_with_a_long_monte_carlo_run() {
    let levels = agrees(&[], 4000, 400.0, 40);
    // second order: each halving of h shrinks the change by about 4 (an interpolation across the
    // belt line, where the flow jumps, made it first order: about 2)
    for name in ["stick_fraction", "sticks_per_second", "mean_slip_duration"] {
        let v: Vec<f64> = levels.iter().map(|l| value(l, name)).collect();
        let ratio = (v[1] - v[0]).abs() / (v[2] - v[1]).abs();
        assert!(ratio > 2.8, "{name}: the change shrinks by {ratio} per halving ({v:?})");
    }
}

#[test]
fn static_friction_and_slow_flips_agree_with_a_long_monte_carlo_run() {
    agrees(&["model.static_friction_coefficient=0.6", "belt.switch_rate=1.0"], 2000, 600.0, 32);
}

/// The dashpot c = 0.5 N·s/m (ζ = 1/8): spirals instead of circles, the stick region shifted
/// by −c v0/k; with μ_s = 0.8 the breakaway slip comes back to stick, with μ_s = μ_k it never does.
#[test]
fn a_damped_scene_agrees_with_a_long_monte_carlo_run() {
    agrees(&["model.damping=0.5"], 2000, 400.0, 32);
    agrees(&["model.damping=0.5", "model.static_friction_coefficient=0.8", "belt.switch_rate=2.0"], 2000, 400.0, 32);
}

/// The largest damping the method takes, ζ = 1/2 (c = 2 N·s/m): the stick region shifted by
/// c v0/k = 0.5 m, 40 % of c_s.
#[test]
fn the_most_damped_scene_the_method_takes_agrees_with_a_long_monte_carlo_run() {
    agrees(&["model.damping=2.0"], 2000, 400.0, 16);
}

#[test]
fn scenes_outside_the_method_are_refused_with_the_reason() {
    for (sets, reason) in [
        (&["model.viscous_friction=0.3"][..], "viscous"),
        (&["belt.process=\"markov\"", "belt.velocities=[1.0, 0.0, -1.0]", "belt.rates=[[0, 2, 0], [1, 0, 1], [0, 4, 0]]"][..], "not a two-state flip process"),
        (&["belt.reverse_speed=0.5", "belt.reverse_switch_rate=0"][..], "belt.reverse_switch_rate is 0"),
        (&["model.friction_coefficient={dist = \"uniform\", low = 0.3, high = 0.7}"][..], "drawn per realization"),
        (&["belt.switch_rate=0"][..], "no stationary law"),
        (&["model.stiffness=0"][..], "without a spring"),
        (&["model.friction_coefficient=0", "model.static_friction_coefficient=0.6"][..], "kinetic friction is below"),
        // a flip every microsecond: the mass moves 1e-6 m between flips, far below the grid
        (&["belt.switch_rate=1e6"][..], "between belt flips"),
        (&["belt.speed=1e-9", "initial_conditions.position=[-1e-9, 1e-9]", "initial_conditions.velocity=[-1e-9, 1e-9]"][..], "velocity scale"),
        (&["model.stiffness=1e9"][..], "velocity scale"),
        // ζ = 0.51, and ζ = 2.5e8, whose grid would not fit in memory
        (&["model.damping=2.04"][..], "zeta <= 0.5"),
        (&["model.damping=1e9"][..], "zeta <= 0.5"),
    ] {
        let e = stationary(&scenario(sets).scene().unwrap(), 8, 1).expect_err("refused");
        assert!(e.contains(reason), "{sets:?}: {e}");
    }
}

#[test]
fn the_command_writes_its_tables_and_refuses_a_viscous_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let o = crate::common::stickslip(&["exact-law", "--out", "e", "--resolution", "16"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = stickslip::table::Table::read_checked(&tmp.path().join("e/stationary.parquet"), &[("quantity", 's'), ("value", 'f'), ("error", 'f')]).unwrap();
    assert_eq!(t.strings("quantity").unwrap(), QUANTITIES.map(String::from));
    assert!(t.floats("error").unwrap().iter().all(|e| e.is_some_and(|e| e.is_finite() && e >= 0.0)));
    let c =
        stickslip::table::Table::read_checked(&tmp.path().join("e/convergence.parquet"), &[("resolution", 'i'), ("quantity", 's'), ("value", 'f')]).unwrap();
    // (the long-run quantities at each resolution, then Table 1's 24 means and 24 variances at each)
    assert_eq!(c.height(), 3 * (QUANTITIES.len() + 48));
    let finest = |q: usize| c.floats("value").unwrap()[2 * QUANTITIES.len() + q].unwrap();
    // the density: the time while slipping and while stuck adds up to 1, the stuck part to the
    // finest level's stick fraction (cells of equal size: their widths from the centres)
    let d = stickslip::table::Table::read_checked(&tmp.path().join("e/density.parquet"), &[("kind", 's'), ("x", 'f'), ("velocity", 'f'), ("density", 'f')])
        .unwrap();
    let (kind, x, v, p) = (d.strings("kind").unwrap(), d.floats("x").unwrap(), d.floats("velocity").unwrap(), d.floats("density").unwrap());
    let step = |k: &str, col: &[Option<f64>]| {
        let mut u: Vec<f64> = col.iter().zip(kind).filter(|(_, kk)| *kk == k).map(|(c, _)| c.unwrap()).collect();
        u.sort_by(f64::total_cmp);
        u.dedup();
        u[1] - u[0]
    };
    let total = |k: &str, area: f64| p.iter().zip(kind).filter(|(_, kk)| *kk == k).map(|(d, _)| d.unwrap()).sum::<f64>() * area;
    let (slip, stuck) = (total("slip", step("slip", x) * step("slip", v)), total("stick", step("stick", x)));
    assert!((slip + stuck - 1.0).abs() < 1e-6 && (stuck - finest(0)).abs() < 1e-9, "slip {slip}, stuck {stuck}, stick fraction {}", finest(0));
    assert!(p.iter().all(|d| d.is_some_and(|d| d >= 0.0 && d.is_finite())));
    assert!(tmp.path().join("e/stationary_density.png").is_file());
    // the stick duration's survival: 1 at 0, non-increasing, 0 past the longest holding time,
    // and its integral — between the right and the left Riemann sums of a non-increasing
    // curve — is the finest level's mean stick duration
    let sv = stickslip::table::Table::read_checked(&tmp.path().join("e/stick_survival.parquet"), &[("t", 'f'), ("survival", 'f')]).unwrap();
    let (times, s): (Vec<f64>, Vec<f64>) = sv.floats("t").unwrap().iter().zip(sv.floats("survival").unwrap()).map(|(t, p)| (t.unwrap(), p.unwrap())).unzip();
    assert!((s[0] - 1.0).abs() < 1e-12 && s.windows(2).all(|w| w[1] <= w[0]) && *s.last().unwrap() == 0.0, "{s:?}");
    let dt = times[1] - times[0];
    let (right, left) = (s[1..].iter().sum::<f64>() * dt, s[..s.len() - 1].iter().sum::<f64>() * dt);
    assert!(right <= finest(1) && finest(1) <= left, "E[D] = {} outside [{right}, {left}]", finest(1));
    // the table it prints carries the same values
    let printed = String::from_utf8_lossy(&o.stdout);
    let sticks = t.floats("value").unwrap()[5].unwrap();
    assert!(printed.contains(&format!("{sticks:.6}")), "{printed}");
    // a point initial condition that is a stick: refused at once, blamed on the input
    let o = crate::common::stickslip(
        &["exact-law", "--out", "d", "--set", "initial_conditions.position=[0.3, 0.3]", "--set", "initial_conditions.velocity=[1.0, 1.0]", "-q"],
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("starts stuck"));
    let o = crate::common::stickslip(&["exact-law", "--out", "d", "--set", "model.viscous_friction=0.3", "-q"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("viscous") && err.lines().count() == 1, "{err}");
    assert!(!tmp.path().join("d").exists());
    // a tail time that is not a time: refused before anything is solved
    let o = crate::common::stickslip(&["exact-law", "--out", "d", "--tail-times", "0.5,-1", "-q"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--tail-times -1") && err.lines().count() == 1, "{err}");
    assert!(!tmp.path().join("d").exists());
}

/// The chain's steps sum their atoms in fixed chunks, in order: the values do not depend on
/// the number of threads, to the bit.
#[test]
fn the_values_do_not_depend_on_the_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |threads: &str, out: &str| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .args(["exact-law", "--out", out, "--resolution", "16", "-q"])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let t = stickslip::table::Table::read_parquet(&tmp.path().join(out).join("convergence.parquet")).unwrap();
        t.floats("value").unwrap().iter().map(|v| v.unwrap().to_bits()).collect::<Vec<u64>>()
    };
    assert_eq!(run("1", "one"), run("3", "three"));
}

/// The paper's Table 1 without sampling: the means and variances of T_k, L_k, D_k and H_k
/// (k ≤ 6) from `exact-law` against 20,000 realizations of the paper scenario read here (a
/// duration counts if it ended before t_a), each within 4.5 standard errors plus its own error
/// estimate (the variance's standard error from the fourth central moment), and the table in
/// `moments.parquet` with analyze's column names.
#[test]
fn the_table_from_the_initial_conditions_agrees_with_monte_carlo() {
    table_agrees(&[]);
}

/// The same on the damped scene (c = 0.5 N·s/m).
#[test]
fn the_damped_table_from_the_initial_conditions_agrees_with_monte_carlo() {
    table_agrees(&["model.damping=0.5"]);
}

/// The same on the asymmetric belt, starting forward and starting at random, over t_a = 20 s (in
/// 10 s, 2e-3 of the realizations have fewer than 7 sticks: the window would cut T_6 and H_6,
/// which the exact laws are not).
#[test]
fn the_asymmetric_table_from_the_initial_conditions_agrees_with_monte_carlo() {
    table_agrees(&["belt.reverse_speed=0.5", "belt.reverse_switch_rate=2", "run.duration=20"]);
    table_agrees(&["belt.reverse_speed=0.5", "belt.reverse_switch_rate=2", "run.duration=20", "belt.initial_sign=\"random\""]);
}

fn table_agrees(sets: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let sc = scenario(sets);
    let times = [0.05, 0.2, 0.5, 1.0];
    let opts = stickslip::law::Options { finest: 20, tail_times: times.to_vec(), counts: None, densities: None };
    let rows = stickslip::stage::exact_law::solve_into(&sc, &opts, &tmp.path().join("e"), stickslip::progress::Control::silent()).unwrap().0.rows;
    let t = stickslip::table::Table::read_checked(
        &tmp.path().join("e/moments.parquet"),
        &[("variable", 's'), ("index", 'i'), ("mean", 'f'), ("variance", 'f'), ("error", 'f'), ("variance_error", 'f')],
    )
    .unwrap();
    assert_eq!(t.height(), 24);
    let runs = outcomes(&sc, 20_000);
    for r in &rows {
        let k = r.index as usize - 1;
        let xs: Vec<f64> = runs
            .iter()
            .filter_map(|o| {
                let e = &o.record;
                match r.variable {
                    "T" => e.stick_start.get(k).copied(),
                    "L" => e.slip_start.get(k).copied(),
                    "D" => e.stick_end.get(k).filter(|end| **end != StickEnd::Horizon).map(|_| e.stick_duration[k]),
                    _ => e.stick_start.get(k + 1).map(|_| e.slip_duration[k]),
                }
            })
            .collect();
        let n = xs.len() as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let m2 = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        let m4 = xs.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
        let (se, se_var) = ((m2 / n).sqrt(), ((m4 - m2 * m2) / n).sqrt());
        let what = format!("{sets:?} {}_{}", r.variable, r.index);
        assert!((r.mean - mean).abs() <= 4.5 * se + r.error, "{what}: exact {} ± {}, Monte Carlo {mean} ± {se}", r.mean, r.error);
        assert!(
            (r.variance - m2).abs() <= 4.5 * se_var + r.variance_error,
            "{what}: exact variance {} ± {}, Monte Carlo {m2} ± {se_var}",
            r.variance,
            r.variance_error
        );
    }
    survival_agrees(&tmp.path().join("e/survival.parquet"), &runs, &times, &format!("{sets:?}"));
}

/// The laws of the counts (`exact-law --counts`): on a 4 s window of the paper scene (λ t_a =
/// 20, the shortest the inversion accepts; about 7 sticks), P(S_T = n) and P(S_L = n) against
/// the shares of 20,000 realizations within 4.5 binomial standard errors plus the error
/// estimate, and the means and variances (moments.parquet, null index) against theirs; and a
/// shorter window is refused with the reason.
#[test]
fn count_laws_agree_with_monte_carlo() {
    let tmp = tempfile::tempdir().unwrap();
    let sc = scenario(&["run.duration=4"]);
    let opts = stickslip::law::Options { finest: 8, tail_times: vec![], counts: Some(8), densities: None };
    let solved = stickslip::stage::exact_law::solve_into(&sc, &opts, &tmp.path().join("e"), stickslip::progress::Control::silent()).unwrap().0;
    let (rows, counts) = (solved.rows, solved.counts);
    let runs = outcomes(&sc, 20_000);
    let n = runs.len() as f64;
    let variables: [(&str, fn(&Outcome) -> usize); 2] = [("S_T", |o| o.record.n_stick()), ("S_L", |o| o.record.n_slip())];
    for (variable, count) in variables {
        let law: Vec<&stickslip::law::counts::CountRow> = counts.iter().filter(|r| r.variable == variable).collect();
        let total: f64 = law.iter().map(|r| r.probability).sum();
        assert!((total - 1.0).abs() < 1e-3, "{variable}: the law sums to {total}");
        for r in &law {
            let share = runs.iter().filter(|o| count(o) == r.value as usize).count() as f64 / n;
            let se = (r.probability.max(1.0 / n) * (1.0 - r.probability) / n).sqrt();
            assert!(
                (r.probability - share).abs() <= 4.5 * se + r.error,
                "P({variable} = {}) exact {} ± {}, Monte Carlo {share} ± {se}",
                r.value,
                r.probability,
                r.error
            );
        }
        let xs: Vec<f64> = runs.iter().map(|o| count(o) as f64).collect();
        let mean = xs.iter().sum::<f64>() / n;
        let m2 = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        let m4 = xs.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
        let r = rows.iter().find(|r| r.variable == variable).expect("the moments row");
        assert!((r.mean - mean).abs() <= 4.5 * (m2 / n).sqrt() + r.error, "E {variable}: exact {} ± {}, Monte Carlo {mean}", r.mean, r.error);
        assert!(
            (r.variance - m2).abs() <= 4.5 * ((m4 - m2 * m2) / n).sqrt() + r.variance_error,
            "Var {variable}: exact {} ± {}, Monte Carlo {m2}",
            r.variance,
            r.variance_error
        );
    }
    // each Table 1 row's reach: T_k and D_k need stick k to start (S_T ≥ k), L_k and H_k need it
    // to end (S_L ≥ k); about half the realizations reach k = 6 in 4 s
    for r in rows.iter().filter(|r| r.index > 0) {
        let (p, e) = r.reached.expect("the reach of every Table 1 row");
        let k = r.index as usize;
        let share = runs.iter().filter(|o| if matches!(r.variable, "T" | "D") { o.record.n_stick() >= k } else { o.record.n_slip() >= k }).count() as f64 / n;
        let se = (p.max(1.0 / n) * (1.0 - p).max(1.0 / n) / n).sqrt();
        assert!((p - share).abs() <= 4.5 * se + e, "{}_{k} reached: exact {p} ± {e}, Monte Carlo {share} ± {se}", r.variable);
    }
    let t =
        stickslip::table::Table::read_checked(&tmp.path().join("e/moments.parquet"), &[("variable", 's'), ("index", 'i'), ("reached_fraction", 'f')]).unwrap();
    assert!(t.floats("reached_fraction").unwrap()[..24].iter().all(Option::is_some), "reached_fraction of every Table 1 row");
    let (vars, idx) = (t.strings("variable").unwrap(), t.ints("index").unwrap());
    assert!((0..t.height()).any(|r| vars[r] == "S_T" && idx[r].is_none()), "moments.parquet: S_T with a null index");
    // report --exact: the count laws beside the shares of 3,000 realizations of the same
    // window (95 % Wilson intervals: a correct law meets about 95 % of them)
    let o = crate::common::stickslip(&["reproduce", "--out", "r", "--realizations", "3000", "--set", "run.duration=4", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = crate::common::stickslip(&["report", "r/dataset", "r/analysis", "r/figures", "--exact", "e", "--out", "x.html", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(tmp.path().join("x.md")).unwrap();
    let judged: Vec<&str> = md.lines().filter(|l| l.starts_with("| P(S_T = ") || l.starts_with("| P(S_L = ")).collect();
    assert!(judged.len() >= 10 && judged.iter().all(|r| r.matches('✓').count() + r.matches('✗').count() == 1), "{judged:?}");
    assert!(judged.iter().filter(|r| r.contains('✗')).count() <= 3, "{judged:?}");
    // 3 s: λ t_a = 15
    let short = scenario(&["run.duration=3"]);
    let err = stickslip::stage::exact_law::solve_into(&short, &opts, &tmp.path().join("f"), stickslip::progress::Control::silent()).unwrap_err().to_string();
    assert!(err.contains("--counts") && err.contains("run.duration"), "{err}");
    assert!(!tmp.path().join("f").exists());
}

/// D_k's law in `survival.parquet` (k ≤ 6): P(D_k > t) at the asked times against the share of
/// the realizations' k-th sticks (ended before t_a) that last longer, within 4.5 binomial standard
/// errors plus its error estimate; and the density against the survival: between two
/// consecutive asked times a < b, the trapezoidal ∫_a^b f dt over the curve's grid equals
/// S(a) − S(b) within 2e-3 plus both points' errors (the survival holds each entry at its
/// node's holding time, the density spreads it over the node's cell).
fn survival_agrees(path: &std::path::Path, runs: &[Outcome], times: &[f64], what: &str) {
    let t = stickslip::table::Table::read_checked(
        path,
        &[("variable", 's'), ("index", 'i'), ("method", 's'), ("t", 'f'), ("survival", 'f'), ("lo", 'f'), ("hi", 'f'), ("error", 'f'), ("density", 'f')],
    )
    .unwrap();
    let (index, time, surv, err, dens) =
        (t.ints("index").unwrap(), t.floats("t").unwrap(), t.floats("survival").unwrap(), t.floats("error").unwrap(), t.floats("density").unwrap());
    for k in 1..=6i64 {
        let rows: Vec<usize> = (0..t.height()).filter(|&r| index[r] == Some(k)).collect();
        assert!(rows.len() > 1000, "{what} D_{k}: {} points", rows.len());
        let at = |x: f64| *rows.iter().find(|&&r| time[r] == Some(x)).unwrap_or_else(|| panic!("{what} D_{k}: no point at t = {x}"));
        let durations: Vec<f64> = runs
            .iter()
            .filter_map(|o| o.record.stick_end.get(k as usize - 1).filter(|end| **end != StickEnd::Horizon).map(|_| o.record.stick_duration[k as usize - 1]))
            .collect();
        let n = durations.len() as f64;
        for &x in times {
            let r = at(x);
            let (exact, e) = (surv[r].unwrap(), err[r].unwrap());
            let share = durations.iter().filter(|&&d| d > x).count() as f64 / n;
            let se = (exact.max(1.0 / n) * (1.0 - exact) / n).sqrt();
            assert!((exact - share).abs() <= 4.5 * se + e, "{what}: P(D_{k} > {x}) exact {exact} ± {e}, Monte Carlo {share} ± {se}");
        }
        for w in times.windows(2) {
            let (a, b) = (at(w[0]), at(w[1]));
            let integral: f64 = (a..b).map(|r| 0.5 * (dens[r].unwrap() + dens[r + 1].unwrap()) * (time[r + 1].unwrap() - time[r].unwrap())).sum();
            let drop = surv[a].unwrap() - surv[b].unwrap();
            assert!(
                (integral - drop).abs() <= 2e-3 + err[a].unwrap() + err[b].unwrap(),
                "{what} D_{k}: ∫ f over [{}, {}] = {integral}, S drops by {drop}",
                w[0],
                w[1]
            );
        }
    }
}

/// `report --exact LAWDIR` puts the exact means and variances beside Table 1's intervals: one
/// row per T_k, L_k, D_k, H_k, each judged against our interval; and P(D_k > t) beside our
/// product-limit bands.
#[test]
fn the_report_shows_the_exact_values_beside_the_intervals() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [vec!["reproduce", "--out", "r", "--realizations", "3000", "-q"], vec!["exact-law", "--out", "law", "--resolution", "16", "-q"]] {
        let o = crate::common::stickslip(&args, tmp.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = crate::common::stickslip(&["report", "r/dataset", "r/analysis", "r/figures", "--exact", "law", "--out", "x.html", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(tmp.path().join("x.md")).unwrap();
    let section = &md[md.find("## Table 1 without sampling").expect("the section")..];
    let rows: Vec<&str> =
        section.lines().filter(|l| l.starts_with("| T_") || l.starts_with("| L_") || l.starts_with("| D_") || l.starts_with("| H_")).collect();
    assert_eq!(rows.len(), 24, "{section}");
    assert!(rows.iter().all(|r| r.matches('✓').count() + r.matches('✗').count() == 2), "{rows:?}");
    // D_k's law beside the product-limit curves at reproduce's five tail times, which exact-law
    // adds to its grid by default: 6 × 5 rows, each judged where our curve has a band (3,000
    // realizations give bands at 0.5 and 1 s: 12 rows, of which a correct law meets about 95 %)
    let tails: Vec<&str> = section.lines().filter(|l| l.starts_with("| P(D_")).collect();
    assert_eq!(tails.len(), 30, "{section}");
    assert!(tails.iter().all(|r| r.contains("no band") || r.matches('✓').count() + r.matches('✗').count() == 1), "{tails:?}");
    let judged = tails.iter().filter(|r| !r.contains("no band")).count();
    assert!(judged >= 12 && tails.iter().filter(|r| r.contains('✓')).count() >= judged - 2, "{tails:?}");
    assert!(std::fs::read_to_string(tmp.path().join("x.html")).unwrap().contains("<h2>Table 1 without sampling</h2>"));
}

/// `exact-law --densities` refuses a point initial condition (T_1 then has a point mass, the
/// path without a flip, and no density) with the reason, before any solve, leaving nothing.
#[test]
fn densities_refuse_a_point_start() {
    let tmp = tempfile::tempdir().unwrap();
    let sc = scenario(&["initial_conditions.position=[0.5, 0.5]", "initial_conditions.velocity=[0.0, 0.0]"]);
    let opts = stickslip::law::Options { finest: 8, tail_times: vec![], counts: None, densities: Some(8) };
    let err = stickslip::stage::exact_law::solve_into(&sc, &opts, &tmp.path().join("e"), stickslip::progress::Control::silent()).unwrap_err().to_string();
    assert!(err.contains("--densities") && err.contains("point"), "{err}");
    assert!(!tmp.path().join("e").exists());
}

/// A cancelled exact law stops within the first iteration of the solve, as cancelled (not as a
/// failure), and leaves no output directory.
#[test]
fn a_cancelled_exact_law_stops_in_its_first_iteration_and_leaves_nothing() {
    use std::sync::atomic::{AtomicU32, Ordering};
    let tmp = tempfile::tempdir().unwrap();
    let asked = AtomicU32::new(0);
    let cancel = || asked.fetch_add(1, Ordering::Relaxed) >= 1; // the check before the solve passes
    let ctl = stickslip::progress::Control { progress: &stickslip::progress::Silent, cancel: &cancel };
    let opts = stickslip::law::Options { finest: 80, tail_times: vec![], counts: None, densities: None };
    let e = stickslip::stage::exact_law::solve_into(&scenario(&[]), &opts, &tmp.path().join("e"), ctl).unwrap_err();
    assert!(matches!(e, stickslip::law::LawError::Cancelled(_)), "{e}");
    // asked before the solve, after its first iteration, and once more to tell the stop from a failure
    assert_eq!(asked.load(Ordering::Relaxed), 3);
    assert!(!tmp.path().join("e").exists());
}

/// Cancelled while the sticks' walks run (after their coarsest resolution), the exact law stops
/// within the next walk's first passage — it asks the token once there and once more to tell the
/// stop from a failure — as cancelled, and leaves no output directory.
#[test]
fn a_cancel_during_the_sticks_walks_stops_at_the_next_passage() {
    use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
    struct Notes<'a>(&'a AtomicBool);
    impl stickslip::progress::Progress for Notes<'_> {
        fn note(&self, line: &str) {
            if line.starts_with("sticks 1-6") {
                self.0.store(true, Ordering::Relaxed);
            }
        }
    }
    let tmp = tempfile::tempdir().unwrap();
    let (walked, asked_after) = (AtomicBool::new(false), AtomicU32::new(0));
    let cancel = || {
        let now = walked.load(Ordering::Relaxed);
        if now {
            asked_after.fetch_add(1, Ordering::Relaxed);
        }
        now
    };
    let sink = Notes(&walked);
    let ctl = stickslip::progress::Control { progress: &sink, cancel: &cancel };
    let opts = stickslip::law::Options { finest: 40, tail_times: vec![], counts: None, densities: None };
    let e = stickslip::stage::exact_law::solve_into(&scenario(&[]), &opts, &tmp.path().join("e"), ctl).unwrap_err();
    assert!(matches!(e, stickslip::law::LawError::Cancelled(_)), "{e}");
    assert_eq!(asked_after.load(Ordering::Relaxed), 2);
    assert!(!tmp.path().join("e").exists());
}
