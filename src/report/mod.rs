//! The `report` stage: one self-contained HTML page (figures inlined as SVG) and a Markdown twin.
//!
//! Contents: provenance of the run, our Table 1 beside the paper's with a 95 % interval on every
//! statistic and every cell marked, S_T and S_L, the growth regressions and renewal check, the
//! independence tests, and every figure. A cell is marked ✓ when the paper's value lies inside our
//! 95 % interval (jackknife, [`crate::analysis::jackknife`]) widened by half a unit of the paper's
//! last printed decimal (the paper gives no errors and rounds to 2–3 decimals), ✗ otherwise, with
//! the relative difference; a cell whose interval is approximate (the moments table's
//! `skewness_approximate`, `kurtosis_approximate`) is shown with ≈, not judged. (An analysis without intervals, from an older stickslip, falls back to
//! three standard errors for the mean and the variance.)

mod error;
mod exact;
mod page;
mod tails;
mod write;

pub use error::ReportError;
pub use page::escape;
pub use write::{check_replaceable, run};
