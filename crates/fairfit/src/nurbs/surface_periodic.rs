//! Periodicity of a surface in one direction: an unclamped knot vector whose spans repeat with the
//! period of the domain and whose last `p` control rows (or columns) repeat the first `p`, as
//! [`crate::fit::lsq::periodic_knots`] builds it. Such a surface is closed and `C^(p−1)` across its
//! seam; the CAD writers flag it so.

use super::knots::is_periodic;
use super::surface::NurbsSurface;

impl NurbsSurface {
    /// True when the surface is periodic in u: periodic u knots and the last `p_u` control rows
    /// (points and weights) equal to the first `p_u`.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsSurface, Vec3};
    /// // a periodic cubic ring of 4 distinct rows (3 repeated), linear in v
    /// let ku: Vec<f64> = (-3..=7).map(|i| i as f64 / 4.0).collect();
    /// let ring = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
    /// let net = (0..7)
    ///     .map(|i| (0..2).map(|j| Vec3::new(ring[i % 4].0, ring[i % 4].1, j as f64)).collect())
    ///     .collect();
    /// let s = NurbsSurface::new(3, 1, ku, vec![0.0, 0.0, 1.0, 1.0], net, None).unwrap();
    /// assert!(s.is_periodic_u() && !s.is_periodic_v());
    /// assert!((s.point(0.0, 0.5) - s.point(1.0, 0.5)).norm() < 1e-15);
    /// ```
    pub fn is_periodic_u(&self) -> bool {
        let (n_u, n_v) = self.net_size();
        let p = self.degree_u();
        is_periodic(self.knots_u(), p) && {
            let h = self.homogeneous_points();
            (0..p).all(|i| (0..n_v).all(|j| h[i * n_v + j] == h[(n_u - p + i) * n_v + j]))
        }
    }

    /// True when the surface is periodic in v (see [`Self::is_periodic_u`]).
    pub fn is_periodic_v(&self) -> bool {
        let (n_u, n_v) = self.net_size();
        let q = self.degree_v();
        is_periodic(self.knots_v(), q) && {
            let h = self.homogeneous_points();
            (0..q).all(|j| (0..n_u).all(|i| h[i * n_v + j] == h[i * n_v + n_v - q + j]))
        }
    }
}
