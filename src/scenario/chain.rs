//! The `[chain]` and `[anchor]` keys → a chain scene ([`crate::chain`]): the masses, springs and
//! dashpots, the anchor's process, and the checks a chain needs.
//!
//! | key | meaning |
//! |---|---|
//! | `chain.masses` | m_1 … m_N [kg], 1 ≤ N ≤ [`MAX_MASSES`] |
//! | `chain.stiffnesses` | k_1 … k_N [N/m] (k_1 ties m_1 to the anchor) |
//! | `chain.dampings` | c_1 … c_N [N·s/m] (absent: zeros) |
//! | `anchor.speed` | U [m/s], any sign (absent: 0, the paper's fixed wall); may be random |
//! | `anchor.process = "markov"` | `anchor.velocities`, `anchor.rates`: the belt's Markov semantics |
//! | `anchor.process = "recorded"` | `anchor.file`: the belt's log format |
//!
//! `[chain]` replaces `model.mass`, `model.stiffness` and `model.damping`: setting both is
//! refused (a value other than the paper's default counts as set). `[anchor]` without `[chain]`
//! moves the anchor of `[model]`'s one mass. A one-mass chain on a fixed anchor *is* `[model]`'s
//! oscillator and runs its closed forms (the same rows).

use std::path::Path;
use std::sync::Arc;

use super::spec::{AnchorProcess, Param};
use super::types::{invalid, shown_list, Scenario, ScenarioError};
use crate::chain::rate as chain_rate;
use crate::physics::{FrictionLaw, Params};
use crate::shown::short;
use crate::simulation::belt::{Belt, InitialSign, Markov, Process, Recorded, MAX_SPEED, MIN_SPEED};
use crate::simulation::keys::{ChainScene, Key};
use crate::solver::SolverKind;

/// Most masses in a chain.
pub const MAX_MASSES: usize = 64;

/// Largest accepted Ω·t_a of a chain (Ω its fastest rate, [`chain_rate`]): the exact chain
/// solver takes one step per 1/‖Ã‖_D of the window (‖Ã‖_D a small multiple of Ω), so its steps
/// grow with Ω·t_a.
pub const MAX_CHAIN_RADIANS: f64 = 1e6;

impl Scenario {
    /// The chain of the scene, if it has one: `[chain]`, or `[model]`'s one mass under a moving
    /// `[anchor]` (None: the one mass on a fixed wall, whose closed forms run; a one-mass
    /// `[chain]` on a fixed anchor sets `params`' mass, stiffness and damping instead).
    pub(super) fn chain_scene(&self, params: &mut Params, value: &impl Fn(&Param) -> f64) -> Result<Option<ChainScene>, ScenarioError> {
        if self.chain.is_none() && self.anchor.is_none() {
            return Ok(None);
        }
        let anchor = self.anchor_process(value)?;
        let (masses, stiffnesses, dampings) = match &self.chain {
            Some(c) => {
                self.refuse_model_keys()?;
                let n = c.masses.len();
                let dampings = c.dampings.clone().unwrap_or_else(|| vec![0.0; n]);
                for (key, list) in [("chain.masses", &c.masses), ("chain.stiffnesses", &c.stiffnesses), ("chain.dampings", &dampings)] {
                    if list.len() != n || n == 0 || n > MAX_MASSES {
                        return Err(invalid(key, &shown_list(list), &format!("needs one value per mass, 1 to {MAX_MASSES} masses (chain.masses has {n})")));
                    }
                }
                for (key, list, k) in
                    [("chain.masses", &c.masses, Key::Mass), ("chain.stiffnesses", &c.stiffnesses, Key::Stiffness), ("chain.dampings", &dampings, Key::Damping)]
                {
                    let (lo, hi) = k.range();
                    if let Some(x) = list.iter().find(|x| !(lo..=hi).contains(*x)) {
                        return Err(invalid(
                            key,
                            &shown_list(list),
                            &format!("{} lies outside [{lo:e}, {hi:e}]{}, the range the solvers are proven on", short(*x), k.unit()),
                        ));
                    }
                }
                (c.masses.clone(), c.stiffnesses.clone(), dampings)
            }
            None => (vec![params.mass], vec![params.stiffness], vec![params.damping]),
        };
        if masses.len() == 1 && anchor.process == Process::Constant(0.0) && self.param(Key::AnchorSpeed).is_none_or(|p| matches!(p, Param::Value(_))) {
            (params.mass, params.stiffness, params.damping) = (masses[0], stiffnesses[0], dampings[0]);
            return Ok(None);
        }
        Ok(Some(ChainScene { masses, stiffnesses, dampings, anchor, from_model: self.chain.is_none() }))
    }

