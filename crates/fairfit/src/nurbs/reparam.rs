//! Reversal and affine reparametrisation of curves: exact operations on the knot vector alone.

use super::curve::NurbsCurve;
use crate::errors::{Error, Result};

/// The knots mapped affinely from `[a, b]` onto `[c, d]`, with the domain ends mapped exactly.
pub(crate) fn affine_knots(
    knots: &[f64],
    (a, b): (f64, f64),
    (c, d): (f64, f64),
) -> Result<Vec<f64>> {
    if !(c.is_finite() && d.is_finite() && c < d) {
        return Err(Error::KnotOperation(format!(
            "target interval [{c}, {d}] must be finite with start < end"
        )));
    }
    let s = (d - c) / (b - a);
    let out: Vec<f64> = knots
        .iter()
        .map(|&k| {
            if k == a {
                c
            } else if k == b {
                d
            } else {
                c + (k - a) * s
            }
        })
        .collect();
    if out.iter().any(|k| !k.is_finite()) || out.windows(2).any(|w| w[1] < w[0]) {
        return Err(Error::KnotOperation(format!(
            "mapping the knots onto [{c}, {d}] overflows or loses their order"
        )));
    }
    Ok(out)
}

impl NurbsCurve {
    /// The same point set traversed backwards: `R(u) = C(a + b − u)` on the same domain `[a, b]`
    /// (knots mirrored as `a + b − U[m − i]`, control points and weights reversed).
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let pts = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 1.0, 1.0)];
    /// let c = NurbsCurve::new(2, vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0], pts, Some(vec![1.0, 3.0, 1.0])).unwrap();
    /// let r = c.reversed();
    /// assert!((r.point(0.5) - c.point(1.5)).norm() < 1e-15);
    /// assert_eq!(r.weights(), &[1.0, 3.0, 1.0]);
    /// ```
    pub fn reversed(&self) -> NurbsCurve {
        let (a, b) = self.domain();
        // the domain ends swap exactly; other knots mirror up to rounding
        let mirror = |k: f64| {
            if k == a {
                b
            } else if k == b {
                a
            } else {
                a + b - k
            }
        };
        let knots: Vec<f64> = self.knots().iter().rev().map(|&k| mirror(k)).collect();
        let mut pts = self.control_points().to_vec();
        pts.reverse();
        let mut w = self.weights().to_vec();
        w.reverse();
        NurbsCurve::from_parts_unchecked(self.degree(), knots, pts, w)
    }

    /// The same curve with its domain mapped affinely onto `[a, b]`: `R(t) = C(u0 + (t − a)(u1 − u0)/(b − a))`.
    /// Control points and weights are unchanged; derivatives scale by powers of `(u1 − u0)/(b − a)`.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let pts = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 1.0, 1.0)];
    /// let c = NurbsCurve::bspline(2, vec![2.0, 2.0, 2.0, 6.0, 6.0, 6.0], pts).unwrap();
    /// let r = c.reparametrized(0.0, 1.0).unwrap();
    /// assert_eq!(r.domain(), (0.0, 1.0));
    /// assert!((r.point(0.25) - c.point(3.0)).norm() < 1e-15);
    /// ```
    pub fn reparametrized(&self, a: f64, b: f64) -> Result<NurbsCurve> {
        let knots = affine_knots(self.knots(), self.domain(), (a, b))?;
        Ok(NurbsCurve::from_parts_unchecked(
            self.degree(),
            knots,
            self.control_points().to_vec(),
            self.weights().to_vec(),
        ))
    }
}
