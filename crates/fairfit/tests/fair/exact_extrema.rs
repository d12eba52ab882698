//! The exact count of curvature extrema (`fair::exact_extrema`): closed-form curves, a wiggle
//! next to a knot that the measurer's 192 samples per span step over, and agreement with a very
//! dense sampling on fitted curves.

use fairfit::diffgeo::arc_length;
use fairfit::fair::exact_extrema::{
    count_extrema_exact, extremum_boundaries, sign_intervals, SignInterval,
};
use fairfit::fair::{count_extrema, count_extrema_sampled};
use fairfit::optim::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::{NurbsCurve, Vec3};

use crate::common::example_data;
use example_data::read_csv;

fn curve(p: usize, knots: &[f64], pts: &[(f64, f64)]) -> NurbsCurve {
    let ctrl = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
    NurbsCurve::bspline(p, knots.to_vec(), ctrl).unwrap()
}

fn intervals(c: &NurbsCurve) -> Vec<SignInterval> {
    let mut iv = Vec::new();
    sign_intervals(
        c.degree(),
        c.knots(),
        c.control_points(),
        Vec3::new(0.0, 0.0, 1.0),
        &mut iv,
    );
    iv
}

/// The parameters of the counted extrema (start of the interval after each sign change).
fn extremum_params(c: &NurbsCurve) -> Vec<f64> {
    let iv = intervals(c);
    extremum_boundaries(&iv, arc_length(c))
        .into_iter()
        .map(|k| iv[k].u0)
        .collect()
}

/// The Bézier cubic of the graph `y = x³`, `x = u` on `[a, b]` (blossoms of `u` and `u³`).
fn cubic_graph(a: f64, b: f64) -> NurbsCurve {
    let x = |u1: f64, u2: f64, u3: f64| (u1 + u2 + u3) / 3.0;
    let y = |u1: f64, u2: f64, u3: f64| u1 * u2 * u3;
    let pts: Vec<(f64, f64)> = [(a, a, a), (a, a, b), (a, b, b), (b, b, b)]
        .iter()
        .map(|&(p, q, r)| (x(p, q, r), y(p, q, r)))
        .collect();
    curve(3, &[a, a, a, a, b, b, b, b], &pts)
}

#[test]
fn the_extrema_of_y_equals_x_cubed_are_at_the_closed_form_roots() {
    // κ = 6x / (1 + 9x⁴)^{3/2}, dκ/dx ∝ 6 (1 + 9x⁴) − 324 x⁴ = 6 − 270 x⁴: extrema at
    // x = ±45^{−1/4} = ±0.38606…
    let r = 45f64.powf(-0.25);
    let c = cubic_graph(-1.0, 1.0);
    let at = extremum_params(&c);
    assert_eq!(at.len(), 2, "{at:?}");
    assert!(
        (at[0] + r).abs() < 1e-12 && (at[1] - r).abs() < 1e-12,
        "{at:?}"
    );
    let e = count_extrema_exact(&c, arc_length(&c));
    assert_eq!((e.curvature_extrema, e.exact), (2, true));
    // on [−1, 0.3] only the one at −45^{−1/4}
    let c = cubic_graph(-1.0, 0.3);
    let at = extremum_params(&c);
    assert_eq!(at.len(), 1);
    assert!((at[0] + r).abs() < 1e-12);
    // the same curve moved into a tilted plane and scaled by 1000: the same count
    let (ca, sa) = (0.6f64, 0.8f64);
    let moved: Vec<Vec3> = c
        .control_points()
        .iter()
        .map(|q| 1000.0 * Vec3::new(q.x(), ca * q.y(), sa * q.y()) + Vec3::new(5.0, -3.0, 7.0))
        .collect();
    let m = NurbsCurve::bspline(3, c.knots().to_vec(), moved).unwrap();
    let e = count_extrema_exact(&m, arc_length(&m));
    assert_eq!((e.curvature_extrema, e.exact), (1, true));
}

#[test]
fn a_parabola_as_a_quadratic_has_its_one_extremum_at_the_vertex() {
    // y = x² on [−1, 2] as one quadratic Bézier: κ = 2 / (1 + 4x²)^{3/2}, a maximum at x = 0
    let c = curve(
        2,
        &[-1., -1., -1., 2., 2., 2.],
        &[(-1., 1.), (0.5, -2.), (2., 4.)],
    );
    let at = extremum_params(&c);
    assert_eq!(at.len(), 1);
    assert!(at[0].abs() < 1e-12, "{at:?}");
}

/// The two-span C² cubic of the graph `y = g_i(u)`, `x = u` on `[−1, 1]` with the knot at 0:
/// `g₂(v) = 2.7v³ − 1.7v² + 0.7v` on `[0, 1]` and `g₁ = g₂ + 3v³` on `[−1, 0]` (C² at 0, `y'''`
/// jumps from 34.2 to 16.2).
fn near_knot_wiggle() -> NurbsCurve {
    let blossom = |a: f64, u: [f64; 3]| {
        let s3 = u[0] * u[1] * u[2];
        let s2 = (u[0] * u[1] + u[0] * u[2] + u[1] * u[2]) / 3.0;
        let s1 = (u[0] + u[1] + u[2]) / 3.0;
        (s1, a * s3 - 1.7 * s2 + 0.7 * s1)
    };
    let pts = [
        blossom(5.7, [-1., -1., -1.]),
        blossom(5.7, [-1., -1., 0.]),
        blossom(5.7, [-1., 0., 1.]),
        blossom(2.7, [0., 1., 1.]),
        blossom(2.7, [1., 1., 1.]),
    ];
    curve(3, &[-1., -1., -1., -1., 0., 1., 1., 1., 1.], &pts)
}

