//! `characteristic.parquet` of `exact-law --densities`: the transforms of every level written
//! out, and read back (by the report, which averages them over its own cells).

use super::clock::C64;
use super::densities::{Transform, Transforms, N, VARIABLES};

/// `characteristic.parquet`: the transforms of every level, from which any cell's average
/// follows ([`super::densities::averages`]): h (the level's grid spacing, coarsest first), variable, index, j,
/// omega = πj/P [rad/s], re and im of E[e^{−iωX}] (the point masses taken out), half_period P
/// [s]; then a row per point mass with j, omega, re, im null and point_at [s], point_mass.
pub(crate) fn characteristic_table(levels: &[(f64, Transforms)], half_period: f64) -> crate::table::Table {
    use crate::table::Col;
    // (h, variable, index, j, value | (t, mass))
    type Row<'a> = (f64, &'a str, u32, Option<usize>, C64, Option<(f64, f64)>);
    let mut rows: Vec<Row> = Vec::new();
    for (h, l) in levels {
        for x in l {
            rows.extend(x.phi.iter().enumerate().map(|(j, f)| (*h, x.variable, x.index, Some(j), *f, None)));
            rows.extend(x.points.iter().map(|p| (*h, x.variable, x.index, None, C64::default(), Some(*p))));
        }
    }
    let f = |g: &dyn Fn(&Row) -> Option<f64>| Col::Float(rows.iter().map(g).collect());
    let mut t = crate::table::Table::default();
    t.put(&super::defs::characteristic::H, f(&|r| Some(r.0)))
        .put(&super::defs::characteristic::VARIABLE, Col::Str(rows.iter().map(|r| r.1.to_string()).collect()))
        .put(&super::defs::characteristic::INDEX, Col::Int(rows.iter().map(|r| Some(i64::from(r.2))).collect()))
        .put(&super::defs::characteristic::J, Col::Int(rows.iter().map(|r| r.3.map(|j| j as i64)).collect()))
        .put(&super::defs::characteristic::OMEGA, f(&|r| r.3.map(|j| std::f64::consts::PI * j as f64 / half_period)))
        .put(&super::defs::characteristic::RE, f(&|r| r.3.map(|_| r.4.re)))
        .put(&super::defs::characteristic::IM, f(&|r| r.3.map(|_| r.4.im)))
        .put(&super::defs::characteristic::HALF_PERIOD, f(&|_| Some(half_period)))
        .put(&super::defs::characteristic::POINT_AT, f(&|r| r.5.map(|p| p.0)))
        .put(&super::defs::characteristic::POINT_MASS, f(&|r| r.5.map(|p| p.1)));
    t
}

/// The levels and the half-period back from `characteristic.parquet` (as written by
/// [`characteristic_table`]).
pub(crate) fn read_characteristic(path: &std::path::Path) -> Result<(f64, Vec<(f64, Transforms)>), String> {
    use super::defs::characteristic as c;
    let t = c::DEF.read_at(path)?;
    let (h, v, k, j) = (t.float(&c::H), t.str(&c::VARIABLE), t.int(&c::INDEX), t.int(&c::J));
    let (re, im, p) = (t.float(&c::RE), t.float(&c::IM), t.float(&c::HALF_PERIOD));
    let (at, mass) = (t.float(&c::POINT_AT), t.float(&c::POINT_MASS));
    let bad = |r: usize| format!("{}: row {r} is not a transform of this version (h, variable, index, j, re, im, point_at, point_mass)", path.display());
    let half_period = p.first().copied().flatten().ok_or_else(|| format!("{}: no rows", path.display()))?;
    let mut levels: Vec<(f64, Transforms)> = Vec::new();
    for r in 0..t.height() {
        let (Some(h), Some(k)) = (h[r], k[r]) else { return Err(bad(r)) };
        let variable = *VARIABLES.iter().find(|x| **x == v[r]).ok_or_else(|| bad(r))?;
        if levels.last().is_none_or(|l| l.0 != h) {
            levels.push((h, Vec::new()));
        }
        let level = &mut levels.last_mut().expect("a level").1;
        if j[r] == Some(0) {
            level.push(Transform { variable, index: u32::try_from(k).map_err(|_| bad(r))?, phi: Box::new([C64::default(); N]), points: Vec::new() });
        }
        let slot = level.last_mut().filter(|x| x.variable == variable && i64::from(x.index) == k).ok_or_else(|| bad(r))?;
        match (j[r], re[r], im[r], at[r], mass[r]) {
            (Some(j), Some(re), Some(im), None, None) => *slot.phi.get_mut(usize::try_from(j).map_err(|_| bad(r))?).ok_or_else(|| bad(r))? = C64::new(re, im),
            (None, None, None, Some(t), Some(m)) => slot.points.push((t, m)),
            _ => return Err(bad(r)),
        }
    }
    Ok((half_period, levels))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::clock::Points;
    use crate::law::densities::averages;
    use crate::law::densities::tests::div;

    #[test]
    fn the_characteristic_table_reads_back_as_written() {
        // two levels of two transforms (an Exp law at two rates): written, read, the same cell
        // averages to the bit
        let p = Points::<N>::cosine(7.5, &[], false);
        let law = |variable: &'static str, index: u32, lambda: f64, points: Vec<(f64, f64)>| Transform {
            variable,
            index,
            phi: Box::new(std::array::from_fn(|j| div(C64::new(lambda, 0.0), C64::new(lambda + p.z[j].re, p.z[j].im)))),
            points,
        };
        let levels: Vec<(f64, Transforms)> = vec![
            (0.2, vec![law("T", 1, 2.0, vec![]), law("H", 3, 3.0, vec![(0.5, 0.01)])]),
            (0.1, vec![law("T", 1, 2.1, vec![]), law("H", 3, 3.1, vec![(0.5, 0.012)])]),
        ];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("characteristic.parquet");
        characteristic_table(&levels, 7.5).write_parquet(&path).unwrap();
        let (half, back) = read_characteristic(&path).unwrap();
        assert_eq!(half, 7.5);
        assert_eq!(back.len(), 2);
        for (a, b) in levels.iter().zip(&back) {
            assert_eq!(a.0, b.0);
            for (x, y) in a.1.iter().zip(&b.1) {
                assert_eq!((x.variable, x.index, &x.points), (y.variable, y.index, &y.points));
                assert!(x.phi.iter().zip(y.phi.iter()).all(|(u, v)| u == v));
            }
        }
        let edges = [0.0, 0.3, 1.0, 2.5];
        assert_eq!(
            averages(&levels, 7.5, 1, &edges, super::super::richardson::Order::Regular),
            averages(&back, 7.5, 1, &edges, super::super::richardson::Order::Regular)
        );
    }
}
