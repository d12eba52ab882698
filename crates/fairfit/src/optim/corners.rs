//! Corners in the integrated method. Data with corner points (a turn above the corner angle
//! between tangents at the tolerance's and the noise's scale, [`crate::fit::corners`], judged on
//! every input point before any reduction) are split there; every piece is fitted by the integrated method on its own (same absolute tolerance),
//! and the pieces are joined with knots of multiplicity `p`: the curve is C0 at the corners and as
//! smooth as the method makes it elsewhere. The join is exact because every piece interpolates its
//! end points (both neighbours end at the corner point itself).
//!
//! A piece with fewer than `p + 1` points (a short straight stretch such as a blunt trailing edge) is
//! a straight Bézier segment between its end points ([`is_straight`]). Such a segment cannot hold a
//! tangent or curvature condition at a data end other than its own, so under end conditions the
//! corner that cuts it off is smoothed over ([`corners_for_conditions`]): the condition the user
//! asked for outranks a corner of the data, and the tolerance, verified on every point, decides
//! whether the data allow it.
//!
//! The split happens on the normalised (snapped) points, so the result stays exactly
//! scale-invariant; the piece's parameter domain is its share of the chord length.

use crate::errors::{Error, Result};
use crate::fit::end_constraints::{EndConstraint, EndConstraints};
use crate::nurbs::{NurbsCurve, Vec3};

/// Whether a piece of `points` data points is too short for a curve of `degree` of its own (it is
/// then the straight segment between its ends).
pub fn is_straight(points: usize, degree: usize) -> bool {
    points < (degree + 1).max(3)
}

/// The `corners` (increasing indices into `n_points` data points) the pieces are cut at under
/// `conditions`: while an end with a tangent or curvature condition would get a straight piece
/// ([`is_straight`]), the corner next to it is dropped (module doc).
pub fn corners_for_conditions(
    n_points: usize,
    corners: &[usize],
    degree: usize,
    conditions: &EndConstraints,
) -> Vec<usize> {
    // G1 or G2: a direction a straight piece may not have
    let shapes = |c: &EndConstraint| c.order() > 0;
    let mut kept: Vec<usize> = corners
        .iter()
        .copied()
        .filter(|&c| c > 0 && c + 1 < n_points)
        .collect();
    if shapes(&conditions.start) {
        while kept.first().is_some_and(|&c| is_straight(c + 1, degree)) {
            kept.remove(0);
        }
    }
    if shapes(&conditions.end) {
        while kept
            .last()
            .is_some_and(|&c| is_straight(n_points - c, degree))
        {
            kept.pop();
        }
    }
    kept
}

/// Index ranges `[a, b]` (inclusive, sharing the corner point) of the pieces between corners; one
/// piece `[0, n − 1]` when there are none.
pub fn pieces(n_points: usize, corners: &[usize]) -> Vec<(usize, usize)> {
    let mut out = Vec::with_capacity(corners.len() + 1);
    let mut a = 0;
    for &c in corners {
        if c > a && c + 1 < n_points {
            out.push((a, c));
            a = c;
        }
    }
    out.push((a, n_points - 1));
    out
}

/// The straight Bézier segment of `degree` from `a` to `b` (control points evenly on the chord).
pub fn straight_piece(a: Vec3, b: Vec3, degree: usize) -> Result<NurbsCurve> {
    let mut knots = vec![0.0; degree + 1];
    knots.extend(std::iter::repeat_n(1.0, degree + 1));
    let ctrl = (0..=degree)
        .map(|i| a + (b - a) * (i as f64 / degree as f64))
        .collect();
    NurbsCurve::bspline(degree, knots, ctrl)
}

