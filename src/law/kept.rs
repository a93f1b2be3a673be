//! The paths of the flow without a flip, and the chance that the belt keeps them: the point
//! masses of the laws [`super::densities`] inverts (the time to the next stick from a point,
//! the slip after a breakaway that sticks again).

use super::flow::{Frame, Slip, Visitor};
use super::passage::Start;

/// The flip-free path from a slip state to its first event, and the chance that the belt leaves
/// it unchanged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Path {
    /// whether it ends in a stick (else at the breakaway point, after which it goes on as the
    /// breakaway slip)
    pub stuck: bool,
    /// its duration [s]
    pub t: f64,
    /// the probability that the belt's flips leave it unchanged ([`path`])
    pub kept: f64,
}

/// The flip-free path of the flow from the slip state `z` in belt state `s` of `frames` (its
/// frame: the belt at +v_s; a flip leads to the next state, belt at −v_o) to its first event,
/// or none for a slip that never reaches belt speed (a periodic slip below it, or a spiral down
/// with a dashpot).
///
/// **Flips it does not see.** Coulomb friction depends on the sign of v_belt − V only, so a flip
/// while V > v_s or V < −v_o (the mass outruns both belt velocities, on one side) changes
/// nothing; what matters is the belt's state when V re-enters (−v_o, v_s). The path is kept
/// when no flip comes while −v_o < V < v_s and the belt is back in state s at the end of each
/// stretch outside it (of length τ: P_ss(τ) = (λ_o + λ_s e^{−(λ_s+λ_o)τ})/(λ_s + λ_o), the two
/// states' chain; (1 + e^{−2λτ})/2 for the symmetric belt):
///
/// ```text
///     kept = e^{−λ_s T_inside} Π_stretches P_ss(τ)
/// ```
///
/// (The paper's box with μ_s = 0.6 and λ = 1: the breakaway slip reaches V < −v0 for 0.415 of
/// its 2.726 s, and 0.0712 of the breakaways re-stick unchanged — 0.0716 ± 0.0012 in 47,638
/// breakaways simulated — where e^{−λ t} would say 0.0655.) Each sample of the walk (at most
/// w0·1e-5 long in the plane) counts inside or outside by its velocity (the paper's box with μ_s = 0.6:
/// 1.8e-7 relative from the closed form).
pub(crate) fn path(frames: &[Frame], s: usize, z: Slip) -> Option<Path> {
    struct Record {
        samples: Vec<(f64, f64)>,
        end: Option<(bool, f64)>,
    }
    impl Visitor for Record {
        fn slip(&mut self, _: f64, v: f64, _: f64, dt: f64, _: f64) {
            self.samples.push((v, dt));
        }
        fn periodic(&mut self, _: Slip, _: f64, _: f64, _: f64) {}
        fn stick(&mut self, _: f64, t: f64) {
            self.end.get_or_insert((true, t));
        }
        fn breakaway_slip(&mut self, t: f64, _: f64) {
            self.end.get_or_insert((false, t));
        }
    }
    let (f, o) = (frames[s], frames[(s + 1) % frames.len()]);
    let mut rec = Record { samples: Vec::new(), end: None };
    f.walk(z, 0.0, f.w0 * 1e-5, f64::INFINITY, &mut rec);
    let (stuck, t) = rec.end?;
    let (ls, lo) = (f.lambda, o.lambda);
    let back = |tau: f64| (lo + ls * (-(ls + lo) * tau).exp()) / (ls + lo);
    let (mut inside, mut kept, mut outside) = (0.0, 1.0, 0.0);
    for (v, dt) in rec.samples {
        if -o.v0 < v && v < f.v0 {
            kept *= back(outside);
            (inside, outside) = (inside + dt, 0.0);
        } else {
            outside += dt;
        }
    }
    kept *= back(outside) * (-ls * inside).exp();
    Some(Path { stuck, t, kept })
}

/// The breakaway slip's path in belt state s if it sticks again ([`path`] from (x_b, v_s)).
pub(crate) fn restick(frames: &[Frame], s: usize) -> Option<Path> {
    path(frames, s, frames[s].breakaway()).filter(|p| p.stuck)
}

/// The point mass of the time to the next stick from a `start` in belt state `at` (module docs):
/// (time, probability) — a slip's first stick, or its first touch of the breakaway point plus
/// the breakaway slip's re-stick; a stick's breakaway plus the re-stick — each path kept
/// ([`path`]; a stick is kept when no flip comes during it).
pub(crate) fn start_point(frames: &[Frame], at: usize, start: Start) -> Option<(f64, f64)> {
    let f = frames[at];
    let again = restick(frames, at);
    match start {
        Start::Stuck(x) => {
            let d = (f.hold_hi() - x).max(0.0) / f.v0;
            again.map(|r| (d + r.t, (-f.lambda * d).exp() * r.kept))
        }
        Start::Slip(z) => match path(frames, at, z)? {
            p if p.stuck => Some((p.t, p.kept)),
            p => again.map(|r| (p.t + r.t, p.kept * r.kept)),
        },
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The undamped breakaway slip (μ_s > μ_k): the circle about c_k of radius ρ from the angle
    /// φ_b = atan2(c_s − c_k, w0) clockwise to 2π − φ_b, where it meets belt speed at 2c_k − c_s
    /// after t_r = (2π − 2φ_b)/ω; below −v0 (W = ρ cos φ < −w0) for φ in (π − φ_b, π + φ_b),
    /// τ = 2φ_b/ω: kept with probability e^{−λ(t_r − τ)} (1 + e^{−2λτ})/2. (t_r, kept).
    pub(crate) fn kept_breakaway_slip(f: Frame) -> (f64, f64) {
        let phi_b = (f.cs - f.ck).atan2(f.w0);
        let (t_r, tau) = ((std::f64::consts::TAU - 2.0 * phi_b) / f.omega, 2.0 * phi_b / f.omega);
        (t_r, (-f.lambda * (t_r - tau)).exp() * (1.0 + (-2.0 * f.lambda * tau).exp()) / 2.0)
    }

    #[test]
    fn the_breakaway_slip_is_kept_through_the_flips_it_does_not_see() {
        // μ_s = 0.6, λ = 1 (the closed form above): 0.0712 — against 0.0716 ± 0.0012 of 47,638
        // breakaways simulated ([`path`]), and e^{−λ t_r} = 0.0655
        let sc = crate::scenario::Scenario::resolve(None, &["model.static_friction_coefficient=0.6".into(), "belt.switch_rate=1".into()]).unwrap();
        let frames = super::super::stationary::frames(&sc.scene().unwrap()).unwrap();
        let (t_r, kept) = kept_breakaway_slip(frames[0]);
        let got = restick(&frames, 0).unwrap();
        assert!((got.t - t_r).abs() < 1e-9 && (got.kept - kept).abs() < 2e-6 * kept, "{got:?} against {t_r}, {kept}");
        assert!((kept - 0.0712).abs() < 1e-4, "{kept}");
        // the paper's breakaway slip grazes the belt line: no re-stick
        let paper = super::super::stationary::frames(&crate::scenario::Scenario::resolve(None, &[]).unwrap().scene().unwrap()).unwrap();
        assert_eq!(restick(&paper, 0), None);
    }
}
