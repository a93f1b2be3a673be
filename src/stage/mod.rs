//! The stages, one module each: a typed request in, a typed result out (what the stage computed
//! and the paths it wrote). A stage parses no arguments and prints nothing: it checks its request
//! (each refusal one line naming the value, [`crate::blame`]), runs, reports through the
//! [`Control`] it is given (a progress sink, and a cancel token asked between chunks of work)
//! and returns. The command line ([`crate::cli`]) parses flags into a request, calls the stage
//! and prints its result; the Python package calls the same stages in-process.
//!
//! | stage | request → result |
//! |---|---|
//! | [`simulate`] | a scenario (a sweep too) → dataset part files |
//! | [`analyze`] | a dataset → the analysis tables |
//! | [`figures`] | an analysis → the paper's figures |
//! | [`report`] | dataset, analysis, figures → one HTML page and its Markdown twin |
//! | [`reproduce`] | a scenario → the four above, in order |
//! | [`tradeoff`] | a scenario → the solvers' speed/accuracy table |
//! | [`sensitivity`] | a scenario with random keys → Sobol indices |
//! | [`exact_law`] | a scenario → the long-run law and Table 1 without sampling |
//! | [`predict`] | a scenario and a state → the next stick |

pub mod analyze;
pub mod exact_law;
mod failure;
pub mod figures;
pub mod predict;
pub mod report;
pub mod reproduce;
mod request;
pub mod sensitivity;
pub mod simulate;
pub mod tradeoff;

/// Every table a stage writes, with the stage that writes it: the one list the generated
/// reference documents (`tests/it/docs_reference.rs`).
pub fn tables() -> Vec<(&'static str, &'static crate::table::Def)> {
    let mut out: Vec<(&'static str, &'static crate::table::Def)> = Vec::new();
    out.extend([("simulate", &crate::simulation::trajectory::samples::DEF), ("simulate", &crate::simulation::trajectory::events::DEF)]);
    out.extend(crate::analysis::tables::ALL.map(|d| ("analyze", d)));
    out.push(("analyze", &crate::analysis::sweep::sweep::DEF));
    out.push(("tradeoff", &crate::tradeoff::tradeoff_table::DEF));
    out.push(("sensitivity", &crate::sensitivity::sobol::DEF));
    out.extend(crate::law::defs::ALL.map(|d| ("exact-law", d)));
    out.extend([("predict", &crate::predict::prediction::DEF), ("predict", &crate::predict::STICK_SURVIVAL), ("predict", &crate::predict::DENSITIES)]);
    out
}

pub use crate::blame::{Culprit, Usage};
pub use crate::progress::{Cancelled, Control, Progress, Silent};
pub use crate::scenario::{Input, Source};
pub use failure::{cancelled, culprit, exit_code, message, INPUT_AT_FAULT, RUN_FAILED};
