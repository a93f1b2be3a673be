//! Validation of a typed scenario — every key in its range, every distribution's support inside
//! its key's, the combinations — and the scene it describes.

use super::spec::Param;
use super::types::{
    invalid, shown_list, shown_param, Scenario, ScenarioError, DURATION_RANGE, MAX_EXPECTED_SWITCHES, MAX_NATURAL_RADIANS, MAX_NATURAL_RADIANS_NUMERICAL,
    MAX_POSITION, MAX_REALIZATIONS, MAX_TRAJECTORY_SAMPLES,
};
use crate::observables::SEVERITY_BOUND;
use crate::physics::{FrictionLaw, Law, Params, Stribeck};
use crate::shown::short;
use crate::simulation::belt::{Belt, Process, MAX_SPEED};
use crate::simulation::keys::{Key, Scene};
use crate::simulation::plan::fastest_rate;
use crate::solver::SolverKind;

impl Scenario {
    /// Whether the scene's slips have closed forms, as the law answers ([`FrictionLaw::has_closed_forms`];
    /// μ_s is μ_k for every realization when `static_friction_coefficient` is absent).
    pub fn has_closed_forms(&self) -> bool {
        self.model.friction_law.unwrap_or(FrictionLaw::Coulomb).has_closed_forms(self.model.static_friction_coefficient.is_none())
    }

    /// Whether this is the paper's physical scene — its oscillator, friction, belt, initial
    /// conditions and window, whatever the seed, the number of realizations, the solver or the
    /// output: the scene the paper's Table 1 describes, and so the only one compared with it.
    /// Keys spelled out at their paper values (`damping = 0`, `viscous_friction = 0`, `friction_law = "coulomb"`, μ_s equal
    /// to μ_k) still are the paper's scene.
    pub fn is_paper_scene(&self) -> bool {
        self.same_scene(&Scenario::paper())
    }

    /// Whether `other` describes the same physical scene — oscillator, friction, belt, initial
    /// conditions and window — whatever the seed, size, solver or output; keys spelled out at
    /// their defaults (a zero dashpot, μ_s = μ_k, the Coulomb law) are the same as absent.
    pub fn same_scene(&self, other: &Scenario) -> bool {
        fn canonical(m: &super::spec::ModelSpec) -> super::spec::ModelSpec {
            let mut m = m.clone();
            for zero_is_absent in [&mut m.damping, &mut m.viscous_friction] {
                if *zero_is_absent == Some(Param::Value(0.0)) {
                    *zero_is_absent = None;
                }
            }
            if m.static_friction_coefficient.as_ref() == Some(&m.friction_coefficient) {
                m.static_friction_coefficient = None;
            }
            if m.friction_law == Some(crate::physics::FrictionLaw::Coulomb) {
                m.friction_law = None;
            }
            if m.friction_law.is_none() {
                (m.stribeck_velocity, m.stribeck_exponent) = (None, None);
            }
            m
        }
        // (the process as inferred: `process = "symmetric"` spelled out is the default belt)
        let belt = |s: &Scenario| super::spec::BeltSpec { process: Some(s.process_name()), ..s.belt.clone() };
        canonical(&self.model) == canonical(&other.model)
            && belt(self) == belt(other)
            && self.initial_conditions == other.initial_conditions
            && self.run.duration == other.run.duration
            && self.chain == other.chain
            && self.anchor == other.anchor
    }

    /// The solver that actually runs: `auto` is `exact` where the scene has closed forms, else
    /// `rk45` at the `[numerics]` tolerances.
    pub fn solver(&self) -> SolverKind {
        match self.run.solver {
            SolverKind::Auto if self.has_closed_forms() => SolverKind::Exact,
            SolverKind::Auto => SolverKind::Rk45,
            other => other,
        }
    }

