//! The exact law's figures (`exact-law`): the stationary density of the state, and the
//! densities of T_k, L_k and H_k, from the law's data ([`crate::law`]).

use super::chart::{Figure, Panel, Series};
use crate::law::densities::DensityRow;
use crate::law::density::Density;
use crate::law::sticks::STICKS;

/// `stationary_density.png`: the slip density over (x, ẋ) and the stick lines' densities.
pub fn stationary_density(d: &Density) -> Figure {
    let n = d.x_edges.len() - 1;
    let m = d.v_edges.len() - 1;
    let heat = (0..n * m)
        .map(|k| {
            let (i, j) = (k / m, k % m);
            [d.x_edges[i], d.x_edges[i + 1], d.v_edges[j], d.v_edges[j + 1], d.slip[k]]
        })
        .collect();
    let line = |k: usize, label: String, color: usize| Series {
        label,
        color,
        points: d.stick_centres(k).into_iter().zip(d.stick[k].iter().copied()).collect(),
        errors: vec![],
    };
    // the axes over the cells above 1e-3 of the largest (the table has them all)
    let top = d.slip.iter().copied().fold(0.0, f64::max);
    let seen = |axis: usize| {
        let edges = if axis == 0 { &d.x_edges } else { &d.v_edges };
        let reach = (0..n * m)
            .filter(|&k| d.slip[k] > 1e-3 * top)
            .map(|k| if axis == 0 { k / m } else { k % m })
            .map(|i| edges[i].abs().max(edges[i + 1].abs()))
            .fold(0.0, f64::max);
        Some((-reach, reach))
    };
    let plane = Panel {
        title: "while slipping".into(),
        x_range: seen(0),
        y_range: seen(1),
        x_label: "x [m]".into(),
        y_label: "velocity [m/s]".into(),
        heat,
        heat_label: "density [1/(m m/s)]".into(),
        ..Default::default()
    };
    let sticks = Panel {
        title: "while stuck (on the belt)".into(),
        x_label: "x [m]".into(),
        y_label: "density [1/m]".into(),
        lines: vec![line(0, format!("velocity = +{} m/s", d.velocities[0]), 0), line(1, format!("velocity = {} m/s", d.velocities[1]), 1)],
        ..Default::default()
    };
    Figure {
        name: "stationary_density".into(),
        title: "Stationary law of the state (x, velocity), without sampling".into(),
        rows: 1,
        cols: 2,
        size: (1400, 620),
        panels: vec![plane, sticks],
    }
}

/// `densities.png`: one panel per variable (T_k, L_k, H_k), the cell averages of k = 1 … 6 as
/// lines through the cells' centres.
pub fn densities(rows: &[DensityRow]) -> Figure {
    let names = [("T", "stick starts T_k"), ("L", "slip starts L_k"), ("H", "slip durations H_k")];
    let panels = names
        .iter()
        .map(|(v, title)| {
            let lines = (1..=STICKS as u32)
                .map(|k| Series {
                    label: format!("k = {k}"),
                    color: k as usize - 1,
                    points: rows.iter().filter(|r| r.variable == *v && r.index == k).map(|r| (0.5 * (r.t_lo + r.t_hi), r.density)).collect(),
                    errors: vec![],
                })
                .collect();
            // the axis over the cells above 1e-3 of the panel's largest (the table has them all)
            let mine: Vec<&DensityRow> = rows.iter().filter(|r| r.variable == *v).collect();
            let top = mine.iter().map(|r| r.density).fold(0.0, f64::max);
            let reach = mine.iter().filter(|r| r.density > 1e-3 * top).map(|r| r.t_hi).fold(0.0, f64::max);
            let x_range = (reach > 0.0).then_some((0.0, reach));
            Panel { title: title.to_string(), x_label: "t [s]".into(), y_label: "density [1/s]".into(), lines, x_range, ..Default::default() }
        })
        .collect();
    Figure {
        name: "densities".into(),
        title: "Densities without sampling (averaged over the cells of [0, t_a])".into(),
        rows: 1,
        cols: 3,
        size: (1800, 560),
        panels,
    }
}
