//! Closed curves in the integrated method (`fairfit::optim::closed`): periodic fits with a seam that
//! is `C^(p−1)`, fairness over the whole loop, auto-detection like the least-squares method.

use fairfit::fair::curve_fairness;
use fairfit::fit::tolerance::{fit_to_tolerance, ClosedMode, FitOptions};
use fairfit::optim::distinct_control_points;
use fairfit::optim::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::Vec3;

use crate::common::sampled;
use sampled::brute_force_deviation;

/// `n` points on an ellipse with semi-axes `a`, `b`, centred at (3, −2), the first repeated at the
/// end when `repeat`.
fn ellipse(n: usize, a: f64, b: f64, repeat: bool) -> Vec<Vec3> {
    let mut v: Vec<Vec3> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            Vec3([3.0 + a * t.cos(), -2.0 + b * t.sin(), 0.0])
        })
        .collect();
    if repeat {
        v.push(v[0]);
    }
    v
}

fn opts() -> IntegratedOptions {
    IntegratedOptions::new(Tolerance::Relative(1e-3)).seed(7)
}

#[test]
fn closed_circle_is_detected_and_fitted_periodically_with_a_smooth_seam() {
    let pts = ellipse(100, 2.0, 2.0, true);
    let r = fit_integrated(&pts, &opts()).unwrap();
    let c = &r.curve;
    let p = c.degree();
    // periodic output like the least-squares method's: unclamped knots, last p points repeat
    let n_u = distinct_control_points(c);
    assert_eq!(n_u + p, c.n_control_points());
    assert!(n_u <= 12, "{n_u} distinct control points");
    assert_eq!(c.domain(), (0.0, 1.0));
    // the seam: derivatives 0..p-1 agree at both ends of the domain (scale: radius 2)
    let (d0, d1) = (c.derivatives(0.0, p), c.derivatives(1.0, p));
    for k in 0..p {
        let scale = d0[k].norm().max(1.0);
        assert!(
            (d0[k] - d1[k]).norm() <= 1e-9 * scale,
            "derivative {k}: {:?} vs {:?}",
            d0[k],
            d1[k]
        );
    }
    // and by finite differences across the seam: curvature on both sides agrees
    let kappa = |u: f64| {
        let d = c.derivatives(u, 2);
        d[1].cross(d[2]).norm() / d[1].norm().powi(3)
    };
    let (k_before, k_after) = (kappa(1.0 - 1e-7), kappa(1e-7));
    assert!((k_before - k_after).abs() < 1e-5, "{k_before} {k_after}");
    // the circle's curvature is 1/R = 0.5 everywhere: within 10 % along the whole loop
    let worst = (0..=2000)
        .map(|i| (kappa(i as f64 / 2000.0) - 0.5).abs() / 0.5)
        .fold(0.0, f64::max);
    assert!(worst < 0.1, "κ off by {worst}");
    // the tolerance holds by brute force, and F ≈ 0 by the independent fairness module
    let dev = brute_force_deviation(c, &pts);
    assert!(
        r.met && dev <= r.tolerance * 1.0001,
        "{dev} vs {}",
        r.tolerance
    );
    assert!((r.tolerance - 4e-3).abs() < 1e-12);
    let f = curve_fairness(c);
    let lsq = fit_to_tolerance(&pts, &FitOptions::default()).unwrap();
    let fl = curve_fairness(&lsq.curve).fairness;
    // F of a circle is 0; a cubic with 7-8 spans within 2e-3 R has F ~ 1e2 (F shrinks like the
    // squared span length), against ~1e5 for a 3:1 ellipse at the same tolerance
    eprintln!(
        "circle: F integrated {} lsq {fl} (n {})",
        f.fairness, lsq.n_control_points
    );
    assert!(
        f.fairness < 200.0 && fl < 200.0,
        "F {} lsq {fl}",
        f.fairness
    );
    assert!(
        (f.length - 4.0 * std::f64::consts::PI).abs() < 2e-2,
        "{}",
        f.length
    );
    // forcing it open gives a clamped curve instead
    let open = fit_integrated(&pts, &opts().closed(ClosedMode::Open)).unwrap();
    assert_eq!(
        distinct_control_points(&open.curve),
        open.curve.n_control_points()
    );
}

