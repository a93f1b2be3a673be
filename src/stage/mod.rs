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

pub use crate::blame::{Culprit, Usage};
pub use crate::progress::{Cancelled, Control, Progress, Silent};
pub use crate::scenario::{Input, Source};
pub use failure::{cancelled, culprit, exit_code, message};
