//! Per-point weights and points to interpolate (`fairfit::fit::point_constraints`) around the
//! least-squares tolerance fit and the integrated method, measured by an independent projection
//! (`CurveProjector`, dense samples then Newton) against the analytic data they were taken from.

use fairfit::diffgeo::CurveProjector;
use fairfit::fit::cad_fit::Fitted;
use fairfit::fit::lsq::LsqSolver;
use fairfit::fit::point_constraints::{
    fit_with_point_constraints, fit_with_point_constraints_inside, Held, PointConstraintTuning,
    PointConstraints,
};
use fairfit::fit::points::bounding_box_extent;
use fairfit::fit::{fit_fixed_knots, LsqOptions};
use fairfit::prelude::*;

type Result<T> = std::result::Result<T, Error>;

/// `n` points of the quarter ellipse `x = 2 cos t, y = sin t`, with a wobble of relative size
/// `wobble` (so the points are not on any cubic).
fn ellipse(n: usize, wobble: f64) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let t = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
            let r = 1.0 + wobble * (13.0 * t).sin();
            Vec3::new(2.0 * r * t.cos(), r * t.sin(), 0.0)
        })
        .collect()
}

/// Distance of `q` from `curve` by the independent projector.
fn distance(curve: &NurbsCurve, q: Vec3) -> f64 {
    CurveProjector::new(curve, 64).project(q).distance
}

/// The least-squares tolerance fit as the method (`tol`: absolute).
fn lsq(tol: f64) -> impl FnMut(&[Vec3], Option<f64>) -> Result<Fitted<()>> {
    move |pts, tighter| {
        let opts = FitOptions {
            tolerance: Tolerance::Absolute(tighter.unwrap_or(tol)),
            ..Default::default()
        };
        let r = fit_to_tolerance(pts, &opts)?;
        Ok(Fitted {
            curve: r.curve,
            tolerance: r.tolerance,
            max_deviation: r.deviation.max,
            extra: (),
        })
    }
}

fn run(
    pts: &[Vec3],
    pc: &PointConstraints,
    reweight: bool,
    fit: impl FnMut(&[Vec3], Option<f64>) -> Result<Fitted<()>>,
) -> Result<fairfit::fit::point_constraints::ConstrainedFit<()>> {
    let t = PointConstraintTuning::default();
    fit_with_point_constraints(pts, pc, Held::default(), reweight, &t, fit)
}

#[test]
fn interpolated_points_lie_on_the_curve_within_1e_9_of_the_size() {
    let pts = ellipse(120, 2e-3);
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let pc = PointConstraints {
        weights: None,
        interpolate: vec![7, 40, 41, 90, 113],
    };
    for reweight in [false, true] {
        let r = run(&pts, &pc, reweight, lsq(tol)).unwrap();
        let plain = run(&pts, &PointConstraints::default(), false, lsq(tol)).unwrap();
        for &k in &pc.interpolate {
            let d = distance(&r.curve, pts[k]);
            assert!(d <= 1e-9 * size, "point {k}: {d:e} (reweight {reweight})");
            // the unconstrained fit does not pass through them: the constraint did the work
            assert!(distance(&plain.curve, pts[k]) > 1e3 * d.max(1e-15));
        }
        let worst = pts
            .iter()
            .map(|&q| distance(&r.curve, q))
            .fold(0.0, f64::max);
        assert!(worst <= tol * (1.0 + 1e-9), "{worst:e} > {tol:e}");
        assert_eq!(r.report.interpolated.len(), 5);
        assert!(r.report.interpolated.iter().all(|&(_, d)| d <= 1e-9 * size));
    }
}

