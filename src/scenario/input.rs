//! Where a stage's scenario comes from: the embedded paper scenario, a TOML file, or TOML text
//! (how Python passes a dict or `stickslip.Toml`), with `KEY=VALUE` overrides on top — the
//! command line's `[SCENARIO] --set KEY=VALUE…` as a typed value.

use std::path::{Path, PathBuf};

use super::resolve::{merged, typed};
use super::types::{Cell, Overrides, Scenario, ScenarioError};

/// The base a scenario's keys are laid on.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Source {
    /// the embedded paper scenario
    #[default]
    Paper,
    /// a TOML file (a relative `belt.file` in it is a path from its directory)
    File(PathBuf),
    /// TOML text (a relative `belt.file` is a path from the working directory)
    Text(String),
}

/// A scenario as a stage is asked for it: a source and overrides.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Input {
    /// the file or text (keys it omits keep the paper's values)
    pub source: Source,
    /// `KEY=VALUE` overrides, applied in order (`--set`)
    pub sets: Vec<String>,
}

/// How TOML text is named in messages.
const TEXT_ORIGIN: &str = "<scenario>";

impl Input {
    /// The scenario file, if it is one (an output must stay apart from it).
    pub fn file(&self) -> Option<&Path> {
        match &self.source {
            Source::File(p) => Some(p),
            _ => None,
        }
    }

    /// The one scene (checked).
    pub fn resolve(&self) -> Result<Scenario, ScenarioError> {
        match &self.source {
            Source::Paper => Scenario::resolve(None, &self.sets),
            Source::File(p) => Scenario::resolve(Some(p), &self.sets),
            Source::Text(t) => Scenario::from_text(Some(t), Path::new(TEXT_ORIGIN), &self.sets),
        }
    }

    /// The cells of a sweep (one cell with the empty path for a plain scene), each checked.
    pub fn resolve_sweep(&self, over: Overrides) -> Result<Vec<Cell>, ScenarioError> {
        match &self.source {
            Source::Paper => Scenario::resolve_sweep(None, &self.sets, over),
            Source::File(p) => Scenario::resolve_sweep(Some(p), &self.sets, over),
            Source::Text(t) => Scenario::sweep_cells(typed(merged(Some(t), Path::new(TEXT_ORIGIN), None, &self.sets)?)?, over),
        }
    }
}
