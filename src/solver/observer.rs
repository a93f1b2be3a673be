//! What a solver reports: the mode changes of one realization, in time order, to an
//! [`Observer`] (the simulation's `Record` counts them; trajectory sampling watches them).

/// What started a slip: the motion at t = 0, a breakaway (the spring force reached the holding
/// limit) or a belt flip (a change of belt velocity ends any stick).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Release {
    /// The motion at t = 0.
    Start,
    /// A breakaway: the spring force reached the holding limit.
    Breakaway,
    /// A belt flip: a change of belt velocity ended the stick.
    Flip,
}

/// Receives the mode changes of one realization, in time order.
pub trait Observer {
    /// A stick begins at time `t` [s] at position `x` [m]; the mass moves with the belt at `v`
    /// [m/s].
    fn stick(&mut self, t: f64, x: f64, v: f64);
    /// A slip interval begins at time `t` [s] from position `x` [m] and velocity `xdot` [m/s];
    /// `by` says what ended the stick before it (if there was one).
    fn slip(&mut self, t: f64, x: f64, xdot: f64, by: Release);
    /// Whether this observer wants [`Observer::motion`] (the solver then computes the ranges).
    fn wants_motion(&self) -> bool {
        false
    }
    /// The velocity ẋ ranged over [`lo`, `hi`] [m/s] on a piece of motion under belt velocity `v`
    /// (pieces cover [0, t_a]; they may overlap).
    fn motion(&mut self, _lo: f64, _hi: f64, _v: f64) {}
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
    fn stick(&mut self, _t: f64, _x: f64, _v: f64) {}
    fn slip(&mut self, _t: f64, _x: f64, _xdot: f64, _by: Release) {}
}
