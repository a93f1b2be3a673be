//! The exact law's tables, one builder each — what `exact-law` writes into its directory (and
//! `predict` the ones it shares) — and the Markdown table the command prints.

use super::counts::CountRow;
use super::densities::DensityRow;
use super::density::Density;
use super::passage::Sequence;
use super::run::Solved;
use super::stationary::{estimates, Level, Rung, QUANTITIES};
use super::sticks::{self, SurvivalRow};
use crate::table::{Col, Table};

/// Every table of a solved law by name (each written as NAME.parquet), in the order written.
pub fn all(s: &Solved) -> Vec<(&'static str, Table)> {
    let mut t = vec![
        ("stationary", stationary(&s.levels)),
        ("convergence", convergence(&s.levels, &s.ladder, &s.sticks)),
        ("density", density(&s.density)),
        ("stick_survival", stick_survival(&s.density)),
        ("moments", moments(&s.rows)),
        ("survival", survival(&s.survival)),
    ];
    if s.asked.0 {
        t.push(("counts", counts(&s.counts)));
    }
    if s.asked.1 {
        t.push(("densities", densities(&s.densities)));
        t.push(("characteristic", s.characteristic.clone()));
    }
    t
}

/// `stick_survival.parquet`: t, survival (P(D > t) of a stick of the long run).
pub fn stick_survival(d: &Density) -> Table {
    let mut t = Table::default();
    t.push("t", Col::Float(d.stick_survival.iter().map(|p| Some(p.0)).collect()))
        .push("survival", Col::Float(d.stick_survival.iter().map(|p| Some(p.1)).collect()));
    t
}

/// `moments.parquet`: variable, index, mean, variance, error (of the mean), variance_error,
/// reached_fraction (with `--counts` or `--densities`; null otherwise), windowed_mean,
/// windowed_error, windowed_variance, windowed_variance_error (T_k and L_k conditioned on
/// X ≤ t_a, with `--densities`; null otherwise).
/// (S_T and S_L, whose rows have index 0, have a null index, as in analyze's.)
pub fn moments(rows: &[sticks::Row]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| (r.index > 0).then_some(i64::from(r.index))).collect()))
        .push("mean", Col::Float(rows.iter().map(|r| Some(r.mean)).collect()))
        .push("variance", Col::Float(rows.iter().map(|r| Some(r.variance)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .push("variance_error", Col::Float(rows.iter().map(|r| Some(r.variance_error)).collect()))
        .push("reached_fraction", Col::Float(rows.iter().map(|r| r.reached.map(|x| x.0)).collect()))
        .push("windowed_mean", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[0])).collect()))
        .push("windowed_error", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[1])).collect()))
        .push("windowed_variance", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[2])).collect()))
        .push("windowed_variance_error", Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[3])).collect()));
    t
}

