//! Knot insertion, refinement, degree elevation, clamping, reversal and reparametrisation keep the
//! geometry: 1000 sampled points agree to 1e-12 (relative to the control-net size), on random rational
//! curves (clamped and unclamped, with multiple knots) and surfaces.

use crate::common;
use common::*;
use fairfit::nurbs::{NurbsCurve, Vec3};
use rand::Rng;

const TOL: f64 = 1e-12;

#[test]
fn insertion_keeps_points() {
    let mut r = rng(1);
    for case in 0..60 {
        let p = 1 + case % 5;
        let c = random_curve(&mut r, p, p + 3 + case % 7, case % 2 == 0, p);
        let (a, b) = c.domain();
        let u = if case % 4 == 0 {
            c.knots()[p + 1].clamp(a, b)
        } else {
            r.random_range(a..b)
        };
        let s = c.knots().iter().filter(|&&k| k == u).count();
        if s >= p {
            assert!(c.insert_knot(u, 1).is_err());
            continue;
        }
        let times = r.random_range(1..=p - s);
        let d = c.insert_knot(u, times).unwrap();
        assert_eq!(d.n_control_points(), c.n_control_points() + times);
        assert_eq!(d.knots().iter().filter(|&&k| k == u).count(), s + times);
        let dev = max_deviation(&c, &d);
        assert!(dev < TOL * scale(&c), "case {case}: p={p} u={u} dev={dev}");
    }
}

#[test]
fn refinement_keeps_points() {
    let mut r = rng(2);
    for case in 0..60 {
        let p = 1 + case % 6;
        let c = random_curve(&mut r, p, p + 2 + case % 9, case % 3 != 0, 1);
        let (a, b) = c.domain();
        let mut x: Vec<f64> = (0..1 + case % 12)
            .map(|_| r.random_range(a..b))
            .filter(|&v| v > a)
            .collect();
        if p >= 2 && !x.is_empty() {
            x.push(x[0]); // a double knot
        }
        x.sort_by(f64::total_cmp);
        let d = c.refine_knots(&x).unwrap();
        assert_eq!(d.knots().len(), c.knots().len() + x.len());
        let dev = max_deviation(&c, &d);
        assert!(dev < TOL * scale(&c), "case {case}: p={p} dev={dev}");
        // same result as one insertion after another
        if let Some(&v) = x.first() {
            let e = c.insert_knot(v, 1).unwrap();
            assert!(max_deviation(&e, &d) < TOL * scale(&c));
        }
    }
}

#[test]
fn refinement_rejects_bad_knots() {
    let c = NurbsCurve::circle(Vec3::ZERO, 1.0).unwrap();
    assert!(c.refine_knots(&[0.0]).is_err());
    assert!(c.refine_knots(&[1.2]).is_err());
    assert!(c.refine_knots(&[f64::NAN]).is_err());
    assert!(c.refine_knots(&[0.5]).is_err()); // multiplicity 3 > 2
    assert!(c.refine_knots(&[0.4, 0.4, 0.4]).is_err());
    assert_eq!(c.refine_knots(&[]).unwrap(), c);
}

#[test]
fn degree_elevation_keeps_points() {
    let mut r = rng(3);
    for case in 0..60 {
        let p = 1 + case % 5;
        let n = p + 1 + case % 8;
        let c = random_curve(&mut r, p, n, case % 3 != 0, p);
        let t = 1 + case % 3;
        let d = c.elevate_degree(t).unwrap();
        assert_eq!(d.degree(), p + t);
        assert_eq!(d.domain(), c.domain());
        let dev = max_deviation(&c, &d);
        assert!(
            dev < TOL * scale(&c),
            "case {case}: p={p} t={t} dev={dev} knots {:?}",
            c.knots()
        );
        // control point count: n + t * (distinct spans) for clamped input
        if fairfit::nurbs::knots::is_clamped(c.knots(), p) {
            let spans = fairfit::nurbs::knots::distinct_breakpoints(c.knots(), p).len() - 1;
            assert_eq!(d.n_control_points(), n + t * spans, "case {case}");
        }
    }
}

#[test]
fn clamping_keeps_points_and_clamps() {
    let mut r = rng(4);
    for case in 0..40 {
        let p = 1 + case % 5;
        let c = random_curve(&mut r, p, p + 2 + case % 6, false, p);
        let d = c.clamped().unwrap();
        assert!(
            fairfit::nurbs::knots::is_clamped(d.knots(), p),
            "{:?}",
            d.knots()
        );
        assert_eq!(d.domain(), c.domain());
        assert!(max_deviation(&c, &d) < TOL * scale(&c), "case {case}");
        assert!((d.control_points()[0] - c.point(c.domain().0)).norm() < TOL * scale(&c));
    }
}

#[test]
fn reversal_mirrors_knots_and_keeps_points() {
    let mut r = rng(5);
    for case in 0..20 {
        let p = 1 + case % 5;
        let c = random_curve(&mut r, p, p + 4, case % 2 == 0, p);
        let rev = c.reversed();
        let (a, b) = c.domain();
        assert_eq!(rev.domain(), (a, b));
        let m = c.knots().len() - 1;
        for (i, k) in rev.knots().iter().enumerate() {
            assert!((k - (a + b - c.knots()[m - i])).abs() <= 1e-15 * (a.abs() + b.abs()));
        }
        for u in samples(a, b, 1000) {
            assert!((rev.point(a + b - u) - c.point(u)).norm() < TOL * scale(&c));
        }
        let back = rev.reversed();
        assert!(max_deviation(&c, &back) < TOL * scale(&c));
    }
}

