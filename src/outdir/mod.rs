//! Output safety: what a stage may write, replace or delete, and how it writes it.
//!
//! The rules (the book: docs/src/reference/output-directories.md):
//! - **Separate.** An output that equals, contains or lies inside any input (dataset, analysis,
//!   figures, scenario file) is refused before anything runs ([`check_separate`]).
//! - **Recognised.** Every directory the tool writes carries a marker file (`marker.rs`) naming its
//!   kind (`dataset`, `analysis`, `figures`, `tradeoff`, `reproduce`) and, for directories
//!   replaced as a whole, every file in it. A directory is replaced only if it is empty or its
//!   marker is of the same kind and lists everything in it: a file the tool did not write is never
//!   deleted. A dataset directory is never replaced, only added to, part file by part file.
//! - **Exclusive.** One writer at a time per output (a directory, or one part file of a dataset):
//!   an advisory lock (`flock`) on a hidden `.NAME.stickslip-lock` beside it, holding the writer's process
//!   id, so a second writer is told at once which process holds it ([`Lock`]).
//! - **Atomic.** Files are written under unique temporary names created exclusively (`O_EXCL`,
//!   never through a symlink), synced, then renamed into place; directories are staged beside
//!   their target and swapped in whole ([`StagedDir`]). Temporaries are removed on failure, on
//!   panic and on SIGINT/SIGTERM ([`crate::interrupt`]); those of a killed process are removed by
//!   the next writer that takes the same lock (a live writer holds it), and are hidden (`.NAME…`),
//!   so readers never see them.
//! - **Deletes only its own.** Stale entries are removed only when their name is exactly one the
//!   tool makes (`.NAME.stickslip-tmp-PID-N-HEX`, `.NAME.stickslip-old-PID-N-HEX`) and, for a
//!   directory, it holds the tool's staging tag or marker ([`names`]); never by prefix.
//!   Hidden names stay within NAME_MAX however long NAME is.

mod dirs;
mod error;
mod files;
mod marker;
mod names;
mod rules;

pub use dirs::{prepare_reproduce, write_new_file, Created, DatasetDir, StagedDir};
pub use error::OutDirError;
pub use files::{check_file_replaceable, write_file, Lock, TempFile};
pub use marker::{is_marked, Kind};
pub use rules::*;
