//! How numbers are shown in messages, tables, file names and hive paths.

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

/// A table value with six decimals (`0.123457`), in exponent notation (`1.234568e12`) outside
/// [1e-3, 1e9) — never hundreds of digits.
pub fn six_decimals(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e9).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.6e}")
    }
}
