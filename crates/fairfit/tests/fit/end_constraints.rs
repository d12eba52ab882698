//! End conditions (G0/G1/G2) of `fairfit::fit::end_constraints`, held by the least-squares solve
//! and by the integrated method, measured against an analytic circular arc (its tangent and its
//! curvature `1/R` in closed form) and a helix (curvature vector `R/(R² + c²)` towards the axis).

use fairfit::fit::end_constraints::{achieved, EndConstraint, EndConstraints};
use fairfit::fit::lsq::{LsqOptions, LsqSolver};
use fairfit::prelude::*;

const R: f64 = 2.0;
const SWEEP: f64 = 1.2;

/// `n` points on the arc of radius `R` from angle 0 to `SWEEP`, anticlockwise, with a slight
/// wobble of relative size `wobble` (so the data do not already carry the conditions exactly).
fn arc(n: usize, wobble: f64) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let a = SWEEP * i as f64 / (n - 1) as f64;
            let r = R * (1.0 + wobble * (7.0 * a).sin());
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

/// The arc's exact conditions: tangent and signed curvature `1/R` at both ends.
fn arc_g2() -> (EndConstraint, EndConstraint) {
    let start = EndConstraint::curvature(Vec3::new(0.0, 1.0, 0.0), 1.0 / R);
    let end = EndConstraint::curvature(Vec3::new(-SWEEP.sin(), SWEEP.cos(), 0.0), 1.0 / R);
    (start, end)
}

fn arc_g1() -> (EndConstraint, EndConstraint) {
    let (s, e) = arc_g2();
    (
        EndConstraint::tangent(s.tangent.unwrap()),
        EndConstraint::tangent(e.tangent.unwrap()),
    )
}

/// Asserts that `curve` holds `start` and `end` to 1e-9: the tangent angle, and the relative
/// curvature where a curvature is asked (0 otherwise).
fn assert_ends_held(curve: &NurbsCurve, start: &EndConstraint, end: &EndConstraint) {
    for (at_end, cond) in [(false, start), (true, end)] {
        let a = achieved(curve, at_end, cond);
        assert!(a.tangent_angle <= 1e-9, "angle {}", a.tangent_angle);
        assert!(
            a.curvature_relative <= 1e-9,
            "curvature {}",
            a.curvature_relative
        );
    }
}

fn clamped(n_ctrl: usize, p: usize) -> Vec<f64> {
    let spans = n_ctrl - p;
    let mut k = vec![0.0; p + 1];
    k.extend((1..spans).map(|i| i as f64 / spans as f64));
    k.extend(vec![1.0; p + 1]);
    k
}

#[test]
fn least_squares_holds_g2_at_both_ends_of_an_arc() {
    let pts = arc(40, 1e-3);
    let u: Vec<f64> = (0..40).map(|i| i as f64 / 39.0).collect();
    let (s, e) = arc_g2();
    for p in [3, 4, 5] {
        let knots = clamped(9, p);
        let mut solver = LsqSolver::new(p);
        let mut ctrl = Vec::new();
        let ends = EndConstraints { start: s, end: e };
        solver
            .solve_constrained(
                &pts,
                &u,
                &knots,
                None,
                &LsqOptions::default(),
                &ends,
                true,
                &mut ctrl,
            )
            .unwrap();
        let c = NurbsCurve::bspline(p, knots, ctrl).unwrap();
        for (at_end, cond) in [(false, &s), (true, &e)] {
            let a = achieved(&c, at_end, cond);
            assert!(
                a.tangent_angle <= 1e-9,
                "degree {p}: angle {}",
                a.tangent_angle
            );
            assert!(
                a.curvature_relative <= 1e-9,
                "degree {p}: curvature {}",
                a.curvature_relative
            );
        }
        // the exact values, independently of `achieved`: κ = |C' × C''| / |C'|³ = 1/R at u = 0
        let d = c.derivatives(0.0, 2);
        let kappa = d[1].cross(d[2])[2] / d[1].norm().powi(3);
        assert!(
            (kappa - 1.0 / R).abs() <= 1e-9 / R,
            "degree {p}: κ(0) = {kappa}"
        );
        assert!(
            d[1][0].abs() <= 1e-9 * d[1].norm(),
            "degree {p}: C'(0) = {:?}",
            d[1]
        );
    }
}

