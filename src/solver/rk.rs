//! Explicit Runge–Kutta steps for `y = (x, ẋ)`, `y' = (ẋ, a(x, ẋ))`, with dense output and
//! root location — the machinery of the numerical solvers.
//!
//! **Dormand–Prince 5(4)** (J. R. Dormand, P. J. Prince, "A family of embedded Runge–Kutta
//! formulae", J. Comput. Appl. Math. 6, 1980; the method of MATLAB's ode45), FSAL, with the error
//! norm `‖e‖ = √(mean((eᵢ / (atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|)))²))` and the step controller
//! `h ← h·clamp(0.9‖e‖^{-1/5}, 0.2, 5)`, never above `max_step` (E. Hairer, S. P. Nørsett,
//! G. Wanner, *Solving ODEs I*, §II.4):
//!
//! ```text
//!  0    |
//!  1/5  | 1/5
//!  3/10 | 3/40        9/40
//!  4/5  | 44/45      −56/15      32/9
//!  8/9  | 19372/6561 −25360/2187 64448/6561 −212/729
//!  1    | 9017/3168  −355/33     46732/5247  49/176  −5103/18656
//!  1    | 35/384      0          500/1113    125/192 −2187/6784    11/84
//!  -----+---------------------------------------------------------------------
//!  b₅   | 35/384      0          500/1113    125/192 −2187/6784    11/84     0
//!  b₅−b₄| 71/57600    0         −71/16695    71/1920 −17253/339200 22/525   −1/40
//! ```
//!
//! **RK4**: the classical fourth-order method at a fixed step.
//!
//! **Dense output** (Hairer–Nørsett–Wanner §II.6, the `CONTD5` of their DOPRI5 code, the
//! interpolant of MATLAB's ode45): with `Δ = y₁ − y₀`, `b = h f₀ − Δ`, `c = Δ − h f₁ − b`,
//!
//! ```text
//!     y(θ) = y₀ + θ (Δ + (1−θ) (b + θ (c + (1−θ) d))),    θ ∈ [0, 1]
//!     d = h (d₁ k₁ + d₃ k₃ + d₄ k₄ + d₅ k₅ + d₆ k₆ + d₇ k₇)      (Dormand–Prince; error O(h⁵))
//!     d₁ = −12715105075/11282082432   d₃ = 87487479700/32700410799   d₄ = −10690763975/1880347072
//!     d₅ = 701980252875/199316789632  d₆ = −1453857185/822651844     d₇ = 69997945/29380423
//! ```
//!
//! With `d = 0` this is the cubic Hermite interpolant of (y, y′) at both ends (error O(h⁴)),
//! RK4's dense output. Events are located on it by bisection to 1e-15 of the step; a zero that
//! the end values cannot show (the function dips below zero and comes back inside one step) is
//! found from the minimum of the interpolant when the caller knows the derivative changes sign.

/// State (x, ẋ).
pub type State = [f64; 2];

/// One accepted step: from `t0`, length `h`, end states and derivatives.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    pub t0: f64,
    pub h: f64,
    pub y0: State,
    pub f0: State,
    pub y1: State,
    pub f1: State,
    /// the dense output's terms beyond the cubic Hermite, `d(θ) = d₀ + θ (d₁ + (1−θ)(d₂ + θ d₃))`:
    /// Dormand–Prince 5(4) fills `d₀` (its fifth-order correction), DOP853 all four (its
    /// seventh-order interpolant); all zero: cubic Hermite
    pub d: [State; 4],
    /// whether `d` is filled: a DOP853 step leaves it to [`Dopri::complete`] (three more
    /// right-hand sides), which is called only when the step is looked inside
    pub complete: bool,
}

