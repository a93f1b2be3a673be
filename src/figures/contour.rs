//! Contour lines of a gridded field (marching squares), for the joint-density figures.
//!
//! The field is given at the centres of the cells of a rectangular grid. Each square between
//! four neighbouring centres contributes the segments where the bilinear field crosses a level;
//! the crossing on each edge is placed by linear interpolation. A square crossed on all four
//! edges (a saddle) is resolved by its centre value, the mean of the four corners.

/// Values `z[i][j]` at the points `(xs[i], ys[j])`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub z: Vec<Vec<f64>>,
}

impl Grid {
    /// The grid of cells `(x0, x1, y0, y1, value)` (absent cells are 0), at the cell centres.
    pub fn from_cells(cells: &[[f64; 5]]) -> Grid {
        let centres = |a: usize, b: usize| {
            let mut v: Vec<f64> = cells.iter().map(|c| 0.5 * (c[a] + c[b])).collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        let (xs, ys) = (centres(0, 1), centres(2, 3));
        let mut z = vec![vec![0.0; ys.len()]; xs.len()];
        for c in cells {
            let (x, y) = (0.5 * (c[0] + c[1]), 0.5 * (c[2] + c[3]));
            if let (Ok(i), Ok(j)) = (xs.binary_search_by(|v| v.total_cmp(&x)), ys.binary_search_by(|v| v.total_cmp(&y))) {
                z[i][j] = c[4];
            }
        }
        Grid { xs, ys, z }
    }

    /// The field smoothed by the 3 × 3 binomial kernel [1 2 1] ⊗ [1 2 1] / 16 (edges reflected):
    /// contours of a raw histogram are ragged at the scale of one bin.
    pub fn smoothed(&self) -> Grid {
        let (n, m) = (self.xs.len(), self.ys.len());
        let at = |i: isize, j: isize| {
            let r = |k: isize, len: usize| k.clamp(0, len as isize - 1) as usize;
            self.z[r(i, n)][r(j, m)]
        };
        let w = [1.0, 2.0, 1.0];
        let z = (0..n as isize)
            .map(|i| {
                (0..m as isize)
                    .map(|j| {
                        let mut s = 0.0;
                        for (di, wi) in (-1..=1).zip(w) {
                            for (dj, wj) in (-1..=1).zip(w) {
                                s += wi * wj * at(i + di, j + dj);
                            }
                        }
                        s / 16.0
                    })
                    .collect()
            })
            .collect();
        Grid { xs: self.xs.clone(), ys: self.ys.clone(), z }
    }

    /// The segments where the field crosses `level`.
    pub fn contour(&self, level: f64) -> Vec<[(f64, f64); 2]> {
        let mut out = Vec::new();
        for i in 0..self.xs.len().saturating_sub(1) {
            for j in 0..self.ys.len().saturating_sub(1) {
                let (x0, x1, y0, y1) = (self.xs[i], self.xs[i + 1], self.ys[j], self.ys[j + 1]);
                // corners counter-clockwise from (x0, y0)
                let p = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
                let v = [self.z[i][j], self.z[i + 1][j], self.z[i + 1][j + 1], self.z[i][j + 1]];
                let above = v.map(|z| z >= level);
                // crossing on edge e (corner e to corner e + 1)
                let cross: Vec<Option<(f64, f64)>> = (0..4)
                    .map(|e| {
                        let k = (e + 1) % 4;
                        (above[e] != above[k]).then(|| {
                            let t = (level - v[e]) / (v[k] - v[e]);
                            (p[e].0 + t * (p[k].0 - p[e].0), p[e].1 + t * (p[k].1 - p[e].1))
                        })
                    })
                    .collect();
                let hits: Vec<(usize, (f64, f64))> = cross.iter().enumerate().filter_map(|(e, c)| c.map(|c| (e, c))).collect();
                match hits.len() {
                    2 => out.push([hits[0].1, hits[1].1]),
                    4 => {
                        let centre_above = v.iter().sum::<f64>() / 4.0 >= level;
                        // corners 0 and 2 on one side: join around the corners of the other side
                        let pairs = if centre_above == above[0] { [(0, 1), (2, 3)] } else { [(3, 0), (1, 2)] };
                        for (a, b) in pairs {
                            if let (Some(a), Some(b)) = (cross[a], cross[b]) {
                                out.push([a, b]);
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contours_of_a_cone_are_circles() {
        let n = 81;
        let c: Vec<f64> = (0..n).map(|i| -2.0 + 4.0 * i as f64 / (n - 1) as f64).collect();
        let z = c.iter().map(|&x| c.iter().map(|&y| (x * x + y * y).sqrt()).collect()).collect();
        let g = Grid { xs: c.clone(), ys: c, z };
        let h = 4.0 / (n - 1) as f64;
        for r in [0.5, 1.0, 1.7] {
            let segs = g.contour(r);
            // the circle's length, from its segments
            let len: f64 = segs.iter().map(|[a, b]| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()).sum();
            assert!((len / (2.0 * std::f64::consts::PI * r) - 1.0).abs() < 0.01, "r = {r}: length {len}");
            for [a, b] in segs {
                for p in [a, b] {
                    let d = (p.0 * p.0 + p.1 * p.1).sqrt();
                    assert!((d - r).abs() < 0.25 * h * h / r + 1e-12, "r = {r}: point at distance {d}");
                }
            }
        }
    }

    #[test]
    fn cells_become_a_grid_and_smoothing_keeps_the_mass() {
        let cells = [[0.0, 1.0, 0.0, 1.0, 4.0], [1.0, 2.0, 1.0, 2.0, 8.0]];
        let g = Grid::from_cells(&cells);
        assert_eq!((g.xs.clone(), g.ys.clone()), (vec![0.5, 1.5], vec![0.5, 1.5]));
        assert_eq!(g.z, vec![vec![4.0, 0.0], vec![0.0, 8.0]]);
        // a constant field stays constant
        let flat = Grid { z: vec![vec![3.0; 2]; 2], ..g.clone() };
        assert_eq!(flat.smoothed().z, flat.z);
    }
}
