//! The leading edge of an airfoil section, found from its points alone, and the parameter it is
//! pinned to when a section is split there (`fairfit curve --split-at-le`, `fairfit surface
//! --split-at-le`).
//!
//! An airfoil's points run from the trailing edge round the leading edge back to the trailing edge
//! (open at a blunt trailing edge, or closed: last point = first). The trailing edge is taken as the
//! midpoint of the first and last points; the leading edge is the point farthest from it. Pinning
//! that point to one common parameter ([`LEADING_EDGE_PARAMETER`]) in every section lines the
//! leading edges up on one iso-curve of a skinned surface.

use crate::nurbs::Vec3;

/// The parameter of the leading edge on a curve on `[0, 1]` split there: `fairfit curve
/// --split-at-le` writes its joined curve with the leading edge at 0.5, and `fairfit surface
/// --split-at-le` holds every section's leading edge at 0.5.
pub const LEADING_EDGE_PARAMETER: f64 = 0.5;

/// The index of the leading edge of airfoil `points`: the point farthest from the midpoint of the
/// first and last points (the trailing edge; the first point of a closed section); `None` when that
/// is an end point (or `points` is empty).
///
/// ```
/// use fairfit::fit::airfoil::leading_edge;
/// use fairfit::Vec3;
/// let pts = [Vec3::new(1.0, 0.01, 0.0), Vec3::new(0.5, 0.06, 0.0), Vec3::new(0.0, 0.0, 0.0),
///            Vec3::new(0.5, -0.04, 0.0), Vec3::new(1.0, -0.01, 0.0)];
/// assert_eq!(leading_edge(&pts), Some(2));
/// assert_eq!(leading_edge(&pts[2..]), None); // the farthest point is the first one
/// ```
pub fn leading_edge(points: &[Vec3]) -> Option<usize> {
    let (first, last) = (points.first()?, points.last()?);
    let te = (*first + *last) * 0.5;
    let (i, _) = points
        .iter()
        .enumerate()
        .max_by(|a, b| (*a.1 - te).norm().total_cmp(&(*b.1 - te).norm()))?;
    (i > 0 && i + 1 < points.len()).then_some(i)
}
