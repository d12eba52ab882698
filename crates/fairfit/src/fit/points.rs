//! Point-set helpers shared by the fitting code and the point readers: the extent of a point set
//! (the scale every relative tolerance is taken of) and the removal of consecutive duplicate points
//! (a repeated point has no chord-length parameter of its own).

use crate::nurbs::Vec3;
use crate::tolerance::Tolerance;

/// `tol` in the units of `points`: an absolute tolerance as it is, a relative one times the points'
/// [`bounding_box_extent`].
pub fn absolute_tolerance(tol: Tolerance, points: &[Vec3]) -> f64 {
    match tol {
        Tolerance::Absolute(t) => t,
        Tolerance::Relative(r) => r * bounding_box_extent(points),
    }
}

/// Drops points equal to their predecessor (within 1e-12 of the data extent); returns the count.
pub fn drop_consecutive_duplicates(pts: &[Vec3]) -> (Vec<Vec3>, usize) {
    let eps = 1e-12 * bounding_box_extent(pts).max(f64::MIN_POSITIVE);
    let mut out: Vec<Vec3> = Vec::with_capacity(pts.len());
    let mut dropped = 0;
    for &p in pts {
        match out.last() {
            Some(&l) if (p - l).max_abs() <= eps => dropped += 1,
            _ => out.push(p),
        }
    }
    (out, dropped)
}

/// For each point of `pts`, the index of the point [`drop_consecutive_duplicates`] keeps for it
/// (its own index among the kept points, or that of the kept point it repeats).
///
/// ```
/// use fairfit::fit::points::kept_point_of_each;
/// use fairfit::Vec3;
/// let p = |x: f64| Vec3::new(x, 0.0, 0.0);
/// assert_eq!(kept_point_of_each(&[p(0.0), p(0.0), p(1.0), p(2.0), p(2.0)]), vec![0, 0, 1, 2, 2]);
/// ```
pub fn kept_point_of_each(pts: &[Vec3]) -> Vec<usize> {
    let eps = 1e-12 * bounding_box_extent(pts).max(f64::MIN_POSITIVE);
    let mut last: Option<Vec3> = None;
    let mut kept = 0usize;
    pts.iter()
        .map(|&p| {
            match last {
                Some(l) if (p - l).max_abs() <= eps => {}
                Some(_) => {
                    kept += 1;
                    last = Some(p);
                }
                None => last = Some(p),
            }
            kept
        })
        .collect()
}

/// Largest side of the axis-aligned bounding box of `pts` (0 for fewer than 2 points).
pub fn bounding_box_extent(pts: &[Vec3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pts {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3)
        .map(|k| hi[k] - lo[k])
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max)
}
