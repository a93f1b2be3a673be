//! How a running stage reports and is stopped: one small interface, the same for the command
//! line and for Python.
//!
//! A stage is given a [`Control`]: a [`Progress`] sink it tells what it is doing (a bar of
//! realizations or iterations, a live status line, a line to keep) and a cancel token it asks
//! between chunks of work. The command line draws the sink as a progress bar on a terminal
//! (nothing with `--quiet`) and never cancels (SIGINT ends the process, see
//! [`crate::interrupt`]); the Python package draws it as a tqdm-style bar and cancels on Ctrl-C.
//! A cancelled stage returns [`Cancelled`]; whatever it staged is removed as on any failure.

/// What a stage tells while it runs. Every method has a default that shows nothing.
pub trait Progress: Sync {
    /// A counted step begins (or begins again): `total` units, `what` names the stage
    /// (`"simulate"`, `"analyze"`).
    fn start(&self, what: &str, total: u64) {
        let _ = (what, total);
    }
    /// `n` more units are done.
    fn advance(&self, n: u64) {
        let _ = n;
    }
    /// A short text beside the bar (the target standard errors reached so far).
    fn message(&self, text: &str) {
        let _ = text;
    }
    /// The counted step is over: the bar is cleared.
    fn finish(&self) {}
    /// A live status line, replaced by the next status or note (an iteration of a solve).
    fn status(&self, line: &str) {
        let _ = line;
    }
    /// A line to keep (a finished level of a solve, a note on the run's cost).
    fn note(&self, line: &str) {
        let _ = line;
    }
}

/// A sink that shows nothing.
pub struct Silent;

impl Progress for Silent {}

/// The stage was cancelled (Ctrl-C in a Python session).
#[derive(Debug, Clone, Copy, thiserror::Error)]
#[error("interrupted")]
pub struct Cancelled;

/// A stage's progress sink and cancel token.
#[derive(Clone, Copy)]
pub struct Control<'a> {
    /// where the stage reports
    pub progress: &'a dyn Progress,
    /// asked between chunks of work: true stops the stage with [`Cancelled`]; once it answers
    /// true it keeps answering true (a stage may ask again to tell a stop from a failure)
    pub cancel: &'a (dyn Fn() -> bool + Sync),
}

fn never() -> bool {
    false
}

impl Control<'static> {
    /// Shows nothing, never cancels.
    pub fn silent() -> Control<'static> {
        Control { progress: &Silent, cancel: &never }
    }
}

impl Control<'_> {
    /// `Err(Cancelled)` once cancellation was asked for.
    pub fn check(&self) -> Result<(), Cancelled> {
        if (self.cancel)() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }
}

impl std::fmt::Debug for Control<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Control")
    }
}
