//! Shared test helpers: run realizations, check the counting invariants, run the CLI.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use stickslip::physics::Params;
use stickslip::scenario::Scenario;
use stickslip::simulation::belt::{BeltPath, Process};
use stickslip::simulation::ensemble::Outcome;
use stickslip::simulation::events::Record;
use stickslip::solver::{Drive, Solver};
use stickslip::tradeoff::match_events;

/// The paper scenario with `KEY=VALUE` overrides.
pub fn scenario(sets: &[&str]) -> Scenario {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scenario::resolve(None, &sets).expect("valid test scenario")
}

/// Realizations `0..n` of a scenario.
pub fn outcomes(sc: &Scenario, n: u64) -> Vec<Outcome> {
    let ens = sc.ensemble().expect("a valid scene");
    (0..n)
        .map(|i| {
            let mut o = Outcome::default();
            ens.realization(i, &mut o).expect("solves");
            o
        })
        .collect()
}

/// The fixed parameters of a scenario's scene.
pub fn params(sc: &Scenario) -> Params {
    sc.scene().expect("a valid scene").params
}

/// Solve a scripted belt (initial sign, switch instants) with the exact solver.
pub fn solve_scripted(sc: &Scenario, sign0: f64, switches: &[f64], x0: f64, xdot0: f64) -> Record {
    let scene = sc.scene().expect("a valid scene");
    let (forward, reverse) = match &scene.belt.process {
        Process::Symmetric(p) => (p.speed, p.speed),
        Process::Telegraph(p) => (p.forward_speed, p.reverse_speed),
        other => panic!("a scripted belt flips between two speeds, not a {} belt", other.name()),
    };
    let level = |sign: f64| if sign > 0.0 { forward } else { -reverse };
    let path = BeltPath::alternating(level(sign0), level(-sign0), switches.to_vec());
    let (mut sw, mut vel) = (Vec::new(), Vec::new());
    path.segments(&mut sw, &mut vel);
    solve_segments(sc, &scene.params, &vel, &sw, x0, xdot0)
}

/// Solve given belt segments with the scenario's solver for the oscillator `p`.
pub fn solve_segments(sc: &Scenario, p: &Params, velocities: &[f64], switches: &[f64], x0: f64, xdot0: f64) -> Record {
    let drive = Drive { velocities, switches, t_end: sc.run.duration };
    let mut rec = Record::default();
    let damped = sc.scene().expect("a valid scene").damped();
    Solver::new(sc.solver(), sc.numerics, damped).solve(&p.per_unit_mass(), &drive, x0, xdot0, &mut rec).expect("solves");
    rec.finish(sc.run.duration);
    rec
}

/// Belt velocity at time t (just after t) for a sorted effective switch list and the segments'
/// velocities.
pub fn belt_velocity(velocities: &[f64], switches: &[f64], t: f64) -> f64 {
    velocities[switches.partition_point(|&y| y <= t)]
}

/// Check the counting invariants of one realization; `Err` describes the first violation.
/// `strict` asks for strictly increasing event times (false only where durations fall below
/// the resolution of t, e.g. absurd friction).
pub fn check_invariants(sc: &Scenario, o: &Outcome, strict: bool) -> Result<(), String> {
    let r = &o.record;
    let ta = sc.run.duration;
    let (nt, nl) = (r.stick_start.len(), r.slip_start.len());
    let all = r.stick_start.iter().chain(&r.stick_duration).chain(&r.slip_start).chain(&r.slip_duration);
    if let Some(x) = all.clone().find(|x| !x.is_finite()) {
        return Err(format!("non-finite value {x}"));
    }
    if r.stick_duration.len() != nt || r.slip_duration.len() != nl {
        return Err("a start without a duration".into());
    }
    if !(nt == nl || nt == nl + 1) {
        return Err(format!("S_T = {nt}, S_L = {nl}"));
    }
    if r.last_truncated != (nt > 0) {
        return Err(format!("last_truncated = {} with S_T = {nt}", r.last_truncated));
    }
    // Interleave T_1 < L_1 < T_2 < L_2 < ... and check order inside [0, t_a].
    let mut seq = Vec::with_capacity(nt + nl);
    for i in 0..nt {
        seq.push(r.stick_start[i]);
        if i < nl {
            seq.push(r.slip_start[i]);
        }
    }
    for w in seq.windows(2) {
        if (strict && !(w[0] < w[1])) || w[0] > w[1] {
            return Err(format!("event times not increasing: {} then {}", w[0], w[1]));
        }
    }
    if let (Some(first), Some(last)) = (seq.first(), seq.last()) {
        if *first < 0.0 || *last > ta {
            return Err(format!("events outside [0, t_a]: {first} .. {last}"));
        }
        let total: f64 = r.stick_duration.iter().chain(&r.slip_duration).sum();
        if (total - (ta - first)).abs() > 1e-9 * ta.max(1.0) {
            return Err(format!("durations sum to {total}, t_a - T_1 = {}", ta - first));
        }
    }
    if let Some(d) = r.stick_duration.iter().chain(&r.slip_duration).find(|&&d| d < 0.0) {
        return Err(format!("negative duration {d}"));
    }
    // (a chain's forces and re-solve: tests/it/chain.rs and chain_reference.rs)
    if sc.scene().expect("a valid scene").chain.is_some() {
        return Ok(());
    }
    // |k x + c v| <= mu_s n throughout every stick: at its start and (x moves with the belt) at
    // its end.
    let p = o.params;
    let (k, c, fmax) = (p.stiffness, p.damping, p.static_ * p.normal_force);
    let traced = solve_segments(sc, &p, o.velocities(), o.switches(), o.x0, o.xdot0);
    if traced != *r {
        return Err("re-solving the same drive gave a different record".into());
    }
    let slack = fmax * 1e-9 + 1e-300;
    for (i, (&t, &x)) in r.stick_start.iter().zip(&traced.stick_entry_position).enumerate() {
        let v = belt_velocity(o.velocities(), o.switches(), t);
        let x_end = x + v * r.stick_duration[i];
        for (what, xx) in [("start", x), ("end", x_end)] {
            let f = (k * xx + c * v).abs();
            if f > fmax + slack * (1.0 + f) {
                return Err(format!("stick {} {what}: |k x + c v| = {f} > mu_s n = {fmax}", i + 1));
            }
        }
    }
    Ok(())
}

/// |event-time errors| of stick and slip starts of `other` against `reference` (matched in time
/// order, sorted), and (missed, spurious) sticks.
pub fn event_errors(reference: &[Record], other: &[Record]) -> (Vec<f64>, u64, u64) {
    let (mut all, mut missed, mut spurious) = (Vec::new(), 0, 0);
    for (e, o) in reference.iter().zip(other) {
        let (err, m, s) = match_events(&e.stick_start, &o.stick_start);
        all.extend(err.iter().map(|x| x.abs()));
        all.extend(match_events(&e.slip_start, &o.slip_start).0.iter().map(|x| x.abs()));
        (missed, spurious) = (missed + m, spurious + s);
    }
    all.sort_by(f64::total_cmp);
    (all, missed, spurious)
}

/// Root mean square.
pub fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
}

/// Run the CLI binary.
pub fn stickslip(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).current_dir(cwd).output().expect("binary runs")
}

/// Every file below `dir` (hidden ones included, directories walked), sorted.
pub fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}
