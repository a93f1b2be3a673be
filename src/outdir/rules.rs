//! The rules (module docs of [`crate::outdir`]): separate, recognised, exclusive, atomic.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Component, Path, PathBuf};

use super::error::*;
use super::marker::*;

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

/// Whether `dir` has no entries (a concurrent writer's marker temporary does not count).
pub(super) fn is_empty_dir(dir: &Path) -> std::io::Result<bool> {
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
pub(super) fn check_replaceable(target: &Path, kind: Kind, flag: &str) -> Result<(), OutDirError> {
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
pub(super) fn create_new(path: &Path) -> std::io::Result<File> {
    OpenOptions::new().write(true).create_new(true).open(path)
}

/// Write a new file at `path` (which must not exist), synced.
pub(super) fn write_new(path: &Path, bytes: &[u8]) -> Result<(), OutDirError> {
    let mut f = create_new(path).map_err(|e| fail(path, e))?;
    f.write_all(bytes).and_then(|()| f.sync_all()).map_err(|e| fail(path, e))
}

/// Sync a directory, so that a rename in it is durable.
pub(super) fn sync_dir(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

pub(super) fn parent_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

pub(super) fn name_of(path: &Path) -> Result<String, OutDirError> {
    match path.file_name() {
        Some(n) => Ok(n.to_string_lossy().into_owned()),
        None => Err(refuse(path, "is not a file or directory name (it ends in `..` or `/`)")),
    }
}

/// Write the marker of `dir`, which must not have one: complete in a unique temporary first,
/// then hard-linked into place (a link fails if the marker exists, and is atomic), so that a
/// concurrent reader never sees a partial marker.
pub(super) fn write_marker(dir: &Path, kind: Kind, files: Vec<String>) -> Result<(), OutDirError> {
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
