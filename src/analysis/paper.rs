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