#[test]
fn reparametrisation_maps_the_domain() {
    let mut r = rng(6);
    for case in 0..20 {
        let p = 1 + case % 4;
        let c = random_curve(&mut r, p, p + 5, case % 2 == 0, p);
        let d = c.reparametrized(0.0, 1.0).unwrap();
        assert_eq!(d.domain(), (0.0, 1.0));
        let (a, b) = c.domain();
        for t in samples(0.0, 1.0, 1000) {
            assert!((d.point(t) - c.point(a + t * (b - a))).norm() < TOL * scale(&c));
        }
        // first derivative scales by (b - a)
        let t = 0.377;
        let dd = d.derivatives(t, 1)[1];
        let dc = c.derivatives(a + t * (b - a), 1)[1] * (b - a);
        assert!((dd - dc).norm() < 1e-10 * dc.norm().max(1.0));
    }
    let c = NurbsCurve::circle(Vec3::ZERO, 1.0).unwrap();
    assert!(c.reparametrized(1.0, 1.0).is_err());
    assert!(c.reparametrized(0.0, f64::INFINITY).is_err());
}

#[test]
fn surface_refinement_elevation_and_iso_curves_keep_points() {
    let mut r = rng(7);
    for case in 0..16 {
        let (p, q) = (1 + case % 4, 1 + (case / 2) % 4);
        let s = random_surface(&mut r, p, q, p + 3, q + 2, case % 3 != 0);
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let xu: Vec<f64> = vec![u0 + 0.3 * (u1 - u0), u0 + 0.61 * (u1 - u0)];
        let xv: Vec<f64> = vec![v0 + 0.45 * (v1 - v0)];
        let variants = [
            s.refine_knots_u(&xu).unwrap(),
            s.refine_knots_v(&xv).unwrap(),
            s.elevate_degree_u(1 + case % 2).unwrap(),
            s.elevate_degree_v(2).unwrap(),
        ];
        let sc = s
            .control_points_flat()
            .iter()
            .fold(1.0f64, |m, p| m.max(p.max_abs()));
        let grid: Vec<(f64, f64)> = samples(u0, u1, 40)
            .into_iter()
            .flat_map(|u| samples(v0, v1, 25).into_iter().map(move |v| (u, v)))
            .collect();
        for (k, t) in variants.iter().enumerate() {
            for &(u, v) in &grid {
                let dev = (t.point(u, v) - s.point(u, v)).norm();
                assert!(dev < TOL * sc, "case {case} variant {k}: dev {dev}");
            }
        }
        for u in samples(u0, u1, 7) {
            let c = s.iso_curve_u(u).unwrap();
            for v in samples(v0, v1, 150) {
                assert!((c.point(v) - s.point(u, v)).norm() < TOL * sc);
            }
        }
        for v in samples(v0, v1, 7) {
            let c = s.iso_curve_v(v).unwrap();
            for u in samples(u0, u1, 150) {
                assert!((c.point(u) - s.point(u, v)).norm() < TOL * sc);
            }
        }
        assert!(s.iso_curve_u(u1 + 1.0).is_err());
    }
}

#[test]
fn absurd_requests_are_errors_not_panics() {
    let c = NurbsCurve::circle(Vec3::ZERO, 1.0).unwrap();
    assert!(c.insert_knot(0.3, usize::MAX).is_err());
    assert!(c.insert_knot(f64::INFINITY, 1).is_err());
    assert!(c.elevate_degree(usize::MAX).is_err());
    assert!(c.elevate_degree(39).is_err());
    assert_eq!(c.elevate_degree(38).unwrap().degree(), 40);
}

mod properties {
    //! Knot insertion as a property: on any random rational curve (degree 1-5, clamped or not, with
    //! multiple knots), inserting any parameter of the domain up to its free multiplicity adds exactly
    //! that many knots and control points and moves no point of the curve (1e-12 of the net's size).
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, rng_seed: proptest::test_runner::RngSeed::Fixed(0x00FA_1AF1), ..ProptestConfig::default() })]

        #[test]
        fn knot_insertion_is_exact(
            seed in any::<u64>(),
            p in 1usize..=5,
            extra in 0usize..8,
            clamped in any::<bool>(),
            at in 0.0f64..=1.0,
            on_a_knot in any::<bool>(),
            times in 1usize..=5,
        ) {
            let mut r = rng(seed);
            let c = random_curve(&mut r, p, p + 1 + extra, clamped, p);
            let (a, b) = c.domain();
            let u = if on_a_knot {
                // an existing knot of the domain (an interior one when there is one)
                let inside: Vec<f64> = c.knots().iter().copied().filter(|&k| a <= k && k <= b).collect();
                inside[((at * inside.len() as f64) as usize).min(inside.len() - 1)]
            } else {
                a + (b - a) * at
            };
            let s = c.knots().iter().filter(|&&k| k == u).count();
            prop_assume!(s < p);
            let times = times.min(p - s);
            let d = c.insert_knot(u, times).unwrap();
            prop_assert_eq!(d.n_control_points(), c.n_control_points() + times);
            prop_assert_eq!(d.knots().len(), c.knots().len() + times);
            prop_assert_eq!(d.knots().iter().filter(|&&k| k == u).count(), s + times);
            prop_assert_eq!(d.domain(), c.domain());
            let dev = max_deviation(&c, &d);
            prop_assert!(dev < TOL * scale(&c), "p={} u={} times={} dev={:e}", p, u, times, dev);
        }
    }
}
