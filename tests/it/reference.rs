//! An independent check: the same belt switches and initial conditions integrated numerically.
//!
//! The reference integrates m ẍ = σ f_k + σ_v (v − ẋ) − k x − c ẋ with classical RK4 at a fixed
//! step h = 1e-4 s (global error O((ωh)^4) ≈ 1e-15 here), locates each event by bisection on RK4
//! sub-steps from the step start (to ~1e-15 s), and applies the friction law directly: at ẋ = v
//! it sticks if |k x + c v| ≤ f_s (within 1e-6 of f_s on the belt's side: a touch, the slip
//! goes on), else the friction becomes sgn(k x + c v); a stick ends when
//! k x + c v reaches f_s in the belt direction (never on a belt at rest) or at a change of the
//! belt velocity, taken per segment from the library's segments (any number of levels). A dip of the velocity across
//! belt speed between two step ends is caught by testing the velocity's extremum inside the step
//! (where ẍ changes sign). It shares no code with the library's solver.

use crate::common::{outcomes, scenario};

pub(crate) struct Params {
    pub m: f64,
    pub k: f64,
    pub c: f64,
    /// kinetic and static friction forces, N
    pub fk: f64,
    pub fs: f64,
    /// σ_v, N·s/m: the viscous term of the slip friction
    pub cv: f64,
    pub ta: f64,
}

const H: f64 = 1e-4;

/// A return to belt speed with the holding force within this relative distance of f_s is a
/// touch of the breakaway point, not a stick: RK4's ~1e-15 velocity errors move a tangential
/// return (the grazing orbit after a breakaway with μ_s = μ_k, one period later) by
/// √(1e-15) ≈ 3e-8 relative in position, to either side of the breakaway point.
const TOUCH: f64 = 1e-6;

fn accel(p: &Params, sigma: f64, belt: f64, x: f64, xd: f64) -> f64 {
    (sigma * p.fk + p.cv * (belt - xd) - p.k * x - p.c * xd) / p.m
}

fn rk4(p: &Params, sigma: f64, belt: f64, (x, v): (f64, f64), h: f64) -> (f64, f64) {
    let acc = |x: f64, v: f64| accel(p, sigma, belt, x, v);
    let (k1x, k1v) = (v, acc(x, v));
    let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
    let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
    let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x, v + h * k3v));
    (x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x), v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))
}

/// Stick start times and slip (after a stick) start times, in order.
pub(crate) fn integrate(p: &Params, velocities: &[f64], switches: &[f64], x0: f64, xd0: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut sticks, mut slips) = (Vec::new(), Vec::new());
    let mut t = 0.0;
    let (mut x, mut xd) = (x0, xd0);
    let mut stuck = false;
    let mut sigma = (velocities[0] - xd).signum();
    let mut bounds: Vec<f64> = switches.to_vec();
    bounds.push(p.ta);
    for (seg, &t_end) in bounds.iter().enumerate() {
        let v = velocities[seg];
        let s = v.signum();
        while t < t_end {
            if stuck {
                let x_break = (s * p.fs - p.c * v) / p.k;
                let t_break = if v == 0.0 { f64::INFINITY } else { t + (x_break - x) / v };
                if t_break < t_end {
                    x = x_break;
                    t = t_break;
                    stuck = false;
                    sigma = s;
                    slips.push(t);
                    // leave belt speed: one tiny step so that the crossing test starts off zero
                    continue;
                }
                x += v * (t_end - t);
                t = t_end;
                break;
            }
            let h = H.min(t_end - t);
            let (nx, nv) = rk4(p, sigma, v, (x, xd), h);
            // crossing of belt speed: σ (v - ẋ) goes from > 0 to <= 0 at the step end, or at the
            // velocity's extremum inside the step (ẍ changes sign: golden-section for it)
            let g = |dt: f64| sigma * (v - rk4(p, sigma, v, (x, xd), dt).1);
            let accel = |dt: f64| {
                let (ax, av) = rk4(p, sigma, v, (x, xd), dt);
                accel(p, sigma, v, ax, av)
            };
            let mut end = h;
            if g(h) > 0.0 && sigma * accel(0.0) > 0.0 && sigma * accel(h) < 0.0 {
                let (mut a, mut b) = (0.0, h);
                for _ in 0..100 {
                    let (c1, c2) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
                    if g(c1) < g(c2) {
                        b = c2
                    } else {
                        a = c1
                    }
                }
                if g(0.5 * (a + b)) <= 0.0 {
                    end = 0.5 * (a + b);
                }
            }
            if g(end) <= 0.0 && sigma * (v - xd) > 1e-12 {
                let (mut lo, mut hi) = (0.0, end);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    let (_, mv) = rk4(p, sigma, v, (x, xd), mid);
                    if sigma * (v - mv) > 0.0 {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                let (ex, _) = rk4(p, sigma, v, (x, xd), hi);
                t += hi;
                x = ex;
                xd = v;
                let force = p.k * x + p.c * v;
                if force.abs() <= p.fs && !(s * force >= p.fs * (1.0 - TOUCH)) {
                    stuck = true;
                    sticks.push(t);
                } else {
                    // through belt speed, or a touch at the breakaway point (the slip goes on
                    // with the friction along the belt, as after a breakaway)
                    sigma = if force.abs() <= p.fs { s } else { force.signum() };
                    // step off the crossing
                    let (nx, nv) = rk4(p, sigma, v, (x, xd), 1e-9);
                    x = nx;
                    xd = nv;
                    t += 1e-9;
                }
                continue;
            }
            x = nx;
            xd = nv;
            t += h;
        }
        if seg < switches.len() {
            if stuck {
                stuck = false;
                xd = v;
                slips.push(t);
            }
            sigma = (velocities[seg + 1] - xd).signum();
        }
    }
    (sticks, slips)
}