#[test]
fn a_weight_2_point_is_held_to_half_the_tolerance() {
    let pts = ellipse(120, 2e-3);
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let plain = run(&pts, &PointConstraints::default(), false, lsq(tol)).unwrap();
    // the point the plain fit leaves farthest: beyond tol / 2 there
    let (k, d0) = pts
        .iter()
        .map(|&q| distance(&plain.curve, q))
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert!(d0 > 0.5 * tol, "{d0:e}");
    let mut w = vec![1.0; pts.len()];
    w[k] = 2.0;
    let pc = PointConstraints {
        weights: Some(w),
        interpolate: vec![],
    };
    for reweight in [true, false] {
        let r = run(&pts, &pc, reweight, lsq(tol)).unwrap();
        let d = distance(&r.curve, pts[k]);
        assert!(d <= 0.5 * tol * (1.0 + 1e-9), "{d:e} > {:e}", 0.5 * tol);
        for (i, &q) in pts.iter().enumerate() {
            assert!(distance(&r.curve, q) <= tol * (1.0 + 1e-9), "point {i}");
        }
        assert!(r.report.weighted_ratio <= 1.0 + 1e-9);
    }
}

#[test]
fn a_weight_0_point_gives_the_fit_without_it() {
    let pts = ellipse(80, 2e-3);
    let tol = 1e-3 * bounding_box_extent(&pts);
    let mut w = vec![1.0; pts.len()];
    w[33] = 0.0;
    let pc = PointConstraints {
        weights: Some(w),
        interpolate: vec![],
    };
    let r = run(&pts, &pc, true, lsq(tol)).unwrap();
    let mut deleted = pts.clone();
    deleted.remove(33);
    let d = run(&deleted, &PointConstraints::default(), true, lsq(tol)).unwrap();
    assert_eq!(r.curve, d.curve);
    assert_eq!(r.report.ignored, vec![33]);
}

#[test]
fn the_integrated_method_keeps_interpolated_points_and_weights() {
    let pts = ellipse(100, 1e-3);
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let mut w = vec![1.0; pts.len()];
    w[60] = 4.0;
    let pc = PointConstraints {
        weights: Some(w),
        interpolate: vec![25, 50],
    };
    let fit = |p: &[Vec3], t: Option<f64>| -> Result<Fitted<()>> {
        let opts = IntegratedOptions::new(Tolerance::Absolute(t.unwrap_or(tol))).degree(3);
        let r = fit_integrated(p, &opts)?;
        Ok(Fitted {
            curve: r.curve,
            tolerance: r.tolerance,
            max_deviation: r.quality.max_deviation,
            extra: (),
        })
    };
    let r = run(&pts, &pc, false, fit).unwrap();
    for k in [25, 50] {
        assert!(distance(&r.curve, pts[k]) <= 1e-9 * size);
    }
    assert!(distance(&r.curve, pts[60]) <= tol / 4.0 * (1.0 + 1e-9));
    assert!(pts
        .iter()
        .all(|&q| distance(&r.curve, q) <= tol * (1.0 + 1e-9)));
    // the end points stay where the method put them (held; the method's own ends are within
    // ~1e-11 of the data's, measured 7.8e-12 and 9.6e-12 here)
    let (a, b) = r.curve.domain();
    let (c0, c1) = (r.curve.point(a), r.curve.point(b));
    let gaps = ((c0 - pts[0]).norm(), (c1 - pts[99]).norm());
    assert!(gaps.0 < 1e-10 * size && gaps.1 < 1e-10 * size, "{gaps:?}");
}

