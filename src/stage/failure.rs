//! How a failed stage is told: the input it blames (from each error type's own answer,
//! [`crate::blame::Blame`]), the exit code that follows, and the one printable line.

use crate::blame::{Blame, Culprit, Usage};

/// The input an error blames: the first link of its chain that names one. Each error type
/// answers for itself ([`Blame`]); transparent wrappers are looked through, since their inner
/// error is not a link of its own.
pub fn culprit(e: &anyhow::Error) -> Option<Culprit> {
    e.chain().find_map(link_culprit)
}

fn link_culprit(e: &(dyn std::error::Error + 'static)) -> Option<Culprit> {
    macro_rules! ask {
        ($($t:ty),* $(,)?) => {
            $(if let Some(x) = e.downcast_ref::<$t>() {
                return x.blame();
            })*
        };
    }
    ask!(
        Usage,
        crate::scenario::ScenarioError,
        crate::analysis::input::InputError,
        crate::outdir::OutDirError,
        crate::analysis::AnalysisError,
        crate::simulation::dataset::DatasetError,
        crate::simulation::simulate::SimulateError,
        crate::report::ReportError,
        crate::figures::FigureError,
        crate::tradeoff::TradeoffError,
        crate::sensitivity::SensitivityError,
        crate::law::LawError,
    );
    None
}

/// Whether the run was cancelled (Ctrl-C in a Python session).
pub fn cancelled(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.is::<crate::progress::Cancelled>())
}

/// The exit code when an input (a flag, key, value, file or output directory) is at fault (as
/// clap's own for a flag it cannot parse).
pub const INPUT_AT_FAULT: u8 = 2;
/// The exit code of a failure while running.
pub const RUN_FAILED: u8 = 1;

/// Exit code of a failed run: [`INPUT_AT_FAULT`] or [`RUN_FAILED`].
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if culprit(e).is_some() {
        INPUT_AT_FAULT
    } else {
        RUN_FAILED
    }
}

/// The error and its causes on one printable line, each cause once (a cause whose text is
/// already shown, as when a message quotes its `source`, is not repeated). Whatever a cause
/// quotes — a user's 100,000-character `--set` value, a file's control bytes — is made
/// printable and shortened ([`printable`]).
pub fn message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = printable(&cause.to_string());
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out += ": ";
        }
        out += &text;
    }
    out
}

/// `text` on one line: control characters (newlines included) become spaces, runs of spaces
/// one, and a run of more than 200 characters without a space keeps its first 80 and says how
/// long it was.
fn printable(text: &str) -> String {
    let clean: String = text.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let words: Vec<String> = clean
        .split_whitespace()
        .map(|w| {
            let n = w.chars().count();
            if n > 200 {
                format!("{}… ({n} characters)", w.chars().take(80).collect::<String>())
            } else {
                w.to_string()
            }
        })
        .collect();
    words.join(" ")
}
