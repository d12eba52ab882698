//! The integrated fitting-and-fairing method on the example data: tolerance met, lower F than the
//! least-squares baseline with the same number of control points, exact scale invariance, and
//! thread-count independent results.

use fairfit::optim::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::Vec3;

use crate::common::example_data;
use example_data::read_csv;

use crate::common::sampled;

fn opts() -> IntegratedOptions {
    IntegratedOptions::new(Tolerance::Relative(1e-3)).seed(42)
}

#[test]
fn at_the_least_squares_count_the_integrated_curve_is_fairer_and_within_tolerance() {
    // the real least-squares method (fairfit::fit, adaptive knots) against the integrated method
    // with the same number of control points; both measured by the fairness module and by the
    // least-squares module's own orthogonal-deviation measure
    use fairfit::fair::curve_fairness;
    use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
    for (name, max_ratio) in [
        ("quarter_ellipse_200.csv", 0.95),
        ("naca4412.csv", 0.8),
        ("e387.csv", 0.8),
    ] {
        let pts = read_csv(name);
        let lsq = fit_to_tolerance(&pts, &FitOptions::default()).unwrap();
        let n = lsq.n_control_points;
        let r = fit_integrated(&pts, &opts().control_points(n)).unwrap();
        let (fi, fl) = (
            curve_fairness(&r.curve).fairness,
            curve_fairness(&lsq.curve).fairness,
        );
        eprintln!(
            "{name}: n={n} F integrated {fi:.4e} lsq {fl:.4e} ratio {:.3}",
            fi / fl
        );
        assert_eq!(r.curve.n_control_points(), n, "{name}");
        assert!(r.met && r.quality.max_deviation <= r.tolerance, "{name}");
        assert!(lsq.deviation.max <= lsq.tolerance, "{name}");
        assert!((r.tolerance - lsq.tolerance).abs() <= 1e-12 * lsq.tolerance);
        assert!(fi < max_ratio * fl, "{name}: F {fi} vs lsq {fl}");
        // free count: within the tolerance, no more control points than least squares, still fairer
        let free = fit_integrated(&pts, &opts()).unwrap();
        let ff = curve_fairness(&free.curve).fairness;
        eprintln!(
            "{name}: free n={} F {ff:.4e}",
            free.curve.n_control_points()
        );
        assert!(
            free.met && free.quality.max_deviation <= free.tolerance,
            "{name}"
        );
        assert!(free.curve.n_control_points() <= n, "{name}");
        assert!(ff < fl, "{name}: F {ff} vs lsq {fl}");
    }
}

fn curve_bits(r: &fairfit::optim::IntegratedResult) -> Vec<u64> {
    let c = &r.curve;
    c.knots()
        .iter()
        .map(|k| k.to_bits())
        .chain(
            c.control_points()
                .iter()
                .flat_map(|p| p.0.map(f64::to_bits)),
        )
        .collect()
}

#[test]
fn same_seed_gives_identical_bits_with_one_and_two_threads() {
    let pts = read_csv("naca4412.csv");
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| fit_integrated(&pts, &opts()).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(curve_bits(&a), curve_bits(&b));
    assert_eq!(a.stats.evaluations, b.stats.evaluations);
    assert_eq!(
        fairfit::io::json::curve_to_json(&a.curve),
        fairfit::io::json::curve_to_json(&b.curve)
    );
}

#[test]
fn scaling_the_input_by_1000_gives_the_same_knots_and_count() {
    let pts = read_csv("e387.csv");
    let big: Vec<Vec3> = pts.iter().map(|p| *p * 1000.0).collect();
    let (a, b) = (
        fit_integrated(&pts, &opts()).unwrap(),
        fit_integrated(&big, &opts()).unwrap(),
    );
    assert_eq!(a.curve.n_control_points(), b.curve.n_control_points());
    let bits = |r: &fairfit::optim::IntegratedResult| {
        r.curve
            .knots()
            .iter()
            .map(|k| k.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a), bits(&b));
    assert!((b.quality.fairness - a.quality.fairness).abs() <= 1e-9 * a.quality.fairness);
    assert!((b.quality.max_deviation / 1000.0 - a.quality.max_deviation).abs() < 1e-12);
    for (p, q) in a
        .curve
        .control_points()
        .iter()
        .zip(b.curve.control_points())
    {
        assert!((*p * 1000.0 - *q).norm() < 1e-9);
    }
}

