//! The exact count of curvature extrema of a B-spline curve (planar polynomial here, rational and
//! spatial through [`super::exact_nurbs`]): the sign changes of `dκ/ds` located as the real roots
//! of a polynomial per knot span, not looked for on samples.
//!
//! [`super::extrema::count_extrema`] (the benchmark measurer's count) samples `dκ/ds` at 192
//! points per span; a wiggle narrower than the sample spacing, typically right next to a knot
//! where `dκ/ds` jumps, is stepped over (main's 33 benchmark curves: 92 extrema at 192 samples per
//! span, 111 at 2000). This count finds every one:
//!
//! - **Polynomial**: on a knot span the curve is a polynomial piece; with `x, y` its coordinates
//!   in the curve's plane and `'` the derivative in the span parameter,
//!   `κ = C / B^{3/2}`, `C = x'y'' − y'x''`, `B = x'² + y'²`, and
//!   `dκ/du = N / B^{5/2}` with
//!   `N = (x'y''' − y'x''') B − 3 C (x'x'' + y'y'')`, a polynomial of degree `4p − 6` (6 for a
//!   cubic); `dκ/ds = N / B³`, so `sign dκ/ds = sign N` wherever the speed is non-zero.
//! - **Span pieces**: the Bézier control points of every span are blossoms of the local de Boor
//!   points (valid for clamped and unclamped knot vectors), projected to the curve's plane and
//!   normalised by the control polygon's extent; `N` is formed in Bernstein form
//!   ([`super::bernstein`]), so nothing is evaluated at a knot: the span's own polynomial gives its
//!   one-sided behaviour at both ends, and `C'''` of the curve is never asked for at a knot.
//! - **Roots**: the sign changes of `N` in the open span by Bernstein subdivision and Descartes'
//!   rule ([`super::bernstein::sign_changes`]); coefficients below [`ZERO_REL`] times the
//!   span's scale (the larger coefficient magnitude of the two products in `N`) are rounding
//!   noise: a span where `N` vanishes identically (a line) has no root.
//! - **Intervals**: the roots cut every span into intervals of one sign of `dκ/ds`; each gets its
//!   sign and the peak of `|dκ/ds|` on [`PEAK_NODES`] Chebyshev nodes inside it (clustered at its
//!   ends, where the peak of an interval ending at a knot sits).
//! - **Noise floor**: the measurer's, on the dimensionless signal `dκ/ds L²`:
//!   `floor = 1e-6 max|signal| + 1e-9` ([`super::extrema::NOISE_FLOOR`],
//!   [`super::extrema::NOISE_ABS`], the maximum over all intervals' peaks). An interval counts
//!   when its peak reaches the floor; the extrema are the sign alternations between consecutive
//!   counted intervals along the whole curve. This is the measurer's hysteresis count in the
//!   limit of infinitely many samples: a sign change across a knot (where `dκ/ds` jumps) counts,
//!   a dip that never leaves the floor does not.
//!
//! **Rational and spatial curves** ([`super::exact_nurbs`]): the same count on the numerators of
//! [`super::curvature_numerators`] (`C = A / w` per span; `dκ/ds` of a planar piece, `d(κ²)/du`
//! of a spatial one, whose sign is that of `dκ/ds` where `κ > 0`), with the same floor on the
//! same dimensionless signal `dκ/ds L²`. For a spatial curve this is the unsigned `κ` of the
//! measurer's spatial formula (`bench/measure.py`, `|C' × C''| / |C'|³`): an isolated zero of `κ`
//! is a minimum and counts, a straight stretch (`κ ≡ 0`, numerator `≡ 0`) has no root and a
//! signal below the floor. Planarity: this crate calls a curve planar when its control points lie
//! in any plane ([`super::energy::plane_normal`]), the measurer only when they lie in a plane
//! `z = const`; a planar curve in a tilted plane is counted with the signed `κ` here and the
//! unsigned one by the measurer, which adds one extremum (the minimum `|κ| = 0`) per inflection.
//!
//! **Fallback**: only a numerator of degree above [`super::exact_nurbs::MAX_NUMERATOR_DEGREE`]
//! (a spatial rational curve of degree 14 or more) or a degenerate curve is counted by dense
//! sampling, [`DENSE_SAMPLES`] per span, with the same floor; [`ExactExtrema::exact`] says which
//! count was made.

use super::bernstein;
use super::exact_nurbs::push_intervals;
use super::extrema::{NOISE_ABS, NOISE_FLOOR};
use super::span_hodograph::{origin_and_extent, plane_frame};
use crate::nurbs::{NurbsCurve, Vec3};

