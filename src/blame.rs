//! Whose fault an error is. Every error type of the crate says, next to its definition, whether
//! the input — a flag, a key, a value, a file or an output directory — is to blame (the command
//! exits with code 2) or the run failed (code 1); the command line only asks
//! (`cli::exit`).

/// An error that knows whether the input is to blame.
pub trait Blame {
    /// True when the user's input caused it (exit code 2).
    fn blames_input(&self) -> bool;
}
