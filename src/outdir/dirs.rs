//! Directories an output is written into: the ones a run creates (removed again unless kept),
//! a dataset directory added to part by part, a staged directory swapped in whole, and the top
//! directory of `reproduce`.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::error::*;
use super::files::{Lock, TempFile};
use super::marker::*;
use super::names::*;
use super::rules::*;
use crate::interrupt;

/// The directories a run created for an output (its missing ancestors, created one by one):
/// removed again, innermost first and only while empty, when the guard is dropped without
/// [`Created::keep`] or the run is interrupted ([`crate::interrupt`]).
#[derive(Debug, Default)]
pub struct Created {
    dirs: Vec<PathBuf>,
    kept: bool,
}

impl Created {
    /// Create `dir` and its missing ancestors (a directory a concurrent writer creates first is
    /// not counted as ours).
    pub fn dir_all(dir: &Path) -> Result<Created, OutDirError> {
        let mut missing = Vec::new();
        let mut p = Some(dir);
        while let Some(q) = p.filter(|q| !q.as_os_str().is_empty() && std::fs::symlink_metadata(q).is_err()) {
            missing.push(q.to_owned());
            p = q.parent();
        }
        let mut created = Created::default();
        for m in missing.iter().rev() {
            match std::fs::create_dir(m) {
                Ok(()) => {
                    interrupt::register_created(m);
                    created.dirs.push(m.clone());
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && m.is_dir() => {}
                Err(e) => return Err(fail(m, e)),
            }
        }
        Ok(created)
    }

    /// Keep the directories.
    pub fn keep(mut self) {
        self.kept = true;
    }
}

impl Drop for Created {
    fn drop(&mut self) {
        for dir in self.dirs.iter().rev() {
            if !self.kept {
                let _ = std::fs::remove_dir(dir); // only succeeds if empty
            }
            interrupt::unregister_created(dir);
        }
    }
}

/// A dataset directory being written into: it exists (created if needed), it is marked as a
/// dataset (or lies inside one), and nothing the run created survives a failure.
#[derive(Debug)]
pub struct DatasetDir {
    dir: PathBuf,
    created: Created,
    marked: bool,
    committed: bool,
}

impl DatasetDir {
    /// Prepare `dir` for new part files: refused if it holds anything but a stickslip dataset.
    pub fn prepare(dir: &Path, inputs: &[&Path]) -> Result<DatasetDir, OutDirError> {
        check_separate(dir, "--out", inputs)?;
        let mut d = DatasetDir { dir: dir.to_owned(), created: Created::default(), marked: false, committed: false };
        match std::fs::symlink_metadata(dir) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => d.created = Created::dir_all(dir)?,
            Err(e) => return Err(fail(dir, e)),
            Ok(m) if !m.is_dir() => return Err(refuse(dir, "--out exists and is not a directory; choose another --out")),
            Ok(_) => {}
        }
        let inside_dataset = dir.ancestors().any(|a| !a.as_os_str().is_empty() && is_marked(a, Kind::Dataset));
        if !inside_dataset {
            // (a concurrent simulate may have marked it since: a complete marker saying "dataset")
            if !is_empty_dir(dir).map_err(|e| fail(dir, e))? && !is_marked(dir, Kind::Dataset) {
                let why = match read_marker(dir) {
                    Some(m) => format!("holds a stickslip {}, not a dataset", m.kind),
                    None => format!("is not empty and is not a stickslip dataset (no {DATASET_MARKER})"),
                };
                return Err(refuse(dir, format!("--out {why}; simulate adds part files only to a dataset directory: choose another --out")));
            }
            match if is_marked(dir, Kind::Dataset) { Err(fail(dir, std::io::Error::other("marked"))) } else { write_marker(dir, Kind::Dataset, Vec::new()) } {
                Ok(()) => {
                    d.marked = true;
                    interrupt::register_marker(&dir.join(DATASET_MARKER));
                }
                // a concurrent shard marked it first
                Err(_) if is_marked(dir, Kind::Dataset) => {}
                Err(e) => return Err(e),
            }
        }
        Ok(d)
    }

    /// Keep what was created.
    pub fn commit(mut self) {
        self.committed = true;
        std::mem::take(&mut self.created).keep();
    }
}

impl Drop for DatasetDir {
    fn drop(&mut self) {
        let marker = self.dir.join(DATASET_MARKER);
        if self.marked {
            interrupt::unregister_created(&marker);
        }
        if self.committed {
            return;
        }
        // Remove only what this run created, and only while nothing else was put there (the
        // created directories go when `self.created` drops, after this).
        if self.marked {
            interrupt::remove_lone_marker(&marker);
        }
    }
}

/// A staging directory for an output directory `target` of `kind`, swapped in whole by
/// [`StagedDir::commit`]; removed on failure, panic or signal, `target` untouched.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    target: PathBuf,
    kind: Kind,
    flag: String,
    committed: bool,
    _lock: Lock,
    /// the target's missing ancestors, kept on commit
    parents: Created,
}

