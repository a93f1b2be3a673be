//! The dataset's column names, the ones the readers and the writers' guard use (the contract's),
//! and the largest severity a dataset may hold: below [`super::events`] and [`super::schema`],
//! which both name them.

/// `int64`: the global realization index 0..N−1
pub const REALIZATION: &str = "realization";
/// `int64`: Q, the belt velocity changes in [0, t_a]
pub const N_SWITCHES: &str = "n_switches";
/// `int64`: S_T, the number of sticks
pub const N_STICK: &str = "n_stick";
/// `int64`: S_L, the number of slips
pub const N_SLIP: &str = "n_slip";
/// `bool`: the last interval was cut at t_a (its duration is censored)
pub const LAST_TRUNCATED: &str = "last_truncated";
/// `list<float64>`: T_1..T_{S_T}, the stick start instants [s]
pub const STICK_START: &str = "stick_start";
/// `list<float64>`: D_1..D_{S_T}, the stick durations [s]
pub const STICK_DURATION: &str = "stick_duration";
/// `list<float64>`: L_1..L_{S_L}, the slip start instants [s] (from the slip after the first
/// stick)
pub const SLIP_START: &str = "slip_start";
/// `list<float64>`: H_1..H_{S_L}, the slip durations [s]
pub const SLIP_DURATION: &str = "slip_duration";
/// `list<float64>`: Y_1..Y_Q, the belt velocity change instants [s] (only with
/// `output.switch_times`)
pub const SWITCH_TIMES: &str = "switch_times";
/// `list<float64>`: the belt velocity after each change [m/s] (with `switch_times`)
pub const SWITCH_VELOCITIES: &str = "switch_velocities";
/// `float64`: the belt velocity at t = 0⁺ [m/s] (schema v3)
pub const INITIAL_VELOCITY: &str = "initial_velocity";
/// `list<utf8>`: how each stick ended, `flip`, `breakaway` or `horizon` (schema v3)
pub const STICK_END: &str = "stick_end";
/// `list<float64>`: x at each stick's start [m] (schema v3)
pub const STICK_ENTRY_POSITION: &str = "stick_entry_position";
/// `list<float64>`: the belt velocity at each stick's start [m/s] (schema v3)
pub const STICK_ENTRY_VELOCITY: &str = "stick_entry_velocity";
/// `float64`: the longest stick within [0, t_a] [s], the cut one counted for its time in the
/// window (schema v3)
pub const LONGEST_STICK: &str = "longest_stick";
/// `float64`: the fraction of [0, t_a] spent stuck (schema v3)
pub const STICK_FRACTION: &str = "stick_fraction";
/// `float64`: the least mass velocity ẋ over [0, t_a] [m/s] (schema v3)
pub const MIN_VELOCITY: &str = "min_velocity";
/// `float64`: the greatest mass velocity ẋ over [0, t_a] [m/s] (schema v3)
pub const MAX_VELOCITY: &str = "max_velocity";
/// `float64`: the largest slip speed |v − ẋ| over [0, t_a] [m/s] (schema v3)
pub const MAX_SLIP_SPEED: &str = "max_slip_speed";
/// `float64`: (max_velocity − min_velocity)/(2 v0), v0 the forward belt speed: the stick-slip
/// severity (schema v3)
pub const SEVERITY: &str = "severity";

/// `float64`: a chain's anchor force T = k₁ (a − x₁) + c₁ (u − ẋ₁) averaged over [0, t_a] [N]
/// (schema v4, chains only)
pub const ANCHOR_FORCE_MEAN: &str = "anchor_force_mean";
/// `float64`: the least anchor force over [0, t_a] [N] (schema v4, chains only)
pub const ANCHOR_FORCE_MIN: &str = "anchor_force_min";
/// `float64`: the greatest anchor force over [0, t_a] [N] (schema v4, chains only)
pub const ANCHOR_FORCE_MAX: &str = "anchor_force_max";
/// `float64`: the contact mass's mean velocity (x_N(t_a) − x_N(0))/t_a [m/s] (schema v4,
/// chains only)
pub const MEAN_VELOCITY: &str = "mean_velocity";

/// A chain realization's columns with their values (the writers' guard checks them).
pub fn chain_values(c: &crate::chain::ChainSummary) -> [(&'static str, f64); 4] {
    [(ANCHOR_FORCE_MEAN, c.anchor_force_mean), (ANCHOR_FORCE_MIN, c.anchor_force_min), (ANCHOR_FORCE_MAX, c.anchor_force_max), (MEAN_VELOCITY, c.mean_velocity)]
}

/// Each list column with the count column of its length, and whether its values are start
/// instants (in increasing order); `switch_times` is present only when the scenario asks.
pub const LISTS: [(&str, &str, bool); 5] = [
    (STICK_START, N_STICK, true),
    (STICK_DURATION, N_STICK, false),
    (SLIP_START, N_SLIP, true),
    (SLIP_DURATION, N_SLIP, false),
    (SWITCH_TIMES, N_SWITCHES, true),
];

/// The largest severity a dataset may hold, 2^24 ≈ 1.7e7 (a rule of the dataset: `simulate`
/// refuses at the door a scene whose initial state implies more, and its writers refuse a
/// realization past it; `analyze` checks it). The analysis' dyadic histograms start at width
/// 2^(24 − 40) = 2^−16 and pack bin indices below 2^42, which holds every value up to 2^26; the
/// paper scene's severities (1 to 1.26) are binned at 2^−13, as under the earlier bound 1024.
pub const SEVERITY_BOUND: f64 = 16_777_216.0;
