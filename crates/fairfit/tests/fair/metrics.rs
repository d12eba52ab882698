//! Fairness metrics against independent truths: the exact rational circle, invariance under similarity
//! transforms and reversal, additivity of F_j, an independent finite-difference computation of F, and
//! extremum/inflection counts on curves whose curvature is known in closed form.

use fairfit::diffgeo::quadrature::GaussLegendre;
use fairfit::diffgeo::{arc_length, differentials};
use fairfit::fair::{curve_fairness, EvaluatorOptions, FairnessEvaluator};
use fairfit::nurbs::knots::uniform_clamped;
use fairfit::nurbs::{NurbsCurve, Vec3};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

fn circle(centre: Vec3, r: f64) -> NurbsCurve {
    let h = FRAC_1_SQRT_2;
    let corners = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
    ];
    let pts = corners
        .iter()
        .map(|&(x, y)| centre + Vec3::new(r * x, r * y, 0.0))
        .collect();
    let knots = vec![
        0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
    ];
    let w = vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0];
    NurbsCurve::new(2, knots, pts, Some(w)).unwrap()
}

fn s_curve() -> NurbsCurve {
    let pts = [
        (0.0, 0.0),
        (1.0, 1.5),
        (2.5, 2.0),
        (3.5, 0.5),
        (4.5, -1.0),
        (6.0, -1.2),
        (7.0, 0.3),
    ]
    .iter()
    .map(|&(x, y)| Vec3::new(x, y, 0.0))
    .collect();
    NurbsCurve::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.7, 1.0, 1.0, 1.0, 1.0],
        pts,
        Some(vec![1.0, 0.8, 1.3, 1.0, 0.7, 1.1, 1.0]),
    )
    .unwrap()
}

fn spatial_curve() -> NurbsCurve {
    let pts = (0..9)
        .map(|i| {
            let t = i as f64 * 0.7;
            Vec3::new(t.cos() * (1.0 + 0.1 * t), t.sin(), 0.3 * t + 0.05 * t * t)
        })
        .collect();
    NurbsCurve::new(
        3,
        uniform_clamped(3, 9),
        pts,
        Some(vec![1.0, 1.2, 0.9, 1.0, 1.1, 0.8, 1.0, 1.3, 1.0]),
    )
    .unwrap()
}

fn map_points(c: &NurbsCurve, f: impl Fn(Vec3) -> Vec3) -> NurbsCurve {
    let pts = c.control_points().iter().map(|&p| f(p)).collect();
    NurbsCurve::new(
        c.degree(),
        c.knots().to_vec(),
        pts,
        Some(c.weights().to_vec()),
    )
    .unwrap()
}

/// Rotation about the unit axis `k` by `angle` (Rodrigues).
fn rotate(p: Vec3, k: Vec3, angle: f64) -> Vec3 {
    let (s, c) = angle.sin_cos();
    p * c + k.cross(p) * s + k * (k.dot(p) * (1.0 - c))
}

fn reversed(c: &NurbsCurve) -> NurbsCurve {
    let (a, b) = c.domain();
    let knots: Vec<f64> = c.knots().iter().rev().map(|&u| a + b - u).collect();
    let pts: Vec<Vec3> = c.control_points().iter().rev().copied().collect();
    let w: Vec<f64> = c.weights().iter().rev().copied().collect();
    NurbsCurve::new(c.degree(), knots, pts, Some(w)).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs())
}

