//! stickslip — stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.
//!
//! Reproduces and extends R. Lima and R. Sampaio, "Analysis of a dry-friction oscillator driven
//! by a stochastic base motion" (Monte Carlo study of stick and slip instants and durations).
//!
//! Dependencies point one way:
//! [`physics`] (parameters, friction law, equation of motion, stick/arrival/breakaway rules,
//! closed forms) → [`solver`] (one driver, the methods) → [`simulation`] (belt processes, scene
//! keys, events, ensemble, dataset, the simulate stage) → [`analysis`] → [`figures`] →
//! [`report`], with [`scenario`] loading and validating input and [`cli`] on top.

#![warn(missing_docs)]

pub mod analysis;
pub mod blame;
pub mod chain;
pub mod cli;
pub mod figures;
pub mod interrupt;
pub mod law;
pub(crate) mod metadata;
pub mod observables;
pub(crate) mod outdir;
pub mod physics;
pub mod predict;
pub mod progress;
pub mod report;
pub mod scenario;
pub mod scenes;
pub mod sensitivity;
pub(crate) mod shown;
pub mod simulation;
pub mod solver;
pub(crate) mod special;
pub mod stage;
pub(crate) mod stats;
pub mod table;
pub mod tradeoff;