#[test]
fn least_squares_without_conditions_is_the_plain_solve() {
    let pts = arc(30, 1e-2);
    let u: Vec<f64> = (0..30).map(|i| i as f64 / 29.0).collect();
    let knots = clamped(8, 3);
    let mut solver = LsqSolver::new(3);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let opts = LsqOptions::default();
    solver.solve(&pts, &u, &knots, None, &opts, &mut a).unwrap();
    solver
        .solve_constrained(
            &pts,
            &u,
            &knots,
            None,
            &opts,
            &EndConstraints::default(),
            true,
            &mut b,
        )
        .unwrap();
    assert_eq!(a, b);
}

#[test]
fn integrated_holds_g1_ends_of_an_arc_within_the_tolerance() {
    let pts = arc(80, 2e-4);
    let (s, e) = arc_g1();
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3))
        .start(s)
        .end(e);
    let r = fit_integrated(&pts, &opts).unwrap();
    assert!(r.met && r.quality.max_deviation <= r.tolerance);
    assert_ends_held(&r.curve, &s, &e);
    // the curve still starts and ends on the data's end points
    assert!((r.curve.point(0.0) - pts[0]).norm() <= 1e-9 * R);
    assert!((r.curve.point(1.0) - pts[79]).norm() <= 1e-9 * R);
}

#[test]
fn integrated_holds_g2_ends_of_an_arc_within_the_tolerance() {
    let pts = arc(80, 2e-4);
    let (s, e) = arc_g2();
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3))
        .start(s)
        .end(e);
    let r = fit_integrated(&pts, &opts).unwrap();
    assert!(r.met && r.quality.max_deviation <= r.tolerance);
    assert_ends_held(&r.curve, &s, &e);
    let (_, b) = r.curve.domain();
    let d = r.curve.derivatives(b, 2);
    let kappa = d[1].cross(d[2])[2] / d[1].norm().powi(3);
    assert!((kappa - 1.0 / R).abs() <= 1e-9 / R, "κ(end) = {kappa}");
}

#[test]
fn integrated_holds_a_curvature_vector_on_a_helix() {
    // helix (R cos t, R sin t, c t): curvature R / (R² + c²) towards the axis
    let (rad, c) = (1.5, 0.4);
    let pts: Vec<Vec3> = (0..70)
        .map(|i| {
            let t = 2.0 * i as f64 / 69.0;
            Vec3::new(rad * t.cos(), rad * t.sin(), c * t)
        })
        .collect();
    let kappa = rad / (rad * rad + c * c);
    let g2 = EndConstraint::curvature_vector(Vec3::new(0.0, rad, c), Vec3::new(-kappa, 0.0, 0.0));
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).start(g2);
    let r = fit_integrated(&pts, &opts).unwrap();
    assert!(r.met);
    let a = achieved(&r.curve, false, &g2);
    assert!(
        a.tangent_angle <= 1e-9 && a.curvature_relative <= 1e-9,
        "{a:?}"
    );
}

#[test]
fn a_tangent_that_leaves_the_band_is_refused_naming_its_end() {
    let pts = arc(60, 0.0);
    // at the start the arc heads +y: a tangent 120° from it would make the curve reverse
    let bad = EndConstraint::tangent(Vec3::new(3f64.sqrt() / 2.0, -0.5, 0.0));
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-4))
        .end(arc_g1().1)
        .start(bad);
    match fit_integrated(&pts, &opts) {
        Err(Error::InvalidSetting { option, reason }) => {
            assert_eq!(option, "start", "{reason}");
            assert!(!reason.contains('\n'));
        }
        other => panic!("expected a refusal, got {:?}", other.map(|r| r.met)),
    }
}

