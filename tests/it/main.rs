//! Integration tests: one binary, one module per kind of check.

mod common;

mod analysis;
mod belts;
mod chain;
mod chain_reference;
mod cli;
mod closed_forms;
mod coverage;
mod dataset;
mod determinism;
mod docs_blocks;
mod docs_links;
mod docs_reference;
mod extremes;
mod figures;
mod fingerprint;
mod invariants;
mod law;
mod observables;
mod pinned;
mod pipelines;
mod precision;
mod predict;
mod python_types;
mod reference;
mod safety;
mod scenes;
mod sensitivity;
mod solvers;
mod stribeck;
mod tails;
mod trust;
mod viscous;
