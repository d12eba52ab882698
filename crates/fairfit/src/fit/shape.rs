//! The shape of the data before fitting: closed or open, and corners.
//!
//! - A curve is *closed* when its last point equals its first within `1e-9` of the bounding-box
//!   extent (scale-free), or when the caller forces it.
//! - A *corner* is a point where the turning angle between its two chords exceeds a threshold (default
//!   [`DEFAULT_CORNER_ANGLE_DEG`]); the fit keeps it as a C0 knot of multiplicity `p`. Smooth data at the
//!   usual sampling turn by well under 60° per point (airfoil leading edges in the test data: at most
//!   53°), while a blunt trailing edge or a machined edge turns by 80–90°.

use super::knot_placement::turning_angle;
use crate::errors::Error;
use crate::fit::points::bounding_box_extent;
use crate::nurbs::Vec3;

/// Default corner threshold, degrees.
pub const DEFAULT_CORNER_ANGLE_DEG: f64 = 60.0;

/// The one check of a corner angle (the integrated method's options, the command line and the Python
/// bindings all use it): `degrees` when it lies in `(0, 180]`, else an [`Error::InvalidSetting`] of
/// `corner_angle` whose reason reads after any name of the setting, so that each front end names it
/// its own way (`--corner-angle must be in (0, 180] degrees, got 0`).
pub fn check_corner_angle(degrees: f64) -> Result<f64, Error> {
    if degrees.is_finite() && degrees > 0.0 && degrees <= 180.0 {
        Ok(degrees)
    } else {
        Err(Error::InvalidSetting {
            option: "corner_angle",
            reason: format!("must be in (0, 180] degrees, got {degrees}"),
        })
    }
}

/// Relative gap (of the bounding-box extent) under which first and last points count as equal.
pub const CLOSED_REL_GAP: f64 = 1e-9;

/// True when the last point equals the first within [`CLOSED_REL_GAP`] of the data extent.
pub fn looks_closed(points: &[Vec3]) -> bool {
    if points.len() < 3 {
        return false;
    }
    let ext = bounding_box_extent(points);
    // the gap in units of the extent: a squared gap of points near 1e-200 would underflow to 0
    ext > 0.0 && ((points[points.len() - 1] - points[0]) / ext).norm() <= CLOSED_REL_GAP
}

/// Indices of corner points: turning angle above `angle_deg`. For `closed` data (the last point is not
/// repeated) every point has two neighbours, including the first and the last.
pub fn detect_corners(points: &[Vec3], closed: bool, angle_deg: f64) -> Vec<usize> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    let thr = angle_deg.to_radians();
    let mut out = Vec::new();
    for k in 0..n {
        let (prev, next) = if closed {
            ((k + n - 1) % n, (k + 1) % n)
        } else if k == 0 || k + 1 == n {
            continue;
        } else {
            (k - 1, k + 1)
        };
        if turning_angle(points[prev], points[k], points[next]) > thr {
            out.push(k);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_has_four_corners_circle_none() {
        let sq: Vec<Vec3> = [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        assert_eq!(detect_corners(&sq, true, 60.0), vec![0, 2, 3, 4]);
        assert_eq!(detect_corners(&sq, false, 60.0), vec![2, 3]);
        let circle: Vec<Vec3> = (0..20)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 20.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        assert!(detect_corners(&circle, true, 60.0).is_empty());
        assert!(!looks_closed(&circle));
        let mut c2 = circle.clone();
        c2.push(circle[0]);
        assert!(looks_closed(&c2));
    }

    #[test]
    fn the_corner_angle_is_checked_in_one_place_with_one_message() {
        for ok in [1e-9, 60.0, 180.0] {
            assert_eq!(check_corner_angle(ok).unwrap(), ok);
        }
        for bad in [0.0, -5.0, 180.5, f64::NAN, f64::INFINITY] {
            match check_corner_angle(bad) {
                Err(Error::InvalidSetting { option, reason }) => {
                    assert_eq!(option, "corner_angle");
                    assert_eq!(reason, format!("must be in (0, 180] degrees, got {bad}"));
                }
                other => panic!("{bad}: {other:?}"),
            }
        }
    }
}
