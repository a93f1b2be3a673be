//! The `stickslip.*` key-value metadata that more than one stage reads or writes: the part
//! files' (written by `simulate`, read by `analysis::input`) and the trajectory tables'. One
//! place for the keys, and for reading a file's footer, below every stage that uses them.

use std::path::Path;

/// the schema version (`dataset::SCHEMA_VERSION`); its presence marks a stickslip part
pub const SCHEMA_VERSION: &str = "stickslip.schema_version";
/// the crate version that wrote the file
pub const VERSION: &str = "stickslip.version";
/// the resolved scenario (TOML), read back as provenance
pub const SCENARIO: &str = "stickslip.scenario";
/// the whole run's number of realizations
pub const REALIZATIONS: &str = "stickslip.realizations";
/// the realizations this file holds, `a..b`
pub const REALIZATION_RANGE: &str = "stickslip.realization_range";
/// the block a shard with `--target-se` was given, `a..b`
pub const SHARD_BLOCK: &str = "stickslip.shard_block";

/// The key-value pairs in the footer of the Parquet file at `path` (None if it is not one).
pub fn footer(path: &Path) -> Option<Vec<(String, Option<String>)>> {
    use parquet::file::reader::FileReader;
    let reader = parquet::file::reader::SerializedFileReader::new(std::fs::File::open(path).ok()?).ok()?;
    Some(reader.metadata().file_metadata().key_value_metadata()?.iter().map(|e| (e.key.clone(), e.value.clone())).collect())
}