    /// The scene every realization is drawn from: fixed parameters, random keys, the belt.
    pub fn scene(&self) -> Result<Scene, ScenarioError> {
        let m = &self.model;
        let value = |p: &Param| match p {
            Param::Value(x) => *x,
            Param::Random(d) => d.mean(),
            Param::Sweep(l) => l[0],
        };
        let kinetic = value(&m.friction_coefficient);
        let mut params = Params {
            mass: value(&m.mass),
            stiffness: value(&m.stiffness),
            damping: m.damping.as_ref().map_or(0.0, value),
            normal_force: value(&m.normal_force),
            kinetic,
            static_: m.static_friction_coefficient.as_ref().map_or(kinetic, value),
            viscous: m.viscous_friction.as_ref().map_or(0.0, value),
            law: match m.friction_law.unwrap_or(FrictionLaw::Coulomb) {
                FrictionLaw::Coulomb => Law::Coulomb,
                // (v_s is required with the law: `check` refuses its absence)
                FrictionLaw::Stribeck => Law::Stribeck(Stribeck {
                    velocity: m.stribeck_velocity.as_ref().map_or(f64::NAN, value),
                    exponent: m.stribeck_exponent.as_ref().map_or(2.0, value),
                }),
            },
        };
        let chain = self.chain_scene(&mut params, &value)?;
        let process = self.process(value)?;
        let belt = Belt { process, initial_sign: self.belt.initial_sign.0, duration: self.run.duration };
        let random = Key::ALL
            .into_iter()
            .filter_map(|k| match self.param(k) {
                Some(Param::Random(d)) => Some((k, *d)),
                _ => None,
            })
            .collect();
        let scene = Scene::new(params, belt, random, m.static_friction_coefficient.is_none());
        Ok(match chain {
            Some(c) => scene.with_chain(c),
            None => scene,
        })
    }

    /// The mean λ t_a of the Poisson number of belt switches: the paper's symmetric belt at a
    /// fixed rate only (None otherwise).
    pub fn poisson_mean(&self) -> Option<f64> {
        if self.process_name() != super::spec::ProcessName::Symmetric {
            return None;
        }
        let scene = self.scene().ok()?;
        let random_rate = scene.random.iter().any(|(k, _)| *k == Key::SwitchRate);
        match &scene.belt.process {
            Process::Symmetric(p) if !random_rate => Some(p.switch_rate * self.run.duration),
            _ => None,
        }
    }

    /// The largest [`fastest_rate`] a realization may have, and the rule that sets it:
    /// rate·t_a ≤ [`MAX_NATURAL_RADIANS`] (exact; [`MAX_NATURAL_RADIANS_NUMERICAL`] for a
    /// numerical solver), and for rk4 rate·step ≤ 1 (RK4 loses accuracy past 1 and is unstable
    /// past 2.8; the rule then names `numerics.step`). Checked at the door on the fixed values
    /// and the finite ends of every distribution, and per draw ([`crate::simulation::ensemble`]).
    pub fn max_rate(&self) -> (f64, String, Option<&'static str>) {
        let radians = if self.solver() == SolverKind::Exact { MAX_NATURAL_RADIANS } else { MAX_NATURAL_RADIANS_NUMERICAL };
        let horizon = radians / self.run.duration;
        let rk4 = if self.solver() == SolverKind::Rk4 { 1.0 / self.numerics.step } else { f64::INFINITY };
        if rk4 < horizon {
            (rk4, format!("rk4 needs it times numerics.step to be at most 1 (numerics.step = {})", short(self.numerics.step)), Some("numerics.step"))
        } else {
            let solver = if radians == MAX_NATURAL_RADIANS { "" } else { " for a numerical solver" };
            (horizon, format!("it times run.duration must be at most {radians:e} radians{solver} (run.duration = {} s)", short(self.run.duration)), None)
        }
    }

