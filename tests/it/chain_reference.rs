//! An independent check of the exact chain solver: the same chains integrated by classical RK4
//! at a fixed step with events located by bisection, sharing no code with the library's solver.
//!
//! The reference integrates the equations of `src/chain/mod.rs` as written there — m_i ẍ_i from
//! the springs and dashpots on both sides, the contact's friction σ f_k + σ_v (v − ẋ_N) in a slip
//! and ẍ_N = 0 with ẋ_N = v in a stick — at the step H (global error O((ΩH)⁴), about 1e-11 here),
//! and applies the rules directly: a slip arriving at ẋ_N = v sticks when |F| ≤ f_s (unless F is
//! within 1e-6 of ±f_s and moving outward: a touch, the slip goes on with σ = sgn F), else goes on
//! with σ = sgn F; a stick ends when |F| reaches f_s (σ = sgn F) or at a belt change (σ =
//! sgn(v_new − v_old)); an anchor change never ends one unless F jumps past f_s. An arrival is
//! caught at a step end, or inside a step at the minimum of σ(v − ẋ_N) (golden section) when
//! the relative velocity turned within it; its instant is bisected on RK4 sub-steps from the
//! step's start.

use stickslip::chain::{Anchor, Chain, ChainExact};
use stickslip::simulation::events::Record;
use stickslip::solver::{drive, Drive};

use crate::common::event_errors;

const H: f64 = 2.5e-4;

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Stick,
    Slip(f64),
}

struct Ref<'a> {
    ch: &'a Chain,
    v: f64,
    u: f64,
}

impl Ref<'_> {
    /// d/dt of (x, ẋ, a) in `mode`.
    fn rate(&self, mode: Mode, s: &[f64]) -> Vec<f64> {
        let n = self.ch.len();
        let (m, k, c) = (&self.ch.masses, &self.ch.stiffnesses, &self.ch.dampings);
        let mut d = vec![0.0; 2 * n + 1];
        for i in 0..n {
            d[i] = s[n + i];
            let (xp, vp) = if i == 0 { (s[2 * n], self.u) } else { (s[i - 1], s[n + i - 1]) };
            let mut f = k[i] * (xp - s[i]) + c[i] * (vp - s[n + i]);
            if i + 1 < n {
                f -= k[i + 1] * (s[i] - s[i + 1]) + c[i + 1] * (s[n + i] - s[n + i + 1]);
            }
            if i == n - 1 {
                match mode {
                    Mode::Stick => f = 0.0,
                    Mode::Slip(sigma) => f += sigma * self.ch.kinetic + self.ch.viscous * (self.v - s[n + i]),
                }
            }
            d[n + i] = f / m[i];
        }
        d[2 * n] = self.u;
        d
    }

    fn rk4(&self, mode: Mode, s: &[f64], h: f64) -> Vec<f64> {
        let add = |a: &[f64], b: &[f64], w: f64| a.iter().zip(b).map(|(x, y)| x + w * y).collect::<Vec<_>>();
        let k1 = self.rate(mode, s);
        let k2 = self.rate(mode, &add(s, &k1, 0.5 * h));
        let k3 = self.rate(mode, &add(s, &k2, 0.5 * h));
        let k4 = self.rate(mode, &add(s, &k3, h));
        (0..s.len()).map(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])).collect()
    }

    /// F = k_N (x_N − x_{N−1}) + c_N (v − ẋ_{N−1}).
    fn force(&self, s: &[f64]) -> f64 {
        let n = self.ch.len();
        let (xp, vp) = if n == 1 { (s[2 * n], self.u) } else { (s[n - 2], s[2 * n - 2]) };
        self.ch.stiffnesses[n - 1] * (s[n - 1] - xp) + self.ch.dampings[n - 1] * (self.v - vp)
    }
}