#[test]
fn pareto_front_trades_deviation_for_fairness_without_dominated_members() {
    use fairfit::optim::{pareto_csv, pareto_front};
    let pts = read_csv("naca4412.csv");
    let r = fit_integrated(&pts, &opts()).unwrap();
    let n = r.curve.n_control_points();
    let knots = r.curve.knots();
    let interior = &knots[4..knots.len() - 4];
    let front = pareto_front(&pts, &opts(), n, Some((interior, r.log_lambda))).unwrap();
    eprintln!("{}", pareto_csv(&front));
    assert!(front.len() >= 5, "{}", front.len());
    for w in front.windows(2) {
        // sorted by deviation, so fairness strictly decreases along a non-dominated front
        assert!(w[0].quality.max_deviation <= w[1].quality.max_deviation);
        assert!(w[0].quality.fairness > w[1].quality.fairness);
    }
    for c in &front {
        assert_eq!(c.curve.n_control_points(), n);
        assert!(c.quality.max_deviation <= 10.0 * r.tolerance * (1.0 + 1e-12));
    }
    // the front reaches below the integrated result's F at larger deviations
    let last = front.last().unwrap();
    assert!(last.quality.fairness < r.quality.fairness);
    assert_eq!(pareto_csv(&front).lines().count(), front.len() + 1);
}

#[test]
fn a_corner_becomes_a_c0_knot_and_both_sides_stay_smooth_and_within_tolerance() {
    // two quarter-ellipse arcs meeting at (1, 0) with a 90° turn: split there, each side fitted
    // on its own, joined with a triple knot through the corner point
    let mut pts: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = std::f64::consts::FRAC_PI_2 * i as f64 / 39.0;
            Vec3([1.0 - t.cos(), 0.5 * t.sin() - 0.5, 0.0])
        })
        .collect();
    let corner = pts.len() - 1;
    assert!((pts[corner] - Vec3([1.0, 0.0, 0.0])).norm() < 1e-12);
    pts.extend((1..40).map(|i| {
        let t = std::f64::consts::FRAC_PI_2 * i as f64 / 39.0;
        Vec3([1.0 + 0.7 * (1.0 - t.cos()), t.sin(), 0.0])
    }));
    let r = fit_integrated(&pts, &opts()).unwrap();
    assert!(r.met, "{:?}", r.quality);
    let p = r.curve.degree();
    let k = r.curve.knots();
    let interior = &k[p + 1..k.len() - p - 1];
    let triple: Vec<f64> = interior
        .windows(3)
        .filter(|w| w[0] == w[1] && w[1] == w[2])
        .map(|w| w[0])
        .collect();
    assert_eq!(triple.len(), 1, "{k:?}");
    // the curve passes through the corner at the triple knot
    assert!((r.curve.point(triple[0]) - pts[corner]).norm() < 1e-9);
    // independent check of the tolerance: brute-force distance to 100 001 curve samples
    let worst = sampled::brute_force_deviation_n(&r.curve, &pts, 100_000);
    assert!(worst <= r.tolerance * 1.001, "{worst} > {}", r.tolerance);
    // one smooth curve through the corner needs far more control points (or misses)
    let smooth = fit_integrated(&pts, &opts().corner_angle(None)).unwrap();
    assert!(
        !smooth.met || smooth.curve.n_control_points() > r.curve.n_control_points() + 3,
        "{} vs {}",
        smooth.curve.n_control_points(),
        r.curve.n_control_points()
    );
}