#[test]
fn exact_circle_has_constant_curvature_and_zero_energy() {
    let r = 3.0;
    let c = circle(Vec3::new(1.0, -2.0, 0.5), r);
    for k in 0..=400 {
        let u = k as f64 / 400.0;
        let g = differentials(&c, u);
        assert!(
            (g.curvature - 1.0 / r).abs() < 1e-10,
            "u={u}: {}",
            g.curvature
        );
        assert!((g.signed_curvature - 1.0 / r).abs() < 1e-10);
    }
    let f = curve_fairness(&c);
    assert!((f.length - 2.0 * PI * r).abs() < 1e-11 * f.length);
    // E ≈ 0 relative to the natural scale 1/L³ of the energy: F = L³ E
    assert!(f.fairness < 1e-12, "F = {}", f.fairness);
    assert!(f.energy * f.length.powi(3) < 1e-12);
    // bending energy of a full circle: ∫ κ² ds = 2π/r
    assert!((f.bending_energy - 2.0 * PI / r).abs() < 1e-11);
    assert_eq!(f.span_fairness.len(), 4);
    assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
}

#[test]
fn degree_elevated_circle_is_still_perfectly_fair() {
    // elevated to cubic and quartic: C''' no longer vanishes, κ stays 1/r, so E ≈ 0
    let r = 0.7;
    let c = circle(Vec3::new(0.0, 3.0, -1.0), r);
    for t in 1..=2 {
        let e = c.elevate_degree(t).unwrap();
        let f = curve_fairness(&e);
        assert!(
            f.fairness < 1e-12,
            "degree {}: F = {}",
            e.degree(),
            f.fairness
        );
        assert!((f.length - 2.0 * PI * r).abs() < 1e-11);
        assert!((f.bending_energy - 2.0 * PI / r).abs() < 1e-10);
        assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
    }
}

#[test]
fn fairness_invariant_under_scaling_rotation_translation() {
    for c in [s_curve(), spatial_curve()] {
        let f0 = curve_fairness(&c);
        assert!(f0.fairness > 1e-3);
        let axis = Vec3::new(1.0, -2.0, 0.5) / Vec3::new(1.0, -2.0, 0.5).norm();
        let variants = [
            map_points(&c, |p| p * 1000.0),
            map_points(&c, |p| rotate(p, axis, 0.9)),
            map_points(&c, |p| p + Vec3::new(123.0, -45.6, 7.8)),
            map_points(&c, |p| {
                rotate(p, axis, -2.1) * 1e-3 + Vec3::new(-5.0, 2.0, 1.0)
            }),
        ];
        for (i, v) in variants.iter().enumerate() {
            let f = curve_fairness(v);
            assert!(
                rel(f.fairness, f0.fairness) < 1e-9,
                "variant {i}: {} vs {}",
                f.fairness,
                f0.fairness
            );
            assert!(rel(f.max_span_fairness, f0.max_span_fairness) < 1e-9);
            for (a, b) in f.span_fairness.iter().zip(&f0.span_fairness) {
                assert!((a - b).abs() <= 1e-9 * f0.fairness);
            }
            assert_eq!(f.curvature_extrema, f0.curvature_extrema, "variant {i}");
            assert_eq!(f.inflections, f0.inflections, "variant {i}");
        }
        // scaling by λ: E → λ⁻³ E, bending → λ⁻¹ bending
        let f = curve_fairness(&variants[0]);
        assert!(rel(f.energy * 1e9, f0.energy) < 1e-9);
        assert!(rel(f.bending_energy * 1e3, f0.bending_energy) < 1e-9);
    }
}

#[test]
fn reversal_keeps_points_and_fairness_and_mirrors_span_fairness() {
    for c in [s_curve(), spatial_curve()] {
        let r = reversed(&c);
        let (a, b) = c.domain();
        for k in 0..=200 {
            let u = a + (b - a) * k as f64 / 200.0;
            assert!((c.point(u) - r.point(a + b - u)).norm() < 1e-12);
        }
        let f = curve_fairness(&c);
        let g = curve_fairness(&r);
        assert!(rel(f.fairness, g.fairness) < 1e-9);
        assert!(rel(f.length, g.length) < 1e-12);
        let n = f.span_fairness.len();
        for j in 0..n {
            assert!((f.span_fairness[j] - g.span_fairness[n - 1 - j]).abs() <= 1e-9 * f.fairness);
        }
        assert_eq!(f.curvature_extrema, g.curvature_extrema);
        assert_eq!(f.inflections, g.inflections);
    }
}

