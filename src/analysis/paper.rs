//! The paper's reported numbers (Lima & Sampaio, Table 1 and section 4), for comparison only.

use super::series::Variable;

/// (variable, k, mean, variance, mode, skewness, kurtosis) from Table 1.
pub const TABLE1: &[(Variable, u32, [f64; 5])] = &[
    (Variable::T, 1, [0.36, 0.13, 0.16, 2.11, 9.73]),
    (Variable::T, 2, [0.96, 0.29, 0.63, 1.14, 5.01]),
    (Variable::T, 3, [1.55, 0.46, 1.44, 0.83, 4.06]),
    (Variable::T, 4, [2.14, 0.62, 1.71, 0.71, 3.83]),
    (Variable::T, 5, [2.74, 0.79, 2.83, 0.66, 3.71]),
    (Variable::T, 6, [3.34, 0.95, 2.30, 0.62, 3.82]),
    (Variable::L, 1, [0.56, 0.16, 0.19, 1.59, 7.25]),
    (Variable::L, 2, [1.17, 0.34, 0.73, 1.03, 4.59]),
    (Variable::L, 3, [1.75, 0.49, 1.88, 0.79, 3.96]),
    (Variable::L, 4, [2.34, 0.65, 2.075, 0.71, 3.79]),
    (Variable::L, 5, [2.94, 0.81, 2.73, 0.63, 3.65]),
    (Variable::L, 6, [3.54, 0.98, 3.02, 0.616, 3.77]),
    (Variable::D, 1, [0.20, 0.04, 0.19, 1.72, 6.76]),
    (Variable::D, 2, [0.20, 0.04, 0.01, 1.87, 7.65]),
    (Variable::D, 3, [0.20, 0.04, 0.01, 1.92, 8.23]),
    (Variable::D, 4, [0.20, 0.04, 0.01, 1.97, 9.07]),
    (Variable::D, 5, [0.20, 0.04, 0.07, 1.83, 7.40]),
    (Variable::D, 6, [0.20, 0.04, 0.01, 1.75, 7.09]),
    (Variable::H, 1, [0.39, 0.13, 0.016, 1.79, 8.80]),
    (Variable::H, 2, [0.38, 0.12, 0.001, 1.75, 8.15]),
    (Variable::H, 3, [0.39, 0.12, 0.001, 1.77, 8.36]),
    (Variable::H, 4, [0.39, 0.13, 0.001, 1.77, 8.04]),
    (Variable::H, 5, [0.40, 0.13, 0.014, 1.94, 9.84]),
    (Variable::H, 6, [0.39, 0.13, 0.013, 1.97, 9.99]),
];

/// (variable, mean, variance) of the counts, section 4.
pub const COUNTS: &[(Variable, f64, f64)] = &[(Variable::St, 16.71, 7.94), (Variable::Sl, 16.54, 7.89)];

/// The paper's (mean, variance, mode, skewness, kurtosis) of a series, if reported.
pub fn table1(var: Variable, index: Option<u32>) -> Option<[f64; 5]> {
    TABLE1.iter().find(|(v, k, _)| *v == var && Some(*k) == index).map(|r| r.2)
}

/// One cell of the comparison: ours with its 95 % interval (or ± se) against the paper's
/// printed value; ✓ when the paper's value lies inside our interval widened by half a unit of its
/// last printed decimal (three standard errors for an analysis without intervals).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub ours: Option<f64>,
    pub se: Option<f64>,
    /// our 95 % interval
    pub interval: Option<(f64, f64)>,
    pub paper: Option<f64>,
}

impl Cell {
    /// Half a unit of the last printed decimal of the paper's value.
    fn rounding(p: f64) -> f64 {
        let text = format!("{p}");
        let decimals = text.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
        0.5 * 10f64.powi(-decimals)
    }

    /// Our value lies at the boundary 0 of the support (a mode of T_1, D_k, H_k, whose densities
    /// peak there) while the paper's does not: a relative difference would always read −100 %
    /// and mean nothing (the paper's mode of a density peaking at its edge is the centre of its
    /// first histogram bin), so such a cell is shown, not judged.
    pub fn at_boundary(&self) -> bool {
        self.ours == Some(0.0) && self.paper.is_some_and(|p| p != 0.0)
    }

    /// `Some(true)` if consistent (see the type's docs), `None` without the numbers to judge or
    /// [at the boundary](Cell::at_boundary).
    pub fn consistent(&self) -> Option<bool> {
        if self.at_boundary() {
            return None;
        }
        let p = self.paper?;
        let r = Self::rounding(p);
        match self.interval {
            Some((lo, hi)) => Some(lo - r <= p && p <= hi + r),
            None => Some((self.ours? - p).abs() <= 3.0 * self.se? + r),
        }
    }

    pub fn text(&self, digits: usize) -> String {
        let f = |x: f64| format!("{x:.digits$}");
        match (self.ours, self.interval, self.se) {
            (Some(o), Some((lo, hi)), _) => format!("{} [{} – {}]", f(o), f(lo), f(hi)),
            (Some(o), None, Some(se)) => format!("{} ± {}", f(o), f(se)),
            (Some(o), None, None) => f(o),
            _ => "–".into(),
        }
    }

    /// `ours [lo – hi] (paper) mark`, as both renderings show a cell.
    pub fn shown(&self, digits: usize) -> String {
        let paper = self.paper.map_or(String::new(), |p| format!(" ({p})"));
        format!("{}{paper} {}", self.text(digits), self.mark()).trim_end().to_string()
    }

    pub fn mark(&self) -> String {
        if self.at_boundary() {
            return "boundary".into();
        }
        match (self.consistent(), self.ours, self.paper) {
            (Some(true), _, _) => "✓".into(),
            (Some(false), Some(o), Some(p)) => format!("✗ {:+.1} %", 100.0 * (o / p - 1.0)),
            _ => String::new(),
        }
    }
}

