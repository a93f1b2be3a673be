//! Mode transitions and how they are counted (the paper's section 4).
//!
//! A solver reports each change of mode to an [`Observer`]: "a stick begins at t, at position x"
//! and "a slip interval begins at t". Friction reversals (slip → slip) and grazing touches are
//! not mode changes and are not reported. [`Record`] turns the stream into the paper's
//! quantities:
//!
//! - T_i, D_i: start and duration of the i-th stick, counted from the first stick;
//! - L_i, H_i: start and duration of the i-th slip counted from the slip that follows the first
//!   stick (the slip before the first stick is not counted, so L_1 > T_1);
//! - S_T, S_L: their numbers, S_T − S_L ∈ {0, 1};
//! - the interval still running at t_a is cut at t_a and flagged by `last_truncated`.

pub use crate::solver::{Observer, Release};

/// How a counted stick ended: the `stick_end` column's strings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StickEnd {
    /// the belt changed velocity
    Flip,
    /// the spring force reached the holding limit
    Breakaway,
    /// still stuck at t_a (the duration is censored there)
    Horizon,
}

impl StickEnd {
    /// Every value, in the order of their codes.
    pub const ALL: [StickEnd; 3] = [StickEnd::Flip, StickEnd::Breakaway, StickEnd::Horizon];

    /// The `stick_end` column's string.
    pub const fn name(self) -> &'static str {
        match self {
            StickEnd::Flip => "flip",
            StickEnd::Breakaway => "breakaway",
            StickEnd::Horizon => "horizon",
        }
    }
}

/// The counted stick and slip intervals of one realization, how each stick ended and the
/// state it was entered in, and the extremes of the motion over [0, t_a].
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// T_i: start of each counted stick [s]
    pub stick_start: Vec<f64>,
    /// D_i: duration of each counted stick [s] (the last one cut at t_a when `last_truncated`)
    pub stick_duration: Vec<f64>,
    /// L_i: start of each counted slip [s] (from the slip after the first stick)
    pub slip_start: Vec<f64>,
    /// H_i: duration of each counted slip [s] (the last one cut at t_a when `last_truncated`)
    pub slip_duration: Vec<f64>,
    /// how each counted stick ended
    pub stick_end: Vec<StickEnd>,
    /// x [m] and belt velocity [m/s] at each counted stick's start
    pub stick_entry_position: Vec<f64>,
    /// the belt velocity at each counted stick's start, m/s
    pub stick_entry_velocity: Vec<f64>,
    /// The last counted interval was still running at t_a and was cut there.
    pub last_truncated: bool,
    /// the least and greatest mass velocity ẋ on [0, t_a], m/s
    pub min_velocity: f64,
    /// the greatest mass velocity ẋ on [0, t_a], m/s
    pub max_velocity: f64,
    /// the largest slip speed |v − ẋ| on [0, t_a], m/s (0 for a motion always stuck)
    pub max_slip_speed: f64,
    in_stick: bool,
}

impl Default for Record {
    fn default() -> Record {
        Record {
            stick_start: Vec::new(),
            stick_duration: Vec::new(),
            slip_start: Vec::new(),
            slip_duration: Vec::new(),
            stick_end: Vec::new(),
            stick_entry_position: Vec::new(),
            stick_entry_velocity: Vec::new(),
            last_truncated: false,
            min_velocity: f64::INFINITY,
            max_velocity: f64::NEG_INFINITY,
            max_slip_speed: 0.0,
            in_stick: false,
        }
    }
}

impl Record {
    /// Forget the previous realization, keeping the buffers.
    pub fn clear(&mut self) {
        for v in [&mut self.stick_start, &mut self.stick_duration, &mut self.slip_start, &mut self.slip_duration] {
            v.clear();
        }
        self.stick_end.clear();
        self.stick_entry_position.clear();
        self.stick_entry_velocity.clear();
        self.last_truncated = false;
        (self.min_velocity, self.max_velocity, self.max_slip_speed) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
        self.in_stick = false;
    }

    /// Cut the running interval at the end of the window `t_a`.
    pub fn finish(&mut self, t_end: f64) {
        if self.in_stick {
            self.stick_duration.push(t_end - self.stick_start.last().unwrap());
            self.stick_end.push(StickEnd::Horizon);
            self.last_truncated = true;
        } else if let Some(&l) = self.slip_start.last() {
            if self.slip_duration.len() < self.slip_start.len() {
                self.slip_duration.push(t_end - l);
                self.last_truncated = true;
            }
        }
        self.in_stick = false;
    }

    /// The severity of the oscillation against the forward belt speed `v0` [m/s]: the swing of
    /// the mass velocity over [0, t_a] in units of 2 v₀ (1 for a mass that only follows a
    /// symmetric belt; drilling practice calls (ω_max − ω_min)/(2 ω_mean) the stick-slip
    /// severity).
    pub fn severity(&self, v0: f64) -> f64 {
        (self.max_velocity - self.min_velocity) / (2.0 * v0)
    }

