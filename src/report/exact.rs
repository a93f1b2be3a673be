//! The report's sections from `exact-law` (`report --exact LAWDIR`): Table 1's means and
//! variances without sampling beside ours, D_k's law beside our product-limit curves, the laws
//! of the counts and the densities of T_k, L_k, H_k beside our histograms.

use std::path::Path;

use super::error::ReportError;
use super::tails::survival_points;
use crate::analysis::paper::Row;

pub(super) const EXACT_HEAD: [&str; 7] = ["variable", "mean, exact", "mean, ours [95 %]", "", "variance, exact", "variance, ours [95 %]", ""];
pub(super) const EXACT_TAILS_HEAD: [&str; 4] = ["quantity", "exact", "ours [95 %]", ""];
pub(super) const EXACT_TAILS_LEGEND: &str = "The law of each stick's duration D_k without sampling (exact-law's survival.parquet: the law of the stick's entry position, then the flip or the breakaway) beside our Kaplan–Meier curve of D_k; with exact-law --counts, the laws of S_T and S_L (counts.parquet) beside our shares (Wilson intervals), where the exact probability is at least 1e-3. ✓: the exact value (± its error) meets our 95 % band.";
pub(super) const EXACT_DENSITIES_HEAD: [&str; 4] = ["density", "our bins", "exact inside our 95 %", ""];
pub(super) const EXACT_DENSITIES_LEGEND: &str = "The densities of T_k, L_k and H_k without sampling (exact-law --densities: the characteristic function's cosine series, integrated over each of our histogram's bins, with its error estimate) beside our histograms: in how many bins the exact probability (± its error; conditioned, as our shares are, on the histogram's span, which the window cuts) meets the Wilson 95 % interval of our share. ✓: at least 90 % of them (a correct law meets about 95 %).";
pub(super) const EXACT_LEGEND: &str = "The means and variances computed from the equations without sampling (stickslip exact-law, with its error estimate) beside ours. ✓: the exact value (± its error) meets our 95 % interval. The exact values are those of the process without the window t_a (the window cuts T_k only for realizations with fewer than k sticks in it), but for T_k and L_k when exact-law ran with --densities: then conditioned on the window, as ours.";

/// A law computed for the dataset's scene (its model, belt, initial conditions and window; the
/// seed, size, solver and output may differ), as its recorded `scenario.toml` says.
pub(super) fn same_scene_as_law(law: &Path, sc: &crate::scenario::Scenario) -> Result<(), ReportError> {
    let path = law.join(crate::law::SCENARIO_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| ReportError::Read {
        path: path.clone(),
        message: format!("{e}: an exact-law directory records the scene it was computed for (run exact-law again with this version)"),
    })?;
    let recorded = crate::scenario::Scenario::recorded(&text, &path).map_err(|e| ReportError::Read { path: path.clone(), message: e.to_string() })?;
    if !recorded.same_scene(sc) {
        return Err(ReportError::Mismatch {
            path: law.to_owned(),
            message: "the exact law was computed for another scene than the dataset's (its scenario.toml differs in [model], [belt], [initial_conditions] or run.duration); compute the law of this scene with exact-law".into(),
        });
    }
    Ok(())
}

