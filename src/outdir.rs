//! Output directories that appear only when complete.
//!
//! A stage writes into a hidden sibling `.NAME.tmp-PID`; [`StagedDir::commit`] moves any previous
//! `NAME` aside, renames the staging directory into place and deletes the old one. If the stage
//! fails (or panics) before committing, the staging directory is removed and `NAME` is untouched.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {message}", path.display())]
pub struct OutDirError {
    pub path: PathBuf,
    pub message: String,
}

fn fail(path: &Path, e: impl std::fmt::Display) -> OutDirError {
    OutDirError { path: path.to_owned(), message: e.to_string() }
}

/// A staging directory for `target`.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl StagedDir {
    pub fn new(target: &Path) -> Result<StagedDir, OutDirError> {
        if target.is_file() {
            return Err(fail(target, "exists and is not a directory"));
        }
        let name = target.file_name().ok_or_else(|| fail(target, "not a directory name"))?.to_string_lossy().into_owned();
        let parent = target.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| fail(parent, e))?;
        let staging = parent.join(format!(".{name}.tmp-{}", std::process::id()));
        std::fs::create_dir_all(&staging).map_err(|e| fail(target, e))?;
        Ok(StagedDir { staging, target: target.to_owned(), committed: false })
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Move the staging directory into place.
    pub fn commit(mut self) -> Result<(), OutDirError> {
        let old = self.staging.with_file_name(format!(
            ".{}.old-{}",
            self.target.file_name().unwrap_or_default().to_string_lossy(),
            std::process::id()
        ));
        if self.target.exists() {
            std::fs::rename(&self.target, &old).map_err(|e| fail(&self.target, e))?;
        }
        std::fs::rename(&self.staging, &self.target).map_err(|e| fail(&self.target, e))?;
        self.committed = true;
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}