impl Step {
    /// The correction `d(θ)` of component `i` and its derivative in θ (see [`Step::d`]). With
    /// d₁ = d₂ = d₃ = 0 (Dormand–Prince 5(4), RK4) they are d₀ and 0 exactly.
    #[inline]
    fn correction(&self, theta: f64, i: usize) -> (f64, f64) {
        let (t, u) = (theta, 1.0 - theta);
        let [d0, d1, d2, d3] = self.d.map(|d| d[i]);
        let inner = d2 + t * d3;
        (d0 + t * (d1 + u * inner), d1 + u * inner + t * (-inner + u * d3))
    }

    /// The dense output at fraction θ ∈ [0, 1] of the step.
    pub fn at(&self, theta: f64) -> State {
        debug_assert!(self.complete || theta == 0.0 || theta == 1.0, "inside a DOP853 step before Dopri::complete");
        let (t, u, h) = (theta, 1.0 - theta, self.h);
        std::array::from_fn(|i| {
            let delta = self.y1[i] - self.y0[i];
            let b = h * self.f0[i] - delta;
            let c = delta - h * self.f1[i] - b;
            let d = self.correction(theta, i).0;
            self.y0[i] + t * (delta + u * (b + t * (c + u * d)))
        })
    }

    /// The least and greatest velocity (component 1) of the dense output on θ ∈ [0, `end`]: the
    /// ends, and a turning point located where the output's slope changes sign between them
    /// (bisection on the slope of the interpolant, which is exact to polynomial order; an
    /// extremum is flat, so its value is as accurate as the dense output).
    pub fn velocity_range(&self, end: f64) -> (f64, f64) {
        let (a, b) = (self.at(0.0)[1], self.at(end)[1]);
        let (mut lo, mut hi) = (a.min(b), a.max(b));
        let slope0 = self.slope(0.0);
        if end > 0.0 && self.turns_before(end) {
            let (mut l, mut r) = (0.0, end);
            for _ in 0..60 {
                let m = 0.5 * (l + r);
                if self.slope(m).signum() == slope0.signum() {
                    l = m;
                } else {
                    r = m;
                }
            }
            let w = self.at(0.5 * (l + r))[1];
            (lo, hi) = (lo.min(w), hi.max(w));
        }
        (lo, hi)
    }

    /// d/dθ of the velocity's dense output.
    fn slope(&self, theta: f64) -> f64 {
        self.rate(theta)[1]
    }

    /// Whether the velocity's dense output turns on θ ∈ [0, `end`]: its slope changes sign
    /// between the ends. At θ = 0 and 1 the slope is h·f₀ and h·f₁ whatever the correction d, so
    /// `turns_before(1.0)` is known before a DOP853 step is completed ([`Dopri::complete`]).
    pub fn turns_before(&self, end: f64) -> bool {
        let (slope0, slope1) = (self.slope(0.0), self.slope(end));
        slope0 != 0.0 && slope0.signum() != slope1.signum()
    }

    /// The first θ ∈ (0, 1] where `g` along the dense output falls to ≤ 0 after being positive.
    ///
    /// `g` is affine in the state (a gap to belt speed). `g(y₀) > 0`, or `g(y₀) = 0` with g
    /// rising (a step that starts at an event). Found: a sign
    /// change at the end of the step (after the interior maximum when g starts at zero: it rose
    /// and fell back), or, when `dips` (the caller knows g′ goes from negative to positive inside
    /// the step, so g has one interior minimum), a dip below zero between two positive ends.
    /// `None` while g stays positive (or never rises above zero in this step).
    pub fn first_zero(&self, g: impl Fn(State) -> f64, dips: bool) -> Option<f64> {
        let (g0, g1) = (g(self.y0), g(self.y1));
        if g1 <= 0.0 {
            let lo = if g0 > 0.0 {
                0.0
            } else {
                let m = self.argmin(&|y| -g(y));
                if g(self.at(m)) <= 0.0 {
                    return None;
                }
                m
            };
            return Some(self.root(&g, lo, 1.0));
        }
        if dips && g0 > 0.0 {
            let m = self.argmin(&g);
            if g(self.at(m)) <= 0.0 {
                return Some(self.root(&g, 0.0, m));
            }
        }
        None
    }