    /// S_T
    pub fn n_stick(&self) -> usize {
        self.stick_start.len()
    }

    /// S_L
    pub fn n_slip(&self) -> usize {
        self.slip_start.len()
    }

    /// The longest counted stick within [0, t_a] (the one cut at t_a counts with its part
    /// inside), s; 0 when there is none.
    pub fn longest_stick(&self) -> f64 {
        self.stick_duration.iter().fold(0.0, |m, &d| if d > m { d } else { m })
    }

    /// The fraction of [0, t_a] spent in counted sticks (the cut one with its part inside).
    pub fn stick_fraction(&self, t_a: f64) -> f64 {
        self.stick_duration.iter().sum::<f64>() / t_a
    }

    /// The first value of the realization's row that is not a finite number or breaks its
    /// column's rule, as (column, value, rule) — the writers' last guard: no dataset, in a file or
    /// in memory, holds NaN or ±∞, nor a severity the analysis cannot take
    /// ([`crate::simulation::columns::SEVERITY_BOUND`]). `severity` is this record's at the run's scale.
    pub fn outside(&self, t_a: f64, severity: f64) -> Option<(&'static str, f64, &'static str)> {
        use crate::simulation::columns as name;
        let finite = "a finite number";
        let lists: [(&'static str, &[f64]); 6] = [
            (name::STICK_START, &self.stick_start),
            (name::STICK_DURATION, &self.stick_duration),
            (name::SLIP_START, &self.slip_start),
            (name::SLIP_DURATION, &self.slip_duration),
            (name::STICK_ENTRY_POSITION, &self.stick_entry_position),
            (name::STICK_ENTRY_VELOCITY, &self.stick_entry_velocity),
        ];
        for (column, values) in lists {
            if let Some(&x) = values.iter().find(|x| !x.is_finite()) {
                return Some((column, x, finite));
            }
        }
        let scalars = [
            (name::MIN_VELOCITY, self.min_velocity),
            (name::MAX_VELOCITY, self.max_velocity),
            (name::MAX_SLIP_SPEED, self.max_slip_speed),
            (name::STICK_FRACTION, self.stick_fraction(t_a)),
        ];
        if let Some((column, x)) = scalars.into_iter().find(|(_, x)| !x.is_finite()) {
            return Some((column, x, finite));
        }
        if !(severity.is_finite() && (0.0..=crate::simulation::columns::SEVERITY_BOUND).contains(&severity)) {
            return Some((name::SEVERITY, severity, "a number in [0, 2^24], the severities the analysis takes"));
        }
        None
    }
}

impl Observer for Record {
    #[inline]
    fn stick(&mut self, t: f64, x: f64, v: f64) {
        if let Some(&l) = self.slip_start.last() {
            if self.slip_duration.len() < self.slip_start.len() {
                self.slip_duration.push(t - l);
            }
        }
        self.stick_start.push(t);
        self.stick_entry_position.push(x);
        self.stick_entry_velocity.push(v);
        self.in_stick = true;
    }

    #[inline]
    fn slip(&mut self, t: f64, _x: f64, _xdot: f64, by: Release) {
        if self.in_stick {
            self.stick_duration.push(t - self.stick_start.last().unwrap());
            self.stick_end.push(if by == Release::Flip { StickEnd::Flip } else { StickEnd::Breakaway });
            self.slip_start.push(t);
            self.in_stick = false;
        }
    }

    fn wants_motion(&self) -> bool {
        true
    }

    #[inline]
    fn motion(&mut self, lo: f64, hi: f64, v: f64) {
        self.min_velocity = self.min_velocity.min(lo);
        self.max_velocity = self.max_velocity.max(hi);
        self.max_slip_speed = self.max_slip_speed.max((hi - v).abs()).max((lo - v).abs());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_from_the_first_stick_and_truncates() {
        let mut r = Record::default();
        r.slip(0.0, 0.0, 0.0, Release::Start);
        r.stick(1.0, 0.25, 1.0);
        r.slip(1.5, 0.0, 0.0, Release::Flip);
        r.stick(2.0, -0.5, -1.0);
        r.finish(10.0);
        assert_eq!(r.stick_start, [1.0, 2.0]);
        assert_eq!(r.stick_duration, [0.5, 8.0]);
        assert_eq!(r.slip_start, [1.5]);
        assert_eq!(r.slip_duration, [0.5]);
        assert_eq!(r.stick_end, [StickEnd::Flip, StickEnd::Horizon]);
        assert_eq!((r.stick_entry_position.as_slice(), r.stick_entry_velocity.as_slice()), (&[0.25, -0.5][..], &[1.0, -1.0][..]));
        assert_eq!((r.longest_stick(), r.stick_fraction(10.0)), (8.0, 0.85));
        assert!(r.last_truncated);
    }

    #[test]
    fn never_sticking_records_nothing() {
        let mut r = Record::default();
        r.slip(0.0, 0.0, 0.0, Release::Start);
        r.finish(10.0);
        assert_eq!(r, Record::default());
    }
}
