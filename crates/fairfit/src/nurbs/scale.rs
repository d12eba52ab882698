//! Exact power-of-two rescaling for geometry far outside unit size.
//!
//! Curvature, torsion, dκ/ds and the fairness integrals use squares, cubes and fifth powers of lengths
//! and speeds: at coordinates around 1e±160 and beyond they overflow to infinity or underflow to zero,
//! and the measures silently become 0. The measuring functions therefore work on a copy scaled by a
//! power of two `f` (exact: only exponents change) and scale the results back (a length by `1/f`, a
//! curvature by `f`, ...). Geometry whose extent lies in `[2^-64, 2^64]` is never rescaled, so results
//! there are unchanged to the bit.

use super::{NurbsCurve, NurbsSurface, Vec3};
use crate::errors::Result;

/// Extents in this range (in powers of two) are measured as they are.
const SAFE_EXPONENT: i32 = 64;

/// The power of two that brings the extent of `points` (largest coordinate range) near 1, or 1 when the
/// extent is already within `[2^-64, 2^64]`, is zero or not finite, or when scaling would push a
/// coordinate beyond `2^1000`.
pub fn normalising_factor(points: &[Vec3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut max_abs = 0.0f64;
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
            max_abs = max_abs.max(p[k].abs());
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
    if !(extent.is_finite() && extent > 0.0) {
        return 1.0;
    }
    let e = extent.log2().round() as i32;
    if e.abs() <= SAFE_EXPONENT {
        return 1.0;
    }
    let f = 2f64.powi(-e);
    if !(max_abs * f).is_finite() || max_abs * f > 2f64.powi(1000) || f == 0.0 {
        return 1.0;
    }
    f
}

/// The power of two that brings the range `knots[last] - knots[0]` near 1, or 1 when the range is
/// already within `[2^-64, 2^64]`, is zero or not finite. Multiplying knots (and parameters) by it is
/// exact and changes no point of the curve, only the parametric derivatives (by powers of the factor);
/// geometric quantities (curvature, torsion, dκ/ds) do not change at all.
pub(crate) fn parameter_factor(knots: &[f64]) -> f64 {
    let range = match (knots.first(), knots.last()) {
        (Some(a), Some(b)) => b - a,
        _ => return 1.0,
    };
    if !(range.is_finite() && range > 0.0) {
        return 1.0;
    }
    let e = range.log2().round() as i32;
    if e.abs() <= SAFE_EXPONENT {
        return 1.0;
    }
    let g = 2f64.powi(-e);
    let max_abs = knots.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    if g == 0.0 || !(max_abs * g).is_finite() {
        return 1.0;
    }
    g
}

/// `curve` with control points multiplied by `f` and knots by `g` (weights kept): the same shape
/// scaled by `f`, at parameter `g u` for the original's `u`. Errors like [`scaled_curve`].
pub(crate) fn scaled_curve_and_parameter(curve: &NurbsCurve, f: f64, g: f64) -> Result<NurbsCurve> {
    let pts = curve.control_points().iter().map(|&p| p * f).collect();
    NurbsCurve::new(
        curve.degree(),
        curve.knots().iter().map(|&k| k * g).collect(),
        pts,
        Some(curve.weights().to_vec()),
    )
}

/// `curve` with control points multiplied by `f` (weights and knots kept). Errors when a scaled
/// weighted control point would overflow (huge weights on a tiny curve); callers then measure the
/// curve unscaled.
pub fn scaled_curve(curve: &NurbsCurve, f: f64) -> Result<NurbsCurve> {
    let pts = curve.control_points().iter().map(|&p| p * f).collect();
    NurbsCurve::new(
        curve.degree(),
        curve.knots().to_vec(),
        pts,
        Some(curve.weights().to_vec()),
    )
}

/// `surface` with control points multiplied by `f` (weights and knots kept). Errors like
/// [`scaled_curve`].
pub fn scaled_surface(surface: &NurbsSurface, f: f64) -> Result<NurbsSurface> {
    let (n_u, n_v) = surface.net_size();
    let net = (0..n_u)
        .map(|i| (0..n_v).map(|j| surface.control_point(i, j) * f).collect())
        .collect();
    let w = (0..n_u)
        .map(|i| (0..n_v).map(|j| surface.weight(i, j)).collect())
        .collect();
    NurbsSurface::new(
        surface.degree_u(),
        surface.degree_v(),
        surface.knots_u().to_vec(),
        surface.knots_v().to_vec(),
        net,
        Some(w),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_are_exact_powers_of_two_only_out_of_range() {
        let unit = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 0.0)];
        assert_eq!(normalising_factor(&unit), 1.0);
        let huge: Vec<Vec3> = unit.iter().map(|&p| p * 1e300).collect();
        let f = normalising_factor(&huge);
        assert_eq!(f, 2f64.powi(-(3e300f64.log2().round() as i32)));
        assert!((3e300 * f - 1.0).abs() < 0.5);
        let tiny: Vec<Vec3> = unit.iter().map(|&p| p * 1e-300).collect();
        assert!((3e-300 * normalising_factor(&tiny) - 1.0).abs() < 0.5);
        // a tiny object far from the origin cannot be scaled up without overflow
        let far = [Vec3::new(1e10, 0.0, 0.0), Vec3::new(1e10 + 1e-6, 0.0, 0.0)];
        assert_eq!(normalising_factor(&far), 1.0);
        assert_eq!(normalising_factor(&[Vec3::ZERO; 2]), 1.0);
    }

    #[test]
    fn parameter_factors_bring_huge_and_tiny_knot_ranges_near_one() {
        assert_eq!(parameter_factor(&[0.0, 0.0, 1.0, 1.0]), 1.0);
        assert_eq!(parameter_factor(&[0.0, 0.0, 1e18, 1e18]), 1.0);
        for range in [1e300, 1e-300, 1e30] {
            let g = parameter_factor(&[0.0, 0.0, range, range]);
            assert_eq!(g, 2f64.powi(-(range.log2().round() as i32)));
            assert!((range * g - 1.0).abs() < 0.5, "{range:e}");
        }
    }
}
