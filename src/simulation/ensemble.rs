//! Monte Carlo over realizations: each realization is a pure function of (scenario, index).
//!
//! Realization `i` draws, from its own stream `realization_rng(seed, i)` and in this order:
//! X0 ~ U[lo, hi], Ẋ0 ~ U[lo, hi] (one 53-bit uniform each), then the belt path
//! ([`Belt::sample_into`]); each random scene key draws from its own sub-stream
//! ([`crate::simulation::keys`]), so the belt and initial conditions do not depend on which keys are random.
//! A chain ([`crate::chain`]) draws its contact mass's X0, Ẋ0 as above (so its belt is the
//! one-mass scene's), the other masses' x_i(0), ẋ_i(0) in order i = 1 … N − 1 from the
//! sub-stream [`CHAIN_INITIAL_PURPOSE`], and its anchor's path from [`ANCHOR_PURPOSE`].
//! Chunks of consecutive indices are the unit of parallel work; the chunk length depends only on
//! the scenario, so the rows — and the bytes written — are the same for any number of threads or
//! shards.

use crate::chain::{Chain, ChainExact, ChainSummary};
use crate::physics::{Params, PerUnitMass};
use crate::simulation::belt::{Belt, BeltPath};
use crate::simulation::events::{Observer, Record};
use crate::simulation::keys::{ChainScene, Scene};
use crate::simulation::plan::Plan;
use crate::simulation::rng::{realization_rng, substream, unit_f64, ANCHOR_PURPOSE, CHAIN_INITIAL_PURPOSE};
use crate::simulation::trajectory::{Sampler, Tee};
use crate::solver::{Drive, SolveError, Solver};

/// A realization that could not be solved.
#[derive(Debug, thiserror::Error)]
#[error("realization {realization}: {source}")]
pub struct RunError {
    /// the realization's index
    pub realization: u64,
    /// why the solver failed
    pub source: SolveError,
}

/// One simulated realization.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// X0, the initial position [m]
    pub x0: f64,
    /// Ẋ0, the initial velocity [m/s]
    pub xdot0: f64,
    /// the belt's velocity path
    pub belt: BeltPath,
    /// the counted events and the extremes of the motion
    pub record: Record,
    /// The drawn values of the scene's random keys ([`Scene::columns`] order).
    pub drawn: Vec<f64>,
    /// The oscillator of this realization (the fixed scene with the drawn values).
    pub params: Params,
    /// Integration steps the solver attempted (0 for `exact`).
    pub steps: u64,
    /// the window t_a, s
    pub t_a: f64,
    /// the belt's speed scale (drawn, when it is random), m/s: the severity's unit
    /// ([`crate::simulation::belt::Process::scale`])
    pub speed_scale: f64,
    /// what a chain's realization adds to its row (None: one mass)
    pub chain: Option<ChainSummary>,
    switches: Vec<f64>,
    velocities: Vec<f64>,
}

impl Outcome {
    /// The effective belt switches (see [`BeltPath::segments`]).
    pub fn switches(&self) -> &[f64] {
        &self.switches
    }

    /// The belt velocity of each segment.
    pub fn velocities(&self) -> &[f64] {
        &self.velocities
    }
}

/// A scenario ready to run.
#[derive(Debug, Clone)]
pub struct Ensemble {
    scene: Scene,
    position: [f64; 2],
    velocity: [f64; 2],
    seed: u64,
    store_switch_times: bool,
    solver: Solver,
    /// the scene per unit mass when no key is random (computed once)
    physics: PerUnitMass,
    /// the rate rule a drawn realization must meet ([`Plan::max_rate`]): the largest rate,
    /// the rule, and whether the solver is numerical (its rate counts c/m too)
    max_rate: (f64, String, bool),
}

impl Ensemble {
    /// Prepare the run `plan`: its scene and solver.
    pub fn new(plan: &Plan) -> Ensemble {
        let scene = plan.scene.clone();
        Ensemble {
            position: plan.position,
            velocity: plan.velocity,
            seed: plan.seed,
            store_switch_times: plan.switch_times,
            solver: Solver::new(plan.solver, plan.numerics, scene.damped()),
            physics: scene.params.per_unit_mass(),
            max_rate: (plan.max_rate.0, plan.max_rate.1.clone(), plan.solver != crate::solver::SolverKind::Exact),
            scene,
        }
    }