/// The exact rows beside Table 1 (`Content::exact`): every T_k, L_k, D_k, H_k (and S_T, S_L)
/// that both have.
/// A cell is inside when the exact value's error bar meets our 95 % interval.
pub(super) fn exact_rows(law: &Path, table1: &[Row]) -> Result<Vec<[String; 7]>, ReportError> {
    use crate::law::defs::moments as m;
    let t = m::DEF.read(law).map_err(|message| ReportError::Read { path: law.join(m::DEF.file), message })?;
    let (vars, idx) = (t.str(&m::VARIABLE), t.int(&m::INDEX));
    let (mean, var, me, ve) = (t.float(&m::MEAN), t.float(&m::VARIANCE), t.float(&m::ERROR), t.float(&m::VARIANCE_ERROR));
    // T_k and L_k within the window, where exact-law ran with --densities (null: none)
    let windowed = |c: &crate::table::Column, k: usize| t.float(c).get(k).copied().flatten();
    let mut out = Vec::new();
    for r in table1 {
        // (T_k, L_k, D_k, H_k by their index; S_T, S_L without one)
        let name = |k: usize| idx[k].map_or_else(|| vars[k].clone(), |i| format!("{}_{i}", vars[k]));
        let Some(k) = (0..vars.len()).find(|&k| name(k) == r.label) else { continue };
        let side = |x: Option<f64>, e: Option<f64>, cell: usize| -> [String; 3] {
            let (x, e) = (x.unwrap_or(f64::NAN), e.unwrap_or(f64::NAN));
            let c = &r.cells[cell];
            let inside = c.interval.map(|(lo, hi)| x + e >= lo && x - e <= hi);
            [format!("{x:.5} ± {e:.1e}"), c.text(4), inside.map_or(String::new(), |i| if i { "✓".into() } else { "✗".into() })]
        };
        let pair =
            |plain: (Option<f64>, Option<f64>), value: &crate::table::Column, error: &crate::table::Column| match (windowed(value, k), windowed(error, k)) {
                (Some(x), Some(e)) => (Some(x), Some(e)),
                _ => plain,
            };
        let (m, e1) = pair((mean[k], me[k]), &m::WINDOWED_MEAN, &m::WINDOWED_ERROR);
        let (v, e2) = pair((var[k], ve[k]), &m::WINDOWED_VARIANCE, &m::WINDOWED_VARIANCE_ERROR);
        let [a, b, c] = side(m, e1, 0);
        let [d, e, f] = side(v, e2, 1);
        out.push([r.label.clone(), a, b, c, d, e, f]);
    }
    Ok(out)
}

/// The exact rows beside the product-limit curves (`Content::exact_tails`): P(D_k > t) at every
/// t > 0 where `exact-law`'s D_k curve and the analysis' Kaplan–Meier curve of D_k both have a
/// point (the asked times, `--tail-times`, which both add to their grids). A row is inside when
/// the exact value's error bar meets our 95 % band.
pub(super) fn exact_tail_rows(law: &Path, adir: &Path) -> Result<Vec<[String; 4]>, ReportError> {
    let (Some(ours), Some(exact)) = (survival_points(adir, &crate::analysis::tables::survival::DEF)?, survival_points(law, &crate::law::defs::survival::DEF)?)
    else {
        return Ok(Vec::new());
    };
    let sig = |x: f64| crate::figures::format::significant(x, 4);
    let mut out = Vec::new();
    for e in exact.iter().filter(|e| e.variable == "D" && e.method == "exact" && e.t.is_some_and(|t| t > 0.0)) {
        let Some(q) = ours.iter().find(|q| q.variable == "D" && q.method == "kaplan_meier" && q.index == e.index && q.t == e.t) else { continue };
        let (Some(k), Some(t), Some(x), Some(y)) = (e.index, e.t, e.survival, q.survival) else { continue };
        let err = e.error.unwrap_or(0.0);
        let (band, inside) = match (q.lo, q.hi) {
            (Some(lo), Some(hi)) => (format!("{} [{} – {}]", sig(y), sig(lo), sig(hi)), if x + err >= lo && x - err <= hi { "✓" } else { "✗" }),
            _ => (format!("{} (no band)", sig(y)), ""),
        };
        out.push([format!("P(D_{k} > {} s)", crate::scenario::short(t)), format!("{} ± {err:.1e}", sig(x)), band, inside.to_string()]);
    }
    out.extend(count_rows(law, adir)?);
    Ok(out)
}

