//! The statistics of the whole process that are not one realization's value: the long-run
//! quantities of the exact law (`stationary.parquet`), the variables `predict` gives the law of
//! (`prediction.parquet`), and the tails' exceedance fractions. Their names are made here and
//! nowhere else; the per-realization quantities are [`super::Observable`]s.

/// A statistic of the process, by the name its tables give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Statistic {
    /// the long-run fraction of time stuck
    StickFraction,
    /// the long-run mean stick duration [s]
    MeanStickDuration,
    /// the long-run mean slip duration [s]
    MeanSlipDuration,
    /// the long-run variance of the stick duration [s²]
    VarStickDuration,
    /// the long-run variance of the slip duration [s²]
    VarSlipDuration,
    /// sticks per unit time in the long run [1/s]
    SticksPerSecond,
    /// the fraction of sticks that end by breakaway (long run, or over a dataset's sticks)
    BreakawayFraction,
    /// the mean stick + slip cycle [s]
    MeanCycle,
    /// R: the rest of the current stick, from a stuck state [s]
    RemainingStick,
    /// τ: the time to the next stick's start [s]
    TimeToStick,
    /// D: the duration of the next stick [s]
    StickDuration,
    /// H: the duration of the slip after the next stick [s]
    SlipDuration,
    /// 1 if the next stick ends by breakaway, else 0 (its mean is the probability)
    Breakaway,
}

impl Statistic {
    /// The long-run quantities of the exact law, in the order of `stationary.parquet`.
    pub const LONG_RUN: [Statistic; 8] = [
        Statistic::StickFraction,
        Statistic::MeanStickDuration,
        Statistic::MeanSlipDuration,
        Statistic::VarStickDuration,
        Statistic::VarSlipDuration,
        Statistic::SticksPerSecond,
        Statistic::BreakawayFraction,
        Statistic::MeanCycle,
    ];

    /// The variables `predict` gives the law of, in the order of `prediction.parquet`.
    pub const PREDICTED: [Statistic; 5] =
        [Statistic::RemainingStick, Statistic::TimeToStick, Statistic::StickDuration, Statistic::SlipDuration, Statistic::Breakaway];

    /// The name its tables give it.
    pub const fn name(self) -> &'static str {
        match self {
            Statistic::StickFraction => "stick_fraction",
            Statistic::MeanStickDuration => "mean_stick_duration",
            Statistic::MeanSlipDuration => "mean_slip_duration",
            Statistic::VarStickDuration => "var_stick_duration",
            Statistic::VarSlipDuration => "var_slip_duration",
            Statistic::SticksPerSecond => "sticks_per_second",
            Statistic::BreakawayFraction => "breakaway_fraction",
            Statistic::MeanCycle => "mean_cycle",
            Statistic::RemainingStick => "remaining_stick",
            Statistic::TimeToStick => "time_to_stick",
            Statistic::StickDuration => "stick_duration",
            Statistic::SlipDuration => "slip_duration",
            Statistic::Breakaway => "breakaway",
        }
    }
}

/// The names of `statistics`, in order (for the `const` lists of the tables that use them).
pub const fn names<const N: usize>(statistics: [Statistic; N]) -> [&'static str; N] {
    let mut out = [""; N];
    let mut i = 0;
    while i < N {
        out[i] = statistics[i].name();
        i += 1;
    }
    out
}
