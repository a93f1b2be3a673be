//! The simulate path, in the order its layers depend on each other: [`rng`] (the named portable
//! generator and its sub-streams) and [`belt`] (belt processes → velocity segments) and [`keys`]
//! (the table of scene keys, their distributions, the scene drawn per realization) → [`plan`]
//! (what a run is, resolved from a scenario above) → [`events`]
//! (what a realization records) → [`ensemble`] (one realization from (seed, index)) →
//! [`trajectory`] (sampled paths) and [`precision`] (targets on standard errors) → [`dataset`]
//! (the Parquet rows) → [`simulate`] (the stage: threads, shards, sweeps, commit).

pub mod belt;
pub mod columns;
pub mod dataset;
pub mod ensemble;
pub mod events;
pub mod keys;
pub mod plan;
pub mod precision;
pub(crate) mod rng;
pub mod schema;
pub mod simulate;
pub(crate) mod trajectory;
pub(crate) mod writeback;
