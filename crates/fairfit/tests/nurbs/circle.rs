//! The exact rational quadratic circle and the same circle degree-elevated to cubic (and quartic):
//! |C − centre| = r to 1e-12 and κ = 1/r to 1e-10 at 1000 parameters; dκ/ds ≈ 0 inside spans.

use fairfit::diffgeo::{curvature, differentials};
use fairfit::nurbs::{NurbsCurve, Vec3};

fn check_circle(c: &NurbsCurve, centre: Vec3, r: f64) {
    for i in 0..1000 {
        let u = i as f64 / 999.0;
        let p = c.point(u);
        assert!(
            ((p - centre).norm() - r).abs() < 1e-12 * r.max(1.0),
            "u={u}"
        );
        assert!((p.z() - centre.z()).abs() < 1e-12 * r.max(1.0));
        let k = curvature(c, u);
        assert!((k - 1.0 / r).abs() < 1e-10 / r, "u={u} κ={k}");
    }
    // third derivatives only strictly inside spans
    for i in 0..200 {
        let u = 0.01
            + 0.2299 * (i % 4) as f64 / 4.0
            + 0.25 * (i / 50) as f64
            + 0.0011 * (i % 50) as f64 / 50.0;
        let d = differentials(c, u);
        assert!(
            d.dkappa_ds.abs() < 1e-8 / (r * r),
            "u={u} dκ/ds={}",
            d.dkappa_ds
        );
        assert!(d.torsion.abs() < 1e-8 / r);
    }
}

#[test]
fn rational_quadratic_circle_is_exact() {
    for &(centre, r) in &[
        (Vec3::ZERO, 1.0),
        (Vec3::new(3.0, -2.0, 7.5), 0.01),
        (Vec3::new(-1.0, 4.0, 0.0), 250.0),
    ] {
        check_circle(&NurbsCurve::circle(centre, r).unwrap(), centre, r);
    }
}

#[test]
fn elevated_circle_stays_exact() {
    for &(centre, r) in &[
        (Vec3::ZERO, 1.0),
        (Vec3::new(3.0, -2.0, 7.5), 0.01),
        (Vec3::new(-1.0, 4.0, 0.0), 250.0),
    ] {
        let c = NurbsCurve::circle(centre, r).unwrap();
        let cubic = c.elevate_degree(1).unwrap();
        assert_eq!(cubic.degree(), 3);
        assert_eq!(cubic.n_control_points(), 9 + 4);
        check_circle(&cubic, centre, r);
        check_circle(&c.elevate_degree(2).unwrap(), centre, r);
    }
}

#[test]
fn arc_matches_the_circle() {
    let c = NurbsCurve::arc(
        Vec3::new(1.0, 1.0, 0.0),
        2.0,
        0.3,
        0.3 + 2.0 * std::f64::consts::PI,
    )
    .unwrap();
    check_circle(&c, Vec3::new(1.0, 1.0, 0.0), 2.0);
    let a = NurbsCurve::arc(Vec3::ZERO, 1.0, 0.0, 1.0).unwrap();
    assert_eq!(a.n_control_points(), 3);
    let end = a.point(1.0);
    assert!((end - Vec3::new(1f64.cos(), 1f64.sin(), 0.0)).norm() < 1e-15);
    assert!(NurbsCurve::arc(Vec3::ZERO, 1.0, 1.0, 1.0).is_err());
    assert!(NurbsCurve::circle(Vec3::ZERO, -1.0).is_err());
}