    /// The scene the realizations are drawn from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Simulate realization `index` into `out` (its buffers are reused).
    pub fn realization(&self, index: u64, out: &mut Outcome) -> Result<(), RunError> {
        self.run(index, &[], out, &mut ())
    }

    /// A realization whose belt and initial conditions are those of realization `intrinsic` and
    /// whose j-th random key is that of realization `params_from[j]` (the pick-freeze design of
    /// `sensitivity`; every draw has its own sub-stream, so the mix is exact).
    pub fn realization_mixed(&self, intrinsic: u64, params_from: &[u64], out: &mut Outcome) -> Result<(), RunError> {
        self.run(intrinsic, params_from, out, &mut ())
    }

    /// Simulate realization `index` and sample its trajectory every `step` seconds.
    pub fn trajectory(&self, index: u64, step: f64, out: &mut Outcome) -> Result<Sampler, RunError> {
        let mut sampler = Sampler::new(step);
        self.run(index, &[], out, &mut sampler)?;
        Ok(sampler)
    }

    /// Simulate realization `index`, counting into `out.record` and also showing `extra` the motion.
    fn run<O: Observer>(&self, index: u64, params_from: &[u64], out: &mut Outcome, extra: &mut O) -> Result<(), RunError> {
        let mut rng = realization_rng(self.seed, index);
        let uniform = |r: [f64; 2], u: f64| r[0] + (r[1] - r[0]) * u;
        out.x0 = uniform(self.position, unit_f64(&mut rng));
        out.xdot0 = uniform(self.velocity, unit_f64(&mut rng));
        let mut physics = self.physics;
        // the scene's belt, or a copy with drawn keys (a chain's tables are shared, not copied)
        let drawn_belt;
        let mut belt = &self.scene.belt;
        let mut drawn_anchor = None;
        out.params = self.scene.params;
        if !self.scene.random.is_empty() {
            match self.scene.draw(self.seed, |j| params_from.get(j).copied().unwrap_or(index), &mut out.params, &mut out.drawn) {
                Ok((b, a)) => {
                    drawn_belt = b;
                    belt = &drawn_belt;
                    drawn_anchor = a;
                }
                Err(key) => {
                    let drawn = format!("{}: 10,000 draws in a row outside its range", key.dotted());
                    return Err(RunError { realization: index, source: SolveError::Drawn { drawn } });
                }
            }
            physics = out.params.per_unit_mass();
            if ![physics.omega2, physics.gamma, physics.viscous, physics.kinetic, physics.breakaway].iter().all(|x| x.is_finite()) {
                let values = self.scene.columns().iter().zip(&out.drawn).map(|(k, x)| format!("{k} = {x:e}")).collect::<Vec<_>>().join(", ");
                let drawn = format!("{values} give non-finite k/m, c/m, sigma_v/m or mu n/m");
                return Err(RunError { realization: index, source: SolveError::Drawn { drawn } });
            }
            let (max_rate, rule, numerical) = &self.max_rate;
            let (rate, _, symbol) =
                crate::simulation::plan::fastest_rate(*numerical, physics.omega2.sqrt(), physics.slip_damping(), crate::simulation::keys::Key::Damping);
            if rate > *max_rate {
                let p = &out.params;
                let drawn = format!(
                    "model.stiffness = {:e} N/m, model.damping = {:e} N·s/m, model.viscous_friction = {:e} N·s/m, model.mass = {:e} kg give {symbol} = {rate:e} 1/s, but {rule}",
                    p.stiffness, p.damping, p.viscous, p.mass
                );
                return Err(RunError { realization: index, source: SolveError::Drawn { drawn } });
            }
        }
        belt.sample_into(&mut rng, &mut out.belt);
        out.belt.segments(&mut out.switches, &mut out.velocities);
        let drive = Drive { velocities: &out.velocities, switches: &out.switches, t_end: belt.duration };
        out.record.clear();
        (out.t_a, out.speed_scale, out.chain) = (belt.duration, belt.scale(), None);
        out.steps = match &self.scene.chain {
            None => self.solver.solve(&physics, &drive, out.x0, out.xdot0, &mut Tee(&mut out.record, extra)),
            Some(chain) => {
                let anchor = drawn_anchor.as_ref().unwrap_or(&chain.anchor);
                self.chain(index, (chain, anchor), &drive, &out.params, (out.x0, out.xdot0), &mut Tee(&mut out.record, extra)).map(|(steps, scale, summary)| {
                    (out.speed_scale, out.chain) = (scale, Some(summary));
                    steps
                })
            }
        }
        .map_err(|source| RunError { realization: index, source })?;
        out.record.finish(belt.duration);
        if let Some((column, x)) = out.chain.iter().flat_map(crate::simulation::columns::chain_values).find(|(_, x)| !x.is_finite()) {
            return Err(RunError { realization: index, source: SolveError::Unwritable { column, value: crate::shown::short(x), rule: "a finite number" } });
        }
        if let Some((column, x, rule)) = out.record.outside(out.t_a, out.record.severity(out.speed_scale)) {
            return Err(RunError { realization: index, source: SolveError::Unwritable { column, value: crate::shown::short(x), rule } });
        }
        Ok(())
    }

