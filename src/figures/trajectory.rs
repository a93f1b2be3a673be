//! Fig. 4: one sampled realization — the mass velocity against the belt's, whole window and
//! first 2 s, from the trajectory tables the simulation wrote beside the dataset.

use std::path::Path;

use super::error::FigureError;
use crate::simulation::trajectory::{events, samples, EVENT_NAMES};
use crate::table::Table;

/// One sampled realization (Fig. 4): its grid samples and its events, in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    /// (t [s], ẋ [m/s], belt velocity [m/s])
    pub samples: Vec<[f64; 3]>,
    /// the belt velocity changes: instant [s] and the velocity from then on [m/s]
    pub belt_switches: Vec<(f64, f64)>,
    /// instants the sticks begin [s] (`stick_start` events)
    pub stick_starts: Vec<f64>,
    /// instants the sticks end [s] (`stick_end` events)
    pub stick_ends: Vec<f64>,
}

impl Trajectory {
    /// Realization 0 from the analysis' trajectory tables (`None` without them).
    pub(super) fn load(adir: &Path) -> Result<Option<Trajectory>, FigureError> {
        let [(_, samples), (_, events)] = crate::analysis::output::TRAJECTORY_TABLES;
        let (sp, ep) = (adir.join(samples), adir.join(events));
        if !(sp.is_file() && ep.is_file()) {
            return Ok(None);
        }
        let read = |def: &crate::table::Def, path: &Path| def.read_at(path).map_err(|message| FigureError::Read { path: path.to_owned(), message });
        let (s, e) = (read(&samples::DEF, &sp)?, read(&events::DEF, &ep)?);
        let first = |t: &Table, c| t.int(c).iter().map(|r| *r == Some(0)).collect::<Vec<bool>>();
        let mut out = Trajectory::default();
        let (keep, t, xdot, v) = (first(&s, &samples::REALIZATION), s.float(&samples::T), s.float(&samples::XDOT), s.float(&samples::BELT_VELOCITY));
        for i in (0..keep.len()).filter(|&i| keep[i]) {
            if let (Some(t), Some(x), Some(v)) = (t[i], xdot[i], v[i]) {
                out.samples.push([t, x, v]);
            }
        }
        let (keep, kind, t) = (first(&e, &events::REALIZATION), e.str(&events::EVENT), e.float(&events::T));
        let belt = e.float(&events::BELT_VELOCITY);
        let [switch, start, end] = EVENT_NAMES;
        for i in (0..keep.len()).filter(|&i| keep[i]) {
            let (Some(t), Some(v)) = (t[i], belt[i]) else { continue };
            match kind[i].as_str() {
                k if k == switch => out.belt_switches.push((t, v)),
                k if k == start => out.stick_starts.push(t),
                k if k == end => out.stick_ends.push(t),
                _ => {}
            }
        }
        Ok(Some(out))
    }
}
