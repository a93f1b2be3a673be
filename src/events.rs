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

/// Receives the mode changes of one realization, in time order.
pub trait Observer {
    /// A stick begins at time `t` [s] at position `x` [m] (the mass moves with the belt).
    fn stick(&mut self, t: f64, x: f64);
    /// A slip interval begins at time `t` [s] from position `x` [m] and velocity `xdot` [m/s].
    fn slip(&mut self, t: f64, x: f64, xdot: f64);
    /// The grid step [s] at which this observer wants the motion sampled (None: never; only
    /// trajectory sampling asks).
    fn sample_step(&self) -> Option<f64> {
        None
    }
    /// A grid sample at time `t`: position, velocity and belt velocity.
    fn sample(&mut self, _t: f64, _x: f64, _xdot: f64, _v: f64) {}
}

/// Observes nothing.
impl Observer for () {
    fn stick(&mut self, _t: f64, _x: f64) {}
    fn slip(&mut self, _t: f64, _x: f64, _xdot: f64) {}
}

/// The counted stick and slip intervals of one realization.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    pub stick_start: Vec<f64>,
    pub stick_duration: Vec<f64>,
    pub slip_start: Vec<f64>,
    pub slip_duration: Vec<f64>,
    /// The last counted interval was still running at t_a and was cut there.
    pub last_truncated: bool,
    in_stick: bool,
}

impl Record {
    /// Forget the previous realization, keeping the buffers.
    pub fn clear(&mut self) {
        self.stick_start.clear();
        self.stick_duration.clear();
        self.slip_start.clear();
        self.slip_duration.clear();
        self.last_truncated = false;
        self.in_stick = false;
    }

    /// Cut the running interval at the end of the window `t_a`.
    pub fn finish(&mut self, t_end: f64) {
        if self.in_stick {
            self.stick_duration.push(t_end - self.stick_start.last().unwrap());
            self.last_truncated = true;
        } else if let Some(&l) = self.slip_start.last() {
            if self.slip_duration.len() < self.slip_start.len() {
                self.slip_duration.push(t_end - l);
                self.last_truncated = true;
            }
        }
        self.in_stick = false;
    }

    /// S_T
    pub fn n_stick(&self) -> usize {
        self.stick_start.len()
    }

    /// S_L
    pub fn n_slip(&self) -> usize {
        self.slip_start.len()
    }
}

impl Observer for Record {
    fn stick(&mut self, t: f64, _x: f64) {
        if let Some(&l) = self.slip_start.last() {
            if self.slip_duration.len() < self.slip_start.len() {
                self.slip_duration.push(t - l);
            }
        }
        self.stick_start.push(t);
        self.in_stick = true;
    }

    fn slip(&mut self, t: f64, _x: f64, _xdot: f64) {
        if self.in_stick {
            self.stick_duration.push(t - self.stick_start.last().unwrap());
            self.slip_start.push(t);
            self.in_stick = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_from_the_first_stick_and_truncates() {
        let mut r = Record::default();
        r.slip(0.0, 0.0, 0.0);
        r.stick(1.0, 0.0);
        r.slip(1.5, 0.0, 0.0);
        r.stick(2.0, 0.0);
        r.finish(10.0);
        assert_eq!(r.stick_start, [1.0, 2.0]);
        assert_eq!(r.stick_duration, [0.5, 8.0]);
        assert_eq!(r.slip_start, [1.5]);
        assert_eq!(r.slip_duration, [0.5]);
        assert!(r.last_truncated);
    }

    #[test]
    fn never_sticking_records_nothing() {
        let mut r = Record::default();
        r.slip(0.0, 0.0, 0.0);
        r.finish(10.0);
        assert_eq!(r, Record::default());
    }
}