#[test]
fn span_fairness_sums_to_fairness_and_evaluator_agrees() {
    let mut ev = FairnessEvaluator::new();
    let mut fj = Vec::new();
    for c in [s_curve(), spatial_curve(), circle(Vec3::ZERO, 1.0)] {
        let f = curve_fairness(&c);
        let sum: f64 = f.span_fairness.iter().sum();
        assert!((sum - f.fairness).abs() <= 1e-14 * f.fairness.max(1e-300));
        let (ff, fmax) = ev.evaluate(&c);
        assert_eq!(ff, f.fairness);
        assert_eq!(fmax, f.max_span_fairness);
        let f2 = ev.span_fairness_into(&c, &mut fj);
        assert_eq!(f2, f.fairness);
        assert_eq!(fj, f.span_fairness);
        assert!((f.length - arc_length(&c)).abs() < 1e-10 * f.length);
    }
}

/// F by an independent route: κ(u) from first and second derivatives only, dκ/du by 6th-order central
/// differences of κ, and composite 20-point Gauss–Legendre on 20 sub-intervals of each span.
fn fairness_by_finite_differences(c: &NurbsCurve, planar: bool) -> f64 {
    let kappa = |u: f64| {
        let d = c.derivatives(u, 2);
        let v = d[1].norm();
        if planar {
            (d[1].x() * d[2].y() - d[1].y() * d[2].x()) / v.powi(3)
        } else {
            d[1].cross(d[2]).norm() / v.powi(3)
        }
    };
    let breaks = fairfit::nurbs::knots::distinct_breakpoints(c.knots(), c.degree());
    let gl = GaussLegendre::new(20);
    let (mut len, mut e) = (0.0, 0.0);
    for w in breaks.windows(2) {
        let m = 20; // sub-intervals per span, 20 Gauss nodes each, all well inside the span
        let sub = (w[1] - w[0]) / m as f64;
        let h = 2e-4 * sub;
        for k in 0..m {
            let a = w[0] + k as f64 * sub;
            len += gl.integrate(a, a + sub, |u| c.derivatives(u, 1)[1].norm());
            e += gl.integrate(a, a + sub, |u| {
                let dk = (-kappa(u - 3.0 * h) + 9.0 * kappa(u - 2.0 * h) - 45.0 * kappa(u - h)
                    + 45.0 * kappa(u + h)
                    - 9.0 * kappa(u + 2.0 * h)
                    + kappa(u + 3.0 * h))
                    / (60.0 * h);
                dk * dk / c.derivatives(u, 1)[1].norm()
            });
        }
    }
    len.powi(3) * e
}

#[test]
fn fairness_matches_independent_finite_difference_computation() {
    let planar = s_curve();
    let f = curve_fairness(&planar).fairness;
    let fd = fairness_by_finite_differences(&planar, true);
    assert!(rel(f, fd) < 1e-8, "{f} vs {fd}");
    let spatial = spatial_curve();
    let f = curve_fairness(&spatial).fairness;
    let fd = fairness_by_finite_differences(&spatial, false);
    assert!(rel(f, fd) < 1e-8, "{f} vs {fd}");
}

#[test]
fn parabola_fairness_matches_closed_form() {
    // y = x² on [0, 1]: κ = 2/(1+4x²)^{3/2}, ds = sqrt(1+4x²) dx,
    // dκ/ds = -24x/(1+4x²)^3, so E = ∫_0^1 576 x² (1+4x²)^{-11/2} dx (Simpson, fine grid, below)
    let c = NurbsCurve::bspline(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ],
    )
    .unwrap();
    let n = 20000;
    let h = 1.0 / n as f64;
    let (mut e, mut l) = (0.0, 0.0);
    for i in 0..=n {
        let x = i as f64 * h;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let q = 1.0 + 4.0 * x * x;
        e += w * h / 3.0 * 576.0 * x * x * q.powf(-5.5);
        l += w * h / 3.0 * q.sqrt();
    }
    let f = curve_fairness(&c);
    assert!(rel(f.length, l) < 1e-12);
    assert!(rel(f.energy, e) < 1e-10, "{} vs {e}", f.energy);
    // κ decreases monotonically from the vertex: no interior extremum, no inflection
    assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
}

