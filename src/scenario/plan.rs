//! The scenario resolved into the run plan the simulate path takes
//! ([`crate::simulation::plan::Plan`]).

use super::types::{Scenario, ScenarioError};
use crate::simulation::ensemble::Ensemble;
use crate::simulation::plan::Plan;

impl Scenario {
    /// The run plan (an error when the scene cannot be built).
    pub fn plan(&self) -> Result<Plan, ScenarioError> {
        let (rate, rule, _) = self.max_rate();
        Ok(Plan {
            scene: self.scene()?,
            position: self.initial_conditions.position,
            velocity: self.initial_conditions.velocity,
            solver: self.solver(),
            numerics: self.numerics,
            seed: self.run.seed,
            realizations: self.run.realizations,
            max_rate: (rate, rule),
            switch_times: self.output.switch_times,
            trajectories: self.output.trajectories,
            trajectory_step: self.output.trajectory_step,
            scenario_toml: self.to_toml(),
            belt_file: self.belt.file.clone(),
        })
    }

    /// The ensemble of the run plan: realizations ready to simulate.
    pub fn ensemble(&self) -> Result<Ensemble, ScenarioError> {
        Ok(Ensemble::new(&self.plan()?))
    }
}
