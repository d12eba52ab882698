//! Iso-parametric curves of surfaces, exact: the homogeneous net contracted with the basis functions
//! of one direction at a fixed parameter gives the control points of a NURBS curve in the other.

use super::basis::basis_funs_into;
use super::curve::NurbsCurve;
use super::insert::{try_from_hom_parts, Hom};
use super::knots::find_span;
use super::surface::NurbsSurface;
use crate::errors::Result;

impl NurbsSurface {
    /// The curve `v ↦ S(u0, v)` (degree `q`, the v knot vector). Errors when `u0` lies outside the u domain.
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let s = NurbsSurface::new(3, 2, uniform_clamped(3, 4), uniform_clamped(2, 3), net, None).unwrap();
    /// let c = s.iso_curve_u(0.4).unwrap();
    /// assert!((c.point(0.7) - s.point(0.4, 0.7)).norm() < 1e-14);
    /// ```
    pub fn iso_curve_u(&self, u0: f64) -> Result<NurbsCurve> {
        self.check_parameter(u0, self.domain_v().0)?;
        let (n_u, n_v) = self.net_size();
        let p = self.degree_u();
        let span = find_span(n_u - 1, p, u0, self.knots_u());
        let n = basis_at(span, u0, p, self.knots_u());
        let cw = self.homogeneous_points();
        let q: Vec<Hom> = (0..n_v)
            .map(|j| contract(&n, |r| &cw[(span - p + r) * n_v + j]))
            .collect();
        try_from_hom_parts(
            self.degree_v(),
            self.knots_v().to_vec(),
            &q,
            self.is_rational(),
        )
    }

    /// The curve `u ↦ S(u, v0)` (degree `p`, the u knot vector). Errors when `v0` lies outside the v domain.
    ///
    /// ```
    /// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
    /// let net: Vec<Vec<Vec3>> = (0..4)
    ///     .map(|i| (0..3).map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64)).collect())
    ///     .collect();
    /// let w: Vec<Vec<f64>> = (0..4).map(|i| (0..3).map(|j| 1.0 + 0.2 * ((i + j) % 2) as f64).collect()).collect();
    /// let s = NurbsSurface::new(3, 2, uniform_clamped(3, 4), uniform_clamped(2, 3), net, Some(w)).unwrap();
    /// let c = s.iso_curve_v(0.25).unwrap();
    /// assert!(c.is_rational());
    /// assert!((c.point(0.6) - s.point(0.6, 0.25)).norm() < 1e-14);
    /// assert!(s.iso_curve_v(-0.5).is_err());
    /// ```
    pub fn iso_curve_v(&self, v0: f64) -> Result<NurbsCurve> {
        self.check_parameter(self.domain_u().0, v0)?;
        let (n_u, n_v) = self.net_size();
        let q = self.degree_v();
        let span = find_span(n_v - 1, q, v0, self.knots_v());
        let n = basis_at(span, v0, q, self.knots_v());
        let cw = self.homogeneous_points();
        let pts: Vec<Hom> = (0..n_u)
            .map(|i| contract(&n, |r| &cw[i * n_v + span - q + r]))
            .collect();
        try_from_hom_parts(
            self.degree_u(),
            self.knots_u().to_vec(),
            &pts,
            self.is_rational(),
        )
    }
}

/// The `p + 1` non-zero basis functions at `u` in `span`.
fn basis_at(span: usize, u: f64, p: usize, knots: &[f64]) -> Vec<f64> {
    let (mut l, mut r, mut n) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    basis_funs_into(span, u, p, knots, &mut l, &mut r, &mut n);
    n
}

/// `Σ_r n[r] · point(r)` over homogeneous points.
fn contract<'a>(n: &[f64], point: impl Fn(usize) -> &'a Hom) -> Hom {
    let mut acc = [0.0; 4];
    for (r, nr) in n.iter().enumerate() {
        let q = point(r);
        for c in 0..4 {
            acc[c] += nr * q[c];
        }
    }
    acc
}
