//! The tails' rows of the report, and the points of a `survival.parquet` (analyze's, or
//! exact-law's).

use crate::observables::{Observable, Statistic};
use std::path::Path;

use super::error::ReportError;
use crate::table::{Def, Table};

/// One point of a `survival.parquet` (analyze's, or exact-law's, which has `error` and no `n`).
pub(super) struct SurvivalPoint {
    pub(super) variable: String,
    pub(super) index: Option<i64>,
    pub(super) method: String,
    pub(super) t: Option<f64>,
    pub(super) survival: Option<f64>,
    pub(super) lo: Option<f64>,
    pub(super) hi: Option<f64>,
    pub(super) n: Option<i64>,
    pub(super) error: Option<f64>,
}

/// The points of `dir`'s `survival.parquet`, read through `def` (analyze's, or exact-law's
/// with `error` and no `n`: the shared columns have the same names); None when there is no such
/// file.
pub(super) fn survival_points(dir: &Path, def: &Def) -> Result<Option<Vec<SurvivalPoint>>, ReportError> {
    use crate::analysis::tables::survival as a;
    if !dir.join(def.file).exists() {
        return Ok(None);
    }
    let s = def.read(dir).map_err(|message| ReportError::Read { path: dir.join(def.file), message })?;
    let (var, idx, method, t, sv, lo, hi) =
        (s.str(&a::VARIABLE), s.int(&a::INDEX), s.str(&a::METHOD), s.float(&a::T), s.float(&a::SURVIVAL), s.float(&a::LO), s.float(&a::HI));
    let (n, error) = (s.int(&a::N), s.float(&crate::law::defs::survival::ERROR));
    Ok(Some(
        (0..s.height())
            .map(|r| SurvivalPoint {
                variable: var[r].clone(),
                index: idx[r],
                method: method[r].clone(),
                t: t[r],
                survival: sv[r],
                lo: lo[r],
                hi: hi[r],
                n: n.get(r).copied().flatten(),
                error: error.get(r).copied().flatten(),
            })
            .collect(),
    ))
}

/// The tails' rows of the report: P(D > t) at each asked time by the three methods
/// (`survival.parquet`, pooled), then the breakaway fraction and the exceedances
/// (`tails.parquet`); empty when the analysis has no tails.
pub(super) fn tails_rows(adir: &Path, moments: &Table, t_a: f64) -> Result<Vec<[String; 3]>, ReportError> {
    use crate::analysis::tables::{moments as m, tails};
    if !adir.join(tails::DEF.file).exists() {
        return Ok(Vec::new());
    }
    let e = tails::DEF.read(adir).map_err(|message| ReportError::Read { path: adir.join(tails::DEF.file), message })?;
    let s = survival_points(adir, &crate::analysis::tables::survival::DEF)?;
    let sig = |x: f64| crate::figures::format::significant(x, 4);
    let shown = |v: Option<f64>, lo: Option<f64>, hi: Option<f64>| match (v, lo, hi) {
        (Some(v), Some(lo), Some(hi)) => format!("{} [{} – {}]", sig(v), sig(lo), sig(hi)),
        (v, _, _) => format!("{} (no band)", v.map_or("–".into(), sig)),
    };
    let short = crate::scenario::short;
    let (stat, threshold, value, lo, hi, n) =
        (e.str(&tails::STATISTIC), e.float(&tails::THRESHOLD), e.float(&tails::VALUE), e.float(&tails::LO), e.float(&tails::HI), e.int(&tails::N));
    let mut out = Vec::new();
    // P(D > t) at the asked times (the longest stick's thresholds are those times)
    if let Some(s) = &s {
        for r in (0..e.height()).filter(|&r| stat[r] == Observable::LongestStick.variable()) {
            for m in ["kaplan_meier", "naive", "conditional"] {
                if let Some(q) =
                    s.iter().find(|q| q.variable == Observable::StickDuration(1).variable() && q.index.is_none() && q.method == m && q.t == threshold[r])
                {
                    let label = format!("P(D > {} s), {}", q.t.map_or("–".into(), short), m.replace('_', "-"));
                    out.push([label, shown(q.survival, q.lo, q.hi), format!("{} sticks", q.n.unwrap_or(0))]);
                }
            }
        }
    }
    // stick cycles per unit time: E[S_T]/t_a, with the mean's interval
    let (var, mean, mlo, mhi, mn) =
        (moments.str(&m::VARIABLE), moments.float(&m::MEAN), moments.float(&m::MEAN_LO), moments.float(&m::MEAN_HI), moments.int(&m::N));
    if let Some(r) = (0..moments.height()).find(|&r| var[r] == Observable::Sticks.variable()) {
        // (columns an older analysis may lack read as missing, not as a panic)
        let per = |c: &[Option<f64>]| c.get(r).copied().flatten().map(|x| x / t_a);
        out.push([
            "sticks per second, E[S_T]/t_a [1/s]".into(),
            shown(per(mean), per(mlo), per(mhi)),
            format!("{} realizations", mn.get(r).copied().flatten().unwrap_or(0)),
        ]);
    }
    for r in 0..e.height() {
        let label = match threshold[r] {
            Some(x) => format!("P({} > {})", stat[r], short(x)),
            None => stat[r].replace('_', " "),
        };
        let of = if stat[r] == Statistic::BreakawayFraction.name() { "sticks" } else { "realizations" };
        out.push([label, shown(value[r], lo[r], hi[r]), format!("{} {of}", n[r].unwrap_or(0))]);
    }
    Ok(out)
}
