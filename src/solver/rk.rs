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
//! **Dense output**: the cubic Hermite interpolant of (y, y') at both ends of a step (error
//! O(h⁴)); events are located on it by bisection to 1e-15 of the step.

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
}

impl Step {
    /// The cubic Hermite interpolant at fraction θ ∈ [0, 1] of the step.
    pub fn at(&self, theta: f64) -> State {
        let (t, h) = (theta, self.h);
        let h00 = (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t);
        let h10 = t * (1.0 - t) * (1.0 - t);
        let h01 = t * t * (3.0 - 2.0 * t);
        let h11 = t * t * (t - 1.0);
        std::array::from_fn(|i| h00 * self.y0[i] + h10 * h * self.f0[i] + h01 * self.y1[i] + h11 * h * self.f1[i])
    }

    /// The first θ ∈ (0, 1] where `g` changes from positive to ≤ 0, given `g(y0) > 0 ≥ g(y1)`.
    pub fn root(&self, g: impl Fn(State) -> f64) -> f64 {
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if g(self.at(mid)) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }
}

fn deriv(a: &impl Fn(State) -> f64, y: State) -> State {
    [y[1], a(y)]
}

fn axpy(y: State, h: f64, terms: &[(f64, State)]) -> State {
    std::array::from_fn(|i| y[i] + h * terms.iter().map(|(c, k)| c * k[i]).sum::<f64>())
}

/// Classical RK4 step of length `h`.
pub fn rk4(a: &impl Fn(State) -> f64, t0: f64, y0: State, h: f64) -> Step {
    let k1 = deriv(a, y0);
    let k2 = deriv(a, axpy(y0, 0.5 * h, &[(1.0, k1)]));
    let k3 = deriv(a, axpy(y0, 0.5 * h, &[(1.0, k2)]));
    let k4 = deriv(a, axpy(y0, h, &[(1.0, k3)]));
    let y1 = axpy(y0, h / 6.0, &[(1.0, k1), (2.0, k2), (2.0, k3), (1.0, k4)]);
    Step { t0, h, y0, f0: k1, y1, f1: deriv(a, y1) }
}

/// The adaptive Dormand–Prince integrator's state between steps.
#[derive(Debug, Clone, Copy)]
pub struct Dopri {
    pub rtol: f64,
    pub atol: f64,
    pub max_step: f64,
    /// the step to try next
    pub h: f64,
}

impl Dopri {
    pub fn new(rtol: f64, atol: f64, max_step: f64) -> Dopri {
        Dopri { rtol, atol, max_step, h: max_step.min(1e-3) }
    }

    /// One accepted step from `(t0, y0)` no longer than `limit`; `trials` counts attempted steps.
    pub fn step(&mut self, a: &impl Fn(State) -> f64, t0: f64, y0: State, limit: f64, trials: &mut u64) -> Step {
        let k1 = deriv(a, y0);
        loop {
            *trials += 1;
            let h = self.h.min(self.max_step).min(limit);
            let k2 = deriv(a, axpy(y0, h, &[(1.0 / 5.0, k1)]));
            let k3 = deriv(a, axpy(y0, h, &[(3.0 / 40.0, k1), (9.0 / 40.0, k2)]));
            let k4 = deriv(a, axpy(y0, h, &[(44.0 / 45.0, k1), (-56.0 / 15.0, k2), (32.0 / 9.0, k3)]));
            let k5 = deriv(a, axpy(y0, h, &[(19372.0 / 6561.0, k1), (-25360.0 / 2187.0, k2), (64448.0 / 6561.0, k3), (-212.0 / 729.0, k4)]));
            let k6 = deriv(
                a,
                axpy(y0, h, &[(9017.0 / 3168.0, k1), (-355.0 / 33.0, k2), (46732.0 / 5247.0, k3), (49.0 / 176.0, k4), (-5103.0 / 18656.0, k5)]),
            );
            let y1 = axpy(y0, h, &[(35.0 / 384.0, k1), (500.0 / 1113.0, k3), (125.0 / 192.0, k4), (-2187.0 / 6784.0, k5), (11.0 / 84.0, k6)]);
            let k7 = deriv(a, y1);
            let e = axpy(
                [0.0, 0.0],
                h,
                &[(71.0 / 57600.0, k1), (-71.0 / 16695.0, k3), (71.0 / 1920.0, k4), (-17253.0 / 339200.0, k5), (22.0 / 525.0, k6), (-1.0 / 40.0, k7)],
            );
            let err = ((0..2)
                .map(|i| (e[i] / (self.atol + self.rtol * y0[i].abs().max(y1[i].abs()))).powi(2))
                .sum::<f64>()
                / 2.0)
                .sqrt();
            let factor = if err > 0.0 { (0.9 * err.powf(-0.2)).clamp(0.2, 5.0) } else { 5.0 };
            if err <= 1.0 || h <= 1e-14 * t0.abs().max(1.0) {
                if h >= self.h.min(self.max_step) * 0.999 || factor < 1.0 {
                    self.h = (h * factor).min(self.max_step);
                }
                return Step { t0, h, y0, f0: k1, y1, f1: k7 };
            }
            self.h = h * factor;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut dp = Dopri::new(1e-10, 1e-10, 1.0);
        let (mut t, mut y, mut trials) = (0.0, [1.0, 0.0], 0);
        while t < 2.0 {
            let s = dp.step(&a, t, y, 2.0 - t, &mut trials);
            t += s.h;
            y = s.y1;
        }
        assert!((y[0] - 2f64.cos()).abs() < 1e-8, "{}", y[0] - 2f64.cos());
        // dense output and root: cos t = 0 at π/2
        let s = rk4(&a, 1.5, [1.5f64.cos(), -(1.5f64).sin()], 0.1);
        let theta = s.root(|y| y[0]);
        assert!((1.5 + 0.1 * theta - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
    }
}