#[test]
fn more_points_to_interpolate_than_the_curve_can_take_is_an_error_naming_them() {
    let pts = ellipse(40, 5e-3);
    let tol = 1e-2 * bounding_box_extent(&pts);
    // a method that always gives one cubic segment: 2 free control points
    let bezier = |p: &[Vec3], _t: Option<f64>| -> Result<Fitted<()>> {
        let u: Vec<f64> = (0..p.len())
            .map(|i| i as f64 / (p.len() - 1) as f64)
            .collect();
        let c = fit_fixed_knots(
            p,
            &u,
            3,
            &[0., 0., 0., 0., 1., 1., 1., 1.],
            &LsqOptions::default(),
        )?;
        Ok(Fitted {
            curve: c,
            tolerance: tol,
            max_deviation: 0.0,
            extra: (),
        })
    };
    let pc = PointConstraints {
        weights: None,
        interpolate: vec![5, 10, 15, 20, 25],
    };
    let e = run(&pts, &pc, false, bezier).unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidSetting {
                option: "interpolate",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn bad_weights_and_indices_are_refused_naming_the_constraint() {
    let n = 10;
    let cases: Vec<(PointConstraints, &str)> = vec![
        (
            PointConstraints {
                weights: Some(vec![-1.0; n]),
                interpolate: vec![],
            },
            "weights",
        ),
        (
            PointConstraints {
                weights: Some(vec![f64::NAN; n]),
                interpolate: vec![],
            },
            "weights",
        ),
        (
            PointConstraints {
                weights: Some(vec![0.0; n]),
                interpolate: vec![],
            },
            "weights",
        ),
        (
            PointConstraints {
                weights: Some(vec![1.0; n - 1]),
                interpolate: vec![],
            },
            "weights",
        ),
        (
            PointConstraints {
                weights: None,
                interpolate: vec![n],
            },
            "interpolate",
        ),
        (
            PointConstraints {
                weights: Some((0..n).map(|i| if i == 3 { 0.0 } else { 1.0 }).collect()),
                interpolate: vec![3],
            },
            "interpolate",
        ),
    ];
    for (pc, name) in cases {
        match pc.validate(n) {
            Err(Error::InvalidSetting { option, .. }) => assert_eq!(option, name, "{pc:?}"),
            other => panic!("{pc:?}: {other:?}"),
        }
    }
}

/// The least-squares data term `Σ w_k² |C(u_k) − Q_k|²` of control points `ctrl`.
fn data_term(knots: &[f64], ctrl: &[Vec3], pts: &[Vec3], u: &[f64], w: &[f64]) -> f64 {
    let c = NurbsCurve::bspline(3, knots.to_vec(), ctrl.to_vec()).unwrap();
    (0..pts.len())
        .map(|k| w[k] * w[k] * (c.point(u[k]) - pts[k]).norm_squared())
        .sum()
}

/// Points of `y = sin 3x` with a wobble, their uniform parameters and a clamped cubic knot vector
/// with 6 interior knots (10 control points).
fn wavy() -> (Vec<Vec3>, Vec<f64>, Vec<f64>) {
    let m = 80;
    let u: Vec<f64> = (0..m).map(|k| k as f64 / (m - 1) as f64).collect();
    let pts = u
        .iter()
        .map(|&x| Vec3::new(x, (3.0 * x).sin() + 0.01 * (41.0 * x).sin(), 0.0))
        .collect();
    let mut knots = vec![0.0; 4];
    knots.extend((1..=6).map(|i| i as f64 / 7.0));
    knots.extend([1.0; 4]);
    (pts, u, knots)
}

#[test]
fn a_weighted_solve_equals_the_solve_with_the_point_repeated_w_squared_times() {
    let (pts, u, knots) = wavy();
    let mut w = vec![1.0; pts.len()];
    w[30] = 2.0;
    w[61] = 3.0;
    let mut solver = LsqSolver::new(3);
    solver.set_point_terms(&w, &[]);
    let mut ctrl = Vec::new();
    solver
        .solve(&pts, &u, &knots, None, &LsqOptions::default(), &mut ctrl)
        .unwrap();
    // the independent truth: unweighted, with point k repeated w_k² times
    let (mut rp, mut ru) = (Vec::new(), Vec::new());
    for k in 0..pts.len() {
        for _ in 0..(w[k] * w[k]) as usize {
            rp.push(pts[k]);
            ru.push(u[k]);
        }
    }
    let mut plain = LsqSolver::new(3);
    let mut want = Vec::new();
    plain
        .solve(&rp, &ru, &knots, None, &LsqOptions::default(), &mut want)
        .unwrap();
    let worst = ctrl
        .iter()
        .zip(&want)
        .map(|(a, b)| (*a - *b).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst:e}");
    // and the weights changed the answer (by more than round-off)
    let mut unweighted = Vec::new();
    plain
        .solve(
            &pts,
            &u,
            &knots,
            None,
            &LsqOptions::default(),
            &mut unweighted,
        )
        .unwrap();
    assert!((ctrl[4] - unweighted[4]).norm() > 1e-5);
}

#[test]
fn interpolated_points_are_met_exactly_and_the_solve_is_optimal_under_them() {
    let (pts, u, knots) = wavy();
    let equal = [12, 40, 41, 70];
    let mut solver = LsqSolver::new(3);
    solver.set_point_terms(&[], &equal);
    let mut ctrl = Vec::new();
    solver
        .solve(&pts, &u, &knots, None, &LsqOptions::default(), &mut ctrl)
        .unwrap();
    let c = NurbsCurve::bspline(3, knots.clone(), ctrl.clone()).unwrap();
    for &k in &equal {
        let d = (c.point(u[k]) - pts[k]).norm();
        assert!(d < 1e-13, "point {k}: {d:e}");
    }
    // optimality on the equalities' null space, by finite differences: moving control point j
    // along x or y with the neighbours that keep every C(u_k) fixed changes the data term only at
    // second order. P_1 acts on u_12 only through span [0, 1/7): its move is balanced by P_2,
    // P_3 with the basis ratios at u_12; the direction here moves P_1 and P_2 so that
    // N_1(u_12) d_1 + N_2(u_12) d_2 = 0 (P_0 is fixed, P_3..P_4 unchanged).
    let w = vec![1.0; pts.len()];
    let f0 = data_term(&knots, &ctrl, &pts, &u, &w);
    let basis = |j: usize, t: f64| {
        let mut e = vec![Vec3::ZERO; ctrl.len()];
        e[j] = Vec3::new(1.0, 1.0, 0.0);
        NurbsCurve::bspline(3, knots.clone(), e).unwrap().point(t)[0]
    };
    let (n1, n2) = (basis(1, u[12]), basis(2, u[12]));
    assert!(n1 > 0.0 && n2 > 0.0);
    // P_2 also acts on u_40/u_41 if they lie in its support [0, 3/7): they do not (0.506, 0.519)
    assert!(u[40] > 3.0 / 7.0);
    let h = 1e-4;
    let mut plus = ctrl.clone();
    let mut minus = ctrl.clone();
    for (s, cp) in [(1.0, &mut plus), (-1.0, &mut minus)] {
        cp[1] += Vec3::new(0.0, s * h * n2, 0.0);
        cp[2] -= Vec3::new(0.0, s * h * n1, 0.0);
    }
    let c1 = NurbsCurve::bspline(3, knots.clone(), plus.clone()).unwrap();
    assert!((c1.point(u[12]) - pts[12]).norm() < 1e-13);
    let (fp, fm) = (
        data_term(&knots, &plus, &pts, &u, &w),
        data_term(&knots, &minus, &pts, &u, &w),
    );
    let slope = (fp - fm) / (2.0 * h);
    let curvature = (fp - 2.0 * f0 + fm) / (h * h);
    assert!(curvature > 0.0);
    // a stationary point: the slope is round-off against the curvature's scale
    assert!(
        slope.abs() < 1e-6 * curvature.max(1.0),
        "{slope:e} vs {curvature:e}"
    );
    // the unconstrained solve misses the points: the equalities did the work
    let mut plain = LsqSolver::new(3);
    let mut free = Vec::new();
    plain
        .solve(&pts, &u, &knots, None, &LsqOptions::default(), &mut free)
        .unwrap();
    let cf = NurbsCurve::bspline(3, knots.clone(), free).unwrap();
    assert!((cf.point(u[40]) - pts[40]).norm() > 1e-5);
}

#[test]
fn more_points_to_interpolate_than_a_span_has_unknowns_is_refused_naming_interpolate() {
    let (pts, u, _) = wavy();
    // one cubic segment: 2 unknown control points, 3 points to interpolate
    let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let mut solver = LsqSolver::new(3);
    solver.set_point_terms(&[], &[20, 40, 60]);
    let mut ctrl = Vec::new();
    let e = solver
        .solve(&pts, &u, &knots, None, &LsqOptions::default(), &mut ctrl)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidSetting {
                option: "interpolate",
                ..
            }
        ),
        "{e}"
    );
}

