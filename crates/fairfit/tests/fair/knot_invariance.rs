//! Exact knot operations keep the fairness measures: the circle elevated to cubic and quartic still has
//! F ≈ 0; reversal keeps F and mirrors the per-span F_j; refinement and elevation keep F (the per-span
//! quadrature sees the same geometry).

use crate::common;
use common::*;
use fairfit::fair::curve_fairness;
use fairfit::nurbs::{NurbsCurve, Vec3};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn elevated_circle_has_zero_fairness() {
    let c = NurbsCurve::circle(Vec3::new(2.0, 1.0, -1.0), 4.0).unwrap();
    for t in 0..=2 {
        let e = c.elevate_degree(t).unwrap();
        let f = curve_fairness(&e);
        assert!((f.length - 8.0 * std::f64::consts::PI).abs() < 1e-11 * f.length);
        assert!(f.fairness < 1e-12, "t={t}: F = {}", f.fairness);
    }
}

#[test]
fn reversal_refinement_and_elevation_keep_fairness() {
    let mut r = rng(31);
    for case in 0..12 {
        let p = 3 + case % 3;
        let c = random_curve(&mut r, p, p + 4, true, 1);
        let f = curve_fairness(&c);
        assert!(f.fairness > 0.0);
        let rev = curve_fairness(&c.reversed());
        assert!(
            rel(rev.fairness, f.fairness) < 1e-9,
            "case {case}: {} vs {}",
            rev.fairness,
            f.fairness
        );
        let mut mirrored = rev.span_fairness.clone();
        mirrored.reverse();
        for (a, b) in mirrored.iter().zip(&f.span_fairness) {
            assert!((a - b).abs() <= 1e-9 * f.fairness, "case {case}");
        }
        let (a, b) = c.domain();
        let refined = c
            .refine_knots(&[a + 0.37 * (b - a), a + 0.81 * (b - a)])
            .unwrap();
        let fr = curve_fairness(&refined);
        // the exact arc length is invariant under refinement to rounding
        let (la, lb) = (
            fairfit::diffgeo::arc_length(&c),
            fairfit::diffgeo::arc_length(&refined),
        );
        assert!(rel(la, lb) < 1e-12, "case {case}: length {la} vs {lb}");
        // the fairness summary's length comes from the energy's adaptive GK15 pass (about 1e-11)
        assert!(
            rel(fr.length, f.length) < 1e-10,
            "case {case}: length {} vs {}",
            fr.length,
            f.length
        );
        assert!(
            rel(fr.fairness, f.fairness) < 1e-6,
            "case {case}: {} vs {}",
            fr.fairness,
            f.fairness
        );
        let fe = curve_fairness(&c.elevate_degree(1).unwrap());
        assert!(
            rel(fe.fairness, f.fairness) < 1e-9,
            "case {case}: {} vs {}",
            fe.fairness,
            f.fairness
        );
    }
}
