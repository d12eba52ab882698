//! Rational B-spline (NURBS) curves in 3D: construction with validation, evaluation of points and
//! derivatives of any order (NURBS Book A3.1, A3.2, A4.1, A4.2), batched evaluation without allocation.
//!
//! Written here rather than taken from a crate: fairfit needs allocation-free batched evaluation,
//! unclamped knot vectors, exact rational derivatives up to order 3 and direct access to the homogeneous
//! control points for the least-squares solvers; no maintained crate offers all of that.

use super::basis::{basis_funs_into, ders_basis_funs_into, with_basis_buffers};
use super::knots::{find_span, validate_knots};
use super::vec3::Vec3;
use crate::errors::{Error, Result};

/// Degrees and derivative orders below this use small stack buffers in single evaluations.
const SMALL: usize = 8;

/// Scratch slices for one derivative evaluation (see [`ders_basis_funs_into`]).
struct DerivBuffers<'a> {
    left: &'a mut [f64],
    right: &'a mut [f64],
    ndu: &'a mut [f64],
    a: &'a mut [f64],
    ders: &'a mut [f64],
    aders: &'a mut [[f64; 4]],
}

/// Heap scratch for derivative evaluation, sized exactly for degree `p` and order `d`.
struct OwnedDerivBuffers {
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
    ders: Vec<f64>,
    aders: Vec<[f64; 4]>,
}

impl OwnedDerivBuffers {
    fn new(p: usize, d: usize) -> Self {
        let p1 = p + 1;
        OwnedDerivBuffers {
            left: vec![0.0; p1],
            right: vec![0.0; p1],
            ndu: vec![0.0; p1 * p1],
            a: vec![0.0; 2 * p1],
            ders: vec![0.0; (d + 1) * p1],
            aders: vec![[0.0; 4]; d + 1],
        }
    }
    fn borrow(&mut self) -> DerivBuffers<'_> {
        DerivBuffers {
            left: &mut self.left,
            right: &mut self.right,
            ndu: &mut self.ndu,
            a: &mut self.a,
            ders: &mut self.ders,
            aders: &mut self.aders,
        }
    }
}

/// A NURBS curve of degree `p >= 1` with control points in 3D and positive weights.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    degree: usize,
    knots: Vec<f64>,
    control_points: Vec<Vec3>,
    weights: Vec<f64>,
    /// Homogeneous control points `(w x, w y, w z, w)`.
    cw: Vec<[f64; 4]>,
    rational: bool,
}