#[test]
fn conditions_that_cannot_hold_are_refused() {
    let pts = arc(30, 0.0);
    let zero = EndConstraint::tangent(Vec3::ZERO);
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).start(zero);
    assert!(matches!(
        fit_integrated(&pts, &opts),
        Err(Error::InvalidSetting {
            option: "start",
            ..
        })
    ));
    let nan = EndConstraint::curvature(Vec3::new(0.0, 1.0, 0.0), f64::NAN);
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).end(nan);
    assert!(matches!(
        fit_integrated(&pts, &opts),
        Err(Error::InvalidSetting { option: "end", .. })
    ));
    // closed data have no ends
    let mut ring: Vec<Vec3> = (0..40)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 40.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    ring.push(ring[0]);
    let g1 = EndConstraint::tangent(Vec3::new(0.0, 1.0, 0.0));
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).start(g1);
    assert!(matches!(
        fit_integrated(&ring, &opts),
        Err(Error::InvalidSetting {
            option: "start",
            ..
        })
    ));
}

/// The tolerance-driven least squares (`--method lsq`) and its fairing (`fit-then-fair`, the
/// conditions' control points held) hold G2 at both ends of the wobbly arc, within the tolerance.
#[test]
fn least_squares_pipeline_and_its_fairing_hold_g2_ends_of_an_arc() {
    use fairfit::fair::{fair_curve, FairingOptions};
    use fairfit::fit::{max_orthogonal_deviation, FitOptions};
    let pts = arc(120, 2e-4);
    let (s, e) = arc_g2();
    let opts = FitOptions {
        tolerance: Tolerance::Absolute(1e-3),
        end_conditions: EndConstraints { start: s, end: e },
        ..FitOptions::default()
    };
    let fit = fit_to_tolerance(&pts, &opts).unwrap();
    assert!(fit.deviation.max <= 1e-3, "{}", fit.deviation.max);
    let fairing = FairingOptions {
        held: (3, 3),
        ..FairingOptions::default()
    };
    let faired = fair_curve(&fit.curve, &fit.points, fit.tolerance, &fairing).unwrap();
    let dev = max_orthogonal_deviation(&faired.curve, &fit.points, &fit.params);
    assert!(dev.max <= 1e-3 * (1.0 + 1e-9), "{}", dev.max);
    for c in [&fit.curve, &faired.curve] {
        for (at_end, cond) in [(false, &s), (true, &e)] {
            let a = achieved(c, at_end, cond);
            assert!(a.tangent_angle <= 1e-9, "angle {}", a.tangent_angle);
            // the arc's curvature 1/R, measured from the curve's own derivatives
            let (u0, u1) = c.domain();
            let d = c.derivatives(if at_end { u1 } else { u0 }, 2);
            let kappa = d[1].cross(d[2]).z() / d[1].norm().powi(3);
            assert!((kappa * R - 1.0).abs() <= 1e-9, "κ R = {}", kappa * R);
        }
    }
}

/// A given end point (G0 away from the data's end, within the tolerance) is where the lsq curve
/// ends, to rounding.
#[test]
fn least_squares_pipeline_ends_on_a_given_point() {
    use fairfit::fit::FitOptions;
    let pts = arc(80, 0.0);
    let at = pts[0] + Vec3::new(2e-4, -1e-4, 0.0);
    let opts = FitOptions {
        tolerance: Tolerance::Absolute(1e-3),
        end_conditions: EndConstraints {
            start: EndConstraint::point(at),
            end: EndConstraint::default(),
        },
        ..FitOptions::default()
    };
    let fit = fit_to_tolerance(&pts, &opts).unwrap();
    let p0 = fit.curve.point(fit.curve.domain().0);
    assert!((p0 - at).norm() <= 1e-12, "{:?}", p0 - at);
    assert!(fit.deviation.max <= 1e-3);
}

