//! The exact law's tables, each defined once: file, columns with type and meaning (`exact-law`
//! writes them through [`super::tables`]; `predict` and `report` read them through these).

use crate::table::table;

/// Every table `exact-law` can write, in the order it writes them (`counts` with `--counts`,
/// `densities` and `characteristic` with `--densities`).
pub const ALL: [&crate::table::Def; 9] = [
    &stationary::DEF,
    &convergence::DEF,
    &density::DEF,
    &stick_survival::DEF,
    &moments::DEF,
    &survival::DEF,
    &counts::DEF,
    &densities::DEF,
    &characteristic::DEF,
];

table! {
    /// `stationary.parquet`: the long run.
    stationary = "stationary.parquet", "the long-run quantities, extrapolated from the finest resolutions, each with an error estimate" {
        QUANTITY: "quantity", Str, "stick_fraction, mean_stick_duration, mean_slip_duration, var_stick_duration, … (law::QUANTITIES)";
        VALUE: "value", Float, "its extrapolated value [s, s² or a fraction]";
        ERROR: "error", Float, "its error estimate (from the three resolutions)";
    }
}

table! {
    /// `convergence.parquet` of `exact-law`: every resolution.
    convergence = "convergence.parquet", "every resolution's value of each long-run quantity and Table 1 statistic" {
        RESOLUTION: "resolution", Int, "the resolution n";
        H: "h", Float, "its grid spacing [m]";
        QUANTITY: "quantity", Str, "the long-run quantity, or mean_T_1, variance_T_1, … of Table 1";
        VALUE: "value", Float, "its value at this resolution";
        ITERATIONS: "iterations", Int, "fixed-point iterations (null for Table 1's rows)";
        LOST: "lost", Float, "probability mass lost by the grid";
    }
}

table! {
    /// `density.parquet`: the stationary density of the state.
    density = "density.parquet", "the stationary density of the state (x, velocity): over the plane while slipping, on the belt lines while stuck" {
        KIND: "kind", Str, "slip (a cell of the plane) or stick (a point of a belt line)";
        X: "x", Float, "position [m] (the cell's centre)";
        VELOCITY: "velocity", Float, "velocity [m/s] (the belt's, for stick)";
        DENSITY: "density", Float, "density [1/(m·m/s)] for slip, [1/m] for stick";
    }
}

table! {
    /// `stick_survival.parquet`: a stick's duration in the long run.
    stick_survival = "stick_survival.parquet", "P(D > t) of a stick of the long run" {
        T: "t", Float, "time [s]";
        SURVIVAL: "survival", Float, "P(D > t)";
    }
}

table! {
    /// `moments.parquet` of `exact-law`: Table 1 without sampling.
    moments = "moments.parquet", "Table 1's means and variances of T_k, L_k, D_k, H_k (and S_T, S_L with --counts) with error estimates, in analyze's names" {
        VARIABLE: "variable", Str, "T, L, D, H (indexed), S_T, S_L";
        INDEX: "index", Int, "k, null for S_T and S_L";
        MEAN: "mean", Float, "the mean [s]";
        VARIANCE: "variance", Float, "the variance [s²]";
        ERROR: "error", Float, "error estimate of the mean";
        VARIANCE_ERROR: "variance_error", Float, "error estimate of the variance";
        REACHED_FRACTION: "reached_fraction", Float, "P(the k-th stick starts in [0, t_a]) (with --counts or --densities; null otherwise)";
        WINDOWED_MEAN: "windowed_mean", Float, "the mean conditioned on starting within t_a (with --densities)";
        WINDOWED_ERROR: "windowed_error", Float, "its error estimate";
        WINDOWED_VARIANCE: "windowed_variance", Float, "the variance conditioned on starting within t_a";
        WINDOWED_VARIANCE_ERROR: "windowed_variance_error", Float, "its error estimate";
    }
}

table! {
    /// `survival.parquet` of `exact-law` (and `predict`'s `stick_survival.parquet`).
    survival = "survival.parquet", "P(D_k > t), in analyze's survival columns with the error and the density" {
        VARIABLE: "variable", Str, "D";
        INDEX: "index", Int, "k";
        METHOD: "method", Str, "exact";
        T: "t", Float, "time [s]";
        SURVIVAL: "survival", Float, "P(D_k > t)";
        LO: "lo", Float, "survival − error, within [0, 1]";
        HI: "hi", Float, "survival + error, within [0, 1]";
        ERROR: "error", Float, "error estimate of survival";
        DENSITY: "density", Float, "the density of D_k at t [1/s] (finest resolution)";
        DENSITY_ERROR: "density_error", Float, "its error estimate";
    }
}

table! {
    /// `counts.parquet`: the laws of S_T and S_L (with `--counts`).
    counts = "counts.parquet", "P(S = n) of the counts S_T and S_L" {
        VARIABLE: "variable", Str, "S_T or S_L";
        VALUE: "value", Int, "n";
        PROBABILITY: "probability", Float, "P(S = n)";
        ERROR: "error", Float, "its error estimate";
    }
}

table! {
    /// `densities.parquet`: the densities of T_k, L_k, H_k (with `--densities`).
    densities = "densities.parquet", "the densities of T_k, L_k and H_k averaged over 100 cells of [0, t_a]" {
        VARIABLE: "variable", Str, "T, L or H";
        INDEX: "index", Int, "k";
        T: "t", Float, "the cell's centre [s]";
        T_LO: "t_lo", Float, "the cell's lower edge [s]";
        T_HI: "t_hi", Float, "the cell's upper edge [s]";
        DENSITY: "density", Float, "the density averaged over the cell [1/s]";
        ERROR: "error", Float, "its error estimate";
        POINT_MASS: "point_mass", Float, "the probability of the point masses in the cell (not part of the density)";
    }
}

table! {
    /// `characteristic.parquet`: the characteristic functions the densities come from.
    characteristic = "characteristic.parquet", "the characteristic functions of T_k, L_k, H_k at each resolution (the densities' cosine series)" {
        H: "h", Float, "the resolution's grid spacing [m]";
        VARIABLE: "variable", Str, "T, L or H";
        INDEX: "index", Int, "k";
        J: "j", Int, "the frequency's number (null for a point-mass row)";
        OMEGA: "omega", Float, "the frequency π j / half_period [rad/s]";
        RE: "re", Float, "real part";
        IM: "im", Float, "imaginary part";
        HALF_PERIOD: "half_period", Float, "the cosine series' half period [s]";
        POINT_AT: "point_at", Float, "a point mass's time [s] (point-mass rows)";
        POINT_MASS: "point_mass", Float, "its probability";
    }
}
