//! How numbers read in the figures and the report alike: p-values, integers, grid values.
//!
//! One place, so that a figure's title and the report's table print the same test the same way.

/// A p-value as a reader should see it: `< 1e-300` below 1e-300 (a double's p-value there is
/// underflow, not a number), `< 0.001` below 0.001 (a Monte Carlo test cannot tell smaller values
/// apart, and `0.000` reads as impossible), otherwise 3 significant digits (`0.548`, `0.0123`,
/// `1.00`); `–` without a value.
pub fn p_value(p: f64) -> String {
    if !p.is_finite() {
        return "–".into();
    }
    if p < 1e-300 {
        return "< 1e-300".into();
    }
    if p < 1e-3 {
        return "< 0.001".into();
    }
    // the exponent after rounding to 3 significant digits (0.09996 is 1.00e-1, not 9.996e-2)
    let exponent: i32 = format!("{p:.2e}").rsplit_once('e').and_then(|(_, e)| e.parse().ok()).unwrap_or(0);
    let decimals = (2 - exponent).max(0) as usize;
    format!("{p:.decimals$}")
}

/// `p = 0.548` or `p < 0.001`: a p-value after its symbol, with the relation it holds.
pub fn p_relation(p: f64) -> String {
    let v = p_value(p);
    if v.starts_with('<') {
        v
    } else {
        format!("= {v}")
    }
}

/// An integer-valued number without decimals (`16`, not `16.000`); `None` for anything else.
pub fn integer(x: f64) -> Option<String> {
    (x.is_finite() && x.fract() == 0.0 && x.abs() < 1e15).then(|| format!("{}", x as i64))
}

pub use crate::shown::six_decimals;

/// `x` to `digits` significant digits, in plain notation (`13.0`, `1.94`, `0.0512`), or in
/// exponent notation outside [1e-3, 1e5).
pub fn significant(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let d = digits.max(1) - 1;
    let e = format!("{x:.d$e}");
    let exponent: i32 = e.rsplit_once('e').and_then(|(_, e)| e.parse().ok()).unwrap_or(0);
    if !(-3..5).contains(&exponent) {
        return e;
    }
    let decimals = (d as i32 - exponent).max(0) as usize;
    format!("{x:.decimals$}")
}

/// A grid value as typed (the shortest text that reads back as the same number: `2.5`, `0.51`).
pub fn grid_value(x: f64) -> String {
    crate::scenario::short(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p_values_read_as_bounds_below_the_floors_and_three_significant_digits_above() {
        assert_eq!(p_value(0.0), "< 1e-300");
        assert_eq!(p_value(1e-301), "< 1e-300");
        assert_eq!(p_value(1e-300), "< 0.001");
        assert_eq!(p_value(2.5e-7), "< 0.001");
        assert_eq!(p_value(0.000_999), "< 0.001");
        assert_eq!(p_value(0.001), "0.00100");
        assert_eq!(p_value(0.012_345), "0.0123");
        assert_eq!(p_value(0.548_2), "0.548");
        assert_eq!(p_value(0.099_96), "0.100");
        assert_eq!(p_value(1.0), "1.00");
        assert_eq!(p_value(f64::NAN), "–");
        assert_eq!(p_relation(0.465), "= 0.465");
        assert_eq!(p_relation(0.0), "< 1e-300");
        assert_eq!(p_relation(1e-5), "< 0.001");
    }

    #[test]
    fn integers_print_without_decimals() {
        assert_eq!(integer(16.0).as_deref(), Some("16"));
        assert_eq!(integer(-3.0).as_deref(), Some("-3"));
        assert_eq!(integer(16.5), None);
        assert_eq!(integer(f64::NAN), None);
        assert_eq!(significant(12.968, 3), "13.0");
        assert_eq!(significant(1.9357, 3), "1.94");
        assert_eq!(significant(-0.051_23, 3), "-0.0512");
        assert_eq!(significant(0.0, 3), "0");
        assert_eq!(grid_value(2.5), "2.5");
        assert_eq!(grid_value(0.51), "0.51");
        assert_eq!(grid_value(10.0), "10");
    }
}
