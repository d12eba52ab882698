//! Closed-curve detection at the tolerance's scale (`fairfit::fit::closure`): a noisy ring whose
//! ends are a fraction of the tolerance apart is closed across its gap; a missing arc, a gap wider
//! than the data's spacing and a blunt trailing edge stay open; the decision is scale-free.

use fairfit::fit::closure::{closure_at_tolerance, Closure};
use fairfit::fit::corners::{seam_turn, CornerScale};
use fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG;
use fairfit::Vec3;

use crate::common::example_data::read_csv;
use crate::common::scan_data::{noisy_ring, RING_TOL};

fn scaled(pts: &[Vec3], k: f64) -> Vec<Vec3> {
    pts.iter().map(|&p| p * k).collect()
}

#[test]
fn a_noisy_ring_with_ends_a_third_of_the_tolerance_apart_is_closed_at_any_scale() {
    let ring = noisy_ring(5000, 0, 0.3);
    let angle = DEFAULT_CORNER_ANGLE_DEG;
    let c = closure_at_tolerance(&ring, RING_TOL, angle);
    let gap = c.gap().expect("closed across its gap");
    assert!((gap / RING_TOL - 0.3).abs() < 1e-9, "gap {gap}");
    // the seam turns by a few degrees at the tolerance's scale (a corner is 60°)
    let scale = CornerScale::measure(&ring, RING_TOL, angle);
    let turn = seam_turn(&ring, &scale).to_degrees();
    eprintln!(
        "ring: gap {gap:.3e}, window {:.3e}, seam turn {turn:.2}°",
        scale.window
    );
    assert!(turn < 20.0, "{turn}°");
    // scaled by 1000, points and tolerance: the same decision, the gap scaled
    for k in [1e3, 1e-3] {
        let big = closure_at_tolerance(&scaled(&ring, k), RING_TOL * k, angle);
        let g = big.gap().expect("closed at every scale");
        assert!((g / (gap * k) - 1.0).abs() < 1e-9, "{g} vs {}", gap * k);
    }
    // the tolerance below the gap: open
    assert_eq!(
        closure_at_tolerance(&ring, 0.25 * RING_TOL, angle),
        Closure::Open
    );
}

#[test]
fn a_ring_missing_an_arc_stays_open() {
    // 16 points dropped: an arc of about 5 tolerances (the step is about 1.3e-3 near the seam)
    let ring = noisy_ring(5000, 16, 5.0);
    assert_eq!(
        closure_at_tolerance(&ring, RING_TOL, DEFAULT_CORNER_ANGLE_DEG),
        Closure::Open
    );
    assert_eq!(
        closure_at_tolerance(
            &scaled(&ring, 1e3),
            RING_TOL * 1e3,
            DEFAULT_CORNER_ANGLE_DEG
        ),
        Closure::Open
    );
    // a clean dense circle (20,000 points) missing an arc of half the tolerance (16 steps): the gap
    // is within the tolerance but not one step of the data
    let n = 20_000;
    let step = std::f64::consts::TAU / n as f64;
    let circle: Vec<Vec3> = (0..n - 15)
        .map(|i| {
            let t = step * i as f64;
            Vec3::new(t.cos(), t.sin(), 0.0)
        })
        .collect();
    let tol = 32.0 * step;
    assert_eq!(
        closure_at_tolerance(&circle, tol, DEFAULT_CORNER_ANGLE_DEG),
        Closure::Open
    );
    // the same circle with its last point one step from the first: closed
    let full: Vec<Vec3> = (0..n)
        .map(|i| {
            let t = step * i as f64;
            Vec3::new(t.cos(), t.sin(), 0.0)
        })
        .collect();
    assert!(closure_at_tolerance(&full, tol, DEFAULT_CORNER_ANGLE_DEG).is_closed());
}

#[test]
fn a_blunt_trailing_edge_stays_open_even_within_the_tolerance() {
    let naca = read_csv("naca4412.csv");
    let n = naca.len();
    let gap = naca[0].distance(naca[n - 1]);
    let chord = 1.0;
    eprintln!("naca4412: {n} points, trailing-edge gap {gap:.3e}");
    assert!(gap > 1e-3 * chord && gap < 4e-3 * chord, "{gap}");
    let angle = DEFAULT_CORNER_ANGLE_DEG;
    // the CLI's default tolerance (1e-3 of the extent): the gap is over the tolerance
    assert_eq!(closure_at_tolerance(&naca, 1e-3, angle), Closure::Open);
    // a tolerance ten times the gap: the tangents reverse at the trailing edge
    let scale = CornerScale::measure(&naca, 10.0 * gap, angle);
    let turn = seam_turn(&naca, &scale).to_degrees();
    eprintln!("naca4412 seam turn at 10 × the gap: {turn:.1}°");
    assert!(turn > 150.0, "{turn}°");
    assert_eq!(
        closure_at_tolerance(&naca, 10.0 * gap, angle),
        Closure::Open
    );
}

#[test]
fn the_bundled_examples_stay_open_or_closed_as_their_points_say() {
    let dir = format!("{}/../../examples/data", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    names.sort();
    assert!(names.len() >= 10, "{names:?}");
    for name in names {
        let pts = read_csv(&name);
        let ext = fairfit::fit::points::bounding_box_extent(&pts);
        for rel in [1e-3, 1e-2] {
            let c = closure_at_tolerance(&pts, rel * ext, DEFAULT_CORNER_ANGLE_DEG);
            assert_eq!(c.gap(), None, "{name} at {rel}: {c:?}");
        }
    }
}