    /// Solve realization `index` of the chain scene `chain` (with its anchor's process, drawn)
    /// under `drive` for the friction of `p`, from the contact mass's state `start`; returns the
    /// steps (0), the mean |u − v| over [0, t_a] (what slides: the severity's unit) and what the
    /// realization adds to its row.
    fn chain<O: Observer>(
        &self,
        index: u64,
        (chain, anchor): (&ChainScene, &Belt),
        drive: &Drive<'_>,
        p: &Params,
        start: (f64, f64),
        obs: &mut O,
    ) -> Result<(u64, f64, ChainSummary), SolveError> {
        let (masses, stiffnesses, dampings) = if chain.from_model {
            (vec![p.mass], vec![p.stiffness], vec![p.damping])
        } else {
            (chain.masses.clone(), chain.stiffnesses.clone(), chain.dampings.clone())
        };
        let n = masses.len();
        let ch = Chain { masses, stiffnesses, dampings, kinetic: p.kinetic * p.normal_force, breakaway: p.static_ * p.normal_force, viscous: p.viscous };
        let mut rng = substream(self.seed, index, CHAIN_INITIAL_PURPOSE);
        let uniform = |r: [f64; 2], u: f64| r[0] + (r[1] - r[0]) * u;
        let (mut x0, mut xd0) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n - 1 {
            x0[i] = uniform(self.position, unit_f64(&mut rng));
            xd0[i] = uniform(self.velocity, unit_f64(&mut rng));
        }
        (x0[n - 1], xd0[n - 1]) = start;
        let mut path = BeltPath::default();
        anchor.sample_into(&mut substream(self.seed, index, ANCHOR_PURPOSE), &mut path);
        let mut a = crate::chain::Anchor::default();
        path.segments(&mut a.switches, &mut a.velocities);
        let scale = crate::chain::mean_slide((drive.velocities, drive.switches), (&a.velocities, &a.switches), drive.t_end);
        let mut method = ChainExact::new(&ch, &a, &x0, &xd0, drive.t_end);
        let steps = crate::solver::drive(&mut method, drive, start.0, start.1, u64::MAX, obs)?;
        Ok((steps, scale, method.summary()))
    }

    /// Whether the scene is a chain (its rows have the chain's columns).
    pub fn has_chain(&self) -> bool {
        self.scene.chain.is_some()
    }

    /// Whether rows keep the belt switch instants (`output.switch_times`).
    pub fn store_switch_times(&self) -> bool {
        self.store_switch_times
    }

    /// Realizations per chunk: about 2^18 list values per chunk (≈ 1,000 paper realizations:
    /// few, large batches for the Parquet encoder), at most 8192 rows.
    pub fn chunk_len(&self) -> u64 {
        let per_realization = 4.0 * self.scene.belt.expected_switches() + 64.0;
        (262_144.0 / per_realization).clamp(1.0, 8192.0) as u64
    }

    /// Room to reserve per realization in each event list: half a value per expected belt change,
    /// and 4 (the paper scene: 29 for 16.6 sticks and as many slips on average). A scene with
    /// more events per change grows its lists once; reserved memory that is never written is
    /// not resident unless the allocator hands out memory an earlier chunk had touched.
    pub(crate) fn list_len_hint(&self) -> usize {
        (0.5 * self.scene.belt.expected_switches()).ceil() as usize + 4
    }
}