#[test]
fn non_finite_or_shrinking_options_are_typed_errors() {
    let pts: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = i as f64 / 39.0;
            Vec3::new(t, (3.0 * t).sin(), 0.0)
        })
        .collect();
    // (the fairness gain per degree is tuning, not a setting: optim::tuning holds it)
    for o in [
        opts().span_fairness(f64::NAN),
        opts().span_fairness(0.0),
        opts().corner_angle(Some(f64::NAN)),
        opts().corner_angle(Some(0.0)),
    ] {
        let e = fit_integrated(&pts, &o).unwrap_err();
        assert!(matches!(e, fairfit::Error::InvalidSetting { .. }), "{e}");
    }
}

#[test]
fn a_count_the_data_cannot_take_is_refused_naming_the_control_points_setting() {
    use fairfit::optim::{fit_lsq_baseline, ClosedMode};
    let named = |r: fairfit::Result<fairfit::optim::IntegratedResult>| match r {
        Err(fairfit::Error::InvalidSetting { option, reason }) => {
            assert_eq!(option, "control_points", "{reason}");
            reason
        }
        other => panic!("expected a refused control-point count, got {other:?}"),
    };
    // open: 40 points take at most 39 control points (a data parameter inside every span)
    let open: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = i as f64 / 39.0;
            Vec3::new(t, (3.0 * t).sin(), 0.0)
        })
        .collect();
    let r = named(fit_integrated(&open, &opts().control_points(40)));
    assert!(r.contains("at most 39"), "{r}");
    // the least-squares baseline: between degree + 1 and the point count
    let r = named(fit_lsq_baseline(&open, 41, &opts()));
    assert!(r.contains("between 4 and 40"), "{r}");
    named(fit_lsq_baseline(&open, 3, &opts()));
    // closed: 30 distinct points on a circle take at most 29 distinct control points
    let circle: Vec<Vec3> = (0..30)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 30.0;
            Vec3::new(t.cos(), t.sin(), 0.0)
        })
        .collect();
    let closed = opts().closed(ClosedMode::Closed);
    let r = named(fit_integrated(&circle, &closed.clone().control_points(30)));
    assert!(r.contains("between 4 and 29"), "{r}");
    // a square's four corners cut it into four straight pieces of 4 control points each: the joined
    // count is at least 4 * 4 - 3 = 13
    let mut square = Vec::new();
    for side in 0..4 {
        for i in 0..10 {
            let s = i as f64 / 10.0;
            let (x, y) = match side {
                0 => (s, 0.0),
                1 => (1.0, s),
                2 => (1.0 - s, 1.0),
                _ => (0.0, 1.0 - s),
            };
            square.push(Vec3::new(x, y, 0.0));
        }
    }
    square.push(square[0]);
    let r = named(fit_integrated(&square, &opts().control_points(5)));
    assert!(r.contains("pieces between corners"), "{r}");
}

#[test]
fn far_from_unit_size_the_fit_is_the_unit_fit_scaled() {
    // at coordinates near 1e-211 squared lengths underflow; at 1e180 they overflow
    let pts: Vec<Vec3> = (0..60)
        .map(|i| {
            let t = std::f64::consts::FRAC_PI_2 * i as f64 / 59.0;
            Vec3([t.cos(), 0.5 * t.sin() + 0.1 * (5.0 * t).sin(), 0.0])
        })
        .collect();
    let unit = fit_integrated(&pts, &opts()).unwrap();
    for f in [2f64.powi(-700), 2f64.powi(600)] {
        let scaled: Vec<Vec3> = pts.iter().map(|p| *p * f).collect();
        let r = fit_integrated(&scaled, &opts()).unwrap();
        assert_eq!(r.curve.n_control_points(), unit.curve.n_control_points());
        assert_eq!(r.curve.knots(), unit.curve.knots());
        assert!((r.quality.fairness / unit.quality.fairness - 1.0).abs() < 1e-9);
        assert!((r.quality.max_deviation / f / unit.quality.max_deviation - 1.0).abs() < 1e-9);
        assert!(r.met);
    }
}
