//! The exact count of inflections of a planar B-spline (polynomial or rational): the sign changes
//! of the signed curvature `κ = w² G / |D|³` located as the real roots of its numerator
//! `G = D × E` per knot span ([`super::curvature_numerators`], degree `2p − 3` polynomial,
//! `4p − 3` as stored rational), not looked for on samples.
//!
//! Semantics are those of the sampled count ([`super::extrema`], the benchmark measurer's): the
//! dimensionless signal `κ L` (`L` the arc length), the floor `1e-6 max|κ L| + 1e-9` with
//! hysteresis, so a sign change across a knot (where `κ` jumps, e.g. a C¹ quadratic) counts, a
//! straight stretch (`G ≡ 0`) counts nothing, and the count is the limit of the sampled one for
//! infinitely many samples per span ([`super::exact_nurbs`] builds the intervals,
//! [`super::exact_extrema::alternations`] counts them).
//!
//! **Fallback**: a spatial curve has no signed curvature; its inflections (reversals of the
//! binormal direction, see [`super::extrema`]) are counted by dense sampling,
//! [`super::exact_extrema::DENSE_SAMPLES`] per span, and [`ExactInflections::exact`] is `false`.
//!
//! [`count_shape_exact`] makes this count and [`super::count_extrema_exact`] in one pass (the span
//! hodographs and curvature numerators formed once, one dense sampling when both fall back), with
//! the same results; the two single counts are that pass asked for one of them.

use super::energy::plane_normal;
use super::exact_extrema::{
    alternations, count_intervals, sign_intervals, ExactExtrema, DENSE_SAMPLES,
};
use super::exact_nurbs::sign_intervals_nurbs_both;
use super::extrema::{count_extrema_sampled, ExtremaCounts};
use crate::nurbs::NurbsCurve;

/// The result of [`count_inflections_exact`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExactInflections {
    /// Inflections (sign changes of the signed curvature above the noise floor).
    pub inflections: usize,
    /// `true`: from the roots of `G`; `false`: the dense-sampling fallback.
    pub exact: bool,
}

/// Counts the inflections of `curve` exactly (see the module documentation); `length` is its arc
/// length (for the scale-free noise floor).
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::fair::exact_inflections::count_inflections_exact;
/// // the graph y = x³ on [−1, 1]: one inflection, at x = 0
/// let pts = [(-1.0, -1.0), (-1.0 / 3.0, 1.0), (1.0 / 3.0, -1.0), (1.0, 1.0)];
/// let ctrl = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
/// let c = NurbsCurve::bspline(3, vec![-1., -1., -1., -1., 1., 1., 1., 1.], ctrl).unwrap();
/// let l = fairfit::diffgeo::arc_length(&c);
/// let e = count_inflections_exact(&c, l);
/// assert_eq!((e.inflections, e.exact), (1, true));
/// ```
pub fn count_inflections_exact(curve: &NurbsCurve, length: f64) -> ExactInflections {
    shape_exact(curve, length, [false, true]).inflections
}

/// Both exact counts of a curve: [`super::count_extrema_exact`] and [`count_inflections_exact`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExactShape {
    /// The curvature extrema.
    pub extrema: ExactExtrema,
    /// The inflections.
    pub inflections: ExactInflections,
}

/// [`super::count_extrema_exact`] and [`count_inflections_exact`] of `curve` (arc length `length`)
/// in one pass (see the module documentation).
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::fair::exact_inflections::count_shape_exact;
/// // the graph y = x³ on [−1, 1]: curvature extrema at x = ±45^{−1/4}, one inflection at x = 0
/// let pts = [(-1.0, -1.0), (-1.0 / 3.0, 1.0), (1.0 / 3.0, -1.0), (1.0, 1.0)];
/// let ctrl = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
/// let c = NurbsCurve::bspline(3, vec![-1., -1., -1., -1., 1., 1., 1., 1.], ctrl).unwrap();
/// let s = count_shape_exact(&c, fairfit::diffgeo::arc_length(&c));
/// assert_eq!((s.extrema.curvature_extrema, s.inflections.inflections), (2, 1));
/// assert!(s.extrema.exact && s.inflections.exact);
/// ```
pub fn count_shape_exact(curve: &NurbsCurve, length: f64) -> ExactShape {
    shape_exact(curve, length, [true, true])
}

/// The counts `want`ed (`[extrema, inflections]`; one not wanted is 0, not exact). Extrema: a
/// planar polynomial curve by [`sign_intervals`], any other by the numerators of
/// [`super::exact_nurbs`]; inflections: a planar curve by the numerators of its signed curvature.
/// A count that cannot be made exactly is [`count_extrema_sampled`]'s with
/// [`DENSE_SAMPLES`] per span (sampled once for both).
pub(super) fn shape_exact(curve: &NurbsCurve, length: f64, want: [bool; 2]) -> ExactShape {
    // far from unit size (beyond 2^±64) the numerators' powers of lengths overflow or underflow and
    // the plane test fails: count on an exactly rescaled copy (a power of two; counts are invariant)
    let f = crate::nurbs::scale::normalising_factor(curve.control_points());
    if f != 1.0 {
        if let Ok(scaled) = crate::nurbs::scale::scaled_curve(curve, f) {
            return shape_at_scale(&scaled, length * f, want);
        }
    }
    shape_at_scale(curve, length, want)
}

/// [`shape_exact`] at the curve's own scale.
fn shape_at_scale(curve: &NurbsCurve, length: f64, want: [bool; 2]) -> ExactShape {
    let normal = plane_normal(curve);
    let planar_polynomial = normal.filter(|_| !curve.is_rational());
    let [dkds, kappa] = sign_intervals_nurbs_both(
        curve,
        normal,
        [want[0] && planar_polynomial.is_none(), want[1]],
    );
    let dkds = match planar_polynomial {
        Some(n) if want[0] => {
            let mut iv = Vec::new();
            sign_intervals(
                curve.degree(),
                curve.knots(),
                curve.control_points(),
                n,
                &mut iv,
            );
            Some(iv)
        }
        _ => dkds,
    };
    let mut sampled: Option<ExtremaCounts> = None;
    let mut dense =
        || *sampled.get_or_insert_with(|| count_extrema_sampled(curve, length, DENSE_SAMPLES));
    let extrema = match (want[0], dkds) {
        (false, _) => ExactExtrema {
            curvature_extrema: 0,
            exact: false,
        },
        (true, Some(iv)) => ExactExtrema {
            curvature_extrema: count_intervals(&iv, length),
            exact: true,
        },
        (true, None) => ExactExtrema {
            curvature_extrema: dense().curvature_extrema,
            exact: false,
        },
    };
    let inflections = match (want[1], kappa) {
        (false, _) => ExactInflections {
            inflections: 0,
            exact: false,
        },
        (true, Some(iv)) => ExactInflections {
            inflections: alternations(&iv, length).len(),
            exact: true,
        },
        (true, None) => ExactInflections {
            inflections: dense().inflections,
            exact: false,
        },
    };
    ExactShape {
        extrema,
        inflections,
    }
}
