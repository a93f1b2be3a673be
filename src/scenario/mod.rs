//! Scenario files: TOML in, a typed and validated [`Scenario`] out — every check happens here,
//! before a single realization runs.
//!
//! Resolution order: the embedded paper scenario (`pipelines/paper.toml`) ← the user's file (any
//! subset of keys) ← `--set key=value` overrides (TOML values) ← typed [`Overrides`]
//! (`--realizations`, `--seed`). The merged table is deserialized once into typed structs (serde,
//! unknown keys denied: a typo never silently keeps a default), then validated with every error
//! naming its key. Provenance is the typed value serialized back ([`Scenario::to_toml`]).
//!
//! Any numeric `[model]` or `[belt]` key is a [`Param`]: a number, a list of numbers (a sweep:
//! one cell per value, resolved by [`Scenario::resolve_sweep`]) or a distribution drawn per
//! realization ([`crate::simulation::keys`]).
//!
//! Files: `spec.rs` the typed sections; `types.rs` the [`Scenario`], its limits, overrides, sweep
//! cells and errors; `resolve.rs` merging, `--set`, typing and sweeps; `input.rs` where a stage's
//! scenario comes from; `belt.rs` the belt keys → the process; `chain.rs` the chain and anchor keys → the chain scene; `check.rs` validation and the
//! scene it describes; `plan.rs` the run plan. This file only declares and re-exports.

mod belt;
mod chain;
mod check;
mod input;
mod plan;
mod resolve;
mod spec;
mod types;

pub use crate::chain::rate as chain_rate;
pub use crate::shown::short;
pub use crate::simulation::plan::fastest_rate;
pub use crate::solver::Numerics;
pub use chain::{MAX_CHAIN_RADIANS, MAX_MASSES};
pub use input::{Input, Source};
pub use spec::{AnchorProcess, AnchorSpec, BeltSpec, ChainSpec, InitialConditions, ModelSpec, Output, Param, ParamSlot, ProcessName, Run, Sign};
pub use types::*;