/// NACA 4412 (`examples/data`) with 4 points to interpolate, by the integrated method holding
/// them inside its search: no control point more than the unconstrained fit, no refit, F near
/// it, the points on the curve within 1e-9 of the size and every point within the tolerance.
#[test]
fn the_integrated_search_holds_interpolated_points_without_an_extra_control_point() {
    let pts = crate::common::example_data::read_csv("naca4412.csv");
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let pc = PointConstraints {
        weights: None,
        interpolate: vec![20, 34, 44, 64],
    };
    let fit = |p: &[Vec3], t: Option<f64>, inside: &PointConstraints| -> Result<Fitted<f64>> {
        let opts = IntegratedOptions::new(Tolerance::Absolute(t.unwrap_or(tol)))
            .point_constraints(inside.clone());
        let r = fit_integrated(p, &opts)?;
        Ok(Fitted {
            curve: r.curve,
            tolerance: r.tolerance,
            max_deviation: r.quality.max_deviation,
            extra: r.quality.fairness,
        })
    };
    let t = PointConstraintTuning::default();
    let plain = fit(&pts, None, &PointConstraints::default()).unwrap();
    let r = fit_with_point_constraints_inside(&pts, &pc, Held::default(), false, &t, fit).unwrap();
    let f = fairfit::fair::curve_fairness(&r.curve).fairness;
    let f0 = fairfit::fair::curve_fairness(&plain.curve).fairness;
    let (n, n0) = (r.curve.n_control_points(), plain.curve.n_control_points());
    eprintln!("interpolated: {n} control points, F {f:.4e}; unconstrained: {n0}, F {f0:.4e}");
    assert!(n <= n0, "{n} > {n0}");
    assert_eq!(r.report.refits, 0);
    // the exact move after the search is at most tol / 1000 long: F barely changes by it
    assert!(
        (f / r.extra - 1.0).abs() < 0.02,
        "{f:e} vs the search's {:e}",
        r.extra
    );
    // measured 1.47 (9 control points; the move-after-the-fit method had 11 and 1.52)
    assert!(f < 1.6 * f0, "{f:e} vs {f0:e}");
    for &k in &pc.interpolate {
        let d = distance(&r.curve, pts[k]);
        assert!(d <= 1e-9 * size, "point {k}: {d:e}");
    }
    let worst = pts
        .iter()
        .map(|&q| distance(&r.curve, q))
        .fold(0.0, f64::max);
    assert!(worst <= tol * (1.0 + 1e-9), "{worst:e}");
}

