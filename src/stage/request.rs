//! What the stages' requests share: the scenario file an output must stay apart from, and the
//! range of the exact methods' resolutions.

use std::path::Path;

use crate::scenario::Input;

/// The scenario file as an input an output must stay apart from.
pub(super) fn inputs(input: &Input) -> Vec<&Path> {
    input.file().into_iter().collect()
}

/// A finer resolution of the exact methods: 8 to 320.
pub(super) fn check_resolution(flag: &str, n: u32) -> anyhow::Result<()> {
    if (8..=320).contains(&n) {
        Ok(())
    } else {
        Err(crate::blame::usage(format!("{flag} {n}: must be between 8 and 320")))
    }
}