#[test]
fn cubic_graph_s_curve_counts() {
    // Bézier (0,0),(1,1),(2,-1),(3,0) is the graph y = f(x) = (x/3)(1-x/3)(2-2x/3)·3 ... with x = 3t,
    // y = 3t(1-t)(1-2t). κ_s = y''/(1+y'²)^{3/2} with y'' ∝ (2t - 1) in t: one inflection at t = 1/2.
    // κ_s is odd about t = 1/2 and has one maximum and one minimum: two extrema.
    let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, -1.0), (3.0, 0.0)]
        .iter()
        .map(|&(x, y)| Vec3::new(x, y, 0.0))
        .collect();
    let c = NurbsCurve::bspline(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], pts).unwrap();
    let f = curve_fairness(&c);
    assert_eq!(f.inflections, 1);
    assert_eq!(f.curvature_extrema, 2);
    // the same curve tilted out of the xy plane is still planar: same counts and F
    let axis = Vec3::new(0.3, 1.0, 0.2) / Vec3::new(0.3, 1.0, 0.2).norm();
    let t = map_points(&c, |p| rotate(p, axis, 0.7));
    let g = curve_fairness(&t);
    assert_eq!(g.inflections, 1);
    assert_eq!(g.curvature_extrema, 2);
    assert!(rel(g.fairness, f.fairness) < 1e-9);
}

#[test]
fn lines_are_perfectly_fair() {
    let pts: Vec<Vec3> = (0..6)
        .map(|i| Vec3::new(i as f64 * 0.3, i as f64 * -0.7, 2.0))
        .collect();
    let c = NurbsCurve::bspline(3, uniform_clamped(3, 6), pts).unwrap();
    let f = curve_fairness(&c);
    assert!(f.fairness < 1e-20, "{}", f.fairness);
    assert!(f.bending_energy * f.length < 1e-20);
    assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
    assert!((f.length - 5.0 * (0.09f64 + 0.49).sqrt()).abs() < 1e-12);
}

/// Bézier control points of the polynomial curve `Σ_k coeffs[k] t^k` on `[0, 1]` (power → Bernstein).
fn bezier_from_power(coeffs: &[Vec3]) -> Vec<Vec3> {
    let n = coeffs.len() - 1;
    let binom = |n: usize, k: usize| -> f64 {
        (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    };
    (0..=n)
        .map(|i| {
            let mut b = Vec3::ZERO;
            for (k, c) in coeffs.iter().enumerate().take(i + 1) {
                b += *c * (binom(i, k) / binom(n, k));
            }
            b
        })
        .collect()
}

#[test]
fn spatial_curve_through_zero_curvature_is_integrated_accurately() {
    // C(t) = (t, (t-a)³, (t-a)⁴): C' × C'' = (12s⁴, -12s², 6s) with s = t - a vanishes at t = a only,
    // where the unsigned κ has a kink (|dκ/du| → 6 from both sides); the adaptive rule must resolve it.
    let a: f64 = 0.37;
    // expand (t-a)³ and (t-a)⁴ in powers of t
    let y = [-a * a * a, 3.0 * a * a, -3.0 * a, 1.0, 0.0];
    let z = [a.powi(4), -4.0 * a.powi(3), 6.0 * a * a, -4.0 * a, 1.0];
    let coeffs: Vec<Vec3> = (0..5)
        .map(|k| Vec3::new(if k == 1 { 1.0 } else { 0.0 }, y[k], z[k]))
        .collect();
    let pts = bezier_from_power(&coeffs);
    let c = NurbsCurve::bspline(
        4,
        vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0],
        pts,
    )
    .unwrap();
    for &t in &[0.0, 0.2, 0.37, 0.9] {
        let s: f64 = t - a;
        assert!((c.point(t) - Vec3::new(t, s.powi(3), s.powi(4))).norm() < 1e-14);
    }
    let f = curve_fairness(&c);
    // reference on [0, a] and [a, 1] separately (kink at the junction), as in the FD helper
    // the same curve with a knot of full multiplicity at a (exact split)
    let split = c.insert_knot(a, 4).unwrap();
    assert_eq!(split.knots().iter().filter(|&&k| k == a).count(), 4);
    let fd = fairness_by_finite_differences(&split, false);
    assert!(rel(f.fairness, fd) < 1e-8, "{} vs {fd}", f.fairness);
    assert_eq!(f.inflections, 1);
    // without bisection a single Gauss–Kronrod rule over the kink is visibly worse
    let mut plain = FairnessEvaluator::with_options(EvaluatorOptions {
        max_depth: 0,
        ..EvaluatorOptions::default()
    });
    let f0 = plain.evaluate(&c).0;
    assert!(rel(f0, fd) > 1e-6, "{f0} vs {fd}");
}

