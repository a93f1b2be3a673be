//! Why `analyze` failed.

use std::path::PathBuf;

use super::input::InputError;
use crate::progress::Cancelled;

/// Why `analyze` failed.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// The dataset could not be found or failed its checks.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Reading the part files failed (in the polars scan, or the rows read disagree with the
    /// footers).
    #[error("reading {}: {message}", path.display())]
    Read {
        /// the file (the dataset's first when the error names none)
        path: PathBuf,
        /// what went wrong
        message: String,
    },
    /// Writing an output file into ADIR failed.
    #[error("writing {}: {message}", path.display())]
    Write {
        /// the file written
        path: PathBuf,
        /// what went wrong
        message: String,
    },
    /// The options cannot work (`Options::check`, or a pair the dataset lacks the columns for).
    #[error("{0}")]
    Options(String),
    /// The output directory could not be staged or replaced.
    #[error(transparent)]
    Out(#[from] crate::outdir::OutDirError),
    /// The caller cancelled the run (Ctrl-C in a Python session).
    #[error("interrupted")]
    Cancelled(#[from] Cancelled),
}

impl crate::blame::Blame for AnalysisError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            AnalysisError::Input(_) | AnalysisError::Read { .. } => Some(crate::blame::Culprit::Dataset),
            AnalysisError::Options(_) => Some(crate::blame::Culprit::Usage),
            AnalysisError::Out(o) => o.blame(),
            AnalysisError::Write { .. } | AnalysisError::Cancelled(_) => None,
        }
    }
}
