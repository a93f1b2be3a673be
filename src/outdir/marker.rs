//! The markers: what kind of output a directory is, and which files the tool wrote into it.

use std::fs::File;
use std::io::Read;
use std::path::Path;

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
    ExactLaw,
    Predict,
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
            Kind::ExactLaw => "exact-law",
            Kind::Predict => "predict",
        }
    }
}

/// The marker of a directory: its kind and (for directories replaced whole) its files.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(super) struct Marker {
    pub(super) kind: String,
    pub(super) stickslip: String,
    #[serde(default)]
    pub(super) files: Vec<String>,
}

pub(super) fn read_marker(dir: &Path) -> Option<Marker> {
    if dir.join(DATASET_MARKER).is_file() {
        return Some(Marker { kind: Kind::Dataset.name().into(), stickslip: String::new(), files: Vec::new() });
    }
    let mut text = String::new();
    File::open(dir.join(MARKER)).ok()?.take(16 << 20).read_to_string(&mut text).ok()?;
    serde_json::from_str(&text).ok()
}

/// Whether `dir` (or, for a dataset, one of its ancestors) is marked as the tool's `kind`.
pub fn is_marked(dir: &Path, kind: Kind) -> bool {
    read_marker(dir).is_some_and(|m| m.kind == kind.name())
}

/// Every file below `dir`, relative, with `/` separators, and every empty directory as `dir/`
/// (a user's empty directory is the user's too); hidden entries of our own (locks, temporaries,
/// the marker) are left out.
pub(super) fn files_below(dir: &Path) -> std::io::Result<Vec<String>> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) -> std::io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let entry = entry?;
            let path = entry.path();
            if entry.file_type()?.is_dir() {
                if std::fs::read_dir(&path)?.next().is_none() {
                    out.push(format!("{}/", path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/")));
                }
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
