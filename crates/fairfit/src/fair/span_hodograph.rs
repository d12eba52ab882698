//! The exact derivative numerators of a (rational) B-spline curve's polynomial pieces: per knot
//! span, `D`, `E = D'` and `E'` in Bernstein form, from which every curvature numerator of
//! [`super::curvature_numerators`] is formed by exact polynomial arithmetic (no sampling).
//!
//! On a knot span the curve is `C = A / w` with `A` (the weighted coordinates) and `w` (the
//! weight) polynomials of the B-spline's degree `p`: their Bernstein coefficients are the blossoms
//! of the local homogeneous de Boor points (valid for clamped and unclamped knot vectors). With
//! `D = A'w − A w'` (degree `2p − 1` as stored; its leading power coefficient cancels),
//!
//! - `C' = D / w²`, `C'' = (w E − 2 w' D) / w³` with `E = D' = A''w − A w''`, and
//!   `C''' = (w² E' − 4 w w' E − 2 w w'' D + 6 w'² D) / w⁴`;
//! - hence `C' × C'' = (D × E) / w⁴` and `C' × C''' = (w D × E' − 4 w' D × E) / w⁵`.
//!
//! A polynomial piece (all weights equal) has `w = 1`, `D = A'`, `E = A''`, `E' = A'''` and is
//! stored without a weight, so its numerators keep their lower polynomial degree.
//!
//! **Frame and scale**: the control points are written relative to the first one and divided by
//! the control polygon's extent (coordinates of order 1), in a plane's orthonormal frame
//! (`e1 × e2 = normal`) for a planar curve or in the world axes for a spatial one; weights are
//! divided by the largest one. Curvature `κ` of the local piece is `extent` times the curve's,
//! `dκ/ds` is `extent²` times the curve's.

use super::bernstein::{combine, derivative, mul};
use crate::nurbs::{NurbsCurve, Vec3};

/// The derivative numerators of one knot span `[a, b]` (span parameter `t = (u − a)/(b − a)`).
#[derive(Clone, Debug, PartialEq)]
pub struct SpanHodograph {
    /// Span start.
    pub a: f64,
    /// Span end.
    pub b: f64,
    /// `D` per local coordinate (`C' = D / w²`).
    pub d: Vec<Vec<f64>>,
    /// `E = D'` per local coordinate.
    pub e: Vec<Vec<f64>>,
    /// `E'` per local coordinate.
    pub e1: Vec<Vec<f64>>,
    /// `(w, w')` of a rational piece; `None` for a polynomial piece (`w = 1`).
    pub weight: Option<(Vec<f64>, Vec<f64>)>,
}

/// The local frame of a curve and the hodographs of its spans.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CurveHodographs {
    /// The control polygon's extent (local coordinates are divided by it).
    pub extent: f64,
    /// One entry per non-empty knot span, in parameter order.
    pub spans: Vec<SpanHodograph>,
}

/// The span hodographs of `curve` in the plane with unit normal `normal` (two local coordinates)
/// or, for `None`, in space (three). `None` for a degenerate curve (all control points equal,
/// non-finite coordinates, degree 0).
pub(crate) fn curve_hodographs(
    curve: &NurbsCurve,
    normal: Option<Vec3>,
) -> Option<CurveHodographs> {
    let p = curve.degree();
    let ctrl = curve.control_points();
    let knots = curve.knots();
    let n = ctrl.len();
    if p == 0 || n <= p || knots.len() != n + p + 1 {
        return None;
    }
    let (origin, extent) = origin_and_extent(ctrl)?;
    let axes: Vec<Vec3> = match normal {
        Some(nv) => {
            let (e1, e2) = plane_frame(nv);
            vec![e1, e2]
        }
        None => vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ],
    };
    let rational = curve.is_rational();
    let wmax = curve.weights().iter().fold(0.0f64, |m, &w| m.max(w));
    let weights: Vec<f64> = if rational {
        curve.weights().iter().map(|&w| w / wmax).collect()
    } else {
        vec![1.0; n]
    };
    if rational && !(wmax > 0.0 && wmax.is_finite()) {
        return None;
    }
    // the weighted local coordinates, one column per axis
    let cols: Vec<Vec<f64>> = axes
        .iter()
        .map(|&e| {
            ctrl.iter()
                .zip(&weights)
                .map(|(&q, &w)| w * ((q - origin) / extent).dot(e))
                .collect()
        })
        .collect();
    let mut spans = Vec::new();
    for s in p..n {
        let (a, b) = (knots[s], knots[s + 1]);
        if b <= a {
            continue;
        }
        let piece = |v: &[f64]| bezier_piece(knots, p, s, &v[s - p..=s]);
        let coords: Vec<Vec<f64>> = cols.iter().map(|c| piece(c)).collect();
        let weight = rational.then(|| piece(&weights));
        spans.push(span_hodograph(a, b, &coords, weight));
    }
    Some(CurveHodographs { extent, spans })
}

