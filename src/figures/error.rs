//! Why `figures` failed.

use std::path::PathBuf;

/// Why `figures` failed.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// An analysis table or `summary.json` could not be read.
    #[error("reading {}: {message}", path.display())]
    Read {
        /// the file
        path: PathBuf,
        /// what went wrong
        message: String,
    },
    /// A figure could not be drawn or written.
    #[error("drawing {name}: {message}")]
    Draw {
        /// the figure (or the sweep cell's directory)
        name: String,
        /// what went wrong
        message: String,
    },
    /// The output directory could not be staged or replaced.
    #[error(transparent)]
    Out(#[from] crate::outdir::OutDirError),
}

impl crate::blame::Blame for FigureError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        match self {
            FigureError::Read { .. } => Some(crate::blame::Culprit::Dataset),
            FigureError::Out(o) => o.blame(),
            FigureError::Draw { .. } => None,
        }
    }
}
