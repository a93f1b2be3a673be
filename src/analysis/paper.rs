//! The paper's reported numbers (Lima & Sampaio, Table 1 and section 4), for comparison only.

use crate::observables::Observable;
use crate::table::Table;

/// (variable, k, mean, variance, mode, skewness, kurtosis) from Table 1.
pub const TABLE1: &[(Observable, [f64; 5])] = &[
    (Observable::StickStart(1), [0.36, 0.13, 0.16, 2.11, 9.73]),
    (Observable::StickStart(2), [0.96, 0.29, 0.63, 1.14, 5.01]),
    (Observable::StickStart(3), [1.55, 0.46, 1.44, 0.83, 4.06]),
    (Observable::StickStart(4), [2.14, 0.62, 1.71, 0.71, 3.83]),
    (Observable::StickStart(5), [2.74, 0.79, 2.83, 0.66, 3.71]),
    (Observable::StickStart(6), [3.34, 0.95, 2.30, 0.62, 3.82]),
    (Observable::SlipStart(1), [0.56, 0.16, 0.19, 1.59, 7.25]),
    (Observable::SlipStart(2), [1.17, 0.34, 0.73, 1.03, 4.59]),
    (Observable::SlipStart(3), [1.75, 0.49, 1.88, 0.79, 3.96]),
    (Observable::SlipStart(4), [2.34, 0.65, 2.075, 0.71, 3.79]),
    (Observable::SlipStart(5), [2.94, 0.81, 2.73, 0.63, 3.65]),
    (Observable::SlipStart(6), [3.54, 0.98, 3.02, 0.616, 3.77]),
    (Observable::StickDuration(1), [0.20, 0.04, 0.19, 1.72, 6.76]),
    (Observable::StickDuration(2), [0.20, 0.04, 0.01, 1.87, 7.65]),
    (Observable::StickDuration(3), [0.20, 0.04, 0.01, 1.92, 8.23]),
    (Observable::StickDuration(4), [0.20, 0.04, 0.01, 1.97, 9.07]),
    (Observable::StickDuration(5), [0.20, 0.04, 0.07, 1.83, 7.40]),
    (Observable::StickDuration(6), [0.20, 0.04, 0.01, 1.75, 7.09]),
    (Observable::SlipDuration(1), [0.39, 0.13, 0.016, 1.79, 8.80]),
    (Observable::SlipDuration(2), [0.38, 0.12, 0.001, 1.75, 8.15]),
    (Observable::SlipDuration(3), [0.39, 0.12, 0.001, 1.77, 8.36]),
    (Observable::SlipDuration(4), [0.39, 0.13, 0.001, 1.77, 8.04]),
    (Observable::SlipDuration(5), [0.40, 0.13, 0.014, 1.94, 9.84]),
    (Observable::SlipDuration(6), [0.39, 0.13, 0.013, 1.97, 9.99]),
];

/// (variable, mean, variance) of the counts, section 4.
pub const COUNTS: &[(Observable, f64, f64)] = &[(Observable::Sticks, 16.71, 7.94), (Observable::Slips, 16.54, 7.89)];

/// One cell of the comparison: ours with its 95 % interval (or ± se) against the paper's
/// printed value; ✓ when the paper's value lies inside our interval widened by half a unit of its
/// last printed decimal (three standard errors for an analysis without intervals).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// our value
    pub ours: Option<f64>,
    /// its standard error (mean and variance only)
    pub se: Option<f64>,
    /// our 95 % interval
    pub interval: Option<(f64, f64)>,
    /// the paper's printed value (None when not compared or not printed)
    pub paper: Option<f64>,
    /// the interval is approximate (its measured coverage falls below 0.93: the moments table's
    /// `skewness_approximate`, `kurtosis_approximate`): shown, not judged
    pub approximate: bool,
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

    /// `Some(true)` if consistent (see the type's docs), `None` without the numbers to judge,
    /// [at the boundary](Cell::at_boundary) or with an [approximate](Cell::approximate) interval.
    pub fn consistent(&self) -> Option<bool> {
        if self.at_boundary() || self.approximate {
            return None;
        }
        let p = self.paper?;
        let r = Self::rounding(p);
        match self.interval {
            Some((lo, hi)) => Some(lo - r <= p && p <= hi + r),
            None => Some((self.ours? - p).abs() <= 3.0 * self.se? + r),
        }
    }

    /// Our value with its interval (`v [lo – hi]`), or `v ± se`, to `digits` decimals; `–` without
    /// one.
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

    /// `✓`, `✗ ±x.x %` (our value's difference from the paper's), `boundary`, `≈` (an approximate
    /// interval beside a paper value), or empty when nothing is judged.
    pub fn mark(&self) -> String {
        if self.at_boundary() {
            return "boundary".into();
        }
        if self.approximate && self.paper.is_some() && self.interval.is_some() {
            return "≈".into();
        }
        match (self.consistent(), self.ours, self.paper) {
            (Some(true), _, _) => "✓".into(),
            (Some(false), Some(o), Some(p)) => format!("✗ {:+.1} %", 100.0 * (o / p - 1.0)),
            _ => String::new(),
        }
    }
}

