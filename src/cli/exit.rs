//! How a failed run ends: one printable line naming the culprit, and the exit code — 2 when the
//! input (a flag, key, value, file or output directory) is to blame, 1 for a failure while
//! running. Each error type answers for itself ([`crate::blame::Blame`]).

use crate::blame::Blame;

/// A usage error found after parsing (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Usage(pub String);

pub(crate) fn usage(message: impl Into<String>) -> anyhow::Error {
    Usage(message.into()).into()
}

/// Exit code of a failed run: 2 when the input (a flag, key, value, file or output directory)
/// is at fault, 1 for a failure while running.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if e.chain().any(is_bad_input) {
        2
    } else {
        1
    }
}

/// Whether an error (one link of a chain) blames the input: each error type says so itself
/// ([`Blame`], next to its definition); transparent wrappers are looked through, since their
/// inner error is not a link of its own.
fn is_bad_input(e: &(dyn std::error::Error + 'static)) -> bool {
    macro_rules! ask {
        ($($t:ty),* $(,)?) => {
            $(if let Some(x) = e.downcast_ref::<$t>() {
                return x.blames_input();
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
    false
}

impl Blame for Usage {
    fn blames_input(&self) -> bool {
        true
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
