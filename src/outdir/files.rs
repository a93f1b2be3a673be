//! Files an output is written through: the per-output lock, the temporary renamed into place,
//! and whole files the tool writes or creates.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use super::error::*;
use super::names::*;
use super::rules::*;
use crate::interrupt;

/// An advisory lock on `.NAME.stickslip-lock` beside an output, released (and the lock file removed) on
/// drop or on SIGINT/SIGTERM; the lock file of a killed writer is simply taken over.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
    file: File,
}

impl Lock {
    /// Lock the output `target` (a directory or a file).
    pub fn acquire(target: &Path) -> Result<Lock, OutDirError> {
        let dir = parent_of(target);
        let path = dir.join(hidden(&name_of(target)?, "lock"));
        loop {
            let mut opts = OpenOptions::new();
            opts.read(true).write(true).create(true).truncate(false);
            #[cfg(unix)]
            std::os::unix::fs::OpenOptionsExt::custom_flags(&mut opts, libc::O_NOFOLLOW);
            let mut file = opts.open(&path).map_err(|e| fail(&path, e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    let mut holder = String::new();
                    let _ = file.read_to_string(&mut holder);
                    let holder = holder.trim();
                    let who = if holder.is_empty() { "another process".to_string() } else { format!("process {holder}") };
                    return Err(refuse(target, format!("is in use by {who} (lock {}); wait for it or choose another output", path.display())));
                }
                Err(std::fs::TryLockError::Error(e)) => return Err(fail(&path, e)),
            }
            // The holder before us may have removed the file between our open and our lock: the
            // lock counts only if the path still names the file we locked.
            if !same_file(&file, &path) {
                continue;
            }
            // A lock file holds nothing or a process id (a killed writer's, taken over): anything
            // else is a user's file with our name, never emptied or removed.
            let mut held = String::new();
            let ours = (&file).take(64).read_to_string(&mut held).is_ok() && held.bytes().all(|b| b.is_ascii_digit());
            if !ours {
                return Err(refuse(&path, "exists and is not a stickslip lock file; refusing to touch it: move it away or choose another output"));
            }
            use std::io::Seek;
            let _ =
                file.set_len(0).and_then(|()| file.seek(std::io::SeekFrom::Start(0))).and_then(|_| file.write_all(std::process::id().to_string().as_bytes()));
            interrupt::register(&path);
            remove_stale(dir, &name_of(target)?);
            return Ok(Lock { path, file });
        }
    }
}

#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

impl Drop for Lock {
    fn drop(&mut self) {
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
        interrupt::unregister(&self.path);
        let _ = self.file.unlock();
    }
}

/// A file written under a unique hidden temporary name beside `path` and renamed into place by
/// [`TempFile::commit`]; removed if dropped before (or on SIGINT/SIGTERM).
#[derive(Debug)]
pub struct TempFile {
    pub(super) tmp: PathBuf,
    path: PathBuf,
    committed: bool,
}

impl TempFile {
    /// Create the temporary file for `path`; the caller holds `path`'s [`Lock`].
    pub fn create(path: &Path) -> Result<(TempFile, File), OutDirError> {
        let tmp = parent_of(path).join(hidden(&name_of(path)?, &format!("tmp-{}", unique())));
        interrupt::register(&tmp);
        let file = create_new(&tmp).map_err(|e| {
            interrupt::unregister(&tmp);
            fail(path, e)
        })?;
        Ok((TempFile { tmp, path: path.to_owned(), committed: false }, file))
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Sync the data and rename it into place.
    pub fn commit(mut self) -> Result<PathBuf, OutDirError> {
        File::open(&self.tmp).and_then(|f| f.sync_all()).map_err(|e| fail(&self.path, e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| fail(&self.path, e))?;
        self.committed = true;
        interrupt::unregister(&self.tmp);
        sync_dir(parent_of(&self.path));
        Ok(self.path.clone())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
            interrupt::unregister(&self.tmp);
        }
    }
}

/// Write a whole file the tool owns: `path` must not exist or must be a file this tool wrote
/// (`ours` says so from its first bytes); written atomically under the lock.
pub fn write_file(path: &Path, bytes: &[u8], ours: impl Fn(&[u8]) -> bool, flag: &str) -> Result<(), OutDirError> {
    let _lock = Lock::acquire(path)?;
    check_file_replaceable(path, &ours, flag)?;
    let (tmp, mut file) = TempFile::create(path)?;
    file.write_all(bytes).map_err(|e| fail(path, e))?;
    drop(file);
    tmp.commit().map(drop)
}

/// Whether [`write_file`] may write `path`: nothing there, or a regular file whose first 4 KiB
/// `ours` recognises. A command that writes several files asks for each before it writes any,
/// so that a refusal leaves nothing behind.
pub fn check_file_replaceable(path: &Path, ours: &impl Fn(&[u8]) -> bool, flag: &str) -> Result<(), OutDirError> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(fail(path, e)),
        Ok(m) if !m.is_file() => return Err(refuse(path, format!("{flag} exists and is not a regular file; choose another {flag}"))),
        Ok(_) => {
            let mut head = Vec::new();
            File::open(path).and_then(|f| f.take(4096).read_to_end(&mut head)).map_err(|e| fail(path, e))?;
            if !ours(&head) {
                return Err(refuse(path, format!("{flag} exists and was not written by stickslip; refusing to replace it: choose another {flag}")));
            }
        }
    }
    Ok(())
}
