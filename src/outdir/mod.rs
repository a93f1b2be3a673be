//! Output safety: what a stage may write, replace or delete, and how it writes it.
//!
//! The rules (README, "Output directories"):
//! - **Separate.** An output that equals, contains or lies inside any input (dataset, analysis,
//!   figures, scenario file) is refused before anything runs ([`check_separate`]).
//! - **Recognised.** Every directory the tool writes carries a marker file [`MARKER`] naming its
//!   kind (`dataset`, `analysis`, `figures`, `tradeoff`, `reproduce`) and, for directories
//!   replaced as a whole, every file in it. A directory is replaced only if it is empty or its
//!   marker is of the same kind and lists everything in it: a file the tool did not write is never
//!   deleted. A dataset directory is never replaced, only added to, part file by part file.
//! - **Exclusive.** One writer at a time per output (a directory, or one part file of a dataset):
//!   an advisory lock (`flock`) on a hidden `.NAME.stickslip-lock` beside it, holding the writer's process
//!   id, so a second writer is told at once which process holds it ([`Lock`]).
//! - **Atomic.** Files are written under unique temporary names created exclusively (`O_EXCL`,
//!   never through a symlink), synced, then renamed into place; directories are staged beside
//!   their target and swapped in whole ([`StagedDir`]). Temporaries are removed on failure, on
//!   panic and on SIGINT/SIGTERM ([`crate::interrupt`]); those of a killed process are removed by
//!   the next writer that takes the same lock (a live writer holds it), and are hidden (`.NAME…`),
//!   so readers never see them.
//! - **Deletes only its own.** Stale entries are removed only when their name is exactly one the
//!   tool makes (`.NAME.stickslip-tmp-PID-N-HEX`, `.NAME.stickslip-old-PID-N-HEX`) and, for a
//!   directory, it holds the tool's staging tag or marker ([`names`]); never by prefix.
//!   Hidden names stay within NAME_MAX however long NAME is.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::interrupt;

mod dirs;
mod files;
mod names;

pub use dirs::{prepare_reproduce, Created, DatasetDir, StagedDir};
pub use files::{check_file_replaceable, write_file, write_new_file, Lock, TempFile};
use names::{hidden, remove_stale, unique, STAGING};

/// The marker file in every directory the tool writes (JSON: kind and files), but a dataset's.
pub const MARKER: &str = ".stickslip-output";

/// A dataset directory's marker: an empty file, because polars' `read_parquet(DIR)` refuses a
/// directory holding any non-empty file that is not Parquet, hidden or not (pyarrow and DuckDB
/// skip hidden files); a dataset is replaced part by part, never whole, so its marker lists no
/// files. Datasets of earlier versions carry the JSON [`MARKER`] of kind `dataset`, still read.
pub const DATASET_MARKER: &str = ".stickslip-dataset";

/// What an output directory holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Dataset,
    Analysis,
    Figures,
    Tradeoff,
    Reproduce,
    Sensitivity,
    ExactLaw,
    Predict,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Dataset => "dataset",
            Kind::Analysis => "analysis",
            Kind::Figures => "figures",
            Kind::Tradeoff => "tradeoff",
            Kind::Reproduce => "reproduce",
            Kind::Sensitivity => "sensitivity",
            Kind::ExactLaw => "exact-law",
            Kind::Predict => "predict",
        }
    }
}

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

fn fail(path: &Path, e: impl std::fmt::Display) -> OutDirError {
    OutDirError { path: path.to_owned(), message: e.to_string(), refused: false }
}

fn refuse(path: &Path, message: impl Into<String>) -> OutDirError {
    OutDirError { path: path.to_owned(), message: message.into(), refused: true }
}

/// `path` made absolute with `.`/`..` and symlinks of its existing ancestors resolved (the
/// part that does not exist yet is appended as written, without `.` and `..`).
pub fn resolved(path: &Path) -> PathBuf {
    let absolute = if path.is_absolute() { path.to_owned() } else { std::env::current_dir().unwrap_or_default().join(path) };
    let mut existing = absolute.as_path();
    let mut rest: Vec<&std::ffi::OsStr> = Vec::new();
    loop {
        if let Ok(real) = existing.canonicalize() {
            let mut out = real;
            for part in rest.iter().rev() {
                match Path::new(part).components().next() {
                    Some(Component::ParentDir) => {
                        out.pop();
                    }
                    Some(Component::CurDir) | None => {}
                    _ => out.push(part),
                }
            }
            return out;
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name);
                existing = parent;
            }
            (Some(parent), None) => existing = parent, // a trailing `..` or `.`
            (None, _) => return absolute,
        }
    }
}

/// Refuse an output that equals, contains or lies inside one of `inputs`.
pub fn check_separate(out: &Path, flag: &str, inputs: &[&Path]) -> Result<(), OutDirError> {
    let o = resolved(out);
    for input in inputs {
        let i = resolved(input);
        let relation = if o == i {
            "is"
        } else if i.starts_with(&o) {
            "contains"
        } else if o.starts_with(&i) {
            "lies inside"
        } else {
            continue;
        };
        return Err(refuse(
            out,
            format!("{flag} {relation} the input {}; an output must be separate from every input, choose another {flag}", input.display()),
        ));
    }
    Ok(())
}

/// The marker of a directory: its kind and (for directories replaced whole) its files.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
struct Marker {
    kind: String,
    stickslip: String,
    #[serde(default)]
    files: Vec<String>,
}

