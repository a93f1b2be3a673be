//! The `stickslip.*` key-value metadata that more than one stage reads or writes: the part
//! files' (written by `simulate`, read by `analysis::input`) and the trajectory tables'. One
//! place for the keys, below every stage that uses them.

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
