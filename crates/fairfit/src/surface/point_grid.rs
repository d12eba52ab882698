//! The nearest of a set of points to a query, on a uniform grid of cubic cells: what a scan of
//! every point finds (the smallest distance, then the smallest index), at a cost that does not grow
//! with the set for queries near it. Points can be removed (a nearest-neighbour tour takes them one
//! by one).
//!
//! The cell size gives about one cell per point of a set spread over a surface or a plane: the
//! square root of the area spanned by the set's two largest extents over the point count. A query
//! looks at rings of cells around its own (Chebyshev distance `r = 0, 1, ...`) and stops once the
//! best distance found is below `r` cells, since every point beyond ring `r` lies at least that far;
//! once the rings have looked at more cells than points remain, it scans the remaining points
//! instead, so a query far from the set costs at most about two scans.
//!
//! Invariant: [`PointGrid::nearest`] returns the index a scan in index order with a strict `<` on
//! the squared distance returns.
//!
//! Written here: the points are few enough per use for a plain hash grid, and no crate in the
//! dependency tree does an exact nearest query with removal and this tie rule.

use crate::nurbs::Vec3;
use std::collections::HashMap;

/// A uniform grid over a set of points (given again to every call, so that the owner can keep them).
#[derive(Clone, Debug)]
pub(crate) struct PointGrid {
    /// The grid's origin and cell size (`f64::INFINITY` when every point coincides: one cell).
    origin: Vec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
    /// The largest cell index distance between two occupied cells: no ring beyond it holds a point.
    max_ring: i64,
    remaining: usize,
}

impl PointGrid {
    /// Every point of `points` (not empty) in the grid.
    pub(crate) fn new(points: &[Vec3]) -> Self {
        let (mut lo, mut hi) = (points[0], points[0]);
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let mut ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        ext.sort_by(|a, b| b.total_cmp(a));
        let area = (ext[0] * ext[1]).max(ext[0] * ext[0] * 1e-6);
        let cell = (area / points.len() as f64).sqrt();
        let cell = if cell > 0.0 && cell.is_finite() {
            cell
        } else {
            f64::INFINITY
        };
        let mut grid = PointGrid {
            origin: lo,
            cell,
            cells: HashMap::new(),
            max_ring: 0,
            remaining: points.len(),
        };
        for (i, &p) in points.iter().enumerate() {
            let key = grid.key(p);
            grid.cells.entry(key).or_default().push(i);
        }
        let span = |k: usize| grid.key(hi)[k] - grid.key(lo)[k];
        grid.max_ring = span(0).max(span(1)).max(span(2));
        grid
    }

    fn key(&self, p: Vec3) -> [i64; 3] {
        if self.cell.is_infinite() {
            return [0; 3];
        }
        let c = |k: usize| ((p[k] - self.origin[k]) / self.cell).floor() as i64;
        [c(0), c(1), c(2)]
    }

    /// Removes point `i` of `points` (the set the grid was built on) from the grid.
    pub(crate) fn remove(&mut self, points: &[Vec3], i: usize) {
        let key = self.key(points[i]);
        if let Some(v) = self.cells.get_mut(&key) {
            if let Some(pos) = v.iter().position(|&j| j == i) {
                v.swap_remove(pos);
                self.remaining -= 1;
            }
        }
    }