#[test]
fn closed_ellipse_is_fairer_than_the_least_squares_closed_fit_at_equal_control_points() {
    // an ellipse sampled at unequal arc-length steps (equal angle), 3:1
    let pts = ellipse(150, 3.0, 1.0, true);
    let lsq = fit_to_tolerance(&pts, &FitOptions::default()).unwrap();
    assert!(lsq.closed && lsq.corners.is_empty());
    let n = lsq.n_control_points;
    let r = fit_integrated(&pts, &opts().control_points(n)).unwrap();
    assert_eq!(distinct_control_points(&r.curve), n);
    let (fi, fl) = (
        curve_fairness(&r.curve).fairness,
        curve_fairness(&lsq.curve).fairness,
    );
    eprintln!("ellipse: n={n} F integrated {fi:.4e} lsq {fl:.4e}");
    let dev = brute_force_deviation(&r.curve, &pts);
    assert!(dev <= r.tolerance * 1.0001, "{dev} vs {}", r.tolerance);
    assert!(fi < 0.75 * fl, "F {fi} vs lsq {fl}");
    // free count: no more control points than least squares, within tolerance
    let free = fit_integrated(&pts, &opts()).unwrap();
    assert!(free.met && distinct_control_points(&free.curve) <= n);
    assert!(brute_force_deviation(&free.curve, &pts) <= free.tolerance * 1.0001);
}

#[test]
fn closed_data_with_a_corner_are_cut_there_and_meet_at_it() {
    // a "D": a half circle closed by its diameter: corners at both ends of the diameter
    let mut pts: Vec<Vec3> = (0..=60)
        .map(|i| {
            let t = std::f64::consts::PI * i as f64 / 60.0;
            Vec3([t.cos(), t.sin(), 0.0])
        })
        .collect();
    pts.extend((1..20).map(|i| Vec3([-1.0 + 2.0 * i as f64 / 20.0, 0.0, 0.0])));
    pts.push(pts[0]);
    let r = fit_integrated(&pts, &opts()).unwrap();
    let c = &r.curve;
    let (a, b) = c.domain();
    assert!((c.point(a) - Vec3([1.0, 0.0, 0.0])).norm() < 1e-12);
    assert!((c.point(b) - Vec3([1.0, 0.0, 0.0])).norm() < 1e-12);
    assert!(r.met && brute_force_deviation(c, &pts) <= r.tolerance * 1.0001);
    // the other corner (-1, 0) is on the curve as a C0 knot: p equal interior knots
    let p = c.degree();
    let k = c.knots();
    let multiple = k[p + 1..k.len() - p - 1]
        .windows(p)
        .any(|w| w.iter().all(|&x| x == w[0]));
    assert!(multiple, "{k:?}");
}

#[test]
fn closed_errors_are_typed_and_actionable() {
    let pts = ellipse(100, 2.0, 1.0, true);
    let e = fit_integrated(&pts, &opts().control_points(200))
        .unwrap_err()
        .to_string();
    assert!(e.contains("between 4 and 99"), "{e}");
    // five points forced closed: too few for a periodic cubic
    let few = &ellipse(4, 1.0, 1.0, false);
    let e = fit_integrated(few, &opts().closed(ClosedMode::Closed).corner_angle(None))
        .unwrap_err()
        .to_string();
    assert!(e.contains("at least 5 distinct points"), "{e}");
}

/// A dense noisy ring whose ends are 0.3 tol apart (not repeated) is fitted closed across that gap
/// (`fairfit::fit::closure`): a periodic curve, its seam as smooth as any closed fit's, every point
/// within the tolerance; the same ring missing an arc of 5 tol stays open; `--open` keeps it open.
#[test]
fn a_noisy_ring_with_a_gap_under_the_tolerance_is_fitted_closed() {
    use crate::common::scan_data::{noisy_ring, RING_TOL};
    use fairfit::optim::{closure, Closure};
    let ring = noisy_ring(5000, 0, 0.3);
    let o = IntegratedOptions::new(Tolerance::Absolute(RING_TOL)).seed(7);
    let r = fit_integrated(&ring, &o).unwrap();
    let gap = r.closure.gap().expect("closed across the gap");
    assert!((gap / RING_TOL - 0.3).abs() < 1e-9, "{gap}");
    assert_eq!(closure(&ring, &o), r.closure);
    let c = &r.curve;
    let p = c.degree();
    let n_u = distinct_control_points(c);
    assert_eq!(n_u + p, c.n_control_points(), "periodic");
    let (d0, d1) = (c.derivatives(0.0, p), c.derivatives(1.0, p));
    for k in 0..p {
        let scale = d0[k].norm().max(1.0);
        assert!(
            (d0[k] - d1[k]).norm() <= 1e-9 * scale,
            "derivative {k} across the seam: {:?} vs {:?}",
            d0[k],
            d1[k]
        );
    }
    let dev = brute_force_deviation(c, &ring);
    eprintln!(
        "noisy ring: gap {gap:.3e}, {n_u} control points, degree {p}, max deviation {dev:.3e} \
         (tol {RING_TOL:.1e}), F {:.3e}",
        r.quality.fairness
    );
    assert!(r.met && dev <= RING_TOL * 1.0001, "{dev}");
    // open on request: clamped, two ends
    let open = closure(&ring, &o.clone().closed(ClosedMode::Open));
    assert_eq!(open, Closure::Open);
    // a missing arc of 5 tol: open
    let cut = noisy_ring(5000, 16, 5.0);
    assert_eq!(closure(&cut, &o), Closure::Open);
}