    /// The θ ∈ (lo, hi] where `g` changes from positive to ≤ 0, given `g(at(lo)) > 0 ≥ g(at(hi))`:
    /// the Illinois variant of regula falsi (superlinear; the bracket shrinks from both sides) to
    /// 1e-15 of the step, returning the ≤ 0 side.
    fn root(&self, g: &impl Fn(State) -> f64, lo: f64, hi: f64) -> f64 {
        let (mut a, mut b) = (lo, hi);
        let (mut fa, mut fb) = (g(self.at(a)), g(self.at(b)));
        let mut side = 0;
        for _ in 0..200 {
            if b - a <= 1e-15 || fb == 0.0 {
                break;
            }
            let mut m = (a * fb - b * fa) / (fb - fa);
            if !(m > a && m < b) {
                m = 0.5 * (a + b);
            }
            let fm = g(self.at(m));
            if fm > 0.0 {
                (a, fa) = (m, fm);
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                (b, fb) = (m, fm);
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
        }
        b
    }

    /// The time derivative of the dense output at θ, times h: `dy/dθ`. With `R = c + (1−θ) d(θ)`,
    /// `Q = b + θ R`, `P = Δ + (1−θ) Q`: `y = y₀ + θ P`, and by the product rule
    /// `R′ = −d + (1−θ) d′`, `Q′ = R + θ R′`, `P′ = −Q + (1−θ) Q′`, `dy/dθ = P + θ P′`.
    fn rate(&self, theta: f64) -> State {
        debug_assert!(self.complete || theta == 0.0 || theta == 1.0, "inside a DOP853 step before Dopri::complete");
        let (t, u, h) = (theta, 1.0 - theta, self.h);
        std::array::from_fn(|i| {
            let delta = self.y1[i] - self.y0[i];
            let b = h * self.f0[i] - delta;
            let c = delta - h * self.f1[i] - b;
            let (d, dd) = self.correction(theta, i);
            let r = c + u * d;
            let q = b + t * r;
            let p = delta + u * q;
            let dr = -d + u * dd;
            p + t * (-q + u * (r + t * dr))
        })
    }

    /// The minimum of `g` along the dense output, `g` affine in the state with `g′` going from
    /// negative to positive inside the step: the zero of `g′(θ) = g(y + dy/dθ) − g(y)` (exact for
    /// an affine g) by the Illinois variant of regula falsi to 1e-10 of the step. Without that
    /// sign change, the end with the smaller g′ side (0 if g rises from the start, 1 if it falls
    /// to the end).
    fn argmin(&self, g: &impl Fn(State) -> f64) -> f64 {
        let slope = |th: f64| {
            let (y, r) = (self.at(th), self.rate(th));
            g([y[0] + r[0], y[1] + r[1]]) - g(y)
        };
        let (mut a, mut b, mut fa, mut fb) = (0.0, 1.0, slope(0.0), slope(1.0));
        if !(fa < 0.0) {
            return 0.0;
        }
        if !(fb > 0.0) {
            return 1.0;
        }
        let mut side = 0;
        for _ in 0..100 {
            let m = (a * fb - b * fa) / (fb - fa);
            let fm = slope(m);
            if fm < 0.0 {
                (a, fa) = (m, fm);
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else if fm > 0.0 {
                (b, fb) = (m, fm);
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            } else {
                return m;
            }
            if b - a <= 1e-10 {
                break;
            }
        }
        0.5 * (a + b)
    }
}

fn deriv(a: &impl Fn(State) -> f64, y: State) -> State {
    [y[1], a(y)]
}

/// `y + h Σ cⱼ kⱼ`, summed as `y + (h c₁) k₁ + (h c₂) k₂ + …` in order: the last stage, the one
/// just computed, enters through one multiply and one add (the other terms are ready earlier),
/// which keeps the chain from one stage's derivative to the next stage's state short.
#[inline]
fn axpy(y: State, h: f64, terms: &[(f64, State)]) -> State {
    std::array::from_fn(|i| terms.iter().fold(y[i], |acc, (c, k)| acc + (h * c) * k[i]))
}

/// Classical RK4 step of length `h`.
pub fn rk4(a: &impl Fn(State) -> f64, t0: f64, y0: State, h: f64) -> Step {
    let k1 = deriv(a, y0);
    let k2 = deriv(a, axpy(y0, 0.5 * h, &[(1.0, k1)]));
    let k3 = deriv(a, axpy(y0, 0.5 * h, &[(1.0, k2)]));
    let k4 = deriv(a, axpy(y0, h, &[(1.0, k3)]));
    let y1 = axpy(y0, h / 6.0, &[(1.0, k1), (2.0, k2), (2.0, k3), (1.0, k4)]);
    Step { t0, h, y0, f0: k1, y1, f1: deriv(a, y1), d: [[0.0; 2]; 4], complete: true }
}

/// The embedded pair of an adaptive integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pair {
    /// Dormand–Prince 5(4) (`rk45`, `smooth`)
    Dp54,
    /// Dormand–Prince 8(5,3) ([`super::dop853`])
    Dop853,
}

impl Pair {
    /// The step controller `h ← h·clamp(0.9‖e‖^{−1/(q+1)}, lo, hi)` (q the estimate's order):
    /// `(1/(q+1), lo, hi)`, the error at or below which the factor is `hi` (so the power is only
    /// taken where it changes the step: (0.9/hi)^{q+1}) and above which it is below one
    /// (0.9^{q+1}).
    fn controller(self) -> (f64, f64, f64, f64, f64) {
        match self {
            Pair::Dp54 => (0.2, 0.2, 5.0, 1.8e-4, 0.59),
            Pair::Dop853 => (0.125, 1.0 / 3.0, 6.0, 2.5e-7, 0.43),
        }
    }
}

/// The adaptive Dormand–Prince integrator's state between steps.
#[derive(Debug, Clone, Copy)]
pub struct Dopri {
    pub pair: Pair,
    pub rtol: f64,
    pub atol: f64,
    pub max_step: f64,
    /// the step to try next
    pub h: f64,
    /// attempted steps allowed (`numerics.step_budget`): past it a step gives up
    pub budget: u64,
    /// the error estimate or the state stayed non-finite down to the smallest step
    pub failed: bool,
    /// the stages of the last step (DOP853's dense output is made from them on demand)
    pub k: [State; 16],
}

impl Dopri {
    /// Dormand–Prince 5(4).
    pub fn new(rtol: f64, atol: f64, max_step: f64) -> Dopri {
        Dopri { pair: Pair::Dp54, rtol, atol, max_step, h: max_step.min(1e-3), budget: u64::MAX, failed: false, k: [[0.0; 2]; 16] }
    }