/// The densities of `exact-law --densities` (characteristic.parquet; none without it) integrated
/// over each bin of the analysis' histogram of T_k, L_k and H_k (histograms.parquet) and
/// conditioned on the bins' span (our shares are of the values in it: the window cuts T_k and
/// L_k), beside the bin's share of our values with its Wilson 95 % interval ([`wilson`]):
/// (density, bins, how many meet, ✓ when at least 90 % do).
pub(super) fn density_rows(law: &Path, adir: &Path) -> Result<Vec<[String; 4]>, ReportError> {
    let path = law.join("characteristic.parquet");
    if !path.exists() {
        return Ok(Vec::new());
    }
    let (half_period, levels) = crate::law::characteristic::read_characteristic(&path).map_err(|message| ReportError::Read { path: path.clone(), message })?;
    let ours = our_bins(adir)?;
    let mut out = Vec::new();
    for (i, x) in levels.last().map_or(&[][..], |l| &l.1[..]).iter().enumerate() {
        let (variable, k) = (x.variable, x.index);
        let bins: Vec<(f64, f64, i64)> = ours.iter().filter(|b| b.0 == variable && b.1 == Some(i64::from(k))).map(|b| (b.2, b.3, b.4)).collect();
        let n: i64 = bins.iter().map(|b| b.2).sum();
        if n == 0 {
            continue;
        }
        let edges: Vec<f64> = bins.iter().map(|b| b.0).chain(bins.last().map(|b| b.1)).collect();
        let exact = crate::law::densities::averages(&levels, half_period, i, &edges, crate::law::Order::Regular);
        // our shares are of the values in the bins' span (the window cuts T_k and L_k, and H_k's
        // slips must end in it): the exact law conditioned on the same span
        let span: f64 = bins.iter().zip(&exact).map(|((lo, hi, _), (f, _, point))| f * (hi - lo) + point).sum();
        if !(span > 0.0) {
            continue;
        }
        let inside = bins
            .iter()
            .zip(&exact)
            .filter(|((lo, hi, count), (f, e, point))| {
                let (a, b) = wilson(*count as f64 / n as f64, n as f64);
                ((f + e) * (hi - lo) + point) / span >= a && ((f - e) * (hi - lo) + point) / span <= b
            })
            .count();
        let ok = inside as f64 >= 0.9 * bins.len() as f64;
        let order = crate::law::densities::VARIABLES.iter().position(|v| *v == variable).unwrap_or(usize::MAX);
        out.push((
            (order, k),
            [format!("{variable}_{k}"), bins.len().to_string(), format!("{inside} of {}", bins.len()), if ok { "✓" } else { "✗" }.to_string()],
        ));
    }
    // T_1 … T_6, L_1 … L_6, H_1 … H_6
    out.sort_by_key(|r| r.0);
    Ok(out.into_iter().map(|r| r.1).collect())
}

/// One bin of the analysis' histograms: (variable, index, lo, hi, count).
type Bin = (String, Option<i64>, f64, f64, i64);

/// Every complete bin of the analysis' `histograms.parquet`.
fn our_bins(adir: &Path) -> Result<Vec<Bin>, ReportError> {
    use crate::analysis::tables::histograms as h;
    let t = h::DEF.read(adir).map_err(|message| ReportError::Read { path: adir.join(h::DEF.file), message })?;
    let (v, i, lo, hi, count) = (t.str(&h::VARIABLE), t.int(&h::INDEX), t.float(&h::LO), t.float(&h::HI), t.int(&h::COUNT));
    Ok((0..t.height()).filter_map(|r| Some((v[r].clone(), i[r], lo[r]?, hi[r]?, count[r]?))).collect())
}

