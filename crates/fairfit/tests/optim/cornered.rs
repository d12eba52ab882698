//! Corners with a fixed control-point count (`fairfit::optim::cornered`): the joined count is
//! shared among the pieces between corners.

use fairfit::fit::tolerance::ClosedMode;
use fairfit::optim::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::{NurbsCurve, Vec3};

use crate::common::sampled;

fn read_csv(name: &str) -> Vec<Vec3> {
    let path = format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|s| s.trim().parse().ok()).collect();
            (v.len() >= 2).then(|| Vec3([v[0], v[1], v.get(2).copied().unwrap_or(0.0)]))
        })
        .collect()
}

fn opts() -> IntegratedOptions {
    IntegratedOptions::new(Tolerance::Relative(1e-3))
        .seed(3)
        // the blunt trailing edge is the closing chord: corners at both of its ends
        .closed(ClosedMode::Closed)
}

/// Parameters of the interior knots of multiplicity >= p (the C0 corners).
fn corner_knots(c: &NurbsCurve) -> Vec<f64> {
    let p = c.degree();
    let k = c.knots();
    let inner = &k[p + 1..k.len() - p - 1];
    let mut out: Vec<f64> = Vec::new();
    for w in inner.windows(p) {
        if w.iter().all(|&x| x == w[0]) && out.last() != Some(&w[0]) {
            out.push(w[0]);
        }
    }
    out
}

/// Largest distance from a point to the curve by dense sampling (independent of the fit).
fn brute_force_deviation(curve: &NurbsCurve, points: &[Vec3]) -> f64 {
    // 400 001 samples: the nearest sample overestimates a distance d by about (h/2)²/(2d), ~3e-9 here
    // (40 001 gave ~3e-7, more than the 1e-4 tol slack when a curve uses the whole band)
    sampled::brute_force_deviation_n(curve, points, 400_000)
}

#[test]
fn blunt_trailing_edge_with_a_fixed_count_keeps_its_corners_and_the_tolerance() {
    // fx77w343 closed: a 4.2 % blunt trailing edge, corners at both of its ends; the loop is cut
    // at the upper one (the curve's ends), the lower one is a C0 knot, the edge a straight piece
    let pts = read_csv("fx77w343.csv");
    let free = fit_integrated(&pts, &opts()).unwrap();
    let n = free.curve.n_control_points();
    let corners = corner_knots(&free.curve);
    assert_eq!(corners.len(), 1, "{:?}", free.curve.knots());
    let (a, b) = free.curve.domain();
    assert!((free.curve.point(a) - pts[0]).norm() < 1e-9);
    assert!((free.curve.point(b) - pts[0]).norm() < 1e-9);
    assert!((free.curve.point(corners[0]) - pts[pts.len() - 1]).norm() < 1e-9);
    assert!(free.met);
    // the default result's count reproduces the default curve
    let same = fit_integrated(&pts, &opts().control_points(n)).unwrap();
    assert_eq!(same.curve.n_control_points(), n);
    assert_eq!(same.curve.knots(), free.curve.knots());
    assert_eq!(same.curve.control_points(), free.curve.control_points());
    let dev = brute_force_deviation(&same.curve, &pts);
    assert!(same.met && dev <= same.tolerance * 1.0001, "{dev}");
    // more points: the exact count, the same corners, still within the tolerance
    let more = fit_integrated(&pts, &opts().control_points(n + 4)).unwrap();
    assert_eq!(more.curve.n_control_points(), n + 4);
    assert_eq!(corner_knots(&more.curve).len(), 1);
    let dev = brute_force_deviation(&more.curve, &pts);
    assert!(more.met && dev <= more.tolerance * 1.0001, "{dev}");
    eprintln!(
        "fx77w343: n={n} F {:.4e}; n+4 F {:.4e}",
        free.quality.fairness, more.quality.fairness
    );
    // too few for the two pieces (a cubic and the straight edge): an actionable error
    let e = fit_integrated(&pts, &opts().control_points(6))
        .unwrap_err()
        .to_string();
    assert!(e.contains("between 7 and"), "{e}");
}