fn read_marker(dir: &Path) -> Option<Marker> {
    if dir.join(DATASET_MARKER).is_file() {
        return Some(Marker { kind: Kind::Dataset.name().into(), stickslip: String::new(), files: Vec::new() });
    }
    let mut text = String::new();
    File::open(dir.join(MARKER)).ok()?.take(16 << 20).read_to_string(&mut text).ok()?;
    serde_json::from_str(&text).ok()
}

/// Write the marker of `dir`, which must not have one: complete in a unique temporary first,
/// then hard-linked into place (a link fails if the marker exists, and is atomic), so that a
/// concurrent reader never sees a partial marker.
fn write_marker(dir: &Path, kind: Kind, files: Vec<String>) -> Result<(), OutDirError> {
    if kind == Kind::Dataset {
        // empty, created exclusively: fails if a concurrent writer marked it first
        let path = dir.join(DATASET_MARKER);
        return create_new(&path).map(drop).map_err(|e| fail(&path, e));
    }
    let m = Marker { kind: kind.name().into(), stickslip: env!("CARGO_PKG_VERSION").into(), files };
    let text = serde_json::to_string_pretty(&m).expect("a marker serializes") + "\n";
    let path = dir.join(MARKER);
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    let tmp = dir.join(format!("{MARKER}.tmp-{}-{nanos}", std::process::id()));
    write_new(&tmp, text.as_bytes())?;
    let linked = std::fs::hard_link(&tmp, &path);
    let _ = std::fs::remove_file(&tmp);
    linked.map_err(|e| fail(&path, e))
}

/// Whether `dir` (or, for a dataset, one of its ancestors) is marked as the tool's `kind`.
pub fn is_marked(dir: &Path, kind: Kind) -> bool {
    read_marker(dir).is_some_and(|m| m.kind == kind.name())
}

/// Every file below `dir`, relative, with `/` separators, and every empty directory as `dir/`
/// (a user's empty directory is the user's too); hidden entries of our own (locks, temporaries,
/// the marker) are left out.
fn files_below(dir: &Path) -> std::io::Result<Vec<String>> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) -> std::io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let entry = entry?;
            let path = entry.path();
            if entry.file_type()?.is_dir() {
                if std::fs::read_dir(&path)?.next().is_none() {
                    out.push(format!("{}/", path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/")));
                }
                walk(root, &path, out)?;
            } else {
                let rel = path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/");
                if rel != MARKER && rel != DATASET_MARKER {
                    out.push(rel);
                }
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out)?;
    out.sort();
    Ok(out)
}

/// Whether `dir` has no entries (a concurrent writer's marker temporary does not count).
fn is_empty_dir(dir: &Path) -> std::io::Result<bool> {
    let marker_tmp = format!("{MARKER}.tmp-");
    for entry in std::fs::read_dir(dir)? {
        if !entry?.file_name().to_string_lossy().starts_with(&marker_tmp) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Whether `target` may be replaced by a new output of `kind` ([`check_replaceable`]): what
/// `reproduce` checks of each stage's output before its first stage runs.
pub fn check_output(target: &Path, kind: Kind, flag: &str) -> Result<(), OutDirError> {
    check_replaceable(target, kind, flag)
}

/// Check that `target` may be replaced by a new output of `kind`: it does not exist, is an empty
/// directory, or is the tool's own output of that kind holding only the files it wrote.
fn check_replaceable(target: &Path, kind: Kind, flag: &str) -> Result<(), OutDirError> {
    let meta = match std::fs::symlink_metadata(target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(fail(target, e)),
        Ok(m) => m,
    };
    if !meta.is_dir() {
        return Err(refuse(target, format!("{flag} exists and is not a directory; choose another {flag}")));
    }
    if is_empty_dir(target).map_err(|e| fail(target, e))? {
        return Ok(());
    }
    let Some(marker) = read_marker(target) else {
        return Err(refuse(
            target,
            format!("{flag} is not empty and was not written by stickslip (no {MARKER}); refusing to replace it: remove it or choose another {flag}"),
        ));
    };
    if marker.kind != kind.name() {
        return Err(refuse(target, format!("{flag} holds a stickslip {}, not a {}; refusing to replace it: choose another {flag}", marker.kind, kind.name())));
    }
    let present = files_below(target).map_err(|e| fail(target, e))?;
    if let Some(foreign) = present.iter().find(|f| !marker.files.contains(f)) {
        return Err(refuse(
            target,
            format!("{flag} holds {foreign}, which stickslip did not write; refusing to replace the directory: move that file away or choose another {flag}"),
        ));
    }
    Ok(())
}

/// Open a new file exclusively: fails if anything, a symlink included, is at `path`.
fn create_new(path: &Path) -> std::io::Result<File> {
    OpenOptions::new().write(true).create_new(true).open(path)
}

/// Write a new file at `path` (which must not exist), synced.
fn write_new(path: &Path, bytes: &[u8]) -> Result<(), OutDirError> {
    let mut f = create_new(path).map_err(|e| fail(path, e))?;
    f.write_all(bytes).and_then(|()| f.sync_all()).map_err(|e| fail(path, e))
}

/// Sync a directory, so that a rename in it is durable.
fn sync_dir(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

fn parent_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

fn name_of(path: &Path) -> Result<String, OutDirError> {
    match path.file_name() {
        Some(n) => Ok(n.to_string_lossy().into_owned()),
        None => Err(refuse(path, "is not a file or directory name (it ends in `..` or `/`)")),
    }
}
