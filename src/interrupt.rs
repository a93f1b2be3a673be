//! Clean exit on SIGINT and SIGTERM: every temporary file, staging directory and lock file the
//! process holds is registered here, removed by the signal thread — and every directory the run
//! created, removed only if empty once the run's own lone marker is gone — and the process exits with
//! 128 + the signal number (130, 143), as a shell expects. SIGKILL cannot be caught: what a killed
//! process leaves is hidden and is removed by the next writer of the same output (see
//! [`crate::outdir`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The exit code of a run ended by a signal is this plus the signal's number (SIGINT 2 → 130,
/// SIGTERM 15 → 143), as a shell expects.
pub const SIGNALLED: i32 = 128;

/// What to remove on a signal.
#[derive(Debug, PartialEq)]
enum Held {
    /// A temporary, staging directory or lock of this process: removed whole.
    Own(PathBuf),
    /// The marker this run wrote into a directory: removed if it is all the directory holds.
    Marker(PathBuf),
    /// A directory this run created: removed if empty.
    Created(PathBuf),
}

static HELD: Mutex<Vec<Held>> = Mutex::new(Vec::new());

fn held() -> std::sync::MutexGuard<'static, Vec<Held>> {
    HELD.lock().unwrap_or_else(|e| e.into_inner())
}

/// Remove `path` if the process is interrupted.
pub fn register(path: &Path) {
    held().push(Held::Own(path.to_owned()));
}

/// `path` was committed or removed.
pub fn unregister(path: &Path) {
    let mut h = held();
    if let Some(i) = h.iter().rposition(|p| matches!(p, Held::Own(q) if q == path)) {
        h.remove(i);
    }
}

/// The run created the directory `dir`: removed on a signal if it is empty by then.
pub fn register_created(dir: &Path) {
    held().push(Held::Created(dir.to_owned()));
}

/// The run wrote the marker file `marker`: removed on a signal if its directory holds nothing else.
pub fn register_marker(marker: &Path) {
    held().push(Held::Marker(marker.to_owned()));
}

/// The run keeps (or has removed) the directory or marker `path`.
pub fn unregister_created(path: &Path) {
    held().retain(|p| !matches!(p, Held::Created(d) | Held::Marker(d) if d == path));
}

/// Remove the marker file `marker` if its directory holds nothing else.
pub fn remove_lone_marker(marker: &Path) {
    let Some(dir) = marker.parent() else { return };
    let alone = std::fs::read_dir(dir).is_ok_and(|entries| {
        let names: Vec<_> = entries.flatten().map(|e| e.file_name()).collect();
        names.len() == 1 && Some(names[0].as_os_str()) == marker.file_name()
    });
    if alone {
        let _ = std::fs::remove_file(marker);
    }
}

/// Remove everything registered (newest first) and exit; the registry stays locked until the
/// process is gone, so no thread registers (and then creates) anything new meanwhile.
fn remove_all_and_exit(code: i32) -> ! {
    let mut h = held();
    while let Some(held) = h.pop() {
        let p = match held {
            Held::Own(p) => p,
            Held::Marker(m) => {
                remove_lone_marker(&m);
                continue;
            }
            Held::Created(dir) => {
                let _ = std::fs::remove_dir(&dir); // only succeeds if empty
                continue;
            }
        };
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.is_dir() => {
                // a writer thread may still add a file: try twice
                if std::fs::remove_dir_all(&p).is_err() {
                    let _ = std::fs::remove_dir_all(&p);
                }
            }
            Ok(_) => {
                let _ = std::fs::remove_file(&p);
            }
            Err(_) => {}
        }
    }
    std::process::exit(code)
}

/// Install the handler (once, from the binary's entry point).
pub fn install() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            remove_all_and_exit(SIGNALLED + sig);
        }
    });
}