/// (stick starts, slip starts after a stick) of the chain under the belt segments and anchor
/// segments given, from (x0, ẋ0).
fn reference(ch: &Chain, belt: (&[f64], &[f64]), anchor: &Anchor, x0: &[f64], xd0: &[f64], t_a: f64) -> (Vec<f64>, Vec<f64>) {
    let n = ch.len();
    let (mut sticks, mut slips) = (Vec::new(), Vec::new());
    let mut s: Vec<f64> = x0.iter().chain(xd0).copied().chain([0.0]).collect();
    // every boundary: belt changes and anchor changes, merged
    let mut bounds: Vec<(f64, bool)> = belt.1.iter().map(|&t| (t, true)).chain(anchor.switches.iter().map(|&t| (t, false))).collect();
    bounds.sort_by(|a, b| a.0.total_cmp(&b.0));
    bounds.push((t_a, false));
    let (mut bi, mut ai) = (0, 0);
    let mut r = Ref { ch, v: belt.0[0], u: anchor.velocities[0] };
    let w0 = r.v - s[2 * n - 1];
    let mut mode = Mode::Slip(w0.signum());
    let mut fresh = false;
    let fs = ch.breakaway;
    // arrival at belt speed at state `s`
    let arrive = |r: &Ref, s: &mut Vec<f64>| -> Mode {
        s[2 * n - 1] = r.v;
        let f = r.force(s);
        let out = r.rk4(Mode::Stick, s, 1e-7);
        let outward = f.signum() * (r.force(&out) - f) > 0.0;
        if f.abs() <= fs && !(f.abs() >= fs * (1.0 - 1e-6) && outward) {
            Mode::Stick
        } else {
            Mode::Slip(f.signum())
        }
    };
    if w0 == 0.0 {
        mode = arrive(&r, &mut s);
        if mode == Mode::Stick {
            sticks.push(0.0);
        }
        fresh = true;
    }
    let mut t = 0.0;
    for &(t_end, is_belt) in &bounds {
        while t < t_end {
            let h = H.min(t_end - t);
            match mode {
                Mode::Stick => {
                    let next = r.rk4(mode, &s, h);
                    let f1 = r.force(&next);
                    if f1.abs() >= fs {
                        let (mut lo, mut hi) = (0.0, h);
                        for _ in 0..80 {
                            let mid = 0.5 * (lo + hi);
                            if r.force(&r.rk4(mode, &s, mid)).abs() >= fs {
                                hi = mid
                            } else {
                                lo = mid
                            }
                        }
                        s = r.rk4(mode, &s, hi);
                        t += hi;
                        slips.push(t);
                        mode = Mode::Slip(r.force(&s).signum());
                        fresh = true;
                        continue;
                    }
                    s = next;
                    t += h;
                }
                Mode::Slip(sigma) => {
                    let g = |dt: f64| sigma * (r.v - r.rk4(mode, &s, dt)[2 * n - 1]);
                    let gd = |dt: f64| -sigma * r.rate(mode, &r.rk4(mode, &s, dt))[2 * n - 1];
                    let mut end = None;
                    if g(h) < 0.0 {
                        end = Some(h);
                    } else if !fresh && gd(0.0) < 0.0 && gd(h) > 0.0 {
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
                            end = Some(0.5 * (a + b));
                        }
                    }
                    fresh = false;
                    if let Some(e) = end {
                        let (mut lo, mut hi) = (0.0, e);
                        for _ in 0..80 {
                            let mid = 0.5 * (lo + hi);
                            if g(mid) > 0.0 {
                                lo = mid
                            } else {
                                hi = mid
                            }
                        }
                        s = r.rk4(mode, &s, hi);
                        t += hi;
                        mode = arrive(&r, &mut s);
                        if mode == Mode::Stick {
                            sticks.push(t);
                        }
                        fresh = true;
                        continue;
                    }
                    s = r.rk4(mode, &s, h);
                    t += h;
                }
            }
        }
        t = t_end;
        if t_end >= t_a {
            break;
        }
        if is_belt {
            bi += 1;
            let v_new = belt.0[bi];
            if mode == Mode::Stick {
                slips.push(t);
                mode = Mode::Slip((v_new - r.v).signum());
            } else {
                let w = v_new - s[2 * n - 1];
                mode = Mode::Slip(w.signum());
            }
            r.v = v_new;
            fresh = false;
        } else {
            ai += 1;
            r.u = anchor.velocities[ai];
            if mode == Mode::Stick && r.force(&s).abs() > fs {
                slips.push(t);
                mode = Mode::Slip(r.force(&s).signum());
                fresh = true;
            }
        }
    }
    (sticks, slips)
}

/// SplitMix64 uniforms on [0, 1).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Switch instants of rate λ on (0, t_a) and the levels between them, alternating from a
    /// random start between `levels`.
    fn path(&mut self, rate: f64, levels: (f64, f64), t_a: f64) -> (Vec<f64>, Vec<f64>) {
        let (mut switches, mut velocities) = (Vec::new(), Vec::new());
        let mut level = if self.next() < 0.5 { levels.0 } else { levels.1 };
        velocities.push(level);
        if rate > 0.0 {
            let mut t = -(1.0 - self.next()).ln() / rate;
            while t < t_a {
                switches.push(t);
                level = if level == levels.0 { levels.1 } else { levels.0 };
                velocities.push(level);
                t += -(1.0 - self.next()).ln() / rate;
            }
        }
        (velocities, switches)
    }
}

