//! The analysis tables, each defined once: its file, its columns (name, type, meaning and unit)
//! in order. `analyze` checks what it writes against these definitions, `figures` and `report`
//! read through them (a table of another shape is refused, naming the column), and the
//! documentation is generated from them. A column is named in code by its constant here
//! (`moments::MEAN`), never by a string.

use crate::table::table;

table! {
    /// `moments.parquet`: one row per observable.
    moments = "moments.parquet", "one row per observable: moments with 95 % jackknife intervals, the mode, the range and how many realizations reached it" {
        VARIABLE: "variable", Str, "the observable: T, L, D, H, Y (indexed), S_T, S_L, Q, stick_fraction, longest_stick, severity, breakaways";
        INDEX: "index", Int, "k of an indexed observable (T_k …), null otherwise";
        N: "n", Int, "values the statistics are computed from";
        N_TRUNCATED_EXCLUDED: "n_truncated_excluded", Int, "intervals cut at t_a, left out of D_k and H_k (censored)";
        MEAN: "mean", Float, "sample mean [s for times and durations]";
        VARIANCE: "variance", Float, "unbiased sample variance [s²]";
        MODE: "mode", Float, "kernel-density mode (a count's most frequent value)";
        SKEWNESS: "skewness", Float, "sample skewness";
        KURTOSIS: "kurtosis", Float, "Pearson kurtosis (3 for a normal)";
        MEAN_SE: "mean_se", Float, "standard error of the mean";
        VARIANCE_SE: "variance_se", Float, "standard error of the variance";
        MIN: "min", Float, "smallest value";
        MAX: "max", Float, "largest value";
        MEAN_LO: "mean_lo", Float, "95 % interval of the mean, lower end";
        MEAN_HI: "mean_hi", Float, "95 % interval of the mean, upper end";
        VARIANCE_LO: "variance_lo", Float, "95 % interval of the variance, lower end";
        VARIANCE_HI: "variance_hi", Float, "95 % interval of the variance, upper end";
        MODE_LO: "mode_lo", Float, "95 % interval of the mode, lower end";
        MODE_HI: "mode_hi", Float, "95 % interval of the mode, upper end";
        SKEWNESS_LO: "skewness_lo", Float, "95 % interval of the skewness, lower end";
        SKEWNESS_HI: "skewness_hi", Float, "95 % interval of the skewness, upper end";
        KURTOSIS_LO: "kurtosis_lo", Float, "95 % interval of the kurtosis, lower end";
        KURTOSIS_HI: "kurtosis_hi", Float, "95 % interval of the kurtosis, upper end";
        SKEWNESS_APPROXIMATE: "skewness_approximate", Int, "1 when the skewness interval is approximate (its measured coverage falls below 0.93): the variable's kurtosis is above 3.5";
        KURTOSIS_APPROXIMATE: "kurtosis_approximate", Int, "1 when the kurtosis interval is approximate: kurtosis above 3.5 and fewer than 18,000 realizations";
        REACHED: "reached", Int, "realizations that have the observable (T_k: at least k sticks)";
        REACHED_FRACTION: "reached_fraction", Float, "reached over the realizations analysed";
    }
}

table! {
    /// `histograms.parquet`: one row per bin.
    histograms = "histograms.parquet", "one row per bin of each observable's histogram: densities integrating to 1, a count's PMF on unit bins" {
        VARIABLE: "variable", Str, "the observable (as in moments)";
        INDEX: "index", Int, "k of an indexed observable, null otherwise";
        BIN: "bin", Int, "the bin's number, from 0";
        LO: "lo", Float, "the bin's lower edge";
        HI: "hi", Float, "the bin's upper edge";
        COUNT: "count", Int, "values in the bin";
        DENSITY: "density", Float, "count / (n · width)";
    }
}

table! {
    /// `joint_histograms.parquet`: one row per cell of each pair's joint histogram.
    joint_histograms = "joint_histograms.parquet", "one row per cell of each requested pair's joint histogram, with the product of the marginals on the same grid" {
        X: "x", Str, "the first observable of the pair (T1, D2 …)";
        Y: "y", Str, "the second observable";
        X_BIN: "x_bin", Int, "the cell's bin along x, from 0";
        Y_BIN: "y_bin", Int, "the cell's bin along y, from 0";
        X_LO: "x_lo", Float, "the cell's lower edge along x";
        X_HI: "x_hi", Float, "the cell's upper edge along x";
        Y_LO: "y_lo", Float, "the cell's lower edge along y";
        Y_HI: "y_hi", Float, "the cell's upper edge along y";
        COUNT: "count", Int, "pairs in the cell";
        DENSITY: "density", Float, "joint density: count / (n · area)";
        PRODUCT_DENSITY: "product_density", Float, "product of the two marginal densities (independence)";
    }
}

