//! Exact knot operations on surfaces, one parametric direction at a time: knot refinement (A5.4) and
//! degree elevation (A5.9) applied to every row or column of the homogeneous net. Used to make skinned
//! sections compatible (same degree and knot vector) without changing any surface.

use super::elevate::elevate_degree_hom;
use super::insert::{dehomogenize, Hom};
use super::refine::refine_knots_hom;
use super::surface::NurbsSurface;
use crate::errors::Result;

/// A parametric direction of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dir {
    U,
    V,
}

/// A curve-level operation on one line of the net: `(degree, knots, points) -> (knots, points)`.
type LineOp<'a> = &'a dyn Fn(usize, &[f64], &[Hom]) -> Result<(Vec<f64>, Vec<Hom>)>;

impl NurbsSurface {
    /// Applies `op` to every line of the net along `dir`; `dp` is the degree increase it causes.
    fn map_lines(&self, dir: Dir, dp: usize, op: LineOp<'_>) -> Result<NurbsSurface> {
        let (n_u, n_v) = self.net_size();
        let cw = self.homogeneous_points();
        let (pu, pv) = (self.degree_u(), self.degree_v());
        let (ku, kv, nu2, nv2, flat) = match dir {
            Dir::V => {
                let mut flat = Vec::new();
                let mut knots = Vec::new();
                for row in cw.chunks(n_v) {
                    let (k, q) = op(pv, self.knots_v(), row)?;
                    flat.extend_from_slice(&q);
                    knots = k;
                }
                let nv2 = flat.len() / n_u;
                (self.knots_u().to_vec(), knots, n_u, nv2, flat)
            }
            Dir::U => {
                let mut cols = Vec::with_capacity(n_v);
                let mut knots = Vec::new();
                let mut col = Vec::with_capacity(n_u);
                for j in 0..n_v {
                    col.clear();
                    col.extend((0..n_u).map(|i| cw[i * n_v + j]));
                    let (k, q) = op(pu, self.knots_u(), &col)?;
                    cols.push(q);
                    knots = k;
                }
                let nu2 = cols[0].len();
                let flat: Vec<Hom> = (0..nu2)
                    .flat_map(|i| cols.iter().map(move |c| c[i]))
                    .collect();
                (knots, self.knots_v().to_vec(), nu2, n_v, flat)
            }
        };
        let (pu2, pv2) = match dir {
            Dir::U => (pu + dp, pv),
            Dir::V => (pu, pv + dp),
        };
        let (pts, w) = dehomogenize(&flat, self.is_rational());
        Ok(NurbsSurface::from_flat_unchecked(
            pu2, pv2, ku, kv, nu2, nv2, pts, w,
        ))
    }

    /// The same surface with the knots `new_knots` (non-decreasing, strictly inside the u domain)
    /// inserted in the u direction (NURBS Book A5.4 on every column of the net).
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let s = NurbsSurface::new(3, 2, uniform_clamped(3, 4), uniform_clamped(2, 3), net, None).unwrap();
    /// let r = s.refine_knots_u(&[0.3, 0.7]).unwrap();
    /// assert_eq!(r.net_size(), (6, 3));
    /// assert!((r.point(0.45, 0.8) - s.point(0.45, 0.8)).norm() < 1e-14);
    /// ```
    pub fn refine_knots_u(&self, new_knots: &[f64]) -> Result<NurbsSurface> {
        self.map_lines(Dir::U, 0, &|p, k, c| refine_knots_hom(p, k, c, new_knots))
    }

    /// The same surface with `new_knots` inserted in the v direction (A5.4 on every row of the net).
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let w: Vec<Vec<f64>> = (0..4).map(|i| (0..3).map(|j| 1.0 + 0.2 * ((i + j) % 2) as f64).collect()).collect();
    /// let s = NurbsSurface::new(3, 2, uniform_clamped(3, 4), uniform_clamped(2, 3), net, Some(w)).unwrap();
    /// let r = s.refine_knots_v(&[0.2, 0.2, 0.9]).unwrap();
    /// assert_eq!(r.net_size(), (4, 6));
    /// assert!((r.point(0.45, 0.8) - s.point(0.45, 0.8)).norm() < 1e-14);
    /// assert!(s.refine_knots_v(&[1.0]).is_err());
    /// ```
    pub fn refine_knots_v(&self, new_knots: &[f64]) -> Result<NurbsSurface> {
        self.map_lines(Dir::V, 0, &|p, k, c| refine_knots_hom(p, k, c, new_knots))
    }

    /// The same surface with the u degree raised by `t` (NURBS Book A5.9 on every column).
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let s = NurbsSurface::new(2, 2, uniform_clamped(2, 4), uniform_clamped(2, 3), net, None).unwrap();
    /// let e = s.elevate_degree_u(2).unwrap();
    /// assert_eq!(e.degree_u(), 4);
    /// assert!((e.point(0.3, 0.6) - s.point(0.3, 0.6)).norm() < 1e-14);
    /// ```
    pub fn elevate_degree_u(&self, t: usize) -> Result<NurbsSurface> {
        self.map_lines(Dir::U, t, &|p, k, c| elevate_degree_hom(p, k, c, t))
    }

    /// The same surface with the v degree raised by `t` (NURBS Book A5.9 on every row).
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let w: Vec<Vec<f64>> = (0..4).map(|i| (0..3).map(|j| 1.0 + 0.2 * ((i + j) % 2) as f64).collect()).collect();
    /// let s = NurbsSurface::new(3, 2, uniform_clamped(3, 4), uniform_clamped(2, 3), net, Some(w)).unwrap();
    /// let e = s.elevate_degree_v(1).unwrap();
    /// assert_eq!((e.degree_u(), e.degree_v()), (3, 3));
    /// assert!((e.point(0.3, 0.6) - s.point(0.3, 0.6)).norm() < 1e-14);
    /// ```
    pub fn elevate_degree_v(&self, t: usize) -> Result<NurbsSurface> {
        self.map_lines(Dir::V, t, &|p, k, c| elevate_degree_hom(p, k, c, t))
    }
}
