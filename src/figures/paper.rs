//! The paper's figures (Figs. 2, 5–14), the convergence figure and a sweep's figure, each built
//! as data from the analysis tables ([`super::inputs::Inputs`]).

use super::chart::{Figure, Panel, Series};
use super::inputs::Inputs;
use super::{contour, format, tails};
use crate::analysis::tables::{convergence, growth, independence, joint_histograms, moments};
use crate::observables::Observable;
use crate::special::ln_gamma;
use crate::table::{Column, Table};

fn poisson_pmf(mean: f64, q: u32) -> f64 {
    if mean == 0.0 {
        return if q == 0 { 1.0 } else { 0.0 };
    }
    (q as f64 * mean.ln() - mean - ln_gamma(q as f64 + 1.0)).exp()
}

/// A probability mass function from unit-bin histogram rows (lo, hi, probability): a stem at
/// each integer.
fn pmf_stems(bars: &[(f64, f64, f64)], label: &str, color: usize) -> Series {
    let points = bars.iter().filter(|b| b.2 > 0.0).map(|&(lo, hi, p)| (0.5 * (lo + hi), p)).collect();
    Series { label: label.into(), color, points, ..Default::default() }
}

fn histogram_panel(title: String, x_label: &str, bars: Vec<(f64, f64, f64)>) -> Panel {
    Panel { title, x_label: x_label.into(), y_label: "density".into(), bars, ..Default::default() }
}

/// Figs 6, 9, 10, 12, 14: the densities of X_1..X_6 on a 2 × 3 grid.
pub fn indexed_histograms(inp: &Inputs, var: &str, name: &str, what: &str) -> Option<Figure> {
    let panels: Vec<Panel> = (1..=6).map(|k| histogram_panel(format!("{var}_{k}"), &format!("{var}_{k} [s]"), inp.histogram(var, Some(k)))).collect();
    panels.iter().any(|p| !p.bars.is_empty()).then(|| Figure {
        name: name.into(),
        title: format!("Normalized histograms of {what}"),
        rows: 2,
        cols: 3,
        size: (1200, 720),
        panels,
    })
}

/// Fig 2: the Poisson PMF of the number of belt flips for several λ t_a (and the scenario's).
pub fn poisson_figure(inp: &Inputs) -> Figure {
    let mut means = vec![1.0, 5.0, 20.0, 50.0];
    if let Some(own) = inp.scenario.poisson_mean().filter(|m| !means.contains(m)) {
        means.push(own);
    }
    let top = means.iter().fold(0.0f64, |m, &x| m.max(x + 4.0 * x.sqrt() + 4.0)).min(1000.0) as u32;
    // a PMF lives on the integers: markers on stems, not a line through them
    let stems = means
        .iter()
        .enumerate()
        .map(|(i, &m)| Series {
            label: format!("λ t_a = {m}"),
            color: i,
            points: (0..=top).map(|q| (q as f64, poisson_pmf(m, q))).filter(|&(_, p)| p >= 1e-5).collect(),
            ..Default::default()
        })
        .collect();
    Figure {
        name: "fig02_poisson_pmf".into(),
        title: "Probability mass function of Q ~ Poisson(λ t_a)".into(),
        rows: 1,
        cols: 1,
        size: (800, 520),
        panels: vec![Panel { x_label: "q".into(), y_label: "Pr(Q = q)".into(), stems, ..Default::default() }],
    }
}

/// Fig 5: the histogram of Q with the Poisson PMF of mean λ t_a.
pub fn q_figure(inp: &Inputs) -> Option<Figure> {
    let bars = inp.histogram("Q", None);
    let (lo, hi) = (bars.first()?.0, bars.last()?.1);
    let observed = pmf_stems(&bars, "observed", 0);
    // the Poisson law holds for the paper's belt at a fixed rate (not for a telegraph belt or a
    // random rate): no overlay otherwise
    let mean = inp.scenario.poisson_mean();
    let pmf = mean.map(|m| (lo.ceil().max(0.0) as u32..=hi.floor() as u32).map(|q| (q as f64, poisson_pmf(m, q))).collect());
    Some(Figure {
        name: "fig05_q".into(),
        title: "Number of belt velocity changes Q".into(),
        rows: 1,
        cols: 1,
        size: (800, 520),
        panels: vec![Panel {
            x_label: "Q".into(),
            y_label: "probability".into(),
            stems: vec![observed],
            points: mean.zip(pmf).map(|(m, points)| Series { label: format!("Poisson({m})"), color: 1, points, ..Default::default() }).into_iter().collect(),
            ..Default::default()
        }],
    })
}