/// A condition read from a curve's end (`EndConstraint::from_curve_end`) is that curve's own
/// position, tangent and curvature: the arc's at its end point (angle `SWEEP`).
#[test]
fn a_condition_from_a_curve_end_is_its_position_tangent_and_curvature() {
    let pts = arc(60, 0.0);
    let opts = IntegratedOptions::new(Tolerance::Absolute(1e-6)).degree(3);
    let r = fit_integrated(&pts, &opts).unwrap();
    let c = EndConstraint::from_curve_end(&r.curve, true, 2).unwrap();
    let end = Vec3::new(R * SWEEP.cos(), R * SWEEP.sin(), 0.0);
    assert!((c.point.unwrap() - end).norm() <= 1e-12);
    let t = c.tangent.unwrap();
    assert!(
        (t - Vec3::new(-SWEEP.sin(), SWEEP.cos(), 0.0)).norm() <= 1e-5,
        "{t:?}"
    );
    let Some(fairfit::fit::end_constraints::EndCurvature::Vector(k)) = c.curvature else {
        panic!("no curvature vector")
    };
    // towards the centre, magnitude 1/R (the fit is within 1e-6 of the arc)
    assert!((k + end / (R * R)).norm() <= 1e-3 / R, "{k:?}");
}

/// G2 ends taken from the unconstrained fit's own ends (NACA 4412, `examples/data`): the fit
/// under them keeps the unconstrained count, its F within 1 % (before the warm start from the
/// unconstrained fit: 11 control points; measured here 10 and ratio 1.0000), no more curvature
/// extrema, and holds the conditions to 1e-9.
#[test]
fn g2_ends_from_the_unconstrained_fit_cost_no_control_point_and_almost_no_fairness() {
    let pts = crate::common::example_data::read_csv("naca4412.csv");
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    let free = fit_integrated(&pts, &opts).unwrap();
    let s = EndConstraint::from_curve_end(&free.curve, false, 2).unwrap();
    let e = EndConstraint::from_curve_end(&free.curve, true, 2).unwrap();
    let r = fit_integrated(&pts, &opts.clone().start(s).end(e)).unwrap();
    assert!(r.met && r.quality.max_deviation <= r.tolerance);
    assert_ends_held(&r.curve, &s, &e);
    let (f, f0) = (
        fairfit::fair::curve_fairness(&r.curve),
        fairfit::fair::curve_fairness(&free.curve),
    );
    eprintln!(
        "{} -> {} control points, F ratio {:.4}, extrema {} -> {}",
        free.curve.n_control_points(),
        r.curve.n_control_points(),
        f.fairness / f0.fairness,
        f0.curvature_extrema,
        f.curvature_extrema
    );
    assert_eq!(r.curve.n_control_points(), free.curve.n_control_points());
    assert!(
        f.fairness <= 1.01 * f0.fairness,
        "{} vs {}",
        f.fairness,
        f0.fairness
    );
    assert!(f.curvature_extrema <= f0.curvature_extrema);
}

#[test]
fn integrated_holds_g2_ends_of_data_with_a_corner_at_its_end_pieces() {
    // the arc, then a corner turning the tangent by 90° and a straight leg of length 1.5: the fit
    // is split at the corner (a C0 knot), the arc piece holds the start condition, the leg the end
    // condition (its direction, curvature 0 is not asked: a G1 end)
    let mut pts = arc(80, 2e-4);
    let c = pts[pts.len() - 1];
    let leg = Vec3::new(SWEEP.cos(), SWEEP.sin(), 0.0) * -1.0;
    pts.extend((1..60).map(|i| c + leg * (1.5 * i as f64 / 59.0)));
    let (s, _) = arc_g2();
    let e = EndConstraint::tangent(leg);
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3))
        .start(s)
        .end(e);
    let r = fit_integrated(&pts, &opts).unwrap();
    assert!(r.met && r.quality.max_deviation <= r.tolerance);
    assert_ends_held(&r.curve, &s, &e);
    // the corner: a knot of full multiplicity (3) inside the domain
    let k = r.curve.knots();
    let inner = &k[4..k.len() - 4];
    assert!(
        inner.windows(3).any(|w| w[0] == w[1] && w[1] == w[2]),
        "no C0 knot in {k:?}"
    );
}