    /// Every check: each key in its range, each distribution's support inside its key's range,
    /// and the combinations (μ_s ≥ μ_k for every draw, finite ratios, budgets).
    pub fn check(&self) -> Result<(), ScenarioError> {
        for key in Key::ALL {
            if let Some(p) = self.param(key) {
                check_param(key, p)?;
            }
        }
        let (lo_s, _) = self.model.static_friction_coefficient.as_ref().map_or((f64::INFINITY, 0.0), support);
        let (_, hi_k) = support(&self.model.friction_coefficient);
        if let Some(static_) = self.model.static_friction_coefficient.as_ref().filter(|_| lo_s < hi_k) {
            return Err(invalid(
                "model.static_friction_coefficient",
                &shown_param(static_),
                &format!(
                    "must be >= model.friction_coefficient for every draw (the smallest possible is {}, the largest friction_coefficient {})",
                    short(lo_s),
                    short(hi_k)
                ),
            ));
        }
        let law = self.model.friction_law.unwrap_or(FrictionLaw::Coulomb);
        if law == FrictionLaw::Stribeck && self.model.stribeck_velocity.is_none() {
            return Err(invalid("model.stribeck_velocity", "(absent)", "the Stribeck law needs v_s > 0 (m/s)"));
        }
        if law != FrictionLaw::Stribeck {
            if let Some(key) = Key::ALL.into_iter().find(|&k| k.info().used_by == "stribeck" && self.param(k).is_some()) {
                return Err(invalid(key.dotted(), "(set)", "only the Stribeck law uses it: set model.friction_law = \"stribeck\" too"));
            }
        }
        if self.run.solver == SolverKind::Exact && !self.has_closed_forms() {
            return Err(invalid(
                "model.friction_law",
                "\"stribeck\"",
                "has no closed-form slip, so run.solver = \"exact\" cannot run it: use \"auto\" (rk45) or a numerical solver",
            ));
        }
        let r = &self.run;
        if !(r.duration >= DURATION_RANGE.0 && r.duration <= DURATION_RANGE.1) {
            return Err(invalid(
                "run.duration",
                &short(r.duration),
                &format!("must be between {} and {} (s), the range the solvers are proven on", bound(DURATION_RANGE.0), bound(DURATION_RANGE.1)),
            ));
        }
        if r.realizations == 0 || r.realizations > MAX_REALIZATIONS {
            return Err(invalid("run.realizations", &r.realizations.to_string(), &format!("must be between 1 and {MAX_REALIZATIONS}")));
        }
        if r.seed > i64::MAX as u64 {
            return Err(invalid("run.seed", &r.seed.to_string(), &format!("must be at most {}", i64::MAX)));
        }
        for (key, [lo, hi]) in
            [("initial_conditions.position", self.initial_conditions.position), ("initial_conditions.velocity", self.initial_conditions.velocity)]
        {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi && (hi - lo).is_finite()) {
                return Err(invalid(key, &format!("[{}, {}]", short(lo), short(hi)), "must be [lo, hi] with finite lo <= hi and a finite width hi - lo"));
            }
        }
        let n = &self.numerics;
        for (key, x, unit) in [
            ("numerics.rtol", n.rtol, ""),
            ("numerics.atol", n.atol, ""),
            ("numerics.max_step", n.max_step, " (s)"),
            ("numerics.step", n.step, " (s)"),
            ("numerics.epsilon", n.epsilon, " (m/s)"),
            ("numerics.stick_velocity", n.stick_velocity, " (m/s)"),
            ("output.trajectory_step", self.output.trajectory_step, " (s)"),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(invalid(key, &short(x), &format!("must be > 0{unit} and finite")));
            }
        }
        if n.step_budget == 0 {
            return Err(invalid("numerics.step_budget", "0", "must be an integer >= 1"));
        }
        self.check_derived()
    }

    /// Checks on combinations of keys, at the extremes of every random key's support where
    /// they are finite (a draw of an unbounded law that still overflows a ratio is refused per
    /// realization, naming it).
    fn check_derived(&self) -> Result<(), ScenarioError> {
        let scene = self.scene()?;
        if let (Some(_), None) = (&self.chain, &scene.chain) {
            // a one-mass chain on a fixed anchor is [model]'s oscillator: its checks, on its values
            let mut one = self.clone();
            one.chain = None;
            (one.model.mass, one.model.stiffness, one.model.damping) =
                (Param::Value(scene.params.mass), Param::Value(scene.params.stiffness), Some(Param::Value(scene.params.damping)));
            return one.check_derived();
        }
        self.check_belt_changes(&scene.belt.process)?;
        self.check_chain(scene.chain.as_ref(), &scene.belt.process)?;
        let (m_lo, m_hi) = self.param(Key::Mass).map_or((1.0, 1.0), bounded);
        let hi = |k: Key| self.param(k).map_or(0.0, |p| bounded(p).1);
        // (the slip's damping per unit mass is (c + σ_v)/m)
        let ratios =
            [hi(Key::Stiffness) / m_lo, (hi(Key::Damping) + hi(Key::Viscous)) / m_lo, hi(Key::NormalForce) * hi(Key::Static).max(hi(Key::Kinetic)) / m_lo];
        if ratios.iter().any(|r| !r.is_finite()) || !(m_hi > 0.0) {
            return Err(ScenarioError::Invalid {
                key: "model".into(),
                value: format!("k/m up to {:e} 1/s², (c + sigma_v)/m up to {:e} 1/s, mu n/m up to {:e} m/s²", ratios[0], ratios[1], ratios[2]),
                reason: "these ratios must be finite".into(),
            });
        }
        if scene.chain.is_none() {
            // (a chain's swing is bounded by the writers' guard, per realization)
            self.check_initial_state(&scene, ratios[0].sqrt())?;
        }
        let o = &self.output;
        if o.trajectories > 1000 || o.trajectories as f64 * self.run.duration / o.trajectory_step > MAX_TRAJECTORY_SAMPLES {
            return Err(ScenarioError::Invalid {
                key: "output.trajectories".into(),
                value: o.trajectories.to_string(),
                reason: format!(
                    "at most 1000 trajectories and {MAX_TRAJECTORY_SAMPLES:e} samples in all (run.duration / output.trajectory_step = {:e} each)",
                    self.run.duration / o.trajectory_step
                ),
            });
        }
        // ω·t_a and rk4's stability, before any realization runs (unbounded laws: per draw)
        let num = &self.numerics;
        let solver = self.solver();
        let fixed = matches!(solver, SolverKind::Rk4 | SolverKind::Moreau);
        let damping_key = if hi(Key::Viscous) > hi(Key::Damping) { Key::Viscous } else { Key::Damping };
        let (rate, rate_key, symbol) = fastest_rate(solver != SolverKind::Exact, ratios[0].sqrt(), ratios[1], damping_key);
        let (max_rate, rule, step_key) = self.max_rate();
        if rate > max_rate {
            let key = step_key.unwrap_or(rate_key.dotted());
            let value = match (key, self.param(rate_key)) {
                ("numerics.step", _) => short(num.step),
                (_, Some(p)) => shown_param(p),
                (_, None) => short(Params::PAPER.stiffness),
            };
            return Err(invalid(key, &value, &format!("with model.mass, {symbol} reaches {rate:e} 1/s: {rule}, so it may be at most {max_rate:e} 1/s")));
        }
        let least_steps = self.run.duration / if fixed { num.step } else { num.max_step };
        if matches!(solver, SolverKind::Rk45 | SolverKind::Dop853 | SolverKind::Rk4 | SolverKind::Moreau) && least_steps > num.step_budget as f64 {
            let key = if fixed { "numerics.step" } else { "numerics.max_step" };
            return Err(invalid(
                key,
                &short(if fixed { num.step } else { num.max_step }),
                &format!("run.duration needs at least {least_steps:e} steps, over numerics.step_budget = {}", num.step_budget),
            ));
        }
        let (forward, reverse) = (hi(Key::SwitchRate), hi(Key::ReverseSwitchRate));
        let (key, rate) = if reverse > forward { ("belt.reverse_switch_rate", reverse) } else { ("belt.switch_rate", forward) };
        let expected = rate * self.run.duration;
        if !(expected <= MAX_EXPECTED_SWITCHES) {
            return Err(invalid(
                key,
                &short(rate),
                &format!("switch rate × run.duration = {expected:e} expected belt switches per realization; at most {MAX_EXPECTED_SWITCHES:e} are supported"),
            ));
        }
        Ok(())
    }
}