/// The hodograph of the piece with Bernstein coefficients `coords` (weighted coordinates) and
/// `weight` (`None`: polynomial).
pub fn span_hodograph(
    a: f64,
    b: f64,
    coords: &[Vec<f64>],
    weight: Option<Vec<f64>>,
) -> SpanHodograph {
    let d: Vec<Vec<f64>> = match &weight {
        None => coords.iter().map(|c| derivative(c)).collect(),
        Some(w) => {
            let w1 = derivative(w);
            coords
                .iter()
                .map(|c| combine(1.0, &mul(&derivative(c), w), -1.0, &mul(c, &w1)))
                .collect()
        }
    };
    let e: Vec<Vec<f64>> = d.iter().map(|c| derivative(c)).collect();
    let e1: Vec<Vec<f64>> = e.iter().map(|c| derivative(c)).collect();
    let weight = weight.map(|w| {
        let w1 = derivative(&w);
        (w, w1)
    });
    SpanHodograph {
        a,
        b,
        d,
        e,
        e1,
        weight,
    }
}

/// The parameters inside the knot spans of `curve` where its speed is stationary: the roots of
/// `D·E = ½ (|D|²)'` (`C' = D / w²`, so the speed vanishes exactly where `D` does, and there `|D|²`
/// has a minimum), isolated per span in Bernstein form
/// ([`super::bernstein::sign_changes_and_zeros`]), not sampled. A zero of the speed strictly inside a span is among them (a knot is not: callers check
/// the knots themselves). Ascending; empty for a degenerate curve or degree 1 (constant speed per
/// span).
///
/// ```
/// use fairfit::fair::span_hodograph::speed_critical_points;
/// use fairfit::{NurbsCurve, Vec3};
/// // C(u) = (u², u³ - u): C' = (2u, 3u² - 1), |C'|² = 9u⁴ - 2u² + 1 is stationary at 0 and ±1/3
/// let c = NurbsCurve::bspline(
///     3,
///     vec![-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0],
///     vec![
///         Vec3::new(1.0, 0.0, 0.0),
///         Vec3::new(-1.0 / 3.0, 4.0 / 3.0, 0.0),
///         Vec3::new(-1.0 / 3.0, -4.0 / 3.0, 0.0),
///         Vec3::new(1.0, 0.0, 0.0),
///     ],
/// )
/// .unwrap();
/// let u = speed_critical_points(&c);
/// assert_eq!(u.len(), 3);
/// for (got, want) in u.iter().zip([-1.0 / 3.0, 0.0, 1.0 / 3.0]) {
///     assert!((got - want).abs() < 1e-14, "{got}");
/// }
/// ```
pub fn speed_critical_points(curve: &NurbsCurve) -> Vec<f64> {
    let Some(h) = curve_hodographs(curve, None).filter(|_| curve.degree() >= 2) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut roots = Vec::new();
    for s in &h.spans {
        let terms: Vec<Vec<f64>> = s.d.iter().zip(&s.e).map(|(d, e)| mul(d, e)).collect();
        let scale = terms.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let Some(dot) = terms
            .iter()
            .cloned()
            .reduce(|acc, t| combine(1.0, &acc, 1.0, &t))
        else {
            continue;
        };
        roots.clear();
        super::bernstein::sign_changes_and_zeros(&dot, 1e-14 * scale, &mut roots);
        out.extend(roots.iter().map(|&t| s.a + (s.b - s.a) * t));
    }
    out
}