/// Coefficients of `N` below this times the span's scale are rounding noise (see the module
/// documentation; a real sign change that small is far below the `1e-6` floor).
pub const ZERO_REL: f64 = 1e-12;
/// Chebyshev nodes per sign interval for its peak `|dκ/ds|`.
pub const PEAK_NODES: usize = 24;
/// Samples per span of the fallback count (see the module documentation).
pub const DENSE_SAMPLES: usize = 4096;

/// The result of [`count_extrema_exact`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExactExtrema {
    /// Curvature extrema (sign changes of `dκ/ds` above the noise floor).
    pub curvature_extrema: usize,
    /// `true`: from the roots of `N`; `false`: the dense-sampling fallback.
    pub exact: bool,
}

/// A maximal parameter interval on which `dκ/ds` has one sign (within one knot span).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignInterval {
    /// Start parameter.
    pub u0: f64,
    /// End parameter.
    pub u1: f64,
    /// Sign of `dκ/ds` (`+1` or `−1`).
    pub sign: i8,
    /// Largest `|dκ/ds|` found inside (at Chebyshev nodes).
    pub peak: f64,
}

/// Counts the curvature extrema of `curve` exactly (see the module documentation); `length` is
/// its arc length (for the scale-free noise floor, as in [`super::count_extrema`]).
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::fair::exact_extrema::count_extrema_exact;
/// // the graph y = x³ on [−1, 1] (x = u): κ = 6x / (1 + 9x⁴)^{3/2} has its extrema where
/// // 1 − 45 x⁴ = 0, at x = ±45^{−1/4}
/// let pts = [(-1.0, -1.0), (-1.0 / 3.0, 1.0), (1.0 / 3.0, -1.0), (1.0, 1.0)];
/// let ctrl = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
/// let c = NurbsCurve::bspline(3, vec![-1., -1., -1., -1., 1., 1., 1., 1.], ctrl).unwrap();
/// let l = fairfit::diffgeo::arc_length(&c);
/// assert_eq!(count_extrema_exact(&c, l).curvature_extrema, 2);
/// ```
pub fn count_extrema_exact(curve: &NurbsCurve, length: f64) -> ExactExtrema {
    super::exact_inflections::shape_exact(curve, length, [true, false]).extrema
}

/// The sign intervals of `dκ/ds` (in parameter order) of the planar polynomial B-spline of degree
/// `p` with `knots` and control points `ctrl` in the plane with unit normal `normal`, into `out`
/// (cleared first). Intervals where `dκ/ds` vanishes identically are left out.
pub fn sign_intervals(
    p: usize,
    knots: &[f64],
    ctrl: &[Vec3],
    normal: Vec3,
    out: &mut Vec<SignInterval>,
) {
    out.clear();
    let n = ctrl.len();
    if p == 0 || n <= p || knots.len() != n + p + 1 {
        return;
    }
    // an in-plane frame (e1 × e2 = normal) and the control polygon's origin and extent
    let (e1, e2) = plane_frame(normal);
    let Some((origin, extent)) = origin_and_extent(ctrl) else {
        return;
    };
    let local: Vec<[f64; 2]> = ctrl
        .iter()
        .map(|&q| {
            let d = (q - origin) / extent;
            [d.dot(e1), d.dot(e2)]
        })
        .collect();
    let mut roots = Vec::new();
    for s in p..n {
        let (a, b) = (knots[s], knots[s + 1]);
        if b <= a {
            continue;
        }
        let (x, y) = bezier_piece(knots, p, s, &local[s - p..=s]);
        let (num, scale) = numerator(&x, &y);
        let speed2 = {
            let (x1, y1) = (bernstein::derivative(&x), bernstein::derivative(&y));
            bernstein::combine(
                1.0,
                &bernstein::mul(&x1, &x1),
                1.0,
                &bernstein::mul(&y1, &y1),
            )
        };
        // dκ/ds in the original units: the local coordinates are divided by `extent` (κ and
        // 1/s scale by `extent`, dκ/ds by its square); dκ/ds does not depend on the parameter,
        // so the span parameter t = (u − a)/(b − a) gives it as well as u
        let unit = 1.0 / (extent * extent);
        // dκ/ds = N / |C'|³ on the span; undefined (skipped) where the speed vanishes
        let dkappa_ds = |t: f64| {
            let bv = bernstein::eval(&speed2, t);
            if bv <= 0.0 {
                f64::NAN
            } else {
                bernstein::eval(&num, t) / (bv * bv * bv)
            }
        };
        let zero = ZERO_REL * scale;
        push_intervals(&num, zero, a, b, dkappa_ds, unit, &mut roots, out);
    }
}