impl NurbsCurve {
    /// Builds a curve, validating every input.
    ///
    /// `knots` must hold `control_points.len() + degree + 1` finite, non-decreasing values; `weights`
    /// (all 1 when `None`) must be finite and positive, one per control point.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// // The paper's example (Hashemian & Hosseini, Section 2.1): a planar cubic with 7 control points
    /// // over U = [0,0,0,0,0.25,0.5,0.75,1,1,1,1].
    /// let pts: Vec<Vec3> = [(0.0, 0.0), (1.0, 2.0), (2.0, 3.0), (3.0, 1.0), (4.0, 0.0), (5.0, 2.0), (6.0, 1.0)]
    ///     .iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
    /// let knots = vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0];
    /// let w = vec![1.0, 0.5, 2.0, 1.0, 1.5, 1.0, 1.0];
    /// let c = NurbsCurve::new(3, knots, pts.clone(), Some(w)).unwrap();
    /// assert_eq!(c.domain(), (0.0, 1.0));
    /// // a clamped curve starts and ends at its end control points
    /// assert!((c.point(0.0) - pts[0]).norm() < 1e-15);
    /// assert!((c.point(1.0) - pts[6]).norm() < 1e-15);
    /// // a wrong knot count is a typed error naming the problem
    /// let bad = NurbsCurve::new(3, vec![0.0, 1.0], pts, None);
    /// assert!(bad.unwrap_err().to_string().contains("expected 11 knots"));
    /// ```
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        control_points: Vec<Vec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        let n = control_points.len();
        if n == 0 {
            return Err(Error::InvalidControlPoints(
                "a curve needs at least one control point".into(),
            ));
        }
        validate_knots(&knots, degree, n, "curve")?;
        if let Some(i) = control_points.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidControlPoints(format!(
                "control point {i} is not finite: {:?}",
                control_points[i].0
            )));
        }
        let weights = weights.unwrap_or_else(|| vec![1.0; n]);
        validate_weights(&weights, n)?;
        validate_homogeneous(&control_points, &weights)?;
        Ok(Self::from_parts_unchecked(
            degree,
            knots,
            control_points,
            weights,
        ))
    }

    /// A non-rational B-spline curve (all weights 1).
    pub fn bspline(degree: usize, knots: Vec<f64>, control_points: Vec<Vec3>) -> Result<Self> {
        Self::new(degree, knots, control_points, None)
    }

    /// Builds a curve from parts the caller has already validated (used by algorithms that preserve
    /// validity, like knot insertion). Debug builds still check.
    pub(crate) fn from_parts_unchecked(
        degree: usize,
        knots: Vec<f64>,
        control_points: Vec<Vec3>,
        weights: Vec<f64>,
    ) -> Self {
        debug_assert!(validate_knots(&knots, degree, control_points.len(), "curve").is_ok());
        debug_assert_eq!(weights.len(), control_points.len());
        let rational = weights.iter().any(|&w| w != 1.0);
        let cw = control_points
            .iter()
            .zip(&weights)
            .map(|(p, &w)| [p[0] * w, p[1] * w, p[2] * w, w])
            .collect();
        NurbsCurve {
            degree,
            knots,
            control_points,
            weights,
            cw,
            rational,
        }
    }

    /// Builds a curve from homogeneous control points `(w x, w y, w z, w)`.
    pub fn from_homogeneous(degree: usize, knots: Vec<f64>, cw: &[[f64; 4]]) -> Result<Self> {
        let weights: Vec<f64> = cw.iter().map(|c| c[3]).collect();
        validate_weights(&weights, cw.len())?;
        let pts = cw
            .iter()
            .map(|c| Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3]))
            .collect();
        Self::new(degree, knots, pts, Some(weights))
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// The full knot vector (`n + p + 2` values).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    /// The control points (Euclidean).
    pub fn control_points(&self) -> &[Vec3] {
        &self.control_points
    }
    /// The weights, one per control point.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }
    /// The homogeneous control points `(w x, w y, w z, w)`.
    pub fn homogeneous_points(&self) -> &[[f64; 4]] {
        &self.cw
    }
    /// True when some weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }
    /// The number of control points `n + 1`.
    pub fn n_control_points(&self) -> usize {
        self.control_points.len()
    }
    /// The parameter domain `[U[p], U[n+1]]`.
    pub fn domain(&self) -> (f64, f64) {
        (
            self.knots[self.degree],
            self.knots[self.control_points.len()],
        )
    }
    /// Index of the last control point, `n`.
    #[inline]
    fn last(&self) -> usize {
        self.control_points.len() - 1
    }

    /// Checks that `u` lies in the domain (up to a relative 1e-12 of its length).
    pub fn check_parameter(&self, u: f64) -> Result<()> {
        let (a, b) = self.domain();
        let slack = 1e-12 * (b - a);
        if !u.is_finite() || u < a - slack || u > b + slack {
            return Err(Error::ParameterOutOfDomain {
                value: u,
                min: a,
                max: b,
            });
        }
        Ok(())
    }

    /// The knot span index holding `u`.
    #[inline]
    pub fn find_span(&self, u: f64) -> usize {
        find_span(self.last(), self.degree, u, &self.knots)
    }

    /// The point `C(u)`. Parameters outside the domain evaluate the polynomial of the end span
    /// (use [`NurbsCurve::check_parameter`] to reject them).
    #[inline]
    pub fn point(&self, u: f64) -> Vec3 {
        with_basis_buffers(self.degree, |left, right, n| {
            self.point_with(u, left, right, n)
        })
    }

    #[inline]
    fn point_with(&self, u: f64, left: &mut [f64], right: &mut [f64], n: &mut [f64]) -> Vec3 {
        self.point_in_span(self.find_span(u), u, left, right, n)
    }

    /// `C(u)` with `span` the knot span holding `u` ([`NurbsCurve::find_span`]).
    #[inline]
    fn point_in_span(
        &self,
        span: usize,
        u: f64,
        left: &mut [f64],
        right: &mut [f64],
        n: &mut [f64],
    ) -> Vec3 {
        let p = self.degree;
        basis_funs_into(span, u, p, &self.knots, left, right, n);
        let mut c = [0.0; 4];
        for (j, nj) in n.iter().take(p + 1).enumerate() {
            let q = &self.cw[span - p + j];
            c[0] += nj * q[0];
            c[1] += nj * q[1];
            c[2] += nj * q[2];
            c[3] += nj * q[3];
        }
        if self.rational {
            Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3])
        } else {
            Vec3::new(c[0], c[1], c[2])
        }
    }

    /// Evaluates `C(u)` for every parameter in `us` into `out` (same length); no allocation for
    /// degrees up to 15.
    ///
    /// # Panics
    /// When `out.len() != us.len()` (a caller's buffer bug, like `copy_from_slice`; never input data).
    pub fn points_into(&self, us: &[f64], out: &mut [Vec3]) {
        assert_eq!(us.len(), out.len(), "points_into: output length must match");
        with_basis_buffers(self.degree, |left, right, n| {
            for (u, o) in us.iter().zip(out.iter_mut()) {
                *o = self.point_with(*u, left, right, n);
            }
        });
    }

    /// Evaluates `C(u)` for every parameter of `us` into `out` as rows of the first `dim`
    /// coordinates (`out.len() == us.len() * dim`, `dim` 1 to 3): the layout of an `(m, dim)`
    /// array, written in place. No allocation for degrees up to 15. The span of each parameter is
    /// found by stepping on from the previous parameter's when it is not smaller (sorted
    /// parameters cost O(1) per point rather than a binary search), by
    /// [`NurbsCurve::find_span`] otherwise; both give the same span, so the numbers equal
    /// [`NurbsCurve::point`]'s bit for bit.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let pts = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 0.0, 0.0)];
    /// let c = NurbsCurve::bspline(1, vec![0.0, 0.0, 0.5, 1.0, 1.0], pts).unwrap();
    /// let mut out = [0.0; 6];
    /// c.points_into_rows(&[0.25, 1.0, 0.5], 2, &mut out);
    /// assert_eq!(out, [0.5, 1.0, 3.0, 0.0, 1.0, 2.0]);
    /// ```
    ///
    /// # Panics
    /// When `out.len() != us.len() * dim` or `dim` is not 1 to 3 (a caller's buffer bug).
    pub fn points_into_rows(&self, us: &[f64], dim: usize, out: &mut [f64]) {
        assert!(
            (1..=3).contains(&dim),
            "points_into_rows: dim must be 1 to 3"
        );
        assert_eq!(
            us.len() * dim,
            out.len(),
            "points_into_rows: output length must be us.len() * dim"
        );
        let p = self.degree;
        let last = self.last();
        let (lo, hi) = (self.knots[p], self.knots[last + 1]);
        let mut span = self.find_span(lo);
        with_basis_buffers(p, |left, right, n| {
            for (&u, row) in us.iter().zip(out.chunks_exact_mut(dim)) {
                // strictly inside the domain and not before the last span: step on to the one span
                // with U[span] <= u < U[span + 1] (what the binary search finds)
                span = if u > lo && u < hi && u >= self.knots[span] {
                    while u >= self.knots[span + 1] {
                        span += 1;
                    }
                    span
                } else {
                    self.find_span(u)
                };
                let c = self.point_in_span(span, u, left, right, n);
                row.copy_from_slice(&c.0[..dim]);
            }
        });
    }

    /// Points at `us`, as a new vector.
    pub fn points(&self, us: &[f64]) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; us.len()];
        self.points_into(us, &mut out);
        out
    }

    /// `C(u)` and its derivatives up to order `d`: `out[k]` receives `C^(k)(u)` for `k = 0..=d`
    /// (rational derivatives by NURBS Book A4.2). `out` needs at least `d + 1` entries.
    ///
    /// At a knot, derivatives of order `>= p - m + 1` (m the multiplicity) are one-sided: the span
    /// `[U[i], U[i+1])` holding `u` is used, i.e. the right-hand limit (the left-hand one at the domain end).
    pub fn derivatives_into(&self, u: f64, d: usize, out: &mut [Vec3]) {
        let p = self.degree;
        if p < SMALL && d < SMALL {
            // small fixed buffers: cheap to zero, no heap
            let mut left = [0.0; SMALL];
            let mut right = [0.0; SMALL];
            let mut ndu = [0.0; SMALL * SMALL];
            let mut a = [0.0; 2 * SMALL];
            let mut ders = [0.0; SMALL * SMALL];
            let mut aders = [[0.0; 4]; SMALL];
            let mut bufs = DerivBuffers {
                left: &mut left,
                right: &mut right,
                ndu: &mut ndu,
                a: &mut a,
                ders: &mut ders,
                aders: &mut aders,
            };
            self.derivatives_with(u, d, &mut bufs, out);
        } else {
            let mut owned = OwnedDerivBuffers::new(p, d);
            self.derivatives_with(u, d, &mut owned.borrow(), out);
        }
    }

    /// [`NurbsCurve::derivatives_into`] with caller-provided buffers.
    #[inline]
    fn derivatives_with(&self, u: f64, d: usize, b: &mut DerivBuffers<'_>, out: &mut [Vec3]) {
        let span = self.find_span(u);
        ders_basis_funs_into(
            span,
            u,
            self.degree,
            d,
            &self.knots,
            b.left,
            b.right,
            b.ndu,
            b.a,
            b.ders,
        );
        self.combine(span, d, b.ders, b.aders, out);
    }

    /// Homogeneous derivatives from basis derivatives, then the rational quotient rule (A4.2).
    #[inline]
    fn combine(
        &self,
        span: usize,
        d: usize,
        ders: &[f64],
        aders: &mut [[f64; 4]],
        out: &mut [Vec3],
    ) {
        let p = self.degree;
        let p1 = p + 1;
        for k in 0..=d {
            let mut c = [0.0; 4];
            let row = &ders[k * p1..k * p1 + p1];
            for (j, nj) in row.iter().enumerate() {
                let q = &self.cw[span - p + j];
                c[0] += nj * q[0];
                c[1] += nj * q[1];
                c[2] += nj * q[2];
                c[3] += nj * q[3];
            }
            aders[k] = c;
        }
        if !self.rational {
            for k in 0..=d {
                out[k] = Vec3::new(aders[k][0], aders[k][1], aders[k][2]);
            }
            return;
        }
        let w0 = aders[0][3];
        for k in 0..=d {
            let mut v = Vec3::new(aders[k][0], aders[k][1], aders[k][2]);
            let mut bin = 1.0; // binom(k, i)
            for i in 1..=k {
                bin = bin * (k - i + 1) as f64 / i as f64;
                v -= out[k - i] * (bin * aders[i][3]);
            }
            out[k] = v / w0;
        }
    }

    /// `[C, C', ..., C^(d)]` at `u`, as a new vector.
    pub fn derivatives(&self, u: f64, d: usize) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; d + 1];
        self.derivatives_into(u, d, &mut out);
        out
    }

    /// Derivatives up to order `d` at each parameter of `us`: `out[i * (d + 1) + k] = C^(k)(us[i])`.
    ///
    /// # Panics
    /// When `out.len() != us.len() * (d + 1)` (a caller's buffer bug; never input data).
    pub fn derivatives_batch_into(&self, us: &[f64], d: usize, out: &mut [Vec3]) {
        assert_eq!(
            out.len(),
            us.len() * (d + 1),
            "derivatives_batch_into: output length"
        );
        // buffers sized once per batch, reused for every parameter
        let mut owned = OwnedDerivBuffers::new(self.degree, d);
        let mut bufs = owned.borrow();
        for (u, chunk) in us.iter().zip(out.chunks_exact_mut(d + 1)) {
            self.derivatives_with(*u, d, &mut bufs, chunk);
        }
    }
}