#[test]
fn a_wiggle_next_to_a_knot_that_192_samples_miss_is_counted() {
    let c = near_knot_wiggle();
    // the blossoms reproduce the two graph pieces (independent check of the construction)
    for &u in &[-0.7, -0.2, 0.3, 0.8] {
        let a = if u < 0.0 { 5.7 } else { 2.7 };
        let q = c.point(u);
        assert!((q.x() - u).abs() < 1e-14);
        assert!((q.y() - (a * u * u * u - 1.7 * u * u + 0.7 * u)).abs() < 1e-14);
    }
    // the truth from the closed form on a grid of 10⁶ cells per span: dκ/ds = N / (1 + y'²)³
    // with N = y''' (1 + y'²) − 3 y' y''², hysteresis floor 1e-6 of max |dκ/ds L²| (+1e-9)
    let l = arc_length(&c);
    let grid = 1_000_000;
    let mut sig = Vec::with_capacity(2 * grid);
    for (lo, a) in [(-1.0, 5.7), (0.0, 2.7)] {
        for i in 0..grid {
            let u: f64 = lo + (i as f64 + 0.5) / grid as f64;
            let (y1, y2, y3) = (3.0 * a * u * u - 3.4 * u + 0.7, 6.0 * a * u - 3.4, 6.0 * a);
            let w = 1.0 + y1 * y1;
            sig.push(l * l * (y3 * w - 3.0 * y1 * y2 * y2) / (w * w * w));
        }
    }
    let floor = 1e-6 * sig.iter().fold(0.0f64, |m, v| m.max(v.abs())) + 1e-9;
    let (mut last, mut truth, mut changes) = (0.0f64, 0, Vec::new());
    for (i, &v) in sig.iter().enumerate() {
        if v.abs() < floor {
            continue;
        }
        if last != 0.0 && (v > 0.0) != (last > 0.0) {
            truth += 1;
            changes.push(i);
        }
        last = v;
    }
    // the knot (dκ/ds > 0 on its left, < 0 on its right) and the root at u ≈ 5.07e-4 after it
    // (0.05 % of the span; the first of 192 midpoint samples is at 0.26 %), plus the others
    let root = changes
        .iter()
        .copied()
        .find(|&i| i > grid && i < grid + 1000)
        .map(|i| (i - grid) as f64 / grid as f64);
    assert!(changes.contains(&grid) && root.is_some(), "{changes:?}");
    let root = root.unwrap();
    let exact = count_extrema_exact(&c, l);
    assert!(exact.exact);
    assert_eq!(exact.curvature_extrema, truth);
    let at = extremum_params(&c);
    assert!(at.contains(&0.0), "{at:?}");
    assert!(at.iter().any(|&u| (u - root).abs() < 2e-6), "{at:?} {root}");
    // the measurer's 192 samples per span see neither sign change; 20 000 do
    assert_eq!(count_extrema(&c, l).curvature_extrema, truth - 2);
    assert_eq!(
        count_extrema_sampled(&c, l, 20_000).curvature_extrema,
        truth
    );
}

#[test]
fn on_fitted_curves_the_exact_count_is_the_count_at_20000_samples_per_span() {
    use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    let lsq = FitOptions::default();
    let mut seen = Vec::new();
    for name in [
        "naca4412.csv",
        "clarky.csv",
        "iea15mw_airfoils/FFA-W3-241.csv",
        "du84132v_noise1e-4.csv",
    ] {
        let pts = read_csv(name);
        // the least-squares fit (wiggly) and the integrated one
        for c in [
            fit_to_tolerance(&pts, &lsq).unwrap().curve,
            fit_integrated(&pts, &opts).unwrap().curve,
        ] {
            let l = arc_length(&c);
            let exact = count_extrema_exact(&c, l);
            let dense = count_extrema_sampled(&c, l, 20_000).curvature_extrema;
            let sampled = count_extrema(&c, l).curvature_extrema;
            eprintln!(
                "{name}: exact {} dense {dense} 192/span {sampled}",
                exact.curvature_extrema
            );
            assert!(exact.exact);
            assert_eq!(exact.curvature_extrema, dense, "{name}");
            assert!(exact.curvature_extrema >= sampled, "{name}");
            seen.push((exact.curvature_extrema, sampled));
        }
    }
    // the least-squares fits have many extrema (measured: naca4412 6, clarky 8, FFA-W3-241 9,
    // du84132v_noise1e-4 12; the integrated fits 1, 1, 1, 3)
    assert_eq!(seen.iter().map(|s| s.0).max(), Some(12), "{seen:?}");
}

#[test]
fn band_fairing_leaves_no_extrema_between_the_samples() {
    // the integrated method at --rel-tol 1e-3: band fairing's sign targets at both ends of every
    // span (BandOptions::edge_signs) and the guard's samples 1e-6 of a span from each knot leave
    // no sign flip next to a knot. Before (main bc6680f, the same fits): clarky 3 exact extrema
    // against 1 at the measurer's 192 samples per span, hq17 7 against 3, naca633418 2 against 1.
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    for (name, want) in [("clarky.csv", 1), ("hq17.csv", 3), ("naca633418.csv", 1)] {
        let c = fit_integrated(&read_csv(name), &opts).unwrap().curve;
        let l = arc_length(&c);
        let exact = count_extrema_exact(&c, l).curvature_extrema;
        let sampled = count_extrema(&c, l).curvature_extrema;
        eprintln!("{name}: exact {exact}, 192/span {sampled}");
        assert_eq!((exact, sampled), (want, want), "{name}");
    }
}