table! {
    /// `independence.parquet`: one row per pair.
    independence = "independence.parquet", "one row per pair: χ², G and mutual-information tests of independence" {
        X: "x", Str, "the first observable";
        Y: "y", Str, "the second observable";
        N: "n", Int, "pairs tested";
        ROWS: "rows", Int, "rows of the contingency table (after merging sparse cells)";
        COLS: "cols", Int, "columns of the contingency table";
        CHI2: "chi2", Float, "Pearson's χ² statistic";
        DF: "df", Float, "its degrees of freedom";
        CHI2_P_VALUE: "chi2_p_value", Float, "χ² p-value";
        G: "g", Float, "the G (likelihood-ratio) statistic";
        G_P_VALUE: "g_p_value", Float, "G p-value";
        MUTUAL_INFORMATION: "mutual_information", Float, "plug-in mutual information [nats]";
        MI_NULL_MEAN: "mi_null_mean", Float, "its mean under independence, from the permutations [nats]";
        MI_P_VALUE: "mi_p_value", Float, "permutation p-value of the mutual information";
        PERMUTATIONS: "permutations", Int, "permutations drawn";
        VERDICT: "verdict", Str, "independent or dependent at the 5 % level (χ²)";
    }
}

table! {
    /// `growth.parquet`: one row per (variable, statistic).
    growth = "growth.parquet", "least-squares lines of the mean and variance of T_k and L_k over k" {
        VARIABLE: "variable", Str, "T or L";
        STATISTIC: "statistic", Str, "mean or variance";
        SLOPE: "slope", Float, "slope over k [s or s² per stick]";
        INTERCEPT: "intercept", Float, "intercept";
        R2: "r2", Float, "coefficient of determination";
        SLOPE_SE: "slope_se", Float, "standard error of the slope";
        POINTS: "points", Int, "values of k fitted";
        SLOPE_LO: "slope_lo", Float, "95 % interval of the slope, lower end";
        SLOPE_HI: "slope_hi", Float, "95 % interval of the slope, upper end";
        K_MAX: "k_max", Int, "the largest k fitted";
        MIN_REACHED_FRACTION: "min_reached_fraction", Float, "the rule: only the k that at least this fraction of the realizations reach are fitted";
    }
}

table! {
    /// `convergence.parquet`: the running mean at checkpoints.
    convergence = "convergence.parquet", "the running mean of S_T, T_1, D_1, H_1 and its 95 % interval at 10 realization counts per decade" {
        VARIABLE: "variable", Str, "the observable";
        INDEX: "index", Int, "k, null for S_T";
        REALIZATIONS: "realizations", Int, "realizations read so far";
        N: "n", Int, "values among them";
        MEAN: "mean", Float, "the running mean";
        MEAN_LO: "mean_lo", Float, "mean − 1.96 se";
        MEAN_HI: "mean_hi", Float, "mean + 1.96 se";
    }
}

table! {
    /// `survival.parquet`: survival curves of the durations (with the tails).
    survival = "survival.parquet", "P(duration > t) of D_k and H_k (and pooled), by Kaplan–Meier, the naive estimate and the conditional estimator, with 95 % bands" {
        VARIABLE: "variable", Str, "D or H";
        INDEX: "index", Int, "k, null pooled over every interval";
        METHOD: "method", Str, "kaplan_meier, naive or conditional";
        N: "n", Int, "intervals observed (the censored included)";
        N_CENSORED: "n_censored", Int, "intervals cut at t_a";
        T: "t", Float, "time [s]";
        SURVIVAL: "survival", Float, "P(duration > t)";
        LO: "lo", Float, "95 % band, lower end";
        HI: "hi", Float, "95 % band, upper end";
    }
}

table! {
    /// `tails.parquet`: tail statistics (with the tails).
    tails = "tails.parquet", "tail statistics with 95 % intervals: P(severity > s) at each threshold, and the fraction of sticks that end by breakaway" {
        STATISTIC: "statistic", Str, "severity (P(severity > threshold)) or breakaway_fraction";
        THRESHOLD: "threshold", Float, "the severity threshold s, null for breakaway_fraction";
        VALUE: "value", Float, "the estimate";
        LO: "lo", Float, "95 % interval, lower end";
        HI: "hi", Float, "95 % interval, upper end";
        N: "n", Int, "realizations (sticks, for breakaway_fraction) it is estimated from";
    }
}

/// Every analysis table's definition, in the order `analyze` writes them.
pub const ALL: [&crate::table::Def; 8] =
    [&moments::DEF, &histograms::DEF, &joint_histograms::DEF, &independence::DEF, &growth::DEF, &convergence::DEF, &survival::DEF, &tails::DEF];
