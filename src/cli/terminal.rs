//! The progress sink of the command line: on a terminal, a bar per counted step and a live
//! status line on stderr; elsewhere only the notes, one per line. (`--quiet` shows nothing: the
//! command line then gives the stages [`crate::progress::Silent`].)

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressStyle};

use crate::progress::Progress;

/// Draws on stderr.
pub(super) struct Terminal {
    /// stderr is a terminal: bars and status lines are drawn
    live: bool,
    bar: Mutex<Option<ProgressBar>>,
}

impl Terminal {
    pub(super) fn new(live: bool) -> Terminal {
        Terminal { live, bar: Mutex::new(None) }
    }

    fn bar(&self) -> std::sync::MutexGuard<'_, Option<ProgressBar>> {
        self.bar.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The bar's template for a stage's counted step.
fn template(what: &str) -> String {
    match what {
        "simulate" => "simulate {bar:40} {pos}/{len} realizations  {per_sec}  eta {eta}  {msg}".into(),
        _ => format!("{what} {{bar:40}} {{pos}}/{{len}} realizations  {{elapsed}}  eta {{eta}}"),
    }
}

impl Progress for Terminal {
    fn start(&self, what: &str, total: u64) {
        if !self.live {
            return;
        }
        let bar = ProgressBar::new(total);
        bar.set_style(ProgressStyle::with_template(&template(what)).expect("valid template"));
        if what != "simulate" {
            bar.enable_steady_tick(std::time::Duration::from_millis(200));
        }
        if let Some(old) = self.bar().replace(bar) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(bar) = self.bar().as_ref() {
            bar.inc(n);
        }
    }

    fn message(&self, text: &str) {
        if let Some(bar) = self.bar().as_ref() {
            bar.set_message(text.to_string());
        }
    }

    fn finish(&self) {
        if let Some(bar) = self.bar().take() {
            bar.finish_and_clear();
        }
    }

    fn status(&self, line: &str) {
        if self.live {
            eprint!("\r\x1b[K{line}");
        }
    }

    fn note(&self, line: &str) {
        eprintln!("{}{line}", if self.live { "\r\x1b[K" } else { "" });
    }
}
