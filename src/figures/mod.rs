//! The `figures` stage: the paper's figures from the analysis tables (never by re-simulating).
//!
//! Each figure is first built as data ([`Figure`] of [`Panel`]s: bars, lines, points, heat cells),
//! then drawn by [`render`] to PNG and SVG. Files, named after the paper's figure numbers:
//! `fig02_poisson_pmf`, `fig04_trajectories` (when the dataset sampled trajectories), `fig05_q`,
//! `fig06_y` (when it stored switch times), `fig07_variance_growth`, `fig08_counts`, `fig09_t`,
//! `fig10_l`, `fig11_t1_t2`, `fig12_d`, `fig13_d1_d2`, `fig14_h`.

pub(crate) mod chart;
pub(crate) mod contour;
mod draw;
mod error;
pub(crate) mod exact;
pub(crate) mod format;
mod inputs;
mod paper;
pub mod render;
pub(crate) mod tails;
mod trajectory;

pub use chart::{Figure, Panel, Series};
pub use draw::run;
pub use error::FigureError;
pub use inputs::Inputs;
pub use paper::*;
pub use trajectory::Trajectory;