    /// `[chain]` replaces the one mass's keys: refuse them set beside it.
    fn refuse_model_keys(&self) -> Result<(), ScenarioError> {
        let paper = &super::types::paper_typed().model;
        for (key, set) in [
            ("model.mass", self.model.mass != paper.mass),
            ("model.stiffness", self.model.stiffness != paper.stiffness),
            ("model.damping", self.model.damping.is_some()),
        ] {
            if set {
                return Err(invalid(key, "(set)", "[chain] gives the masses, stiffnesses and dampings: set them there, not in [model]"));
            }
        }
        Ok(())
    }

    /// The anchor's velocity process.
    fn anchor_process(&self, value: &impl Fn(&Param) -> f64) -> Result<Belt, ScenarioError> {
        let a = self.anchor.clone().unwrap_or_default();
        let name = a.process.unwrap_or(AnchorProcess::Constant);
        let uses = |key: &str, set: bool, by: AnchorProcess, by_name: &str| {
            if set && name != by {
                Err(invalid(key, "(set)", &format!("only anchor.process = \"{by_name}\" uses it")))
            } else {
                Ok(())
            }
        };
        uses("anchor.speed", a.speed.is_some(), AnchorProcess::Constant, "constant")?;
        uses("anchor.velocities", a.velocities.is_some(), AnchorProcess::Markov, "markov")?;
        uses("anchor.rates", a.rates.is_some(), AnchorProcess::Markov, "markov")?;
        uses("anchor.file", a.file.is_some(), AnchorProcess::Recorded, "recorded")?;
        let levels = |key: &str, shown: &str, v: &[f64]| match v.iter().find(|v| !(v.abs() <= MAX_SPEED)) {
            Some(x) => Err(invalid(
                key,
                shown,
                &format!("holds {}: a level must be finite and at most {MAX_SPEED:e} m/s in size, the range the solvers are proven on", short(*x)),
            )),
            None => Ok(()),
        };
        let process = match name {
            AnchorProcess::Constant => Process::Constant(a.speed.as_ref().map_or(0.0, value)),
            AnchorProcess::Markov => {
                let (Some(velocities), Some(rates)) = (&a.velocities, &a.rates) else {
                    let missing = if a.velocities.is_none() { "anchor.velocities" } else { "anchor.rates" };
                    return Err(invalid(missing, "(absent)", "the markov anchor needs anchor.velocities (m/s) and anchor.rates (1/s, an n×n matrix)"));
                };
                levels("anchor.velocities", &shown_list(velocities), velocities)?;
                let m = Markov::new(velocities.clone(), rates.clone()).map_err(|e| invalid("anchor.rates", "(the matrix)", &e.replace("belt.", "anchor.")))?;
                let (_, max_rate) = Key::SwitchRate.range();
                if m.leave_rates().iter().any(|r| *r > max_rate) {
                    return Err(invalid(
                        "anchor.rates",
                        "(the matrix)",
                        &format!("a level is left at more than {max_rate:e} 1/s, the range the solvers are proven on"),
                    ));
                }
                Process::Markov(Arc::new(m))
            }
            AnchorProcess::Recorded => {
                let Some(file) = &a.file else {
                    return Err(invalid(
                        "anchor.file",
                        "(absent)",
                        "the recorded anchor needs anchor.file, a CSV or Parquet file with columns time (s) and velocity (m/s)",
                    ));
                };
                let (times, velocities) = super::belt::read_log(Path::new(file)).map_err(|e| invalid("anchor.file", &format!("{file:?}"), &e))?;
                levels("anchor.file", &format!("{file:?}"), &velocities)?;
                Process::Recorded(Arc::new(Recorded::new(times, velocities).map_err(|e| invalid("anchor.file", &format!("{file:?}"), &e))?))
            }
        };
        let anchor = Belt { process, initial_sign: InitialSign::Positive, duration: self.run.duration };
        let expected = anchor.expected_switches();
        if !(expected <= super::types::MAX_EXPECTED_SWITCHES) {
            return Err(invalid(
                "anchor",
                "(the process)",
                &format!("{expected:e} velocity changes per realization; at most {:e} are supported", super::types::MAX_EXPECTED_SWITCHES),
            ));
        }
        Ok(anchor)
    }