/// A row of Table 1: series label and (mean, variance, mode, skewness, kurtosis) cells.
#[derive(Debug, Clone)]
pub struct Row {
    /// the observable's name (e.g. `T_1`, `S_T`)
    pub label: String,
    /// values the statistics are computed from (column `n` of `moments.parquet`)
    pub n: i64,
    /// mean, variance, mode, skewness, kurtosis
    pub cells: [Cell; 5],
    /// a count (S_T, S_L): its mode is an integer, and so are the bounds of its interval
    pub count: bool,
}

impl Row {
    /// Cell `i` as shown (`ours [lo – hi] (paper) mark`) and whether it agrees with the paper's
    /// (`None`: nothing to judge, or nothing a reader should be alarmed by).
    ///
    /// A count's mode prints as the integer it is (`16 [13 – 19]`); a mode at the boundary 0 is
    /// shown, not judged ([`Cell::at_boundary`]).
    pub fn shown(&self, i: usize, digits: usize) -> (String, Option<bool>) {
        let c = &self.cells[i];
        let digits = if i == 2 && self.count { 0 } else { digits };
        (c.shown(digits), c.consistent())
    }
}

/// Table 1 from an analysis' moments table (`moments.parquet`), beside the paper's values when
/// `compare` (the dataset is of the paper's scene, [`crate::scenario::Scenario::is_paper_scene`]):
/// built once, for `table1.md`, the printed table and the report alike.
pub fn table1(moments: &Table, compare: bool) -> Vec<Row> {
    use super::tables::moments as m;
    let (vars, idx, n) = (moments.str(&m::VARIABLE), moments.int(&m::INDEX), moments.int(&m::N));
    let col = |c: &crate::table::Column| moments.float(c);
    let (mean, var, mode, skew, kurt, mse, vse) =
        (col(&m::MEAN), col(&m::VARIANCE), col(&m::MODE), col(&m::SKEWNESS), col(&m::KURTOSIS), col(&m::MEAN_SE), col(&m::VARIANCE_SE));
    let iv: Vec<(&[Option<f64>], &[Option<f64>])> = [
        (m::MEAN_LO, m::MEAN_HI),
        (m::VARIANCE_LO, m::VARIANCE_HI),
        (m::MODE_LO, m::MODE_HI),
        (m::SKEWNESS_LO, m::SKEWNESS_HI),
        (m::KURTOSIS_LO, m::KURTOSIS_HI),
    ]
    .iter()
    .map(|(lo, hi)| (col(lo), col(hi)))
    .collect();
    // (per cell: the flag of its interval; mean, variance and mode have none; an analysis from
    // before the flags has no such columns and reads as not approximate)
    let (no_flag, skew_flag, kurt_flag) = (&[][..], moments.int(&m::SKEWNESS_APPROXIMATE), moments.int(&m::KURTOSIS_APPROXIMATE));
    let approx: [&[Option<i64>]; 5] = [no_flag, no_flag, no_flag, skew_flag, kurt_flag];
    let mut rows = Vec::new();
    let wanted = TABLE1.iter().map(|(o, p)| (*o, Some(*p))).chain(COUNTS.iter().map(|(o, m, s2)| (*o, Some([*m, *s2, f64::NAN, f64::NAN, f64::NAN]))));
    for (o, p) in wanted {
        let Some(r) = (0..vars.len()).find(|&r| vars[r] == o.variable() && idx.get(r).copied().flatten() == o.index().map(i64::from)) else { continue };
        let pv = |i: usize| p.filter(|_| compare).map(|p| p[i]).filter(|x| x.is_finite());
        let interval = |i: usize| iv[i].0.get(r).copied().flatten().zip(iv[i].1.get(r).copied().flatten());
        let approximate = |i: usize| approx.get(i).and_then(|c| c.get(r).copied().flatten()) == Some(1);
        let cell = |ours: Option<f64>, se: Option<f64>, i: usize| Cell { ours, se, interval: interval(i), paper: pv(i), approximate: approximate(i) };
        // a column the table lacks reads as no value, never as an index out of bounds
        let at = |c: &[Option<f64>]| c.get(r).copied().flatten();
        // (a count's mode interval is stored rounded outward to integers, `SeriesStats::mode_interval`)
        let count = o.is_count();
        let mode_cell = cell(at(mode), None, 2);
        rows.push(Row {
            label: o.name(),
            n: n.get(r).copied().flatten().unwrap_or(0),
            cells: [cell(at(mean), at(mse), 0), cell(at(var), at(vse), 1), mode_cell, cell(at(skew), None, 3), cell(at(kurt), None, 4)],
            count,
        });
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_approximate_interval_is_shown_not_judged() {
        let cell = |approximate| Cell { ours: Some(2.0), se: None, interval: Some((1.9, 2.1)), paper: Some(3.0), approximate };
        assert_eq!(cell(false).consistent(), Some(false));
        assert!(cell(false).mark().starts_with('✗'));
        assert_eq!(cell(true).consistent(), None);
        assert_eq!(cell(true).mark(), "≈");
        assert_eq!(cell(true).shown(1), "2.0 [1.9 – 2.1] (3) ≈");
        // without a paper value there is nothing to mark
        assert_eq!(Cell { paper: None, ..cell(true) }.mark(), "");
    }
}