impl Scenario {
    /// The initial state against what it implies: |ẋ0| ≤ [`MAX_SPEED`] and |x0| ≤
    /// [`MAX_POSITION`] (the solvers square velocities and amplitudes: ẋ0 = 1e150 overflowed v² in
    /// the arrival test, x0 = 1e308 the spring force);
    /// and the severity it implies within what the analysis takes: the mass velocity stays within
    /// about U = |ẋ0| + ω|x0| + (the belt's top speed) while friction only brakes a mass faster
    /// than the belt, so the severity (max ẋ − min ẋ)/(2 v0) is about U/v0 at most, which must
    /// not exceed [`SEVERITY_BOUND`] (v0 the belt's speed scale, its least value when drawn). A
    /// realization past the bound all the same is refused by the writers' guard, naming it.
    fn check_initial_state(&self, scene: &crate::simulation::keys::Scene, omega: f64) -> Result<(), ScenarioError> {
        let ic = &self.initial_conditions;
        let largest = |r: [f64; 2]| r[0].abs().max(r[1].abs());
        let (x, v) = (largest(ic.position), largest(ic.velocity));
        let shown = |r: [f64; 2]| format!("[{}, {}]", short(r[0]), short(r[1]));
        if !(v <= MAX_SPEED) {
            return Err(invalid(
                "initial_conditions.velocity",
                &shown(ic.velocity),
                &format!("|Ẋ0| must be at most {MAX_SPEED:e} m/s, the range the solvers are proven on"),
            ));
        }
        if !(x <= MAX_POSITION) {
            return Err(invalid(
                "initial_conditions.position",
                &shown(ic.position),
                &format!("|X0| must be at most {MAX_POSITION:e} m, the range the solvers are proven on"),
            ));
        }
        // The severity ≈ (the initial swing + the breakaway swing)/v0 + (the belt's top speed)/v0:
        // the belt's own part is a ratio per draw (1 for the symmetric belt, whose speed is both;
        // v_r/v_f at most for the telegraph belt), the swings are over the least scale v0 a draw
        // may have (a drawn speed at its least value, or its mean where the law is unbounded: a
        // draw past the bound is refused per realization, naming it). A stick held up to the
        // static limit and released slips about the kinetic centre: the velocity swing grows by
        // ω (c_s − c_k) = (μ_s − μ_k) n/(m ω) (tests/it/trust.rs has the scene that showed it).
        let process = &scene.belt.process;
        let (mut scale, top) = (scene.belt.scale(), process.top_speed(self.run.duration));
        let belt_ratio = match process {
            Process::Symmetric(_) => 1.0,
            Process::Telegraph(_) => {
                let forward = self.param(Key::Speed).map_or(scale, |p| bounded(p).0);
                (top.max(self.param(Key::ReverseSpeed).map_or(0.0, |p| bounded(p).1)) / forward).max(1.0)
            }
            _ => top / scale,
        };
        if matches!(process, Process::Symmetric(_) | Process::Telegraph(_)) {
            scale = scale.min(self.param(Key::Speed).map_or(scale, |p| bounded(p).0));
        }
        let hi = |k: Key| self.param(k).map_or(0.0, |p| bounded(p).1);
        let normal_per_mass = hi(Key::NormalForce) / self.param(Key::Mass).map_or(1.0, |p| bounded(p).0);
        let kinetic_lo = self.param(Key::Kinetic).map_or(0.0, |p| bounded(p).0);
        let excess = self.model.static_friction_coefficient.as_ref().map_or(0.0, |p| (bounded(p).1 - kinetic_lo).max(0.0));
        let breakaway = if omega > 0.0 { excess * normal_per_mass / omega } else { 0.0 };
        let swing = v + omega * x + breakaway;
        let severity = swing / scale + belt_ratio;
        if !(severity <= SEVERITY_BOUND) {
            return Err(invalid(
                "initial_conditions",
                &format!("position = {}, velocity = {}", shown(ic.position), shown(ic.velocity)),
                &format!(
                    "with the belt's speed scale v0 = {} m/s the mass may swing at |Ẋ0| + ω|X0| + (μ_s − μ_k) n/(m ω) = {} m/s, a severity up to {:.3e}; the analysis takes severities up to {SEVERITY_BOUND:e}: narrow the initial conditions, speed up the belt or narrow μ_s − μ_k",
                    short(scale),
                    short(swing),
                    severity
                ),
            ));
        }
        Ok(())
    }
}