/// Fig 7: the variance of T_k and L_k against k, with the OLS line.
pub fn growth_figure(inp: &Inputs) -> Option<Figure> {
    let g = &inp.growth;
    let (vars, stats) = (g.str(&growth::VARIABLE), g.str(&growth::STATISTIC));
    let (slope, icpt, r2) = (g.float(&growth::SLOPE), g.float(&growth::INTERCEPT), g.float(&growth::R2));
    let panels: Vec<Panel> = ["T", "L"]
        .iter()
        .filter_map(|&var| {
            let r = (0..g.height()).find(|&r| vars[r] == var && stats[r] == "variance")?;
            let pts: Vec<(f64, f64)> = (1..=64).filter_map(|k| Some((k as f64, inp.moment(var, Some(k), &moments::VARIANCE)?))).collect();
            let (a, b) = (icpt[r]?, slope[r]?);
            // the line over the indices it was fitted on (those most realizations reach); older
            // tables without `k_max` were fitted on every index shown
            let fitted = g.int(&growth::K_MAX)[r].map(|k| k as f64);
            let kmax = fitted.unwrap_or(pts.last()?.0);
            let reach = fitted.filter(|&k| k < pts.last().map_or(0.0, |p| p.0)).map_or(String::new(), |k| format!(", fitted on k ≤ {k}"));
            Some(Panel {
                title: format!("Var {var}_k = {a:.3} + {b:.3} k   (R² = {:.4}{reach})", r2[r].unwrap_or(f64::NAN)),
                x_label: "k".into(),
                y_label: format!("variance of {var}_k [s²]"),
                points: vec![Series { label: "sample variance".into(), color: 0, points: pts, ..Default::default() }],
                lines: vec![Series { label: "OLS fit".into(), color: 1, points: vec![(1.0, a + b), (kmax, a + b * kmax)], ..Default::default() }],
                ..Default::default()
            })
        })
        .collect();
    (!panels.is_empty()).then(|| Figure {
        name: "fig07_variance_growth".into(),
        title: "Variance of the instants at which sticks (a) and slips (b) start".into(),
        rows: 1,
        cols: panels.len(),
        size: (1200, 500),
        panels,
    })
}

/// Fig 8: the distributions of S_T and S_L.
pub fn counts_figure(inp: &Inputs) -> Figure {
    let panel = |var: &str, what: &str| Panel {
        title: format!(
            "{var}: mean {:.2}, variance {:.2}",
            inp.moment(var, None, &moments::MEAN).unwrap_or(f64::NAN),
            inp.moment(var, None, &moments::VARIANCE).unwrap_or(f64::NAN)
        ),
        x_label: what.into(),
        y_label: "probability".into(),
        stems: vec![pmf_stems(&inp.histogram(var, None), "", 0)],
        ..Default::default()
    };
    Figure {
        name: "fig08_counts".into(),
        title: "Number of time intervals with stick (a) and slip (b)".into(),
        rows: 1,
        cols: 2,
        size: (1200, 500),
        panels: vec![panel(Observable::Sticks.variable(), "S_T (sticks)"), panel(Observable::Slips.variable(), "S_L (slips)")],
    }
}

