//! Clean exit on SIGINT and SIGTERM: every temporary file, staging directory and lock file the
//! process holds is registered here, removed by the signal thread, and the process exits with
//! 128 + the signal number (130, 143), as a shell expects. SIGKILL cannot be caught: what a killed
//! process leaves is hidden and is removed by the next writer of the same output (see
//! [`crate::outdir`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

static HELD: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn held() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    HELD.lock().unwrap_or_else(|e| e.into_inner())
}

/// Remove `path` if the process is interrupted.
pub fn register(path: &Path) {
    held().push(path.to_owned());
}

/// `path` was committed or removed.
pub fn unregister(path: &Path) {
    let mut h = held();
    if let Some(i) = h.iter().rposition(|p| p == path) {
        h.remove(i);
    }
}

/// Remove everything registered (newest first) and exit; the registry stays locked until the
/// process is gone, so no thread registers (and then creates) anything new meanwhile.
fn remove_all_and_exit(code: i32) -> ! {
    let mut h = held();
    while let Some(p) = h.pop() {
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
            remove_all_and_exit(128 + sig);
        }
    });
}