#[test]
fn degenerate_curves_give_finite_zero_measures() {
    // every control point equal: zero length, nothing to measure, no NaN
    let p = Vec3::new(1.0, 2.0, 3.0);
    let c = NurbsCurve::bspline(3, uniform_clamped(3, 5), vec![p; 5]).unwrap();
    let f = curve_fairness(&c);
    assert!(f.length < 1e-12);
    assert_eq!(f.fairness, 0.0);
    assert_eq!(f.bending_energy, 0.0);
    assert_eq!(f.max_span_fairness, 0.0);
    assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
    // degree 1 and 2: C''' = 0 inside spans; a polyline is straight inside each span
    let poly = NurbsCurve::bspline(
        1,
        vec![0.0, 0.0, 0.5, 1.0, 1.0],
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
            Vec3::new(3.0, 10.0, 0.0),
        ],
    )
    .unwrap();
    let f = curve_fairness(&poly);
    assert!((f.length - 11.0).abs() < 1e-12);
    assert_eq!(f.fairness, 0.0);
    assert_eq!(f.span_fairness.len(), 2);
}

#[test]
fn coordinates_near_the_ends_of_the_f64_range_are_measured_exactly_rescaled() {
    // without rescaling, |C'|³ and |C' × C''|² over- or underflow at 1e±160 and the measures became 0
    let c = s_curve();
    let f0 = curve_fairness(&c);
    let d0 = differentials(&c, 0.3);
    for s in [1e-300, 1e-160, 1e160, 1e300] {
        let cs = map_points(&c, |p| p * s);
        let f = curve_fairness(&cs);
        assert!(rel(f.fairness, f0.fairness) < 1e-12, "{s}: {}", f.fairness);
        assert!(rel(f.max_span_fairness, f0.max_span_fairness) < 1e-12);
        assert!(rel(f.length, f0.length * s) < 1e-12, "{s}: {}", f.length);
        assert!(rel(f.bending_energy, f0.bending_energy / s) < 1e-12);
        assert_eq!(
            (f.curvature_extrema, f.inflections),
            (f0.curvature_extrema, f0.inflections)
        );
        // E = F / L³ is 1e±900 here: beyond f64, so infinite or zero, never NaN
        assert!(!f.energy.is_nan());
        let d = differentials(&cs, 0.3);
        assert!(
            rel(d.curvature, d0.curvature / s) < 1e-12,
            "{s}: {}",
            d.curvature
        );
        assert!(rel(d.signed_curvature, d0.signed_curvature / s) < 1e-12);
        assert!(rel(d.speed, d0.speed * s) < 1e-12);
        assert!(!d.dkappa_ds.is_nan() && !d.torsion.is_nan());
    }
    // at 1e-100 every measure is representable: dκ/ds scales as 1/s², E as 1/s³
    let cs = map_points(&c, |p| p * 1e-100);
    let d = differentials(&cs, 0.3);
    assert!(
        rel(d.dkappa_ds, d0.dkappa_ds * 1e200) < 1e-12,
        "{}",
        d.dkappa_ds
    );
    let f = curve_fairness(&cs);
    assert!(rel(f.energy, f0.energy * 1e300) < 1e-12, "{}", f.energy);
}

