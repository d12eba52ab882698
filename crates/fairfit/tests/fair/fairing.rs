//! Fit-then-fair baseline: Eck–Hadenfeld local energy fairing lowers F on a noisy curve while every data
//! point stays within the tolerance (checked independently by global closest-point projection).

use fairfit::diffgeo::project_point;
use fairfit::fair::{curve_fairness, fair_curve, FairingOptions};
use fairfit::nurbs::knots::uniform_clamped;
use fairfit::nurbs::{NurbsCurve, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn smooth(x: f64) -> f64 {
    0.05 * x * x
}

/// A "fitted" curve: control points of a smooth graph plus noise, and the data it approximates.
fn noisy_case(seed: u64, planar: bool) -> (NurbsCurve, Vec<Vec3>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = 18;
    let ctrl: Vec<Vec3> = (0..n)
        .map(|i| {
            let x = i as f64 * 0.5;
            let z = if planar { 0.0 } else { 0.3 * (0.4 * x).cos() };
            let noise = if i == 0 || i + 1 == n {
                0.0
            } else {
                rng.random_range(-0.01..0.01)
            };
            Vec3::new(x, smooth(x) + noise, z)
        })
        .collect();
    let c = NurbsCurve::bspline(3, uniform_clamped(3, n), ctrl).unwrap();
    let data: Vec<Vec3> = (0..=300)
        .map(|k| {
            let u = k as f64 / 300.0;
            c.point(u) + Vec3::new(0.0, rng.random_range(-0.002..0.002), 0.0)
        })
        .collect();
    (c, data)
}

fn max_distance(c: &NurbsCurve, data: &[Vec3]) -> f64 {
    data.iter()
        .map(|&q| project_point(c, q).distance)
        .fold(0.0, f64::max)
}

#[test]
fn fairing_lowers_fairness_within_tolerance() {
    for (seed, planar) in [(1, true), (2, true), (3, false)] {
        let (c, data) = noisy_case(seed, planar);
        let tol = 0.02;
        let before = max_distance(&c, &data);
        assert!(
            before < tol,
            "the test case must start inside the tolerance: {before}"
        );
        let r = fair_curve(&c, &data, tol, &FairingOptions::default()).unwrap();
        let f0 = curve_fairness(&c).fairness;
        let f1 = curve_fairness(&r.curve).fairness;
        assert!((r.fairness_before - f0).abs() <= 1e-12 * f0);
        assert!((r.fairness_after - f1).abs() <= 1e-12 * f0);
        assert!(
            f1 < 0.5 * f0,
            "seed {seed}: F {f0} -> {f1} after {} moves",
            r.iterations
        );
        assert!(r.iterations > 0);
        let after = max_distance(&r.curve, &data);
        assert!(
            after <= tol * (1.0 + 1e-9),
            "seed {seed}: max deviation {after}"
        );
        assert!(r.max_deviation_after >= after - 1e-12);
        // ends and knots untouched
        let (a, b) = c.domain();
        assert!((r.curve.point(a) - c.point(a)).norm() == 0.0);
        assert!((r.curve.point(b) - c.point(b)).norm() == 0.0);
        assert_eq!(r.curve.knots(), c.knots());
        // deterministic
        let again = fair_curve(&c, &data, tol, &FairingOptions::default()).unwrap();
        assert_eq!(again, r);
    }
}

#[test]
fn a_tight_tolerance_never_makes_a_point_worse() {
    let (c, data) = noisy_case(7, true);
    let tol = 1e-4; // below the data noise: each point may not move further than it already is
    let d0: Vec<f64> = data
        .iter()
        .map(|&q| project_point(&c, q).distance)
        .collect();
    let r = fair_curve(&c, &data, tol, &FairingOptions::default()).unwrap();
    assert!(r.fairness_after <= r.fairness_before);
    for (q, d) in data.iter().zip(&d0) {
        let d1 = project_point(&r.curve, *q).distance;
        assert!(d1 <= d.max(tol) * (1.0 + 1e-9) + 1e-12, "{d1} > {d}");
    }
}

#[test]
fn invalid_arguments_are_errors() {
    let (c, data) = noisy_case(1, true);
    let o = FairingOptions::default();
    assert!(fair_curve(&c, &data, 0.0, &o).is_err());
    assert!(fair_curve(&c, &data, f64::NAN, &o).is_err());
    assert!(fair_curve(&c, &[], 0.1, &o).is_err());
    assert!(fair_curve(&c, &[Vec3::new(f64::NAN, 0.0, 0.0)], 0.1, &o).is_err());
}

/// Fairing near 1e±300 runs on an exactly rescaled copy: the same moves as at unit scale, and the
/// faired control points are the unit-scale ones scaled by the same power of two.
#[test]
fn fairing_is_scale_invariant_near_the_floating_point_limits() {
    let pts = |s: f64| -> Vec<Vec3> {
        (0..10)
            .map(|i| {
                let x = i as f64;
                Vec3::new(x, x * x / 10.0 + 0.02 * (-1f64).powi(i), 0.0) * s
            })
            .collect()
    };
    let data = |s: f64| -> Vec<Vec3> {
        (0..=90)
            .map(|i| {
                let x = i as f64 / 10.0;
                Vec3::new(x, x * x / 10.0, 0.0) * s
            })
            .collect()
    };
    let knots = fairfit::nurbs::knots::uniform_clamped(3, 10);
    let run = |s: f64| {
        let c = NurbsCurve::bspline(3, knots.clone(), pts(s)).unwrap();
        fair_curve(&c, &data(s), 0.05 * s, &FairingOptions::default()).unwrap()
    };
    let unit = run(1.0);
    assert!(unit.iterations > 0);
    for e in [990, -990] {
        let s = 2f64.powi(e);
        let r = run(s);
        assert_eq!(r.iterations, unit.iterations, "2^{e}");
        for (a, b) in r
            .curve
            .control_points()
            .iter()
            .zip(unit.curve.control_points())
        {
            assert_eq!(*a, *b * s, "2^{e}");
        }
        assert_eq!(r.max_deviation_after, unit.max_deviation_after * s);
    }
}