impl StagedDir {
    /// Check `target` (flag `flag`) against the rules and the `inputs`, lock it, and stage.
    pub fn new(target: &Path, kind: Kind, flag: &str, inputs: &[&Path]) -> Result<StagedDir, OutDirError> {
        check_separate(target, flag, inputs)?;
        let name = name_of(target)?;
        let parent = parent_of(target);
        let parents = Created::dir_all(parent)?;
        let lock = Lock::acquire(target)?;
        check_replaceable(target, kind, flag)?;
        let staging = parent.join(hidden(&name, &format!("tmp-{}", unique())));
        interrupt::register(&staging);
        if let Err(e) = std::fs::create_dir(&staging).and_then(|()| create_new(&staging.join(STAGING)).map(drop)) {
            let _ = std::fs::remove_dir_all(&staging);
            interrupt::unregister(&staging);
            return Err(fail(target, e));
        }
        Ok(StagedDir { staging, target: target.to_owned(), kind, flag: flag.into(), committed: false, _lock: lock, parents })
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Mark the staged directory and swap it in for `target` (checked again: a file put into
    /// `target` meanwhile stops the swap).
    pub fn commit(mut self) -> Result<(), OutDirError> {
        std::fs::remove_file(self.staging.join(STAGING)).map_err(|e| fail(&self.target, e))?;
        let files = files_below(&self.staging).map_err(|e| fail(&self.target, e))?;
        write_marker(&self.staging, self.kind, files)?;
        check_replaceable(&self.target, self.kind, &self.flag)?;
        let old = parent_of(&self.target).join(hidden(&name_of(&self.target)?, &format!("old-{}", unique())));
        let had_old = self.target.exists();
        // the replaced directory's permissions carry over (a user's `chmod 555` output stays so)
        let permissions = std::fs::metadata(&self.target).ok().map(|m| m.permissions());
        if had_old {
            interrupt::register(&old);
            std::fs::rename(&self.target, &old).map_err(|e| fail(&self.target, e))?;
        }
        if let Err(e) = std::fs::rename(&self.staging, &self.target) {
            if had_old {
                let _ = std::fs::rename(&old, &self.target);
                interrupt::unregister(&old);
            }
            return Err(fail(&self.target, e));
        }
        self.committed = true;
        if let Some(p) = permissions {
            let _ = std::fs::set_permissions(&self.target, p);
        }
        std::mem::take(&mut self.parents).keep();
        interrupt::unregister(&self.staging);
        sync_dir(parent_of(&self.target));
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
            interrupt::unregister(&old);
        }
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            interrupt::unregister(&self.staging);
        }
    }
}

/// The top directory of `reproduce`, prepared: what the run created there (the directory and its
/// marker) is removed again if it fails or is interrupted before [`ReproduceDir::keep`].
#[derive(Debug)]
pub struct ReproduceDir {
    created: Created,
    marker: Option<PathBuf>,
    kept: bool,
}

impl ReproduceDir {
    /// Keep the directory.
    pub fn keep(mut self) {
        self.kept = true;
        std::mem::take(&mut self.created).keep();
    }
}

impl Drop for ReproduceDir {
    fn drop(&mut self) {
        if let Some(m) = &self.marker {
            interrupt::unregister_created(m);
            if !self.kept {
                interrupt::remove_lone_marker(m);
            }
        }
    }
}

/// Prepare the top directory of `reproduce`: new, empty, or a previous `reproduce` output.
pub fn prepare_reproduce(dir: &Path, inputs: &[&Path]) -> Result<ReproduceDir, OutDirError> {
    check_separate(dir, "--out", inputs)?;
    let mut created = Created::default();
    if dir.exists() {
        if !dir.is_dir() {
            return Err(refuse(dir, "--out exists and is not a directory; choose another --out"));
        }
        if is_marked(dir, Kind::Reproduce) {
            return Ok(ReproduceDir { created, marker: None, kept: false });
        }
        if !is_empty_dir(dir).map_err(|e| fail(dir, e))? {
            return Err(refuse(dir, format!("--out is not empty and is not a stickslip reproduce output (no {MARKER}); choose another --out")));
        }
    } else {
        created = Created::dir_all(dir)?;
    }
    write_marker(dir, Kind::Reproduce, Vec::new())?;
    let marker = dir.join(MARKER);
    interrupt::register_marker(&marker);
    Ok(ReproduceDir { created, marker: Some(marker), kept: false })
}

/// Write a new file at `path`: refused if anything is there (a file the user asked for, never a
/// replacement); written atomically (a temporary renamed into place), its missing directories
/// created.
pub fn write_new_file(path: &Path, bytes: &[u8], flag: &str) -> Result<(), OutDirError> {
    let created = match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(dir) => Created::dir_all(dir)?,
        None => Created::default(),
    };
    let _lock = Lock::acquire(path)?;
    if std::fs::symlink_metadata(path).is_ok() {
        return Err(refuse(path, format!("{flag} exists; refusing to replace it: choose another {flag}")));
    }
    let (tmp, mut file) = TempFile::create(path)?;
    file.write_all(bytes).and_then(|()| file.sync_all()).map_err(|e| fail(path, e))?;
    drop(file);
    // a hard link fails if a file appeared meanwhile: never replace one
    let final_path = tmp.path().to_owned();
    std::fs::hard_link(&tmp.tmp, &final_path).map_err(|e| fail(path, e))?;
    drop(tmp);
    sync_dir(parent_of(path));
    created.keep();
    Ok(())
}