mod properties {
    //! F's invariance as a property: on random cubic and quartic curves (rational or not), F, every
    //! F_j and the largest F_j are unchanged (1e-9 relative) under any scaling by 10^-3..10^3, any
    //! rotation and any translation (up to 100 sizes of the curve), while E scales as λ⁻³ and the bending energy as λ⁻¹.
    use super::*;
    use proptest::prelude::*;
    use rand::{Rng, SeedableRng};

    /// A regular random curve: control points advancing along x (so the speed never vanishes on a
    /// polynomial curve) with random offsets in y and z; mild random weights when `rational`.
    fn random_regular_curve(seed: u64, p: usize, n: usize, rational: bool) -> NurbsCurve {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let pts: Vec<Vec3> = (0..n)
            .map(|i| {
                Vec3::new(
                    i as f64 + r.random_range(-0.3..0.3),
                    r.random_range(-1.5..1.5),
                    r.random_range(-0.5..0.5),
                )
            })
            .collect();
        let w = rational.then(|| (0..n).map(|_| r.random_range(0.8..1.25)).collect());
        NurbsCurve::new(p, uniform_clamped(p, n), pts, w).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, failure_persistence: None, rng_seed: proptest::test_runner::RngSeed::Fixed(0x00FA_1AF1), ..ProptestConfig::default() })]

        #[test]
        fn fairness_is_invariant_under_scale_rotation_and_translation(
            seed in any::<u64>(),
            p in 3usize..=4,
            extra in 1usize..8,
            rational in any::<bool>(),
            log_scale in -3.0f64..3.0,
            axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            angle in -PI..PI,
            shift in (-100.0f64..100.0, -100.0f64..100.0, -100.0f64..100.0),
        ) {
            let c = random_regular_curve(seed, p, p + 1 + extra, rational);
            let k = Vec3::new(axis.0, axis.1, axis.2);
            prop_assume!(k.norm() > 0.1);
            let k = k / k.norm();
            let lambda = 10f64.powf(log_scale);
            // a shift of up to 100 sizes of the scaled curve: coordinates keep their relative
            // precision (a shift of 100 absolute on a curve scaled to 1e-3 would cost 1e5 ulps)
            let t = Vec3::new(shift.0, shift.1, shift.2) * lambda;
            let m = map_points(&c, |q| rotate(q, k, angle) * lambda + t);
            let (f0, f) = (curve_fairness(&c), curve_fairness(&m));
            prop_assume!(f0.fairness > 1e-6);
            prop_assert!(rel(f.fairness, f0.fairness) < 1e-9, "F {:e} vs {:e}", f.fairness, f0.fairness);
            prop_assert!(rel(f.max_span_fairness, f0.max_span_fairness) < 1e-9);
            prop_assert_eq!(f.span_fairness.len(), f0.span_fairness.len());
            for (a, b) in f.span_fairness.iter().zip(&f0.span_fairness) {
                prop_assert!((a - b).abs() <= 1e-9 * f0.fairness, "F_j {:e} vs {:e}", a, b);
            }
            prop_assert!(rel(f.length, lambda * f0.length) < 1e-12);
            prop_assert!(rel(f.energy * lambda.powi(3), f0.energy) < 1e-9);
            prop_assert!(rel(f.bending_energy * lambda, f0.bending_energy) < 1e-9);
        }
    }
}
