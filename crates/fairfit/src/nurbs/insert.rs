//! Knot insertion (NURBS Book A5.1) on homogeneous control points, so rational curves stay exact.
//!
//! The homogeneous helper [`insert_knot_hom`] works on one row of control points; curves call it
//! directly and surfaces call it once per row or column.

use super::curve::NurbsCurve;
use crate::errors::{Error, Result};

/// A homogeneous control point `(w x, w y, w z, w)`.
pub(crate) type Hom = [f64; 4];

/// `a * x + b * y` for homogeneous points.
#[inline]
pub(crate) fn lerp(a: f64, x: &Hom, b: f64, y: &Hom) -> Hom {
    [
        a * x[0] + b * y[0],
        a * x[1] + b * y[1],
        a * x[2] + b * y[2],
        a * x[3] + b * y[3],
    ]
}

/// Inserts `u` `times` times into the knot vector of degree `p` with homogeneous points `cw`
/// (NURBS Book A5.1). `u` must lie in the domain `[U[p], U[n+1]]` and its multiplicity after
/// insertion must not exceed `p`.
pub(crate) fn insert_knot_hom(
    p: usize,
    knots: &[f64],
    cw: &[Hom],
    u: f64,
    times: usize,
) -> Result<(Vec<f64>, Vec<Hom>)> {
    let np = cw.len() - 1;
    let (a, b) = (knots[p], knots[np + 1]);
    if !u.is_finite() || u < a || u > b {
        return Err(Error::KnotOperation(format!(
            "knot {u} lies outside the domain [{a}, {b}]"
        )));
    }
    if times == 0 {
        return Ok((knots.to_vec(), cw.to_vec()));
    }
    let s = knots.iter().filter(|&&k| k == u).count();
    if s > p || times > p - s {
        return Err(Error::KnotOperation(format!(
            "knot {u} has multiplicity {s}; inserting it {times} more times exceeds the degree {p}"
        )));
    }
    let r = times;
    // k: the span with U[k] <= u < U[k+1] (the last knot not above u)
    let k = knots.partition_point(|&x| x <= u) - 1;
    let mut uq = Vec::with_capacity(knots.len() + r);
    uq.extend_from_slice(&knots[..=k]);
    uq.extend(std::iter::repeat_n(u, r));
    uq.extend_from_slice(&knots[k + 1..]);
    let mut qw = vec![[0.0; 4]; cw.len() + r];
    qw[..=k - p].copy_from_slice(&cw[..=k - p]);
    qw[k - s + r..].copy_from_slice(&cw[k - s..]);
    let mut rw: Vec<Hom> = cw[k - p..=k - s].to_vec();
    let mut l = 0;
    for j in 1..=r {
        l = k - p + j;
        for i in 0..=p - j - s {
            let alpha = (u - knots[l + i]) / (knots[i + k + 1] - knots[l + i]);
            rw[i] = lerp(alpha, &rw[i + 1], 1.0 - alpha, &rw[i]);
        }
        qw[l] = rw[0];
        qw[k + r - j - s] = rw[p - j - s];
    }
    if l + 1 < k - s {
        qw[l + 1..k - s].copy_from_slice(&rw[1..k - s - l]);
    }
    Ok((uq, qw))
}

impl NurbsCurve {
    /// The same curve with the knot `u` inserted `times` times (NURBS Book A5.1); the geometry is
    /// unchanged (exactly, up to rounding), rational curves included.
    ///
    /// Errors when `u` lies outside the domain or its multiplicity would exceed the degree.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let c = NurbsCurve::circle(Vec3::ZERO, 2.0).unwrap();
    /// let d = c.insert_knot(0.3, 2).unwrap();
    /// assert_eq!(d.n_control_points(), c.n_control_points() + 2);
    /// assert!((d.point(0.41) - c.point(0.41)).norm() < 1e-14);
    /// assert!(c.insert_knot(0.25, 1).is_err()); // 0.25 already has multiplicity 2 = degree
    /// ```
    pub fn insert_knot(&self, u: f64, times: usize) -> Result<NurbsCurve> {
        let (knots, cw) = insert_knot_hom(
            self.degree(),
            self.knots(),
            self.homogeneous_points(),
            u,
            times,
        )?;
        try_from_hom_parts(self.degree(), knots, &cw, self.is_rational())
    }

    /// A curve of the same degree (and the same rationality) from new knots and homogeneous points
    /// produced by an exact knot operation. Non-rational curves keep weights exactly 1.
    pub(crate) fn with_homogeneous(&self, knots: Vec<f64>, cw: &[Hom]) -> NurbsCurve {
        from_hom_parts(self.degree(), knots, cw, self.is_rational())
    }
}

/// Builds a curve from homogeneous points known to be valid; `rational == false` forces weights 1.
pub(crate) fn from_hom_parts(
    degree: usize,
    knots: Vec<f64>,
    cw: &[Hom],
    rational: bool,
) -> NurbsCurve {
    let (pts, w) = dehomogenize(cw, rational);
    NurbsCurve::from_parts_unchecked(degree, knots, pts, w)
}

/// Builds a curve from homogeneous points, validating the result: with weights spanning hundreds of
/// orders of magnitude a combined weight can underflow to 0 (or a point overflow), which is a typed
/// error here instead of a curve holding NaN.
pub(crate) fn try_from_hom_parts(
    degree: usize,
    knots: Vec<f64>,
    cw: &[Hom],
    rational: bool,
) -> crate::errors::Result<NurbsCurve> {
    let (pts, w) = dehomogenize(cw, rational);
    NurbsCurve::new(degree, knots, pts, Some(w))
}

/// Euclidean points and weights from homogeneous points; `rational == false` forces weights 1.
pub(crate) fn dehomogenize(cw: &[Hom], rational: bool) -> (Vec<super::Vec3>, Vec<f64>) {
    use super::Vec3;
    if rational {
        let pts = cw
            .iter()
            .map(|c| Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3]))
            .collect();
        (pts, cw.iter().map(|c| c[3]).collect())
    } else {
        let pts = cw.iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        (pts, vec![1.0; cw.len()])
    }
}
