//! `fit::corners`: no false corner on smooth noisy data at any density, true corners found within the
//! tolerance of their position, the same decisions for a scaled input.

use crate::common::rng;
use crate::common::scan_data::{extent, gauss, noisy_corner, noisy_spiral};
use fairfit::fit::corners::corners_at_tolerance;
use fairfit::fit::shape::detect_corners;
use fairfit::nurbs::Vec3;

/// Circular arcs of `lengths` and signed curvatures `curvatures` in the plane, joined by corners
/// that turn the tangent by `turns` degrees; `n` points even in arc length with a point on every
/// corner (as a table of a cornered shape has), isotropic Gaussian noise `sigma` (in units of
/// `1e-3 ×` the clean points' extent, the tolerance). Returns the points, the tolerance and the
/// clean corner positions.
pub fn arcs(
    lengths: &[f64],
    curvatures: &[f64],
    turns: &[f64],
    n: usize,
    sigma_tols: f64,
    seed: u64,
) -> (Vec<Vec3>, f64, Vec<Vec3>) {
    let total: f64 = lengths.iter().sum();
    let arc = |o: Vec3, th: f64, k: f64, s: f64| {
        if k.abs() < 1e-12 {
            o + Vec3::new(s * th.cos(), s * th.sin(), 0.0)
        } else {
            o + Vec3::new(
                ((th + k * s).sin() - th.sin()) / k,
                -((th + k * s).cos() - th.cos()) / k,
                0.0,
            )
        }
    };
    let (mut o, mut th) = (Vec3::new(0.0, 0.0, 0.0), 0.0f64);
    let mut pts = vec![o];
    let mut corners = Vec::new();
    let mut done = 0usize;
    for (i, (&l, &k)) in lengths.iter().zip(curvatures).enumerate() {
        let m = if i + 1 == lengths.len() {
            n - 1 - done
        } else {
            ((n - 1) as f64 * l / total).round() as usize
        };
        done += m;
        pts.extend((1..=m).map(|j| arc(o, th, k, l * j as f64 / m as f64)));
        o = arc(o, th, k, l);
        th += k * l;
        if let Some(&t) = turns.get(i) {
            th += t.to_radians();
            corners.push(o);
        }
    }
    let tol = 1e-3 * extent(&pts);
    let mut g = rng(seed);
    for p in &mut pts {
        *p += Vec3::new(gauss(&mut g), gauss(&mut g), 0.0) * (sigma_tols * tol);
    }
    (pts, tol, corners)
}

/// The corner sets of the table: a smooth shape (curvature jumps, no tangent turn), a 90° and a
/// 45° corner, a 30° corner; with the corner angle each is judged at.
type Shape = (
    &'static str,
    &'static [f64],
    &'static [f64],
    &'static [f64],
    f64,
);
const SHAPES: [Shape; 3] = [
    (
        "smooth",
        &[1.0, 0.8, 1.0],
        &[0.6, -0.8, 0.5],
        &[0.0, 0.0],
        20.0,
    ),
    (
        "90+45",
        &[1.0, 0.8, 1.0],
        &[0.6, -0.8, 0.5],
        &[90.0, -45.0],
        30.0,
    ),
    ("30", &[1.2, 1.0], &[0.5, 0.7], &[30.0], 20.0),
];

/// Every corner of `found` within `tol` of a distinct true corner, and as many as there are.
fn check(name: &str, pts: &[Vec3], found: &[usize], truth: &[Vec3], tol: f64) {
    assert_eq!(found.len(), truth.len(), "{name}: found {found:?}");
    for (&i, c) in found.iter().zip(truth) {
        let off = (pts[i] - *c).norm();
        assert!(off <= tol, "{name}: corner {i} is {} tol off", off / tol);
    }
}

#[test]
fn corner_table_over_densities_noise_and_corner_sets() {
    for (name, lengths, curvatures, turns, angle) in SHAPES {
        for n in [100, 1000, 10_000, 100_000] {
            for (k, noise) in [0.0, 0.01, 0.1].into_iter().enumerate() {
                let (pts, tol, truth) = arcs(lengths, curvatures, turns, n, noise, 7 + k as u64);
                let truth: Vec<Vec3> = truth
                    .into_iter()
                    .zip(turns.iter())
                    .filter(|(_, &t)| f64::abs(t) >= angle)
                    .map(|(c, _)| c)
                    .collect();
                let found = corners_at_tolerance(&pts, false, angle, tol);
                let case = format!("{name} at {n} points, noise {noise} tol, {angle}°");
                check(&case, &pts, &found, &truth, tol);
            }
        }
    }
}

/// The table's largest density, for a manual check (`-- --ignored`): about 10 s.
#[test]
#[ignore]
fn corner_table_at_a_million_points() {
    for (name, lengths, curvatures, turns, angle) in SHAPES {
        for (k, noise) in [0.0, 0.01, 0.1].into_iter().enumerate() {
            let (pts, tol, truth) =
                arcs(lengths, curvatures, turns, 1_000_000, noise, 7 + k as u64);
            let truth: Vec<Vec3> = truth
                .into_iter()
                .zip(turns.iter())
                .filter(|(_, &t)| f64::abs(t) >= angle)
                .map(|(c, _)| c)
                .collect();
            let found = corners_at_tolerance(&pts, false, angle, tol);
            let case = format!("{name} at 10^6 points, noise {noise} tol, {angle}°");
            check(&case, &pts, &found, &truth, tol);
        }
    }
}

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