/// Figs 11 and 13: joint density of a pair beside the product of its marginals.
pub fn joint_figure(inp: &Inputs, x: &str, y: &str, name: &str) -> Option<Figure> {
    let j = &inp.joints;
    let (xs, ys) = (j.str(&joint_histograms::X), j.str(&joint_histograms::Y));
    let col = |c: &crate::table::Column| j.floats(c.name);
    let (x0, x1, y0, y1) = (col(&joint_histograms::X_LO)?, col(&joint_histograms::X_HI)?, col(&joint_histograms::Y_LO)?, col(&joint_histograms::Y_HI)?);
    let (dens, prod) = (col(&joint_histograms::DENSITY)?, col(&joint_histograms::PRODUCT_DENSITY)?);
    let rows: Vec<usize> = (0..j.height()).filter(|&r| xs[r] == x && ys[r] == y).collect();
    if rows.is_empty() {
        return None;
    }
    let cells = |v: &[Option<f64>]| -> Vec<[f64; 5]> {
        rows.iter().filter_map(|&r| Some([x0[r]?, x1[r]?, y0[r]?, y1[r]?, v[r]?])).filter(|c| c.iter().all(|x| x.is_finite())).collect()
    };
    let it = &inp.independence;
    let test = (0..it.height())
        .find(|&r| it.str(&independence::X)[r] == x && it.str(&independence::Y)[r] == y)
        .map(|r| {
            let p = |c: &crate::table::Column| format::p_relation(it.float(c).get(r).copied().flatten().unwrap_or(f64::NAN));
            let verdict = it.str(&independence::VERDICT)[r].clone();
            format!(
                ": χ² p {}, G p {}, MI permutation p {} → {verdict}",
                p(&independence::CHI2_P_VALUE),
                p(&independence::G_P_VALUE),
                p(&independence::MI_P_VALUE)
            )
        })
        .unwrap_or_default();
    // one colour scale for both panels, so that they compare cell by cell, taken from this
    // pair's cells alone: the pairs' densities differ by an order of magnitude (T_1, T_2 peak
    // near 2 /s², D_1, D_2 near 13 /s²), so a scale shared across figures washes one out and
    // saturates the other
    let (joint, product) = (cells(dens), cells(prod));
    let (top, above) = colour_top(&[&joint, &product]);
    let heat_label = if above > 0.0 {
        let share = if above < 0.001 { "< 0.1".to_string() } else { format!("{:.1}", 100.0 * above) };
        format!("density [1/s²] ({share} % of non-empty cells above the top)")
    } else {
        "density [1/s²]".to_string()
    };
    // contours at the same levels in both panels, of the lightly smoothed field (as the paper's
    // Fig. 11); the cells themselves are drawn unsmoothed
    let grids = [&joint, &product].map(|c| contour::Grid::from_cells(c).smoothed());
    let smax = grids.iter().flat_map(|g| g.z.iter().flatten()).copied().fold(0.0, f64::max);
    let levels = [0.05, 0.15, 0.3, 0.5, 0.75].map(|f| f * smax);
    let panel = |title: &str, heat: Vec<[f64; 5]>, grid: &contour::Grid| Panel {
        title: title.into(),
        x_label: format!("{x} [s]"),
        y_label: format!("{y} [s]"),
        contours: levels.iter().flat_map(|&l| grid.contour(l)).collect(),
        heat,
        heat_max: Some(top),
        heat_label: heat_label.clone(),
        ..Default::default()
    };
    Some(Figure {
        name: name.into(),
        title: format!("({x}, {y}){test}"),
        rows: 1,
        cols: 2,
        size: (1300, 600),
        panels: vec![panel("(a) joint density", joint, &grids[0]), panel("(b) product of the marginals", product, &grids[1])],
    })
}

/// The top of a joint figure's colour scale, from its own cells: the 99.5th percentile of the
/// non-empty cells, so that a few spike cells (e.g. at T_1 ≈ 0) do not wash the rest out, and
/// the share of those cells above it (drawn in the top colour; 0 when the top is the largest).
pub fn colour_top(panels: &[&[[f64; 5]]]) -> (f64, f64) {
    let mut positive: Vec<f64> = panels.iter().flat_map(|p| p.iter().map(|c| c[4])).filter(|v| *v > 0.0 && v.is_finite()).collect();
    if positive.is_empty() {
        return (1.0, 0.0);
    }
    positive.sort_by(f64::total_cmp);
    let top = positive[((positive.len() as f64 * 0.995) as usize).min(positive.len() - 1)];
    let above = positive.iter().filter(|&&v| v > top).count();
    (top, above as f64 / positive.len() as f64)
}

/// Every figure the inputs allow.
pub fn all(inp: &Inputs) -> Vec<Figure> {
    let mut out = vec![poisson_figure(inp)];
    out.extend(trajectory_figure(inp));
    out.extend(q_figure(inp));
    out.extend(indexed_histograms(inp, "Y", "fig06_y", "the first six belt velocity changes Y_1..Y_6"));
    out.extend(growth_figure(inp));
    out.push(counts_figure(inp));
    out.extend(indexed_histograms(inp, "T", "fig09_t", "the first six stick starts T_1..T_6"));
    out.extend(indexed_histograms(inp, "L", "fig10_l", "the first six slip starts L_1..L_6"));
    out.extend(joint_figure(inp, "T_1", "T_2", "fig11_t1_t2"));
    out.extend(indexed_histograms(inp, "D", "fig12_d", "the first six stick durations D_1..D_6"));
    out.extend(joint_figure(inp, "D_1", "D_2", "fig13_d1_d2"));
    out.extend(indexed_histograms(inp, "H", "fig14_h", "the first six slip durations H_1..H_6"));
    out.extend(convergence_figure(inp));
    out.extend(tails::tails_figure(inp));
    out
}