#[test]
fn pareto_front_of_a_blunt_trailing_edge_keeps_its_corner_and_is_monotone() {
    use fairfit::optim::pareto_front_of_result;
    let pts = read_csv("fx77w343.csv");
    let r = fit_integrated(&pts, &opts()).unwrap();
    let front = pareto_front_of_result(&pts, &opts(), &r).unwrap();
    assert!(front.len() >= 3, "{} members", front.len());
    let corner = corner_knots(&r.curve);
    for w in front.windows(2) {
        assert!(w[0].quality.max_deviation < w[1].quality.max_deviation);
        assert!(w[0].quality.fairness > w[1].quality.fairness);
    }
    for m in &front {
        // every member: C0 at the lower trailing-edge corner, ends at the upper one
        let c = corner_knots(&m.curve);
        assert_eq!(c.len(), 1);
        assert!((m.curve.point(c[0]) - pts[pts.len() - 1]).norm() < 1e-9);
        let (a, b) = m.curve.domain();
        assert!((m.curve.point(a) - pts[0]).norm() < 1e-9);
        assert!((m.curve.point(b) - pts[0]).norm() < 1e-9);
        assert!(m.quality.max_deviation <= 10.0 * r.tolerance * 1.0001);
        // the reported F is the joined curve's own
        let f = fairfit::fair::curve_fairness(&m.curve).fairness;
        assert!((f - m.quality.fairness).abs() <= 1e-9 * f);
        // the deviation is real: dense sampling agrees
        let dev = brute_force_deviation(&m.curve, &pts);
        assert!(
            dev <= m.quality.max_deviation * 1.001 + 1e-12,
            "{dev} vs {:?}",
            m.quality
        );
    }
    assert_eq!(corner.len(), 1);
    eprintln!(
        "fx77w343 front: {} members, deviation {:.3e}..{:.3e}, F {:.3e}..{:.3e}",
        front.len(),
        front[0].quality.max_deviation,
        front[front.len() - 1].quality.max_deviation,
        front[0].quality.fairness,
        front[front.len() - 1].quality.fairness
    );
}

/// SNL-FFA-W3-500 (IEA 15 MW) starts and ends in the middle of its flatback, so fitted open its
/// first and last pieces up to the flatback's corners hold two points each: straight segments,
/// which cannot hold a tangent other than their own. Under tangent conditions along the flatback
/// the corners next to the ends are smoothed over and the fit holds both conditions within the
/// tolerance (it was refused: "too few points for a curve of their own").
#[test]
fn tangent_ends_at_straight_end_pieces_smooth_their_corners_over() {
    use fairfit::fit::end_constraints::{achieved, EndConstraint};
    let pts = read_csv("iea15mw_airfoils/SNL-FFA-W3-500.csv");
    let up = EndConstraint::tangent(Vec3::new(0.0, 1.0, 0.0));
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3))
        .closed(ClosedMode::Open)
        .start(up)
        .end(up);
    let r = fit_integrated(&pts, &opts).unwrap();
    let dev = brute_force_deviation(&r.curve, &pts);
    eprintln!(
        "SNL-FFA-W3-500 open, G1 ends: {} control points, F {:.3e}, max dev {dev:.3e} (tol {:.3e})",
        r.curve.n_control_points(),
        r.quality.fairness,
        r.tolerance
    );
    assert!(r.met && dev <= r.tolerance * 1.0001, "{dev}");
    for at_end in [false, true] {
        let a = achieved(&r.curve, at_end, &up);
        assert!(a.tangent_angle <= 1e-9, "{a:?}");
    }
    // the ends stay on the data's end points, and no corner is left next to them
    let (a, b) = r.curve.domain();
    assert!((r.curve.point(a) - pts[0]).norm() < 1e-9);
    assert!((r.curve.point(b) - pts[pts.len() - 1]).norm() < 1e-9);
    assert!(corner_knots(&r.curve).is_empty(), "{:?}", r.curve.knots());
}
