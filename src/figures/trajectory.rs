//! Fig. 4: one sampled realization — the mass velocity against the belt's, whole window and
//! first 2 s, from the trajectory tables the simulation wrote beside the dataset.

use std::path::Path;

use super::{Figure, FigureError, Inputs, Panel, Series};
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

/// Fig 4: mass and belt velocity of the first sampled realization, whole window and first 2 s,
/// with belt velocity changes (grey), stick starts (black) and stick ends (green).
pub fn trajectory_figure(inp: &Inputs) -> Option<Figure> {
    let tr = inp.trajectory.as_ref()?;
    let mass: Vec<(f64, f64)> = tr.samples.iter().map(|s| (s[0], s[1])).collect();
    let belt: Vec<(f64, f64)> = tr.samples.iter().map(|s| (s[0], s[2])).collect();
    let flips: Vec<f64> = tr.belt_switches.iter().map(|s| s.0).collect();
    let (starts, ends) = (&tr.stick_starts, &tr.stick_ends);
    // the window ends at t_a, which the last sample may fall short of (samples at 0, dt, …)
    let last = mass.last()?.0;
    let t_a = inp.scenario.run.duration;
    let t_end = if t_a.is_finite() && t_a >= last { t_a } else { last };
    // The belt as an exact step function through its changes (few, truly vertical segments), at
    // the velocity each change records; an older analysis without them alternates between the
    // two velocities sampled (+v_f and −v_r on an asymmetric belt; −v0 when no sample shows the
    // other state).
    let v0 = belt.first()?.1;
    let v1 = belt.iter().map(|b| b.1).find(|v| v.signum() != v0.signum()).unwrap_or(-v0);
    let level = |i: usize| match i.checked_sub(1).map(|j| tr.belt_switches[j].1) {
        None => v0,
        Some(v) if !v.is_nan() => v,
        Some(_) => {
            if i.is_multiple_of(2) {
                v0
            } else {
                v1
            }
        }
    };
    let mut step = vec![(0.0, v0)];
    for (i, &t) in flips.iter().enumerate() {
        step.extend([(t, level(i)), (t, level(i + 1))]);
    }
    step.push((t_end, level(flips.len())));
    // belt velocity just after t (stick starts) or just before t (stick ends, which a flip may cause)
    let after = |t: f64| step.iter().rev().find(|p| p.0 <= t).map_or(v0, |p| p.1);
    let before = |t: f64| step.iter().rev().find(|p| p.0 < t).map_or(v0, |p| p.1);
    fn mark(ts: &[f64], at: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        ts.iter().map(|&t| (t, at(t))).collect()
    }
    let panel = |title: &str, until: f64| {
        let keep = |v: &[(f64, f64)]| v.iter().copied().filter(|p| p.0 <= until).collect::<Vec<_>>();
        // the belt up to the window's end: its corners inside, then its level on to `until`
        // (dropping the corners beyond would end the line at the last flip inside)
        let mut belt_shown = keep(&step);
        if belt_shown.last().is_some_and(|p| p.0 < until) {
            belt_shown.push((until, after(until)));
        }
        // about one sample per pixel column of a 1200-pixel figure
        let shown = keep(&mass);
        let stride = shown.len().div_ceil(1000).max(1);
        Panel {
            title: title.into(),
            x_label: "t [s]".into(),
            y_label: "velocity [m/s]".into(),
            lines: vec![
                Series { label: "mass".into(), color: 0, points: shown.iter().copied().step_by(stride).collect(), ..Default::default() },
                Series { label: "belt".into(), color: 1, points: belt_shown, ..Default::default() },
            ],
            points: vec![
                Series { label: "stick starts".into(), color: 6, points: keep(&mark(starts, after)), ..Default::default() },
                Series { label: "stick ends".into(), color: 2, points: keep(&mark(ends, before)), ..Default::default() },
            ],
            vlines: flips.iter().copied().filter(|&t| t <= until).collect(),
            x_range: Some((0.0, until)),
            ..Default::default()
        }
    };
    Some(Figure {
        name: "fig04_trajectories".into(),
        title: "A realization of the mass velocity (realization 0)".into(),
        rows: 2,
        cols: 1,
        size: (1200, 900),
        panels: vec![panel("(a) whole window", t_end), panel("(b) first 2 s", t_end.min(2.0))],
    })
}