/// `counts.parquet`: variable (S_T, S_L), value n, probability P(S = n), error.
pub fn counts(rows: &[CountRow]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("value", Col::Int(rows.iter().map(|r| Some(i64::from(r.value))).collect()))
        .push("probability", Col::Float(rows.iter().map(|r| Some(r.probability)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()));
    t
}

/// `densities.parquet`: variable (T, L, H), index k, the cell t_lo ≤ t < t_hi, its centre t,
/// the density averaged over it [1/s], error, point_mass (the probability of the point masses
/// in it, not part of the density).
pub fn densities(rows: &[DensityRow]) -> Table {
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .push("t", Col::Float(rows.iter().map(|r| Some(0.5 * (r.t_lo + r.t_hi))).collect()))
        .push("t_lo", Col::Float(rows.iter().map(|r| Some(r.t_lo)).collect()))
        .push("t_hi", Col::Float(rows.iter().map(|r| Some(r.t_hi)).collect()))
        .push("density", Col::Float(rows.iter().map(|r| Some(r.density)).collect()))
        .push("error", Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .push("point_mass", Col::Float(rows.iter().map(|r| Some(r.point_mass)).collect()));
    t
}

/// `survival.parquet`, in analyze's columns (`variable` D, `index` k, `method` exact, `t`,
/// `survival` = P(D_k > t), `lo`, `hi`: the value ∓ its error estimate, within [0, 1]) with
/// `error`, `density` (at the finest resolution, [`sticks::SurvivalRow`]) and `density_error`.
pub fn survival(rows: &[SurvivalRow]) -> Table {
    let f = |g: &dyn Fn(&sticks::SurvivalRow) -> f64| Col::Float(rows.iter().map(|r| Some(g(r))).collect());
    let mut t = Table::default();
    t.push("variable", Col::Str(rows.iter().map(|_| "D".to_string()).collect()))
        .push("index", Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .push("method", Col::Str(rows.iter().map(|_| "exact".to_string()).collect()))
        .push("t", f(&|r| r.t))
        .push("survival", f(&|r| r.survival))
        .push("lo", f(&|r| (r.survival - r.error).max(0.0)))
        .push("hi", f(&|r| (r.survival + r.error).min(1.0)))
        .push("error", f(&|r| r.error))
        .push("density", f(&|r| r.density))
        .push("density_error", f(&|r| r.density_error));
    t
}

/// `stationary.parquet`: quantity, value, error.
pub fn stationary(levels: &[Level]) -> Table {
    let est = estimates(levels);
    let mut t = Table::default();
    t.push("quantity", Col::Str(QUANTITIES.iter().map(|q| q.to_string()).collect()))
        .push("value", Col::Float(est.iter().map(|e| Some(e.0)).collect()))
        .push("error", Col::Float(est.iter().map(|e| Some(e.1)).collect()));
    t
}

/// `convergence.parquet`: resolution, h, quantity, value, iterations, lost — one row per
/// resolution and long-run quantity, then per resolution and Table 1 statistic (`mean_T_1`,
/// `variance_T_1`, …; iterations null).
pub(crate) fn convergence(levels: &[Level], ladder: &[Rung], sticks: &[(f64, Sequence)]) -> Table {
    // (resolution, h, quantity, value, iterations, lost)
    let mut rows: Vec<(u32, f64, String, f64, Option<i64>, f64)> = levels
        .iter()
        .flat_map(|l| QUANTITIES.iter().zip(l.values).map(move |(q, v)| (l.n, l.h, q.to_string(), v, Some(i64::from(l.iterations)), l.lost)))
        .collect();
    for (&(n, _), (h, s)) in ladder.iter().map(|r| (r.0, ())).collect::<Vec<_>>().iter().zip(sticks) {
        for (v, k, (mean, variance)) in sticks::values(s) {
            rows.push((n, *h, format!("mean_{v}_{k}"), mean, None, s.lost));
            rows.push((n, *h, format!("variance_{v}_{k}"), variance, None, s.lost));
        }
    }
    let mut t = Table::default();
    t.push("resolution", Col::Int(rows.iter().map(|r| Some(i64::from(r.0))).collect()))
        .push("h", Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .push("quantity", Col::Str(rows.iter().map(|r| r.2.clone()).collect()))
        .push("value", Col::Float(rows.iter().map(|r| Some(r.3)).collect()))
        .push("iterations", Col::Int(rows.iter().map(|r| r.4).collect()))
        .push("lost", Col::Float(rows.iter().map(|r| Some(r.5)).collect()));
    t
}

/// `density.parquet`: kind (`slip`: a cell of the plane, density in 1/(m · m/s); `stick`: a
/// cell of a stick line ẋ = ±v0, density in 1/m), x and velocity (the cell's centre), density.
pub fn density(d: &Density) -> Table {
    let centres = |e: &[f64]| e.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect::<Vec<f64>>();
    let (xs, vs) = (centres(&d.x_edges), centres(&d.v_edges));
    let mut rows: Vec<(&str, f64, f64, f64)> = Vec::new();
    for (i, &x) in xs.iter().enumerate() {
        for (j, &v) in vs.iter().enumerate() {
            rows.push(("slip", x, v, d.slip[i * vs.len() + j]));
        }
    }
    for (k, (line, v)) in d.stick.iter().zip(d.velocities).enumerate() {
        rows.extend(d.stick_centres(k).into_iter().zip(line).map(|(x, &p)| ("stick", x, v, p)));
    }
    let mut t = Table::default();
    t.push("kind", Col::Str(rows.iter().map(|r| r.0.to_string()).collect()))
        .push("x", Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .push("velocity", Col::Float(rows.iter().map(|r| Some(r.2)).collect()))
        .push("density", Col::Float(rows.iter().map(|r| Some(r.3)).collect()));
    t
}

/// The table `exact-law` prints: each quantity at every resolution, the value and its error.
pub fn markdown(levels: &[Level]) -> String {
    let est = estimates(levels);
    let mut m = String::from("| quantity |");
    for l in levels {
        m += &format!(" n = {} |", l.n);
    }
    m += " value | error |\n|---|";
    m += &"---:|".repeat(levels.len() + 2);
    m += "\n";
    for (q, name) in QUANTITIES.iter().enumerate() {
        m += &format!("| {name} |");
        for l in levels {
            m += &format!(" {} |", crate::shown::six_decimals(l.values[q]));
        }
        m += &format!(" {} | {:.1e} |\n", crate::shown::six_decimals(est[q].0), est[q].1);
    }
    m
}
