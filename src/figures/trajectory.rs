//! Fig. 4: one sampled realization — the mass velocity against the belt's, whole window and
//! first 2 s, from the trajectory tables the simulation wrote beside the dataset.

use std::path::Path;

use super::error::FigureError;
use crate::table::Table;

/// One sampled realization (Fig. 4): its grid samples and its events, in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    /// (t [s], ẋ [m/s], belt velocity [m/s])
    pub samples: Vec<[f64; 3]>,
    /// the belt velocity changes: instant [s] and the velocity from then on [m/s] (NaN in an
    /// analysis written before the events carried it: the figure then alternates two levels)
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
        let read = |path: &Path, columns: &[(&str, char)]| {
            Table::read_checked(path, columns).map_err(|e| FigureError::Read { path: path.to_owned(), message: e.to_string() })
        };
        let s = read(&sp, &[("realization", 'i'), ("t", 'f'), ("xdot", 'f'), ("belt_velocity", 'f')])?;
        let e = read(&ep, &[("realization", 'i'), ("event", 's'), ("t", 'f')])?;
        let first = |t: &Table| t.ints("realization").unwrap_or_default().iter().map(|r| *r == Some(0)).collect::<Vec<bool>>();
        let mut out = Trajectory::default();
        let (keep, t, xdot, v) =
            (first(&s), s.floats("t").unwrap_or_default(), s.floats("xdot").unwrap_or_default(), s.floats("belt_velocity").unwrap_or_default());
        for i in (0..keep.len()).filter(|&i| keep[i]) {
            if let (Some(t), Some(x), Some(v)) = (t[i], xdot[i], v[i]) {
                out.samples.push([t, x, v]);
            }
        }
        let (keep, kind, t) = (first(&e), e.strings("event").unwrap_or_default(), e.floats("t").unwrap_or_default());
        let belt = e.floats("belt_velocity").unwrap_or_default();
        for i in (0..keep.len()).filter(|&i| keep[i]) {
            let Some(t) = t[i] else { continue };
            match kind[i].as_str() {
                "belt_switch" => out.belt_switches.push((t, belt.get(i).copied().flatten().unwrap_or(f64::NAN))),
                "stick_start" => out.stick_starts.push(t),
                "stick_end" => out.stick_ends.push(t),
                _ => {}
            }
        }
        Ok(Some(out))
    }
}