    /// What a chain scene needs of the rest: the exact solver, Coulomb friction, Ω·t_a within
    /// [`MAX_CHAIN_RADIANS`], and something that slides (the anchor and the belt not both
    /// constant at the same velocity). A constant belt without a chain must move.
    pub(super) fn check_chain(&self, chain: Option<&ChainScene>, belt: &Process) -> Result<(), ScenarioError> {
        let Some(c) = chain else {
            if let Process::Constant(v) = belt {
                if v.abs() < MIN_SPEED {
                    return Err(invalid(
                        "belt.velocity",
                        &short(*v),
                        "a belt at rest under a fixed anchor moves nothing: give the anchor a speed ([anchor] speed) or the belt one",
                    ));
                }
            }
            return Ok(());
        };
        if !matches!(self.run.solver, SolverKind::Exact | SolverKind::Auto) {
            return Err(invalid(
                "run.solver",
                &format!("\"{}\"", self.run.solver.name()),
                "a chain of masses or a moving anchor runs the exact chain solver only (the numerical solvers do not take chains yet): use \"exact\" or \"auto\"",
            ));
        }
        if self.model.friction_law.unwrap_or(FrictionLaw::Coulomb) != FrictionLaw::Coulomb {
            return Err(invalid(
                "model.friction_law",
                "\"stribeck\"",
                "a chain's exact solver runs Coulomb friction (with the viscous term); the Stribeck law needs a numerical solver, which does not take chains yet",
            ));
        }
        let viscous = self.param(Key::Viscous).map_or(0.0, |p| super::check::bounded(p).1);
        let rate = chain_rate(&c.masses, &c.stiffnesses, &c.dampings, viscous);
        let radians = rate * self.run.duration;
        if !(radians <= MAX_CHAIN_RADIANS) {
            // (the dampings name it when the springs alone stay within the limit)
            let springs = chain_rate(&c.masses, &c.stiffnesses, &vec![0.0; c.masses.len()], 0.0) * self.run.duration;
            let (key, list) = if springs <= MAX_CHAIN_RADIANS { ("chain.dampings", &c.dampings) } else { ("chain.stiffnesses", &c.stiffnesses) };
            return Err(invalid(
                key,
                &shown_list(list),
                &format!(
                    "with chain.masses and chain.dampings the fastest rate is {rate:e} 1/s; times run.duration it must be at most {MAX_CHAIN_RADIANS:e} radians (the chain solver's steps grow with it)"
                ),
            ));
        }
        let top = |p: &Process| p.top_speed(self.run.duration);
        let anchor_top = top(&c.anchor.process).max(self.param(Key::AnchorSpeed).map_or(0.0, |p| super::check::bounded(p).1.abs()));
        if anchor_top < MIN_SPEED && top(belt) < MIN_SPEED {
            return Err(invalid("anchor", "(the process)", "neither the anchor nor the belt ever moves: nothing slides, so the severity has no unit"));
        }
        if let (Process::Constant(u), Process::Constant(v)) = (&c.anchor.process, belt) {
            if (u - v).abs() < MIN_SPEED && self.param(Key::AnchorSpeed).is_none_or(|p| matches!(p, Param::Value(_))) {
                return Err(invalid(
                    "anchor.speed",
                    &short(*u),
                    &format!("is within {MIN_SPEED:e} m/s of belt.velocity = {}: nothing slides, so the severity has no unit", short(*v)),
                ));
            }
        }
        Ok(())
    }
}