/// The Wilson 95 % interval of a share p̂ of N: (p̂ + z²/2N ± z √(p̂(1 − p̂)/N + z²/4N²)) /
/// (1 + z²/N), z = 1.96.
fn wilson(share: f64, n: f64) -> (f64, f64) {
    let z2 = 1.96f64 * 1.96;
    let centre = (share + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = 1.96 * (share * (1.0 - share) / n + z2 / (4.0 * n * n)).sqrt() / (1.0 + z2 / n);
    (centre - half, centre + half)
}

/// P(S_T = n) and P(S_L = n) of `exact-law --counts` (counts.parquet; none without it) beside the
/// analysis' shares of the same values (histograms.parquet: a count's bins are its values),
/// with the Wilson 95 % interval ([`wilson`]). Values whose exact probability is below 1e-3 are
/// left out.
fn count_rows(law: &Path, adir: &Path) -> Result<Vec<[String; 4]>, ReportError> {
    let path = law.join("counts.parquet");
    if !path.exists() {
        return Ok(Vec::new());
    }
    use crate::law::defs::counts as c;
    let exact = c::DEF.read(law).map_err(|message| ReportError::Read { path, message })?;
    let ours = our_bins(adir)?;
    let (ev, evalue, ep, ee) = (exact.str(&c::VARIABLE), exact.int(&c::VALUE), exact.float(&c::PROBABILITY), exact.float(&c::ERROR));
    let sig = |x: f64| crate::figures::format::significant(x, 4);
    let mut out = Vec::new();
    for variable in crate::law::counts::VARIABLES {
        let bins: Vec<&Bin> = ours.iter().filter(|b| b.0 == variable).collect();
        let total: i64 = bins.iter().map(|b| b.4).sum();
        if total == 0 {
            continue;
        }
        let n = total as f64;
        for r in (0..exact.height()).filter(|&r| ev[r] == variable) {
            let (Some(value), Some(p), Some(err)) = (evalue[r], ep[r], ee[r]) else { continue };
            if p < 1e-3 {
                continue;
            }
            // the bin that holds the value (a count's bins are one value wide)
            let count = bins.iter().find(|b| b.3 - b.2 <= 1.0 && b.2 <= value as f64 && (value as f64) < b.3).map_or(0, |b| b.4);
            let share = count as f64 / n;
            let (lo, hi) = wilson(share, n);
            let inside = if p + err >= lo && p - err <= hi { "✓" } else { "✗" };
            out.push([
                format!("P({variable} = {value})"),
                format!("{} ± {err:.1e}", sig(p)),
                format!("{} [{} – {}]", sig(share), sig(lo), sig(hi)),
                inside.to_string(),
            ]);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::characteristic::characteristic_table;
    use crate::law::clock::{Points, C64};
    use crate::law::densities::{Transform, N};
    use crate::table::{Col, Table};

    /// The report's density rows on a law whose histogram is known: T_1 ~ Exp(2) (φ = 2/(2 + iω))
    /// against a histogram of 10^5 values with the expected count in every bin of 0.1 s up to
    /// 3 s — inside in every bin — and against the histogram of Exp(3) — outside in most.
    #[test]
    fn the_exact_density_meets_a_histogram_of_its_own_law_and_not_of_another() {
        let dir = tempfile::tempdir().unwrap();
        let (law, ours) = (dir.path().join("law"), dir.path().join("ours"));
        std::fs::create_dir_all(&law).unwrap();
        std::fs::create_dir_all(&ours).unwrap();
        let p = Points::<N>::cosine(20.0, &[], false);
        let phi: Box<[C64; N]> = Box::new(std::array::from_fn(|j| {
            let (a, b) = (2.0, p.z[j].im);
            C64::new(a * a / (a * a + b * b), -a * b / (a * a + b * b))
        }));
        let levels = vec![(0.1, vec![Transform { variable: "T", index: 1, phi, points: vec![] }])];
        characteristic_table(&levels, 20.0).write_parquet(&law.join("characteristic.parquet")).unwrap();
        let bins: Vec<(f64, f64)> = (0..30).map(|b| (0.1 * b as f64, 0.1 * (b + 1) as f64)).collect();
        for (rate, want_ok) in [(2.0, true), (3.0, false)] {
            let n = 100_000.0;
            let counts: Vec<i64> = bins.iter().map(|(a, b)| (n * ((-rate * a).exp() - (-rate * b).exp())).round() as i64).collect();
            let mut t = Table::default();
            let density = counts.iter().map(|&c| Some(c as f64 / (n * 0.1))).collect();
            t.push("variable", Col::Str(vec!["T".into(); bins.len()]))
                .push("index", Col::Int(vec![Some(1); bins.len()]))
                .push("bin", Col::Int((0..bins.len() as i64).map(Some).collect()))
                .push("lo", Col::Float(bins.iter().map(|b| Some(b.0)).collect()))
                .push("hi", Col::Float(bins.iter().map(|b| Some(b.1)).collect()))
                .push("count", Col::Int(counts.into_iter().map(Some).collect()))
                .push("density", Col::Float(density));
            t.write_parquet(&ours.join("histograms.parquet")).unwrap();
            let rows = density_rows(&law, &ours).unwrap();
            assert_eq!(rows.len(), 1);
            let inside: usize = rows[0][2].split(' ').next().unwrap().parse().unwrap();
            assert_eq!(rows[0][3] == "✓", want_ok, "rate {rate}: {:?}", rows[0]);
            if want_ok {
                assert_eq!(inside, 30, "{:?}", rows[0]);
            } else {
                assert!(inside < 10, "{:?}", rows[0]);
            }
        }
    }
}