    /// The point of the grid nearest to `q` (module doc); `None` when none is left.
    pub(crate) fn nearest(&self, points: &[Vec3], q: Vec3) -> Option<usize> {
        if self.remaining == 0 {
            return None;
        }
        if !q.0.iter().all(|v| v.is_finite()) {
            // no distance compares: the scan keeps its first point
            return self.cells.values().flatten().copied().min();
        }
        let mut best: Option<(f64, usize)> = None;
        let consider = |best: &mut Option<(f64, usize)>, j: usize| {
            let d = (points[j] - q).norm_squared();
            if best.is_none_or(|(bd, bj)| d < bd || (d == bd && j < bj)) {
                *best = Some((d, j));
            }
        };
        let c = self.key(q);
        // a query outside the occupied cells needs rings out to its distance from them
        let outside = (0..3)
            .map(|k| (c[k] - self.max_ring.max(0)).max(-c[k]).max(0))
            .max()
            .unwrap_or(0);
        let mut looked = 0usize;
        for r in 0..=self.max_ring + outside {
            // ring r has (2r + 1)³ − (2r − 1)³ cells: once the rings cost more cells than points
            // remain, scan the points (a far query costs at most about two scans)
            looked = looked.saturating_add(if r == 0 { 1 } else { (24 * r * r + 2) as usize });
            if r > 0 && looked > self.remaining {
                for v in self.cells.values() {
                    for &j in v {
                        consider(&mut best, j);
                    }
                }
                return best.map(|b| b.1);
            }
            for dx in -r..=r {
                for dy in -r..=r {
                    for dz in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        if let Some(v) = self.cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                            for &j in v {
                                consider(&mut best, j);
                            }
                        }
                    }
                }
            }
            if let Some((bd, _)) = best {
                let reach = r as f64 * self.cell;
                if bd < reach * reach {
                    return best.map(|b| b.1);
                }
            }
        }
        best.map(|b| b.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nearest-neighbour tour by a scan of every unused point (the definition).
    fn brute_force_tour(points: &[Vec3], start: usize) -> Vec<usize> {
        let mut used = vec![false; points.len()];
        let (mut tour, mut cur) = (vec![start], start);
        used[start] = true;
        for _ in 1..points.len() {
            let mut best = (f64::INFINITY, usize::MAX);
            for (j, &u) in used.iter().enumerate() {
                let d = (points[j] - points[cur]).norm_squared();
                if !u && d < best.0 {
                    best = (d, j);
                }
            }
            used[best.1] = true;
            tour.push(best.1);
            cur = best.1;
        }
        tour
    }

    #[test]
    fn the_grid_finds_the_tour_a_scan_of_every_point_finds() {
        // a noisy band around a wavy loop (3-D, near a plane), with repeated points (ties go to the
        // smaller index) and a far cluster (reached by the linear scan past the rings)
        let mut s = 987654321u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts: Vec<Vec3> = (0..3000)
            .map(|_| {
                let t = std::f64::consts::TAU * rnd();
                let r = 1.0 + 0.2 * (3.0 * t).sin() + 0.01 * rnd();
                Vec3::new(r * t.cos(), r * t.sin(), 1e-3 * rnd())
            })
            .collect();
        let repeated: Vec<Vec3> = pts[..50].to_vec();
        pts.extend(repeated);
        pts.extend((0..20).map(|k| Vec3::new(40.0 + 0.1 * k as f64, 40.0, 0.0)));
        let mut grid = PointGrid::new(&pts);
        let mut tour = vec![7];
        grid.remove(&pts, 7);
        while let Some(j) = grid.nearest(&pts, pts[*tour.last().unwrap()]) {
            grid.remove(&pts, j);
            tour.push(j);
        }
        assert_eq!(tour, brute_force_tour(&pts, 7));
    }

    #[test]
    fn coincident_points_are_one_cell_and_every_one_is_found() {
        let pts = vec![Vec3::new(1.0, 2.0, 3.0); 5];
        let mut grid = PointGrid::new(&pts);
        assert!(grid.cell.is_infinite());
        for i in 0..5 {
            assert_eq!(grid.nearest(&pts, Vec3::ZERO), Some(i));
            grid.remove(&pts, i);
        }
        assert_eq!(grid.nearest(&pts, Vec3::ZERO), None);
    }

    #[test]
    fn the_nearest_sample_of_a_surface_grid_is_the_scans_for_near_and_far_queries() {
        // samples of a saddle; queries on it, beside it and far away
        let pts: Vec<Vec3> = (0..60)
            .flat_map(|i| {
                (0..40).map(move |j| {
                    let (x, y) = (i as f64 / 59.0 * 3.0, j as f64 / 39.0 * 2.0);
                    Vec3::new(x, y, 0.3 * (x - 1.5) * (y - 1.0))
                })
            })
            .collect();
        let grid = PointGrid::new(&pts);
        let scan = |q: Vec3| {
            let mut best = (f64::INFINITY, 0);
            for (j, p) in pts.iter().enumerate() {
                let d = (*p - q).norm_squared();
                if d < best.0 {
                    best = (d, j);
                }
            }
            best.1
        };
        for k in 0..200 {
            let t = k as f64 * 0.37;
            let far = if k % 10 == 0 { 50.0 } else { 1.0 };
            let q = Vec3::new(
                1.5 + far * t.cos(),
                1.0 + far * t.sin(),
                0.2 * (t * 3.0).sin(),
            );
            assert_eq!(grid.nearest(&pts, q), Some(scan(q)), "query {k}");
        }
    }
}