/// The exact solver against the reference on realizations 0..n of the paper scenario with `sets`.
pub(crate) fn compare(sets: &[&str], p: &Params, n: u64) {
    let sc = scenario(sets);
    let mut compared = 0;
    let mut worst: f64 = 0.0;
    for (i, o) in outcomes(&sc, n).iter().enumerate() {
        let (sticks, slips) = integrate(p, o.velocities(), o.switches(), o.x0, o.xdot0);
        let r = &o.record;
        assert_eq!(sticks.len(), r.stick_start.len(), "realization {i}: S_T");
        assert_eq!(slips.len(), r.slip_start.len(), "realization {i}: S_L");
        for (a, b) in sticks.iter().zip(&r.stick_start).chain(slips.iter().zip(&r.slip_start)) {
            worst = worst.max((a - b).abs());
            compared += 1;
        }
    }
    assert!(compared > 5 * n as usize, "{sets:?}: {compared} event times compared");
    assert!(worst <= 1e-8, "{sets:?}: largest event-time difference {worst:e} s");
}

pub(crate) const PAPER: Params = Params { m: 1.0, k: 4.0, c: 0.0, fk: 0.51 * 9.8, fs: 0.51 * 9.8, cv: 0.0, ta: 10.0 };

#[test]
fn exact_solver_agrees_with_an_accurate_numerical_integration() {
    compare(&[], &PAPER, 36);
}

#[test]
fn with_damping_and_static_friction_too() {
    // under-damped with μ_s > μ_k, critically damped (ζ = 1, where step-end sign tests miss
    // shallow dips), over-damped with μ_s > μ_k
    compare(&["model.damping=0.5", "model.static_friction_coefficient=0.6"], &Params { c: 0.5, fs: 0.6 * 9.8, ..PAPER }, 24);
    compare(&["model.damping=4"], &Params { c: 4.0, ..PAPER }, 24);
    compare(&["model.damping=4.5", "model.static_friction_coefficient=0.7"], &Params { c: 4.5, fs: 0.7 * 9.8, ..PAPER }, 24);
}

#[test]
fn with_viscous_friction() {
    // σ_v alone (under-damped slips), with μ_s > μ_k and a dashpot, and at the over-damped
    // extreme (σ_v/m = 10/s against ω = 2/s: the slips creep back to belt speed)
    compare(&["model.viscous_friction=0.8"], &Params { cv: 0.8, ..PAPER }, 24);
    compare(
        &["model.viscous_friction=0.3", "model.damping=0.5", "model.static_friction_coefficient=0.6"],
        &Params { cv: 0.3, c: 0.5, fs: 0.6 * 9.8, ..PAPER },
        24,
    );
    compare(&["model.viscous_friction=10"], &Params { cv: 10.0, ..PAPER }, 24);
}
