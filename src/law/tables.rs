//! The exact law's tables, each defined once ([`super::defs`]: file, columns with type and meaning) and
//! built by one builder — what `exact-law` writes into its directory (and
//! `predict` the ones it shares) — and the Markdown table the command prints.

use super::counts::CountRow;
use super::defs;
use super::densities::DensityRow;
use super::density::Density;
use super::passage::Sequence;
use super::run::Solved;
use super::stationary::{estimates, Level, Rung, QUANTITIES};
use super::sticks::{self, SurvivalRow};
use crate::table::{Col, Def, Table};

/// Every table of a solved law with its definition, in the order written; each is checked
/// against its definition first.
pub fn all(s: &Solved) -> Result<Vec<(&'static Def, Table)>, String> {
    let mut t = vec![
        (&defs::stationary::DEF, stationary(&s.levels)),
        (&defs::convergence::DEF, convergence(&s.levels, &s.ladder, &s.sticks)),
        (&defs::density::DEF, density(&s.density)),
        (&defs::stick_survival::DEF, stick_survival(&s.density)),
        (&defs::moments::DEF, moments(&s.rows)),
        (&defs::survival::DEF, survival(&s.survival)),
    ];
    if s.asked.0 {
        t.push((&defs::counts::DEF, counts(&s.counts)));
    }
    if s.asked.1 {
        t.push((&defs::densities::DEF, densities(&s.densities)));
        t.push((&defs::characteristic::DEF, s.characteristic.clone()));
    }
    for (d, table) in &t {
        d.check(table)?;
    }
    Ok(t)
}

/// `stick_survival.parquet`: t, survival (P(D > t) of a stick of the long run).
pub fn stick_survival(d: &Density) -> Table {
    let mut t = Table::default();
    t.put(&defs::stick_survival::T, Col::Float(d.stick_survival.iter().map(|p| Some(p.0)).collect()))
        .put(&defs::stick_survival::SURVIVAL, Col::Float(d.stick_survival.iter().map(|p| Some(p.1)).collect()));
    t
}

/// `moments.parquet`: variable, index, mean, variance, error (of the mean), variance_error,
/// reached_fraction (with `--counts` or `--densities`; null otherwise), windowed_mean,
/// windowed_error, windowed_variance, windowed_variance_error (T_k and L_k conditioned on
/// X ≤ t_a, with `--densities`; null otherwise).
/// (S_T and S_L, whose rows have index 0, have a null index, as in analyze's.)
pub fn moments(rows: &[sticks::Row]) -> Table {
    let mut t = Table::default();
    t.put(&defs::moments::VARIABLE, Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .put(&defs::moments::INDEX, Col::Int(rows.iter().map(|r| (r.index > 0).then_some(i64::from(r.index))).collect()))
        .put(&defs::moments::MEAN, Col::Float(rows.iter().map(|r| Some(r.mean)).collect()))
        .put(&defs::moments::VARIANCE, Col::Float(rows.iter().map(|r| Some(r.variance)).collect()))
        .put(&defs::moments::ERROR, Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .put(&defs::moments::VARIANCE_ERROR, Col::Float(rows.iter().map(|r| Some(r.variance_error)).collect()))
        .put(&defs::moments::REACHED_FRACTION, Col::Float(rows.iter().map(|r| r.reached.map(|x| x.0)).collect()))
        .put(&defs::moments::WINDOWED_MEAN, Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[0])).collect()))
        .put(&defs::moments::WINDOWED_ERROR, Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[1])).collect()))
        .put(&defs::moments::WINDOWED_VARIANCE, Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[2])).collect()))
        .put(&defs::moments::WINDOWED_VARIANCE_ERROR, Col::Float(rows.iter().map(|r| r.windowed.map(|w| w[3])).collect()));
    t
}

