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

use super::energy::plane_normal;
use super::exact_extrema::{alternations, DENSE_SAMPLES};
use super::exact_nurbs::{sign_intervals_nurbs, Signal};
use super::extrema::count_extrema_sampled;
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
    let iv = plane_normal(curve).and_then(|n| sign_intervals_nurbs(curve, Some(n), Signal::Kappa));
    match iv {
        Some(iv) => ExactInflections {
            inflections: alternations(&iv, length).len(),
            exact: true,
        },
        None => ExactInflections {
            inflections: count_extrema_sampled(curve, length, DENSE_SAMPLES).inflections,
            exact: false,
        },
    }
}
