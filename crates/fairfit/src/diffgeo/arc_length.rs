//! Arc length of curves, `L = ∫ |C'(u)| du`, by Gauss–Legendre quadrature over each distinct knot span
//! (nodes strictly inside the span, where the curve is smooth), with adaptive bisection of a span while
//! its two halves disagree with the whole (so near-zero speed and strongly rational spans stay accurate).

use super::quadrature::GaussLegendre;
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsCurve, Vec3};

/// Nodes per (sub)span.
const NODES: usize = 16;
/// Relative agreement required between a span and its two halves.
const REL_TOL: f64 = 1e-13;
/// Maximum bisection depth.
const MAX_DEPTH: usize = 12;

/// Arc length of each distinct knot span of the domain, in order (spans of zero width are skipped).
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::diffgeo::arc_length::{arc_length, span_arc_lengths};
/// // a straight cubic from (0,0,0) to (3,4,0) with an interior knot: length 5
/// let pts: Vec<Vec3> = (0..5).map(|i| Vec3::new(0.75 * i as f64, i as f64, 0.0)).collect();
/// let c = NurbsCurve::bspline(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.], pts).unwrap();
/// assert!((arc_length(&c) - 5.0).abs() < 1e-12);
/// assert_eq!(span_arc_lengths(&c).len(), 2);
/// ```
pub fn span_arc_lengths(curve: &NurbsCurve) -> Vec<f64> {
    let rule = GaussLegendre::new(NODES);
    let breaks = distinct_breakpoints(curve.knots(), curve.degree());
    breaks
        .windows(2)
        .map(|w| adaptive_length(curve, &rule, w[0], w[1], MAX_DEPTH))
        .collect()
}

/// Total arc length over the domain.
pub fn arc_length(curve: &NurbsCurve) -> f64 {
    span_arc_lengths(curve).iter().sum()
}

/// Arc length between parameters `a <= b` (clamped to the domain), integrating span by span.
pub fn arc_length_between(curve: &NurbsCurve, a: f64, b: f64) -> f64 {
    let (lo, hi) = curve.domain();
    let (a, b) = (a.clamp(lo, hi), b.clamp(lo, hi));
    if b <= a {
        return 0.0;
    }
    let rule = GaussLegendre::new(NODES);
    let breaks = distinct_breakpoints(curve.knots(), curve.degree());
    breaks
        .windows(2)
        .filter_map(|w| {
            let (x, y) = (w[0].max(a), w[1].min(b));
            (y > x).then(|| adaptive_length(curve, &rule, x, y, MAX_DEPTH))
        })
        .sum()
}

fn gl_length(curve: &NurbsCurve, rule: &GaussLegendre, a: f64, b: f64) -> f64 {
    let mut d = [Vec3::ZERO; 2];
    rule.integrate(a, b, |u| {
        curve.derivatives_into(u, 1, &mut d);
        d[1].norm()
    })
}

fn adaptive_length(curve: &NurbsCurve, rule: &GaussLegendre, a: f64, b: f64, depth: usize) -> f64 {
    let whole = gl_length(curve, rule, a, b);
    let m = 0.5 * (a + b);
    if depth == 0 || m <= a || m >= b {
        return whole;
    }
    let halves = gl_length(curve, rule, a, m) + gl_length(curve, rule, m, b);
    if (halves - whole).abs() <= REL_TOL * halves.abs() {
        halves
    } else {
        adaptive_length(curve, rule, a, m, depth - 1)
            + adaptive_length(curve, rule, m, b, depth - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_circle_rational_length() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let r = 2.5;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(r, 0.0, 0.0),
                Vec3::new(r, r, 0.0),
                Vec3::new(0.0, r, 0.0),
            ],
            Some(vec![1.0, h, 1.0]),
        )
        .unwrap();
        let l = arc_length(&c);
        assert!((l - r * std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{l}");
        let half = arc_length_between(&c, 0.0, 0.5);
        // by symmetry the parameter midpoint is the arc midpoint
        assert!((half - l / 2.0).abs() < 1e-12);
    }

    #[test]
    fn parabola_length_matches_closed_form() {
        // C(u) = (u, u², 0) on [0, 2] as a quadratic Bézier with an inserted knot
        let c = NurbsCurve::bspline(
            2,
            vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0],
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(2.0, 4.0, 0.0),
            ],
        )
        .unwrap();
        // ∫_0^2 sqrt(1 + 4u²) du = [u/2 sqrt(1+4u²) + asinh(2u)/4]_0^2
        let exact = 17f64.sqrt() + 4f64.asinh() / 4.0;
        assert!((arc_length(&c) - exact).abs() < 1e-12);
        assert!(
            (arc_length_between(&c, 1.0, 2.0) + arc_length_between(&c, 0.0, 1.0) - exact).abs()
                < 1e-12
        );
    }
}