/// The control polygon's origin (its first point) and extent (largest coordinate distance from it),
/// the local coordinates' origin and unit; `None` when the extent is zero or not finite.
pub(crate) fn origin_and_extent(ctrl: &[Vec3]) -> Option<(Vec3, f64)> {
    let origin = ctrl[0];
    let extent = ctrl
        .iter()
        .fold(0.0f64, |m, &q| m.max((q - origin).max_abs()));
    (extent > 0.0 && extent.is_finite()).then_some((origin, extent))
}

/// An in-plane frame `(e1, e2)` with `e1 × e2 = normal` for the unit `normal`.
pub(crate) fn plane_frame(normal: Vec3) -> (Vec3, Vec3) {
    let t = if normal.x().abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let e1 = {
        let v = t - normal * t.dot(normal);
        v / v.norm()
    };
    (e1, normal.cross(e1))
}

/// The Bernstein coefficients of knot span `s` of the degree-`p` scalar B-spline with the local
/// de Boor values `vals` (`v_{s−p} … v_s`): the blossoms `b_k = f(a^{p−k}, b^k)`.
pub fn bezier_piece(knots: &[f64], p: usize, s: usize, vals: &[f64]) -> Vec<f64> {
    let (a, b) = (knots[s], knots[s + 1]);
    let mut out = Vec::with_capacity(p + 1);
    let mut d = vals.to_vec();
    for k in 0..=p {
        d.copy_from_slice(vals);
        // de Boor's recurrence with the argument of level r: a for r ≤ p − k, else b
        for r in 1..=p {
            let u = if r <= p - k { a } else { b };
            for j in (r..=p).rev() {
                let i = s - p + j;
                let den = knots[i + p + 1 - r] - knots[i];
                let al = if den > 0.0 { (u - knots[i]) / den } else { 0.0 };
                d[j] = (1.0 - al) * d[j - 1] + al * d[j];
            }
        }
        out.push(d[p]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::bernstein::eval;

    #[test]
    fn the_hodograph_gives_the_rational_derivatives() {
        // a rational cubic in space: C' = D / w² and C' × C'' = (D × E) / w⁴ at interior points
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
        let ctrl: Vec<Vec3> = [
            (0., 0., 0.),
            (1., 2., 0.5),
            (2., 3., -1.),
            (3., 1., 0.),
            (4., 0., 2.),
        ]
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z))
        .collect();
        let w = vec![1.0, 0.5, 2.0, 0.8, 1.0];
        let c = NurbsCurve::new(3, knots, ctrl.clone(), Some(w)).unwrap();
        let h = curve_hodographs(&c, None).unwrap();
        assert_eq!(h.spans.len(), 2);
        for sp in &h.spans {
            let (wp, _) = sp.weight.as_ref().unwrap();
            for &t in &[0.1, 0.5, 0.9] {
                let u = sp.a + (sp.b - sp.a) * t;
                let der = c.derivatives(u, 2);
                let wt = eval(wp, t);
                let dv = Vec3::new(eval(&sp.d[0], t), eval(&sp.d[1], t), eval(&sp.d[2], t));
                let ev = Vec3::new(eval(&sp.e[0], t), eval(&sp.e[1], t), eval(&sp.e[2], t));
                // local units: coordinates / extent, derivatives in t = (u − a)/(b − a)
                let du = sp.b - sp.a;
                let c1 = dv / (wt * wt) * (h.extent / du);
                assert!((c1 - der[1]).max_abs() < 1e-12 * der[1].max_abs(), "{c1:?}");
                let cross = dv.cross(ev) / wt.powi(4) * (h.extent * h.extent / du.powi(3));
                let want = der[1].cross(der[2]);
                assert!(
                    (cross - want).max_abs() < 1e-11 * want.max_abs(),
                    "{cross:?}"
                );
            }
        }
    }
}
