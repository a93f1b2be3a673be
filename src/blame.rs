//! Whose fault an error is. Every error type of the crate says, next to its definition, which
//! input — a flag or argument, the scenario, a dataset or other input file, the output
//! directory — is to blame, or that the run failed ([`Blame`]). From that one answer the stage
//! layer derives the command line's exit code (2 when an input is to blame, 1 otherwise) and the
//! Python package's exception class (`stickslip.UsageError`, `ScenarioError`, `DatasetError`,
//! `OutputError`, all `ValueError`s; `RunError`, a `RuntimeError`).

/// The input at fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Culprit {
    /// a flag or argument (its value, or values that cannot go together)
    Usage,
    /// the scenario: a key, a value, the scenario file, or a scene a stage cannot take
    Scenario,
    /// a dataset or another stage's output read as input
    Dataset,
    /// the output directory or file
    Output,
}

impl Culprit {
    /// Every culprit, in the order the documentation lists them.
    pub const ALL: [Culprit; 4] = [Culprit::Usage, Culprit::Scenario, Culprit::Dataset, Culprit::Output];

    /// The Python package's exception class for it (each a `ValueError` subclass).
    pub const fn python_class(self) -> &'static str {
        match self {
            Culprit::Usage => "UsageError",
            Culprit::Scenario => "ScenarioError",
            Culprit::Dataset => "DatasetError",
            Culprit::Output => "OutputError",
        }
    }

    /// What it blames, as the documentation says it.
    pub const fn meaning(self) -> &'static str {
        match self {
            Culprit::Usage => "a flag or argument: its value, or values that cannot go together",
            Culprit::Scenario => "the scenario: a key, a value, the scenario file, or a scene the stage cannot take",
            Culprit::Dataset => "a dataset, or another stage's output read as input, that fails its checks",
            Culprit::Output => "the output directory or file, refused by the output rules",
        }
    }
}

/// An error that knows whether an input is to blame.
pub trait Blame {
    /// The input at fault, or None for a failure while running (exit code 1).
    fn blame(&self) -> Option<Culprit>;
}

/// A usage error found after parsing: an argument's value out of range (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Usage(pub String);

pub(crate) fn usage(message: impl Into<String>) -> anyhow::Error {
    Usage(message.into()).into()
}

impl Blame for Usage {
    fn blame(&self) -> Option<Culprit> {
        Some(Culprit::Usage)
    }
}