    /// No step: what [`Dopri::step_from`] returns when it gives up (over the budget, or
    /// [`Dopri::failed`]); the driver then stops the realization with the reason.
    fn null(t0: f64, y0: State, f0: State) -> Step {
        Step { t0, h: 0.0, y0, f0, y1: y0, f1: f0, d: [[0.0; 2]; 4], complete: true }
    }

    /// The step the next trial takes when nothing shorter is asked for.
    #[inline]
    pub fn next(&self) -> f64 {
        self.h.min(self.max_step)
    }

    /// One accepted step from `(t0, y0)` no longer than `limit`; `trials` counts attempted steps.
    pub fn step(&mut self, a: &impl Fn(State) -> f64, t0: f64, y0: State, limit: f64, trials: &mut u64) -> Step {
        self.step_from(a, t0, y0, deriv(a, y0), limit, trials)
    }

    /// [`Dopri::step`] given the derivative `k1 = f(y0)` — the previous step's last stage when
    /// the right-hand side has not changed (FSAL: first same as last).
    pub fn step_from(&mut self, a: &impl Fn(State) -> f64, t0: f64, y0: State, k1: State, limit: f64, trials: &mut u64) -> Step {
        let (exponent, lo, hi, fast, shrinks) = self.pair.controller();
        // the stages live in `self.k`: the last accepted trial's are what `complete` reads
        self.k[0] = k1;
        loop {
            *trials += 1;
            if *trials > self.budget {
                return Dopri::null(t0, y0, k1);
            }
            let h = self.next().min(limit);
            let (y1, err) = match self.pair {
                Pair::Dp54 => dp54_trial(a, y0, h, &mut self.k, (self.rtol, self.atol)),
                Pair::Dop853 => super::dop853::trial(a, y0, h, &mut self.k, (self.rtol, self.atol)),
            };
            // the controller's factor 0.9 err^(−1/(q+1)), clamped to [lo, hi]; most steps are cut
            // short by a belt switch or the Stribeck guard with a tiny error, and keep the
            // controller's step
            let factor = || if err > fast { (0.9 * err.powf(-exponent)).clamp(lo, hi) } else { hi };
            let floor = h <= 1e-14 * t0.abs().max(1.0);
            if !(err.is_finite() && y1[0].is_finite() && y1[1].is_finite()) {
                // an overflow inside the step: shrink as far as the floor, then give up (never
                // accept a non-finite state, never grow the step on a NaN estimate)
                if floor {
                    self.failed = true;
                    return Dopri::null(t0, y0, k1);
                }
                self.h = h * 0.2;
                continue;
            }
            if err <= 1.0 || floor {
                if h >= self.next() * 0.999 {
                    self.h = (h * factor()).min(self.max_step);
                } else if err > shrinks {
                    let f = factor();
                    if f < 1.0 {
                        self.h = (h * f).min(self.max_step);
                    }
                }
                return match self.pair {
                    Pair::Dp54 => Step { t0, h, y0, f0: k1, y1, f1: self.k[6], d: [dp54_dense(h, &self.k), [0.0; 2], [0.0; 2], [0.0; 2]], complete: true },
                    Pair::Dop853 => Step { t0, h, y0, f0: k1, y1, f1: self.k[12], d: [[0.0; 2]; 4], complete: false },
                };
            }
            self.h = h * factor();
        }
    }
}

impl Dopri {
    /// Fill the dense output of `step`, the last step this integrator returned (DOP853: three
    /// more right-hand sides; nothing for a step already complete).
    pub fn complete(&mut self, a: &impl Fn(State) -> f64, step: &mut Step) {
        if !step.complete {
            step.d = super::dop853::dense(a, step.y0, step.h, &mut self.k);
            step.complete = true;
        }
    }
}

/// One Dormand–Prince 5(4) trial step of length `h` from `y0` with `k[0] = f(y0)`: fills stages
/// 1–6 (`k[6] = f(y₁)`, FSAL) and returns `(y₁, ‖e‖)` with the norm of the module docs.
#[inline(always)]
fn dp54_trial(a: &impl Fn(State) -> f64, y0: State, h: f64, k: &mut [State; 16], (rtol, atol): (f64, f64)) -> (State, f64) {
    let k1 = k[0];
    let k2 = deriv(a, axpy(y0, h, &[(1.0 / 5.0, k1)]));
    let k3 = deriv(a, axpy(y0, h, &[(3.0 / 40.0, k1), (9.0 / 40.0, k2)]));
    let k4 = deriv(a, axpy(y0, h, &[(44.0 / 45.0, k1), (-56.0 / 15.0, k2), (32.0 / 9.0, k3)]));
    let k5 = deriv(a, axpy(y0, h, &[(19372.0 / 6561.0, k1), (-25360.0 / 2187.0, k2), (64448.0 / 6561.0, k3), (-212.0 / 729.0, k4)]));
    let k6 = deriv(a, axpy(y0, h, &[(9017.0 / 3168.0, k1), (-355.0 / 33.0, k2), (46732.0 / 5247.0, k3), (49.0 / 176.0, k4), (-5103.0 / 18656.0, k5)]));
    let y1 = axpy(y0, h, &[(35.0 / 384.0, k1), (500.0 / 1113.0, k3), (125.0 / 192.0, k4), (-2187.0 / 6784.0, k5), (11.0 / 84.0, k6)]);
    let k7 = deriv(a, y1);
    let e = axpy(
        [0.0, 0.0],
        h,
        &[(71.0 / 57600.0, k1), (-71.0 / 16695.0, k3), (71.0 / 1920.0, k4), (-17253.0 / 339200.0, k5), (22.0 / 525.0, k6), (-1.0 / 40.0, k7)],
    );
    let err = ((0..2).map(|i| (e[i] / (atol + rtol * y0[i].abs().max(y1[i].abs()))).powi(2)).sum::<f64>() / 2.0).sqrt();
    k[1..7].copy_from_slice(&[k2, k3, k4, k5, k6, k7]);
    (y1, err)
}

/// The fifth-order correction `d` of Dormand–Prince 5(4)'s dense output (module docs).
#[inline(always)]
fn dp54_dense(h: f64, k: &[State; 16]) -> State {
    axpy(
        [0.0, 0.0],
        h,
        &[
            (-12715105075.0 / 11282082432.0, k[0]),
            (87487479700.0 / 32700410799.0, k[2]),
            (-10690763975.0 / 1880347072.0, k[3]),
            (701980252875.0 / 199316789632.0, k[4]),
            (-1453857185.0 / 822651844.0, k[5]),
            (69997945.0 / 29380423.0, k[6]),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x'' = −x from (1, 0) to t = 2 by `dp`: (x(2), the attempted steps).
    fn oscillator_to_2(mut dp: Dopri) -> (f64, u64) {
        let a = |y: State| -y[0];
        let (mut t, mut y, mut trials) = (0.0, [1.0, 0.0], 0);
        while t < 2.0 {
            let s = dp.step(&a, t, y, 2.0 - t, &mut trials);
            t += s.h;
            y = s.y1;
        }
        (y[0], trials)
    }

    #[test]
    fn methods_integrate_a_harmonic_oscillator_at_their_order() {
        // x'' = −x from (1, 0): x(t) = cos t
        let a = |y: State| -y[0];
        let run_rk4 = |h: f64| {
            let (mut t, mut y) = (0.0, [1.0, 0.0]);
            while t < 2.0 - 1e-12 {
                y = rk4(&a, t, y, h).y1;
                t += h;
            }
            (y[0] - 2f64.cos()).abs()
        };
        let (e1, e2) = (run_rk4(0.02), run_rk4(0.01));
        assert!((e1 / e2 - 16.0).abs() < 2.0, "RK4 error ratio {}", e1 / e2);
        let (x, _) = oscillator_to_2(Dopri::new(1e-10, 1e-10, 1.0));
        assert!((x - 2f64.cos()).abs() < 1e-8, "{}", x - 2f64.cos());
        // dense output and root: cos t = 0 at π/2
        let s = rk4(&a, 1.5, [1.5f64.cos(), -(1.5f64).sin()], 0.1);
        let theta = s.first_zero(|y| y[0], false).unwrap();
        assert!((1.5 + 0.1 * theta - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
    }

    /// One Dormand–Prince step of length h on x'' = −x from (cos t0, −sin t0), forced (no
    /// rejection), and the largest dense-output error in x over the step against cos t.
    fn dense_error(t0: f64, h: f64, hermite: bool) -> f64 {
        let a = |y: State| -y[0];
        let mut dp = Dopri::new(1.0, 1.0, h);
        dp.h = h;
        let mut step = dp.step(&a, t0, [t0.cos(), -t0.sin()], h, &mut 0);
        assert_eq!(step.h, h);
        if hermite {
            step.d = [[0.0; 2]; 4];
        }
        (1..20).map(|i| i as f64 / 20.0).map(|th| (step.at(th)[0] - (t0 + th * h).cos()).abs()).fold(0.0, f64::max)
    }

    /// One DOP853 step of length h on x'' = −x from (cos t0, −sin t0), forced: the largest
    /// dense-output error in x over the step against cos t, and the end point's error.
    fn dop853_errors(t0: f64, h: f64) -> (f64, f64) {
        let a = |y: State| -y[0];
        let mut dp = Dopri { pair: Pair::Dop853, ..Dopri::new(1.0, 1.0, h) };
        dp.h = h;
        let mut step = dp.step(&a, t0, [t0.cos(), -t0.sin()], h, &mut 0);
        assert_eq!(step.h, h);
        dp.complete(&a, &mut step);
        let dense = (1..20).map(|i| i as f64 / 20.0).map(|th| (step.at(th)[0] - (t0 + th * h).cos()).abs()).fold(0.0, f64::max);
        (dense, (step.y1[0] - (t0 + h).cos()).abs())
    }

    #[test]
    fn dop853_is_eighth_order_with_a_seventh_order_dense_output() {
        // local errors: the step O(h^9), the dense output O(h^8) — halving h divides them by
        // 512 and 256 (within the pre-asymptotic spread)
        let (d1, e1) = dop853_errors(0.3, 0.8);
        let (d2, e2) = dop853_errors(0.3, 0.4);
        assert!((300.0..=900.0).contains(&(e1 / e2)), "step error ratio {}", e1 / e2);
        assert!((150.0..=450.0).contains(&(d1 / d2)), "dense error ratio {}", d1 / d2);
        // global: x'' = −x to t = 2 at rtol = atol = 1e-12, far beyond what rk45 reaches in as
        // many steps
        let a = |y: State| -y[0];
        let (x, trials) = oscillator_to_2(Dopri { pair: Pair::Dop853, ..Dopri::new(1e-12, 1e-12, 1.0) });
        assert!((x - 2f64.cos()).abs() < 1e-11, "{}", x - 2f64.cos());
        assert!(trials < 60, "{trials} trials");
        // the derivative of the dense output (rate, slope) against a central difference
        let mut dp = Dopri { pair: Pair::Dop853, ..Dopri::new(1.0, 1.0, 0.6) };
        dp.h = 0.6;
        let mut step = dp.step(&a, 1.2, [1.2f64.cos(), -(1.2f64).sin()], 0.6, &mut 0);
        dp.complete(&a, &mut step);
        for &th in &[0.1, 0.5, 0.9] {
            let fd = (step.at(th + 1e-6)[1] - step.at(th - 1e-6)[1]) / 2e-6;
            assert!((step.slope(th) - fd).abs() < 1e-7, "θ {th}: {} vs {fd}", step.slope(th));
            // and dx/dθ = h ẋ of the exact solution, to the interpolant's accuracy
            let t = 1.2 + 0.6 * th;
            assert!((step.rate(th)[0] / 0.6 + t.sin()).abs() < 1e-7, "θ {th}: ẋ {} vs {}", step.rate(th)[0] / 0.6, -t.sin());
        }
    }

    #[test]
    fn velocity_range_finds_the_turning_point_inside_a_step() {
        // x'' = −x from t0 = 1.4: ẋ = −sin t has its minimum −1 at π/2, inside [1.4, 1.8]
        let a = |y: State| -y[0];
        let (t0, h) = (1.4, 0.4);
        let mut dp = Dopri::new(1.0, 1.0, h);
        dp.h = h;
        let step = dp.step(&a, t0, [t0.cos(), -t0.sin()], h, &mut 0);
        // the slope is the derivative of the dense output (an independent central difference)
        for &th in &[0.1, 0.5, 0.9] {
            let fd = (step.at(th + 1e-6)[1] - step.at(th - 1e-6)[1]) / 2e-6;
            assert!((step.slope(th) - fd).abs() < 1e-7, "θ {th}: {} vs {fd}", step.slope(th));
        }
        let (lo, hi) = step.velocity_range(1.0);
        // the interpolant's own minimum (a fine grid), and the true one within its error
        let grid = (0..=10_000).map(|i| step.at(i as f64 / 1e4)[1]).fold(f64::INFINITY, f64::min);
        assert!(lo <= grid && grid - lo < 1e-9, "minimum {lo}, grid {grid}");
        assert!((lo + 1.0).abs() < 1e-5, "minimum {lo}");
        assert_eq!(hi, step.y0[1].max(step.y1[1]));
        // cut before the turning point: only the ends
        let end = 0.2 / h * 0.5;
        let (lo, hi) = step.velocity_range(end);
        assert_eq!((lo, hi), (step.at(end)[1].min(step.y0[1]), step.at(end)[1].max(step.y0[1])));
    }

    #[test]
    fn dense_output_is_fourth_order_and_hermite_third() {
        // local interpolation errors: O(h^5) with the Dormand–Prince correction, O(h^4) without
        let dp = dense_error(0.3, 0.2, false) / dense_error(0.3, 0.1, false);
        let he = dense_error(0.3, 0.2, true) / dense_error(0.3, 0.1, true);
        assert!((24.0..=40.0).contains(&dp), "DP dense output error ratio for h/2: {dp}");
        assert!((12.0..=20.0).contains(&he), "Hermite error ratio for h/2: {he}");
        assert!(dense_error(0.3, 0.2, false) < 0.1 * dense_error(0.3, 0.2, true));
    }

    #[test]
    fn a_dip_between_positive_ends_is_found_from_the_minimum() {
        // x = cos t over [π − 0.3, π + 0.3]: g = x + 0.999 > 0 at both ends, < 0 around π; its
        // first zero is at π − acos(0.999)
        let (t0, h) = (std::f64::consts::PI - 0.3, 0.6);
        let a = |y: State| -y[0];
        let mut dp = Dopri::new(1.0, 1.0, h);
        dp.h = h;
        let step = dp.step(&a, t0, [t0.cos(), -t0.sin()], h, &mut 0);
        assert_eq!(step.h, h);
        let g = |y: State| y[0] + 0.999;
        assert!(g(step.y1) > 0.0);
        assert_eq!(step.first_zero(g, false), None);
        let theta = step.first_zero(g, true).expect("dip found");
        let expected = (std::f64::consts::PI - 0.999f64.acos() - t0) / h;
        assert!((theta - expected).abs() < 2e-3, "{theta} vs {expected}");
        // a shallower function stays positive: no zero
        assert_eq!(step.first_zero(|y| y[0] + 1.001, true), None);
    }

    #[test]
    fn a_non_finite_estimate_shrinks_then_gives_up_and_the_budget_counts_trials() {
        // a right-hand side that overflows for every step: never accepted, never grown
        let mut dp = Dopri::new(1e-6, 1e-6, 1.0);
        let mut trials = 0;
        let s = dp.step(&|_: State| f64::NAN, 0.0, [1.0, 0.0], 1.0, &mut trials);
        assert!(dp.failed && s.h == 0.0 && trials < 100, "{trials} trials");
        // overflow only for steps above 1e-3: shrinks past it and is accepted there
        let mut dp = Dopri::new(1e-6, 1e-6, 1.0);
        let a = |y: State| if y[0] > 1.0 + 1e-4 || y[0] < 1.0 - 1e-3 { f64::INFINITY } else { -y[0] };
        let s = dp.step(&a, 0.0, [1.0, 0.0], 1.0, &mut 0);
        assert!(!dp.failed && s.h > 0.0 && s.y1.iter().all(|v| v.is_finite()), "{:?}", s.y1);
        // rejected trials count against the budget of attempted steps, inside one step
        let mut dp = Dopri { budget: 5, ..Dopri::new(1e-6, 1e-6, 1.0) };
        let mut trials = 0;
        let s = dp.step(&|_: State| f64::NAN, 0.0, [1.0, 0.0], 1.0, &mut trials);
        assert!(trials == 6 && s.h == 0.0 && !dp.failed, "{trials} trials, h = {}", s.h);
    }
}