/// The running mean of S_T, T_1, D_1 and H_1 against the number of realizations (log axis), with
/// its 95 % interval: how many realizations a precision needs.
pub fn convergence_figure(inp: &Inputs) -> Option<Figure> {
    let t = inp.convergence.as_ref()?;
    let (vars, idx, n) = (t.str(&convergence::VARIABLE), t.int(&convergence::INDEX), t.int(&convergence::REALIZATIONS));
    let (mean, lo, hi) = (t.float(&convergence::MEAN), t.float(&convergence::MEAN_LO), t.float(&convergence::MEAN_HI));
    let panels: Vec<Panel> = crate::analysis::CONVERGENCE
        .iter()
        .map(|o| {
            let rows: Vec<usize> = (0..t.height()).filter(|&r| vars[r] == o.variable() && idx[r] == o.index().map(i64::from)).collect();
            let line = |col: &[Option<f64>]| rows.iter().filter_map(|&r| Some((n[r]? as f64, col[r]?))).collect::<Vec<_>>();
            let name = o.name();
            Panel {
                title: format!("running mean of {name}"),
                x_label: "realizations".into(),
                y_label: format!("mean of {name}"),
                lines: vec![
                    Series { label: "mean".into(), color: 0, points: line(mean), ..Default::default() },
                    Series { label: "95 % interval".into(), color: 1, points: line(lo), ..Default::default() },
                    Series { label: String::new(), color: 1, points: line(hi), ..Default::default() },
                ],
                x_log: true,
                ..Default::default()
            }
        })
        .collect();
    panels.iter().any(|p| !p.lines[0].points.is_empty()).then(|| Figure {
        name: "convergence".into(),
        title: "Monte Carlo convergence: running mean ± 95 % interval against the number of realizations".into(),
        rows: 2,
        cols: 2,
        size: (1200, 800),
        panels,
    })
}

/// The per-cell metrics of `sweep.parquet` drawn by [`sweep_figure`]: (column, panel title, its
/// standard error's column).
pub const SWEEP_METRICS: [(Column, &str, Option<Column>); 6] = {
    use crate::analysis::sweep::sweep as s;
    [
        (s::MEAN_S_T, "E[S_T]", Some(s::MEAN_S_T_SE)),
        (s::STICK_FRACTION, "fraction of time in stick", None),
        (s::MEAN_D, "E[D] [s]", None),
        (s::MEAN_H, "E[H] [s]", None),
        (s::VAR_T_SLOPE, "slope of Var T_k [s²]", Some(s::VAR_T_SLOPE_SE)),
        (s::MEAN_T_SLOPE, "mean cycle E[D] + E[H] [s]", None),
    ]
};

/// A swept key (a sweep table's column: the last component of the key) as an axis title: the
/// key as written with its unit, e.g. `belt.switch_rate [1/s]`.
pub fn key_axis_label(column: &str) -> String {
    if column == "duration" {
        return "run.duration [s]".into();
    }
    match crate::simulation::keys::Key::ALL.iter().find(|k| k.name() == column) {
        Some(k) => {
            // Key::unit reads " (kg)" for messages; friction coefficients and the Stribeck
            // exponent have none
            let unit = k.unit().trim().trim_start_matches('(').trim_end_matches(')');
            if unit.is_empty() {
                format!("{} (dimensionless)", k.dotted())
            } else {
                format!("{} [{unit}]", k.dotted())
            }
        }
        None => column.to_string(),
    }
}

/// Ticks at a sweep's grid values, labelled as typed.
fn grid_ticks(values: &[f64]) -> Vec<(f64, String)> {
    values.iter().map(|&v| (v, format::grid_value(v))).collect()
}

/// Whether a swept key's values span a factor of 10 or more (then its axis is logarithmic).
fn wide(values: &[f64]) -> bool {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    lo > 0.0 && hi / lo >= 10.0
}

/// Cell edges around sorted distinct grid values: midpoints (geometric on a log axis), the outer
/// edges half a spacing out.
fn edges(v: &[f64], log: bool) -> Vec<(f64, f64)> {
    let (to, from) = (|x: f64| if log { x.ln() } else { x }, |u: f64| if log { u.exp() } else { u });
    let u: Vec<f64> = v.iter().map(|&x| to(x)).collect();
    (0..u.len())
        .map(|i| {
            let left = if i > 0 {
                0.5 * (u[i - 1] + u[i])
            } else if u.len() > 1 {
                u[0] - 0.5 * (u[1] - u[0])
            } else {
                u[0] - 0.5
            };
            let right = if i + 1 < u.len() {
                0.5 * (u[i] + u[i + 1])
            } else if u.len() > 1 {
                u[i] + 0.5 * (u[i] - u[i - 1])
            } else {
                u[0] + 0.5
            };
            (from(left), from(right))
        })
        .collect()
}

