//! `fit::corners`: no false corner on smooth noisy data at any density, true corners found within the
//! tolerance of their position, the same decisions for a scaled input.

use crate::common::scan_data::{extent, noisy_corner, noisy_spiral};
use fairfit::fit::corners::corners_at_tolerance;
use fairfit::fit::shape::detect_corners;
use fairfit::nurbs::Vec3;

#[test]
fn no_corner_on_a_smooth_noisy_spiral_at_ten_thousand_and_a_hundred_thousand_points() {
    for n in [10_000, 100_000] {
        let tol = 1e-3 * extent(&noisy_spiral(n, 0.0, 1));
        let pts = noisy_spiral(n, tol / 10.0, 3);
        // the chord rule sees the noise as corners; the scaled rule sees none
        assert!(detect_corners(&pts, false, 60.0).len() > 10);
        assert_eq!(
            corners_at_tolerance(&pts, false, 60.0, tol),
            Vec::<usize>::new(),
            "{n} points"
        );
        assert_eq!(
            corners_at_tolerance(&pts, false, 20.0, tol),
            Vec::<usize>::new(),
            "{n} points, 20°"
        );
    }
}

#[test]
fn true_corners_found_within_the_tolerance() {
    for (turn, angle) in [(90.0, 60.0), (45.0, 40.0), (30.0, 20.0)] {
        for n in [1000, 20_000] {
            let pts = noisy_corner(n, turn, 0.0, 1);
            let tol = 1e-3 * extent(&pts);
            let pts = noisy_corner(n, turn, tol / 10.0, 5);
            let found = corners_at_tolerance(&pts, false, angle, tol);
            assert_eq!(found.len(), 1, "{turn}° at {n} points: {found:?}");
            let off = (pts[found[0]] - Vec3::new(1.0, 0.0, 0.0)).norm();
            assert!(
                off <= tol,
                "{turn}° at {n} points: {} tol from the corner",
                off / tol
            );
        }
    }
}

#[test]
fn scaling_by_a_thousand_keeps_the_decisions() {
    let pts = noisy_corner(20_000, 90.0, 2e-4, 9);
    let big: Vec<Vec3> = pts.iter().map(|&p| p * 1000.0).collect();
    let tol = 1e-3 * extent(&pts);
    let a = corners_at_tolerance(&pts, false, 60.0, tol);
    assert_eq!(a.len(), 1);
    assert_eq!(a, corners_at_tolerance(&big, false, 60.0, 1000.0 * tol));
}