/// `counts.parquet`: variable (S_T, S_L), value n, probability P(S = n), error.
pub fn counts(rows: &[CountRow]) -> Table {
    let mut t = Table::default();
    t.put(&defs::counts::VARIABLE, Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .put(&defs::counts::VALUE, Col::Int(rows.iter().map(|r| Some(i64::from(r.value))).collect()))
        .put(&defs::counts::PROBABILITY, Col::Float(rows.iter().map(|r| Some(r.probability)).collect()))
        .put(&defs::counts::ERROR, Col::Float(rows.iter().map(|r| Some(r.error)).collect()));
    t
}

/// `densities.parquet`: variable (T, L, H), index k, the cell t_lo ≤ t < t_hi, its centre t,
/// the density averaged over it [1/s], error, point_mass (the probability of the point masses
/// in it, not part of the density).
pub fn densities(rows: &[DensityRow]) -> Table {
    let mut t = Table::default();
    t.put(&defs::densities::VARIABLE, Col::Str(rows.iter().map(|r| r.variable.to_string()).collect()))
        .put(&defs::densities::INDEX, Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .put(&defs::densities::T, Col::Float(rows.iter().map(|r| Some(0.5 * (r.t_lo + r.t_hi))).collect()))
        .put(&defs::densities::T_LO, Col::Float(rows.iter().map(|r| Some(r.t_lo)).collect()))
        .put(&defs::densities::T_HI, Col::Float(rows.iter().map(|r| Some(r.t_hi)).collect()))
        .put(&defs::densities::DENSITY, Col::Float(rows.iter().map(|r| Some(r.density)).collect()))
        .put(&defs::densities::ERROR, Col::Float(rows.iter().map(|r| Some(r.error)).collect()))
        .put(&defs::densities::POINT_MASS, Col::Float(rows.iter().map(|r| Some(r.point_mass)).collect()));
    t
}

/// `survival.parquet`, in analyze's columns (`variable` D, `index` k, `method` exact, `t`,
/// `survival` = P(D_k > t), `lo`, `hi`: the value ∓ its error estimate, within [0, 1]) with
/// `error`, `density` (at the finest resolution, [`sticks::SurvivalRow`]) and `density_error`.
pub fn survival(rows: &[SurvivalRow]) -> Table {
    let f = |g: &dyn Fn(&sticks::SurvivalRow) -> f64| Col::Float(rows.iter().map(|r| Some(g(r))).collect());
    let mut t = Table::default();
    t.put(&defs::survival::VARIABLE, Col::Str(rows.iter().map(|_| crate::observables::Observable::StickDuration(1).variable().to_string()).collect()))
        .put(&defs::survival::INDEX, Col::Int(rows.iter().map(|r| Some(i64::from(r.index))).collect()))
        .put(&defs::survival::METHOD, Col::Str(rows.iter().map(|_| "exact".to_string()).collect()))
        .put(&defs::survival::T, f(&|r| r.t))
        .put(&defs::survival::SURVIVAL, f(&|r| r.survival))
        .put(&defs::survival::LO, f(&|r| (r.survival - r.error).max(0.0)))
        .put(&defs::survival::HI, f(&|r| (r.survival + r.error).min(1.0)))
        .put(&defs::survival::ERROR, f(&|r| r.error))
        .put(&defs::survival::DENSITY, f(&|r| r.density))
        .put(&defs::survival::DENSITY_ERROR, f(&|r| r.density_error));
    t
}

/// `stationary.parquet`: quantity, value, error.
pub fn stationary(levels: &[Level]) -> Table {
    let est = estimates(levels);
    let mut t = Table::default();
    t.put(&defs::stationary::QUANTITY, Col::Str(QUANTITIES.iter().map(|q| q.to_string()).collect()))
        .put(&defs::stationary::VALUE, Col::Float(est.iter().map(|e| Some(e.0)).collect()))
        .put(&defs::stationary::ERROR, Col::Float(est.iter().map(|e| Some(e.1)).collect()));
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
    t.put(&defs::convergence::RESOLUTION, Col::Int(rows.iter().map(|r| Some(i64::from(r.0))).collect()))
        .put(&defs::convergence::H, Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .put(&defs::convergence::QUANTITY, Col::Str(rows.iter().map(|r| r.2.clone()).collect()))
        .put(&defs::convergence::VALUE, Col::Float(rows.iter().map(|r| Some(r.3)).collect()))
        .put(&defs::convergence::ITERATIONS, Col::Int(rows.iter().map(|r| r.4).collect()))
        .put(&defs::convergence::LOST, Col::Float(rows.iter().map(|r| Some(r.5)).collect()));
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
    t.put(&defs::density::KIND, Col::Str(rows.iter().map(|r| r.0.to_string()).collect()))
        .put(&defs::density::X, Col::Float(rows.iter().map(|r| Some(r.1)).collect()))
        .put(&defs::density::VELOCITY, Col::Float(rows.iter().map(|r| Some(r.2)).collect()))
        .put(&defs::density::DENSITY, Col::Float(rows.iter().map(|r| Some(r.3)).collect()));
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
