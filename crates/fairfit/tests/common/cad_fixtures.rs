//! Geometry shared by the CAD file tests (`cad_read`, `cad_roundtrip`, `cad_exact_fit`, `cad_skin`):
//! a rational space cubic and a rational surface, both with non-uniform knots and weights, and the
//! wiggly space cubic of the CLI tests, sized in millimetres.
#![allow(dead_code)] // each test file uses some of them

use fairfit::{NurbsCurve, NurbsSurface, Vec3};

/// A rational cubic with 6 control points, interior knots 0.3 and 0.55, weights 0.6-1.3.
pub fn rational_curve() -> NurbsCurve {
    let pts = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(12.5, 30.0, 1.0),
        Vec3::new(40.0, 35.0, -2.0),
        Vec3::new(70.0, 5.0, 3.0),
        Vec3::new(95.0, 20.0, 0.5),
        Vec3::new(120.0, 60.0, 8.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.55, 1.0, 1.0, 1.0, 1.0];
    NurbsCurve::new(3, knots, pts, Some(vec![1.0, 0.8, 1.3, 1.0, 0.6, 1.0])).unwrap()
}

/// A rational surface, cubic in u (6 columns, interior knots 0.35 and 0.7) and of degree
/// `degree_v` in v (one interior knot 0.5, so `degree_v + 2` rows), weights 1.0-1.4.
pub fn rational_surface(degree_v: usize) -> NurbsSurface {
    let ku = vec![0.0, 0.0, 0.0, 0.0, 0.35, 0.7, 1.0, 1.0, 1.0, 1.0];
    let mut kv = vec![0.0; degree_v + 1];
    kv.push(0.5);
    kv.extend(std::iter::repeat_n(1.0, degree_v + 1));
    let n_v = degree_v + 2;
    let net = (0..6)
        .map(|i| {
            (0..n_v)
                .map(|j| {
                    let (x, y) = (i as f64 * 20.0, j as f64 * 15.0);
                    Vec3::new(x + 0.1 * y, y, 8.0 * (x / 50.0).sin() * (y / 40.0).cos())
                })
                .collect()
        })
        .collect();
    let w = (0..6)
        .map(|i| (0..n_v).map(|j| 1.0 + 0.2 * ((i + j) % 3) as f64).collect())
        .collect();
    NurbsSurface::new(3, degree_v, ku, kv, net, Some(w)).unwrap()
}

/// The wiggly spatial cubic of the CLI tests (7 poles, a double interior knot), scaled by `s` about
/// the origin and lifted to height `z`, in mm.
pub fn wiggly(s: f64, z: f64) -> NurbsCurve {
    let pts = [
        [0.0, 0.0, 0.0],
        [10.0, 25.0, 2.0],
        [30.0, 32.0, -4.0],
        [55.0, 5.0, 3.0],
        [70.0, -10.0, 0.0],
        [90.0, 15.0, 6.0],
        [110.0, 30.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::new(s * p[0], s * p[1], s * p[2] + z))
    .collect();
    NurbsCurve::bspline(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.45, 1.0, 1.0, 1.0, 1.0],
        pts,
    )
    .unwrap()
}