/// A weight-4 point is held to tol / 4 by the integrated search itself: its fit already has it
/// there (the move has nothing to do), at no control point more.
#[test]
fn the_integrated_search_holds_a_weighted_point_to_its_band() {
    let pts = crate::common::example_data::read_csv("naca4412.csv");
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let opts = IntegratedOptions::new(Tolerance::Absolute(tol));
    let plain = fit_integrated(&pts, &opts).unwrap();
    // the point the plain fit leaves farthest (beyond tol / 4)
    let (k, d0) = pts
        .iter()
        .map(|&q| distance(&plain.curve, q))
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert!(d0 > 0.25 * tol);
    let mut w = vec![1.0; pts.len()];
    w[k] = 4.0;
    let pc = PointConstraints {
        weights: Some(w),
        interpolate: vec![],
    };
    let r = fit_integrated(&pts, &opts.clone().point_constraints(pc)).unwrap();
    let d = distance(&r.curve, pts[k]);
    eprintln!(
        "point {k}: {d0:.3e} -> {d:.3e} (tol/4 {:.3e}); {} -> {} control points",
        0.25 * tol,
        plain.curve.n_control_points(),
        r.curve.n_control_points()
    );
    assert!(d <= 0.25 * tol * (1.0 + 1e-6), "{d:e}");
    assert!(r.curve.n_control_points() <= plain.curve.n_control_points() + 1);
    let worst = pts
        .iter()
        .map(|&q| distance(&r.curve, q))
        .fold(0.0, f64::max);
    assert!(worst <= tol * (1.0 + 1e-6), "{worst:e}");
}
