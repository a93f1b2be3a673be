//! An independent check: the same belt switches and initial conditions integrated numerically.
//!
//! The reference integrates m ẍ = σ f_max − k x with classical RK4 at a fixed step h = 1e-4 s
//! (global error O((ωh)^4) ≈ 1e-15 here), locates each event by bisection on RK4 sub-steps from
//! the step start (to ~1e-15 s), and applies the friction law directly: at ẋ = v it sticks if
//! |k x| ≤ f_max, else the friction reverses; a stick ends when |k x| reaches f_max in the belt
//! direction or at a belt flip. It shares no code with the library's solver.

use crate::common::{outcomes, scenario};

struct Params {
    m: f64,
    k: f64,
    fmax: f64,
    v0: f64,
    ta: f64,
}

const H: f64 = 1e-4;

fn rk4(p: &Params, sigma: f64, (x, v): (f64, f64), h: f64) -> (f64, f64) {
    let acc = |x: f64| (sigma * p.fmax - p.k * x) / p.m;
    let (k1x, k1v) = (v, acc(x));
    let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x));
    let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x));
    let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x));
    (x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x), v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))
}

/// Stick start times and slip (after a stick) start times, in order.
fn integrate(p: &Params, sign0: f64, switches: &[f64], x0: f64, xd0: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut sticks, mut slips) = (Vec::new(), Vec::new());
    let mut t = 0.0;
    let mut s = sign0;
    let (mut x, mut xd) = (x0, xd0);
    let mut stuck = false;
    let mut sigma = (s * p.v0 - xd).signum();
    let mut bounds: Vec<f64> = switches.to_vec();
    bounds.push(p.ta);
    for (seg, &t_end) in bounds.iter().enumerate() {
        let v = s * p.v0;
        while t < t_end {
            if stuck {
                let t_break = t + (s * p.fmax / p.k - x) / v;
                if t_break < t_end {
                    x = s * p.fmax / p.k;
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
            let (nx, nv) = rk4(p, sigma, (x, xd), h);
            // crossing of belt speed: σ (v - ẋ) goes from > 0 to <= 0
            if sigma * (v - nv) <= 0.0 && sigma * (v - xd) > 1e-12 {
                let (mut lo, mut hi) = (0.0, h);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    let (_, mv) = rk4(p, sigma, (x, xd), mid);
                    if sigma * (v - mv) > 0.0 { lo = mid } else { hi = mid }
                }
                let (ex, _) = rk4(p, sigma, (x, xd), hi);
                t += hi;
                x = ex;
                xd = v;
                if (p.k * x).abs() <= p.fmax {
                    stuck = true;
                    sticks.push(t);
                } else {
                    sigma = (p.k * x).signum();
                    // step off the crossing
                    let (nx, nv) = rk4(p, sigma, (x, xd), 1e-9);
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
            s = -s;
            sigma = (s * p.v0 - xd).signum();
        }
    }
    (sticks, slips)
}

#[test]
fn exact_solver_agrees_with_an_accurate_numerical_integration() {
    let sc = scenario(&[]);
    let p = Params { m: 1.0, k: 4.0, fmax: 0.51 * 9.8, v0: 1.0, ta: 10.0 };
    let mut compared = 0;
    let mut worst: f64 = 0.0;
    for (i, o) in outcomes(&sc, 36).iter().enumerate() {
        let (s0, sw) = (o.velocities()[0].signum(), o.switches());
        let (sticks, slips) = integrate(&p, s0, sw, o.x0, o.xdot0);
        let r = &o.record;
        assert_eq!(sticks.len(), r.stick_start.len(), "realization {i}: S_T");
        assert_eq!(slips.len(), r.slip_start.len(), "realization {i}: S_L");
        for (a, b) in sticks.iter().zip(&r.stick_start).chain(slips.iter().zip(&r.slip_start)) {
            worst = worst.max((a - b).abs());
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared} event times compared");
    assert!(worst <= 1e-8, "largest event-time difference {worst:e} s");
}