/// Checks that every weighted control point `w·P` (what evaluation sums) is finite: a weight of 1e300
/// on a coordinate of 1e300 overflows and would evaluate as NaN.
pub(crate) fn validate_homogeneous(points: &[Vec3], weights: &[f64]) -> Result<()> {
    if let Some(i) = points
        .iter()
        .zip(weights)
        .position(|(p, &w)| !(*p * w).is_finite())
    {
        return Err(Error::InvalidWeights(format!(
            "weight {i} ({}) times control point {i} {:?} overflows; scale the weights down",
            weights[i], points[i].0
        )));
    }
    Ok(())
}

/// Checks weights: right count, finite, strictly positive.
pub(crate) fn validate_weights(weights: &[f64], n: usize) -> Result<()> {
    if weights.len() != n {
        return Err(Error::InvalidWeights(format!(
            "expected {n} weights (one per control point), got {}",
            weights.len()
        )));
    }
    if let Some(i) = weights.iter().position(|w| !w.is_finite() || *w <= 0.0) {
        return Err(Error::InvalidWeights(format!(
            "weight {i} is {}; weights must be finite and > 0",
            weights[i]
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact rational quadratic quarter-circles (NURBS Book Ex. 7.1, 9 control points, full circle).
    fn circle(r: f64) -> NurbsCurve {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let pts = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ]
        .iter()
        .map(|&(x, y)| Vec3::new(r * x, r * y, 0.0))
        .collect();
        let w = vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0];
        let k = vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        NurbsCurve::new(2, k, pts, Some(w)).unwrap()
    }

    #[test]
    fn rational_circle_is_exact() {
        let c = circle(2.5);
        for i in 0..=400 {
            let u = i as f64 / 400.0;
            let d = c.derivatives(u, 2);
            assert!((d[0].norm() - 2.5).abs() < 1e-12);
            // velocity orthogonal to radius
            assert!(d[0].dot(d[1]).abs() < 1e-10 * d[1].norm());
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = circle(1.0);
        let h = 1e-5;
        for &u in &[0.1, 0.3, 0.6, 0.9] {
            let d = c.derivatives(u, 3);
            let dp = c.derivatives(u + h, 3);
            let dm = c.derivatives(u - h, 3);
            for k in 0..3 {
                let fd = (dp[k] - dm[k]) / (2.0 * h);
                assert!(
                    (fd - d[k + 1]).norm() < 1e-5 * (1.0 + d[k + 1].norm()),
                    "k={k} u={u}"
                );
            }
        }
    }
}