/// Joins clamped non-rational pieces of one degree, each on `[0, 1]` and each starting where the
/// previous one ends, into one curve on `[0, 1]`: piece `i` gets the parameter share `shares[i]`
/// (normalised here), and the joints become knots of multiplicity `p`.
pub fn join(pieces: &[NurbsCurve], shares: &[f64]) -> Result<NurbsCurve> {
    let Some(first) = pieces.first() else {
        return Err(Error::InvalidData("no pieces to join".into()));
    };
    if shares.len() != pieces.len() {
        return Err(Error::InvalidData(format!(
            "{} pieces to join but {} parameter shares",
            pieces.len(),
            shares.len()
        )));
    }
    let p = first.degree();
    let total: f64 = shares.iter().sum();
    let mut knots = vec![0.0; p + 1];
    let mut ctrl: Vec<Vec3> = Vec::new();
    let mut start = 0.0;
    for (i, (c, s)) in pieces.iter().zip(shares).enumerate() {
        let last = i + 1 == pieces.len();
        let width = s / total;
        let (k, n) = (c.knots(), c.knots().len());
        let (lo, hi) = (k[p], k[n - p - 1]);
        for &t in &k[p + 1..n - p - 1] {
            knots.push(start + width * (t - lo) / (hi - lo));
        }
        let end = if last { 1.0 } else { start + width };
        knots.extend(std::iter::repeat_n(end, if last { p + 1 } else { p }));
        let skip = usize::from(i > 0);
        ctrl.extend_from_slice(&c.control_points()[skip..]);
        start = end;
    }
    NurbsCurve::bspline(p, knots, ctrl)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_share_corner_points() {
        assert_eq!(pieces(10, &[]), vec![(0, 9)]);
        assert_eq!(pieces(10, &[3, 7]), vec![(0, 3), (3, 7), (7, 9)]);
        // end points are never corners of an open curve
        assert_eq!(pieces(10, &[0, 9]), vec![(0, 9)]);
    }

    #[test]
    fn corners_cutting_off_straight_ends_are_dropped_under_shaping_conditions() {
        let g1 = EndConstraint::tangent(Vec3::new(0.0, 1.0, 0.0));
        let g0 = EndConstraint::point(Vec3::ZERO);
        let both = |start, end| EndConstraints { start, end };
        // pieces [0, 1] (2 points) and [8, 9] (2 points) are straight for a cubic; [0, 2] is too
        let corners = [1, 2, 5, 8];
        assert_eq!(
            corners_for_conditions(10, &corners, 3, &both(g1, g1)),
            vec![5]
        );
        assert_eq!(
            corners_for_conditions(10, &corners, 3, &both(g1, EndConstraint::default())),
            vec![5, 8]
        );
        // a point condition is held by a straight piece: nothing dropped
        assert_eq!(
            corners_for_conditions(10, &corners, 3, &both(g0, g0)),
            corners
        );
        // a piece of 4 points is a cubic of its own
        assert_eq!(
            corners_for_conditions(10, &[3, 6], 3, &both(g1, g1)),
            vec![3, 6]
        );
        assert!(is_straight(3, 3) && !is_straight(4, 3) && is_straight(2, 1) && !is_straight(3, 1));
    }

    #[test]
    fn joined_curve_passes_through_both_pieces() {
        // an L: two straight pieces (0,0)→(1,0) and (1,0)→(1,2), shares by length 1 : 2
        let a = straight_piece(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 3).unwrap();
        let b = straight_piece(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), 3).unwrap();
        let c = join(&[a, b], &[1.0, 2.0]).unwrap();
        assert_eq!(c.n_control_points(), 7);
        let k = c.knots();
        assert_eq!(&k[3..7], &[0.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0]);
        assert!((c.point(1.0 / 3.0) - Vec3::new(1.0, 0.0, 0.0)).norm() < 1e-12);
        assert!((c.point(1.0 / 6.0) - Vec3::new(0.5, 0.0, 0.0)).norm() < 1e-12);
        assert!((c.point(2.0 / 3.0) - Vec3::new(1.0, 1.0, 0.0)).norm() < 1e-12);
        assert!((c.point(1.0) - Vec3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
    }
}