/// Curvature extrema of the sign intervals `iv` of a curve of arc length `length`: sign
/// alternations between consecutive intervals whose peak `|dκ/ds| L²` reaches the measurer's
/// floor.
pub(crate) fn count_intervals(iv: &[SignInterval], length: f64) -> usize {
    extremum_boundaries(iv, length).len()
}

/// Where the counted extrema are: for each, the index into `iv` of the first counted interval
/// after the sign change (the extremum lies between its start and the end of the previous
/// counted interval, exactly at its start when the two are adjacent).
pub fn extremum_boundaries(iv: &[SignInterval], length: f64) -> Vec<usize> {
    alternations(iv, length * length)
}

/// The sign alternations between consecutive intervals of `iv` whose dimensionless peak
/// (`peak · factor`, e.g. `|dκ/ds| L²` or `|κ| L`) reaches the measurer's floor
/// `1e-6 max + 1e-9`: for each, the index into `iv` of the first counted interval after it.
pub fn alternations(iv: &[SignInterval], factor: f64) -> Vec<usize> {
    if !(factor.is_finite() && factor > 0.0) {
        return Vec::new();
    }
    let peak = iv.iter().fold(0.0f64, |m, i| m.max(i.peak * factor));
    let floor = NOISE_FLOOR * peak + NOISE_ABS;
    let mut last = 0i8;
    let mut out = Vec::new();
    for (k, i) in iv.iter().enumerate() {
        if i.peak * factor < floor {
            continue;
        }
        if last != 0 && i.sign != last {
            out.push(k);
        }
        last = i.sign;
    }
    out
}

/// The Bernstein coefficients `(x, y)` of knot span `s` of the degree-`p` B-spline with the
/// local de Boor points `pts` (`P_{s−p} … P_s`), one coordinate at a time by
/// [`span_hodograph::bezier_piece`](super::span_hodograph::bezier_piece).
fn bezier_piece(knots: &[f64], p: usize, s: usize, pts: &[[f64; 2]]) -> (Vec<f64>, Vec<f64>) {
    let coordinate = |c: usize| -> Vec<f64> {
        let vals: Vec<f64> = pts.iter().map(|q| q[c]).collect();
        super::span_hodograph::bezier_piece(knots, p, s, &vals)
    };
    (coordinate(0), coordinate(1))
}

/// `N = (x'y''' − y'x''')(x'² + y'²) − 3 (x'y'' − y'x'')(x'x'' + y'y'')` of the Bézier piece
/// `(x, y)` and its scale (the largest coefficient magnitude of the two products).
fn numerator(x: &[f64], y: &[f64]) -> (Vec<f64>, f64) {
    use bernstein::{combine, derivative as d, mul};
    let (x1, y1) = (d(x), d(y));
    let (x2, y2) = (d(&x1), d(&y1));
    let (x3, y3) = (d(&x2), d(&y2));
    let a = combine(1.0, &mul(&x1, &y3), -1.0, &mul(&y1, &x3));
    let b = combine(1.0, &mul(&x1, &x1), 1.0, &mul(&y1, &y1));
    let c = combine(1.0, &mul(&x1, &y2), -1.0, &mul(&y1, &x2));
    let e = combine(1.0, &mul(&x1, &x2), 1.0, &mul(&y1, &y2));
    let (ab, ce) = (mul(&a, &b), mul(&c, &e));
    let scale = ab
        .iter()
        .chain(&ce)
        .fold(0.0f64, |m, v| m.max(v.abs() * 3.0));
    (combine(1.0, &ab, -3.0, &ce), scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bezier_piece_of_a_span_is_the_curve_there() {
        // a clamped cubic with uneven knots: each span's Bernstein form reproduces the curve
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.45, 1.0, 1.0, 1.0, 1.0];
        let ctrl: Vec<Vec3> = [(0., 0.), (1., 2.), (2., 3.), (3., 1.), (4., 0.), (5., 2.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        let c = NurbsCurve::bspline(3, knots.clone(), ctrl.clone()).unwrap();
        let local: Vec<[f64; 2]> = ctrl.iter().map(|q| [q.x(), q.y()]).collect();
        for s in 3..6 {
            let (x, y) = bezier_piece(&knots, 3, s, &local[s - 3..=s]);
            for &t in &[0.1, 0.5, 0.9] {
                let u = knots[s] + (knots[s + 1] - knots[s]) * t;
                let q = c.point(u);
                assert!((bernstein::eval(&x, t) - q.x()).abs() < 1e-14);
                assert!((bernstein::eval(&y, t) - q.y()).abs() < 1e-14);
            }
        }
    }
}
