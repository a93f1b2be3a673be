//! stickslip — stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.
//!
//! Reproduces and extends R. Lima and R. Sampaio, "Analysis of a dry-friction oscillator driven
//! by a stochastic base motion" (Monte Carlo study of stick and slip instants and durations).
//!
//! Dependencies point one way:
//! [`model`] → [`excitation`] → [`solver`] → [`events`] → [`ensemble`] → [`dataset`] →
//! [`simulate`] → [`analysis`] → [`figures`] → [`report`], with [`scenario`] loading and validating input and [`cli`] on top.

pub mod analysis;
pub mod cli;
pub mod dataset;
pub mod ensemble;
pub mod events;
pub mod excitation;
pub mod figures;
pub mod interrupt;
pub mod model;
pub mod outdir;
pub mod report;
pub mod rng;
pub mod scenario;
pub mod simulate;
pub mod solver;
pub mod tradeoff;
pub mod trajectory;