struct Case {
    name: &'static str,
    chain: Chain,
    belt: (f64, (f64, f64)),
    anchor: (f64, (f64, f64)),
    t_a: f64,
}

fn cases() -> Vec<Case> {
    let paper = |masses: Vec<f64>, stiffnesses: Vec<f64>, dampings: Vec<f64>, fk: f64, fs: f64, viscous: f64| Chain {
        masses,
        stiffnesses,
        dampings,
        kinetic: fk,
        breakaway: fs,
        viscous,
    };
    vec![
        Case {
            name: "two masses, paper belt, fixed anchor, mu_s = mu_k, damped",
            chain: paper(vec![1.0, 1.0], vec![4.0, 6.0], vec![0.1, 0.2], 5.0, 5.0, 0.0),
            belt: (1.0, (2.0, -2.0)),
            anchor: (0.0, (0.0, 0.0)),
            t_a: 12.0,
        },
        Case {
            name: "two masses, resting belt, moving anchor, mu_s > mu_k (a drillstring)",
            chain: paper(vec![2.0, 1.0], vec![3.0, 5.0], vec![0.3, 0.4], 4.0, 6.0, 0.0),
            belt: (0.0, (0.0, 0.0)),
            anchor: (0.0, (1.5, 1.5)),
            t_a: 12.0,
        },
        Case {
            name: "three masses, switching anchor, paper belt, viscous, mu_s > mu_k",
            chain: paper(vec![1.0, 0.5, 1.5], vec![2.0, 8.0, 5.0], vec![0.2, 0.0, 0.3], 3.0, 4.5, 0.3),
            belt: (0.5, (1.0, -1.0)),
            anchor: (0.3, (0.5, 2.0)),
            t_a: 12.0,
        },
        Case {
            name: "one mass, switching anchor with a dashpot, resting belt",
            chain: paper(vec![1.0], vec![4.0], vec![0.5], 3.0, 5.0, 0.0),
            belt: (0.0, (0.0, 0.0)),
            anchor: (0.5, (0.5, 3.0)),
            t_a: 12.0,
        },
    ]
}

#[test]
fn the_exact_chain_agrees_with_an_independent_reference() {
    let realizations = 60;
    for case in cases() {
        let mut rng = Uniform(7);
        let n = case.chain.len();
        let (mut exact, mut reference_) = (Vec::new(), Vec::new());
        for _ in 0..realizations {
            let belt = rng.path(case.belt.0, case.belt.1, case.t_a);
            let (u_velocities, u_switches) = rng.path(case.anchor.0, case.anchor.1, case.t_a);
            let anchor = Anchor { velocities: u_velocities, switches: u_switches };
            let x0: Vec<f64> = (0..n).map(|_| 2.0 * rng.next() - 1.0).collect();
            let xd0: Vec<f64> = (0..n).map(|_| 2.0 * rng.next() - 1.0).collect();
            let mut m = ChainExact::new(&case.chain, &anchor, &x0, &xd0, case.t_a);
            let d = Drive { velocities: &belt.0, switches: &belt.1, t_end: case.t_a };
            let mut rec = Record::default();
            drive(&mut m, &d, x0[n - 1], xd0[n - 1], u64::MAX, &mut rec).expect("solves");
            rec.finish(case.t_a);
            let (sticks, slips) = reference(&case.chain, (&belt.0, &belt.1), &anchor, &x0, &xd0, case.t_a);
            let mut r = Record::default();
            r.stick_start = sticks;
            r.slip_start = slips;
            exact.push(rec);
            reference_.push(r);
        }
        let (errors, missed, spurious) = event_errors(&reference_, &exact);
        let worst = errors.last().copied().unwrap_or(0.0);
        eprintln!("reference, {}: {} events, worst difference {worst:e} s", case.name, errors.len());
        assert!(errors.len() > 100, "{}: only {} events", case.name, errors.len());
        assert_eq!((missed, spurious), (0, 0), "{}", case.name);
        assert!(worst < 1e-8, "{}: worst event-time difference {worst:e} s", case.name);
    }
}