/// The least and greatest value a key can take where they are finite and (the least) positive,
/// else the law's mean: what the door's derived checks use (a draw of an unbounded law past
/// them is refused per realization).
pub(super) fn bounded(p: &Param) -> (f64, f64) {
    let (lo, hi) = support(p);
    let mean = match p {
        Param::Random(d) => d.mean(),
        _ => lo,
    };
    (if lo > 0.0 && lo.is_finite() { lo } else { mean }, if hi.is_finite() { hi } else { mean })
}

/// The smallest and largest value a key can take: the number, or the distribution's support
/// (a sweep's extremes).
fn support(p: &Param) -> (f64, f64) {
    match p {
        Param::Value(x) => (*x, *x),
        Param::Sweep(l) => l.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x))),
        Param::Random(d) => d.support(),
    }
}

/// One key's value or distribution against the key's range ([`Key::range`]).
fn check_param(key: Key, p: &Param) -> Result<(), ScenarioError> {
    let (lo, hi) = key.range();
    let unit = key.unit();
    let ok = |x: f64| x >= lo && x <= hi;
    let range = format!("between {} and {}{unit}, the range the solvers are proven on", bound(lo), bound(hi));
    match p {
        Param::Value(x) => {
            if !ok(*x) {
                let finite = if x.is_finite() { "" } else { "finite and " };
                return Err(invalid(key.dotted(), &short(*x), &format!("must be {finite}{range}")));
            }
        }
        Param::Sweep(list) => {
            if let Some(x) = list.iter().find(|x| !ok(**x)) {
                return Err(invalid(key.dotted(), &shown_list(list), &format!("the value {} must be {range}", short(*x))));
            }
        }
        Param::Random(d) => {
            d.check().map_err(|reason| invalid(key.dotted(), &shown_param(p), &reason))?;
            if let crate::simulation::keys::Dist::Uniform { low, high } = *d {
                if !(ok(low) && ok(high)) {
                    return Err(invalid(
                        key.dotted(),
                        &shown_param(p),
                        &format!("the distribution can draw from {} to {}, but the key must be {range}", short(low), short(high)),
                    ));
                }
            } else if d.truncated() && !ok(d.mean()) {
                return Err(invalid(key.dotted(), &shown_param(p), &format!("a normal is truncated to the key's range; its mean must lie in it ({range})")));
            }
            let share = d.share_in((lo, hi));
            if !(share >= d.min_share()) {
                let shown = shown_share(share);
                // (a share just below the threshold must not print as the threshold)
                let shown = if shown.parse::<f64>().is_ok_and(|x| x >= d.min_share()) { format!("{share:.9}") } else { shown };
                return Err(invalid(
                    key.dotted(),
                    &shown_param(p),
                    &format!(
                        "only {shown} of this law lies {range} (draws outside are drawn again): at least {} % must; narrow the law",
                        d.min_share() * 100.0
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A range end for a message: `0`, `0.3`, `1e-6`, `1e9`.
fn bound(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A probability for a message: `0.13`, `2.1e-9`, `< 1e-300`.
fn shown_share(p: f64) -> String {
    if !p.is_finite() {
        "an unknown share (it could not be computed)".into()
    } else if p < 1e-300 {
        "< 1e-300".into()
    } else if p < 1e-3 {
        format!("{p:.1e}")
    } else {
        format!("{:.3}", p)
    }
}
