//! Why an output could not be prepared, replaced or written.

use std::path::{Path, PathBuf};

/// Why an output cannot be written. `refused` errors are the user's to fix (exit code 2);
/// the others are failures while running (exit code 1).
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct OutDirError {
    pub path: PathBuf,
    pub message: String,
    pub refused: bool,
}

impl crate::blame::Blame for OutDirError {
    fn blame(&self) -> Option<crate::blame::Culprit> {
        self.refused.then_some(crate::blame::Culprit::Output)
    }
}

pub(super) fn fail(path: &Path, e: impl std::fmt::Display) -> OutDirError {
    OutDirError { path: path.to_owned(), message: e.to_string(), refused: false }
}

pub(super) fn refuse(path: &Path, message: impl Into<String>) -> OutDirError {
    OutDirError { path: path.to_owned(), message: message.into(), refused: true }
}
