//! How numbers are shown in messages, file names and hive paths.

/// A number in its shortest round-trip form, never as hundreds of digits (hive values, errors):
/// positional while that takes at most 16 characters (0.51, 0.00001, 2.5), else with an exponent.
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 16 {
        plain
    } else {
        format!("{x:e}")
    }
}