/// Maps of a sweep. One or three and more swept keys: each metric against the first key (one
/// line per value of the second), with ±1.96 standard-error bars where the table has them. Two
/// keys: each metric as a heat map over the grid, with a colour bar. An axis is logarithmic when
/// its key spans a factor of 10 or more.
pub fn sweep_figure(sweep: &Table) -> Option<Figure> {
    let keys: Vec<&str> = sweep.columns.iter().map(|(n, _)| n.as_str()).take_while(|n| *n != crate::analysis::sweep::sweep::REALIZATIONS.name).collect();
    let x = *keys.first()?;
    let xs = sweep.floats(x)?;
    let distinct = |k: &str| -> Option<Vec<f64>> {
        let mut v: Vec<f64> = sweep.floats(k)?.iter().flatten().copied().collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        Some(v)
    };
    let x_values = distinct(x)?;
    let x_log = wide(&x_values);
    if keys.len() == 2 {
        let y = keys[1];
        let (ys, y_values) = (sweep.floats(y)?, distinct(y)?);
        let y_log = wide(&y_values);
        let (xe, ye) = (edges(&x_values, x_log), edges(&y_values, y_log));
        let panels = SWEEP_METRICS
            .iter()
            .filter_map(|&(col, title, _)| {
                let v = sweep.floats(col.name)?;
                let heat: Vec<[f64; 5]> = (0..sweep.height())
                    .filter_map(|r| {
                        let (i, j) = (x_values.iter().position(|&a| Some(a) == xs[r])?, y_values.iter().position(|&b| Some(b) == ys[r])?);
                        Some([xe[i].0, xe[i].1, ye[j].0, ye[j].1, v[r].filter(|z| z.is_finite()).unwrap_or(f64::NAN)])
                    })
                    .collect();
                let missing = heat.iter().any(|c| c[4].is_nan());
                (!heat.is_empty()).then(|| Panel {
                    title: if missing { format!("{title} (grey: no value)") } else { title.into() },
                    x_label: key_axis_label(x),
                    y_label: key_axis_label(y),
                    x_ticks: grid_ticks(&x_values),
                    y_ticks: grid_ticks(&y_values),
                    heat,
                    heat_label: title.into(),
                    heat_values: x_values.len() * y_values.len() <= 64,
                    heat_linear: true,
                    x_log,
                    y_log,
                    ..Default::default()
                })
            })
            .collect::<Vec<_>>();
        return Some(Figure { name: "sweep_maps".into(), title: format!("Sweep over {x} × {y}"), rows: 2, cols: 3, size: (1500, 860), panels });
    }
    let groups: Vec<Option<f64>> = match keys.get(1) {
        Some(k) => distinct(k)?.into_iter().map(Some).collect(),
        None => vec![None],
    };
    let panels = SWEEP_METRICS
        .iter()
        .filter_map(|&(col, title, se)| {
            let ys = sweep.floats(col.name)?;
            let se = se.and_then(|c| sweep.floats(c.name));
            let lines: Vec<Series> = groups
                .iter()
                .enumerate()
                .map(|(i, g)| {
                    let mut rows: Vec<(f64, f64, f64)> = (0..sweep.height())
                        .filter(|&r| g.is_none_or(|g| keys.get(1).and_then(|k| sweep.floats(k)).is_some_and(|v| v[r] == Some(g))))
                        .filter_map(|r| Some((xs[r]?, ys[r]?, se.and_then(|s| s[r]).map_or(0.0, |s| 1.96 * s))))
                        .collect();
                    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let label = g.map_or(String::new(), |g| format!("{} = {g}", keys[1]));
                    let points = rows.iter().map(|r| (r.0, r.1)).collect();
                    let errors = if se.is_some() { rows.iter().map(|r| r.2).collect() } else { Vec::new() };
                    Series { label, color: i, points, errors }
                })
                .collect();
            let points = lines.iter().map(|l: &Series| Series { label: String::new(), errors: Vec::new(), ..l.clone() }).collect();
            let title = if se.is_some() { format!("{title} (± 1.96 se)") } else { title.to_string() };
            Some(Panel { title, x_label: key_axis_label(x), y_label: String::new(), points, lines, x_log, ..Default::default() })
        })
        .collect::<Vec<_>>();
    Some(Figure { name: "sweep_maps".into(), title: format!("Sweep over {}", keys.join(" × ")), rows: 2, cols: 3, size: (1400, 820), panels })
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
    // the velocity each change records (an older analysis without them is refused on read).
    let v0 = belt.first()?.1;
    let level = |i: usize| i.checked_sub(1).map_or(v0, |j| tr.belt_switches[j].1);
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
