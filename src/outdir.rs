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
//!   directory, it holds the tool's staging tag or marker ([`remove_stale`]); never by prefix.
//!   Hidden names stay within NAME_MAX however long NAME is ([`hidden`]).

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::interrupt;

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

fn fail(path: &Path, e: impl std::fmt::Display) -> OutDirError {
    OutDirError { path: path.to_owned(), message: e.to_string(), refused: false }
}

fn refuse(path: &Path, message: impl Into<String>) -> OutDirError {
    OutDirError { path: path.to_owned(), message: message.into(), refused: true }
}

/// `path` made absolute with `.`/`..` and symlinks of its existing ancestors resolved (the
/// part that does not exist yet is appended as written, without `.` and `..`).
pub fn resolved(path: &Path) -> PathBuf {
    let absolute = if path.is_absolute() {
        path.to_owned()
    } else {
        std::env::current_dir().unwrap_or_default().join(path)
    };
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

/// Every file below `dir`, relative, with `/` separators; hidden entries of our own (locks,
/// temporaries, the marker) are left out.
fn files_below(dir: &Path) -> std::io::Result<Vec<String>> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) -> std::io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let entry = entry?;
            let path = entry.path();
            if entry.file_type()?.is_dir() {
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
        return Err(refuse(
            target,
            format!("{flag} holds a stickslip {}, not a {}; refusing to replace it: choose another {flag}", marker.kind, kind.name()),
        ));
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

/// A unique token for temporary names: process id, a per-process counter and the clock's
/// nanoseconds (`PID-N-HEX`, at most 40 bytes).
fn unique() -> String {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
    format!("{}-{}-{nanos:x}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed))
}

/// Whether `s` is a token [`unique`] makes: decimal, decimal and hexadecimal fields.
fn is_token(s: &str) -> bool {
    let f: Vec<&str> = s.split('-').collect();
    let digits = |x: &str, hex: bool| !x.is_empty() && x.len() <= 20 && x.chars().all(|c| if hex { c.is_ascii_hexdigit() && !c.is_ascii_uppercase() } else { c.is_ascii_digit() });
    f.len() == 3 && digits(f[0], false) && digits(f[1], false) && digits(f[2], true)
}

/// The longest file name the file systems we write to accept (NAME_MAX on Linux and macOS).
const NAME_MAX: usize = 255;

/// The part of our hidden names that stands for an output named `name`: the name itself, or,
/// when a hidden name built on it would exceed [`NAME_MAX`], a prefix of it and a 64-bit
/// FNV-1a hash of the whole name (distinct outputs keep distinct locks).
fn hidden_base(name: &str) -> String {
    // room for ".", "." and the longest suffix: "stickslip-tmp-" + a token
    const ROOM: usize = NAME_MAX - 2 - 14 - 40;
    if name.len() <= ROOM {
        return name.to_string();
    }
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    let mut cut = ROOM - 17;
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!("{}~{hash:016x}", &name[..cut])
}

/// The hidden name `.BASE.stickslip-SUFFIX` beside the output `name` (within [`NAME_MAX`]).
fn hidden(name: &str, suffix: &str) -> String {
    format!(".{}.stickslip-{suffix}", hidden_base(name))
}

/// The file a staging directory holds from its creation until it is committed: with the
/// directory's exact name it proves the directory is ours (see [`remove_stale`]).
const STAGING: &str = ".stickslip-staging";

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

/// Remove what a killed writer of the output `name` left in `dir`: call only while holding
/// `name`'s lock (a live writer would hold it). Only entries the tool can prove it wrote go: a
/// name of exactly the form `.BASE.stickslip-tmp-TOKEN` or `.BASE.stickslip-old-TOKEN`
/// ([`hidden`], [`unique`]), and, for a directory, holding our staging tag ([`STAGING`]) or our
/// marker. Anything else — a user's `.NAME.old` or `.NAME.tmp-notes` — is left alone.
fn remove_stale(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let (tmp, old) = (hidden(name, "tmp-"), hidden(name, "old-"));
    for entry in entries.flatten() {
        let n = entry.file_name().to_string_lossy().into_owned();
        let Some(token) = n.strip_prefix(&tmp).or_else(|| n.strip_prefix(&old)) else { continue };
        if !is_token(token) {
            continue;
        }
        let p = entry.path();
        match entry.file_type() {
            Ok(t) if t.is_dir() => {
                if p.join(STAGING).is_file() || p.join(MARKER).is_file() {
                    let _ = std::fs::remove_dir_all(&p);
                }
            }
            Ok(t) if t.is_file() => {
                let _ = std::fs::remove_file(&p);
            }
            _ => {}
        }
    }
}

/// An advisory lock on `.NAME.lock` beside an output, released (and the lock file removed) on
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
            let _ = file.set_len(0).and_then(|()| file.seek(std::io::SeekFrom::Start(0))).and_then(|_| file.write_all(std::process::id().to_string().as_bytes()));
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
    tmp: PathBuf,
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
    let (tmp, mut file) = TempFile::create(path)?;
    file.write_all(bytes).map_err(|e| fail(path, e))?;
    drop(file);
    tmp.commit().map(drop)
}

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

    pub fn path(&self) -> &Path {
        &self.dir
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

    /// The final path.
    pub fn target(&self) -> &Path {
        &self.target
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
