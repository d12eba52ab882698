//! `surface::measure`: the projection onto a surface periodic in u, for points just either side of
//! its seam, against the independent truth of their construction: a point `d` along the surface's
//! unit normal (finite differences of `S`) from `S(u, v)`, with `d` far below the curvature radius,
//! lies `d` from the surface.

use fairfit::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};
use fairfit::surface::{surface_deviation, surface_deviation_near, SurfaceProjector};

/// A periodic cubic ring of 8 distinct rows (3 repeated) around an ellipse, linear in v from
/// height 0 to 1: closed and C2 across its seam at u = 0 = 1.
fn ring() -> NurbsSurface {
    let ku: Vec<f64> = (-3..=11).map(|i| i as f64 / 8.0).collect();
    let net = (0..11)
        .map(|i| {
            let t = std::f64::consts::TAU * (i % 8) as f64 / 8.0;
            (0..2)
                .map(|j| Vec3::new(1.2 * t.cos(), 0.8 * t.sin(), j as f64))
                .collect()
        })
        .collect();
    let s = NurbsSurface::new(3, 1, ku, vec![0.0, 0.0, 1.0, 1.0], net, None).unwrap();
    assert!(s.is_periodic_u());
    s
}

/// `S(u, v)` moved `d` along the unit normal (central differences).
fn off_surface(s: &NurbsSurface, u: f64, v: f64, d: f64) -> Vec3 {
    let h = 1e-6;
    let su = s.point(u + h, v) - s.point(u - h, v);
    let sv = s.point(u, v + h) - s.point(u, v - h);
    let n = su.cross(sv);
    s.point(u, v) + n / n.norm() * d
}

#[test]
fn points_by_the_seam_of_a_periodic_surface_are_projected_across_it() {
    let s = ring();
    let proj = SurfaceProjector::new(&s, 6);
    let mut ws = SurfaceWorkspace::new(&s, 2);
    let d = 1e-3;
    let mut points = Vec::new();
    // within a sample spacing (1/48) of the seam on both sides, so that the seam's sample, at
    // u = 0 and at u = 1, is the nearest
    for u in [0.002, 0.01, 0.015, 0.985, 0.99, 0.998] {
        for v in [0.1, 0.5, 0.9] {
            for sign in [1.0, -1.0] {
                let q = off_surface(&s, u, v, sign * d);
                points.push(q);
                let whole = proj.project(q, None, &mut ws);
                assert!(
                    (whole.distance / d - 1.0).abs() < 1e-6,
                    "u {u}, v {v}: {} for {d}",
                    whole.distance
                );
                // near a hint on the wrong side of the seam
                let hint = (if u < 0.5 { 1.0 } else { 0.0 }, v);
                let near = proj.project_near(q, hint, &mut ws);
                assert!(
                    (near.distance / d - 1.0).abs() < 1e-6,
                    "u {u}, v {v}, hint {hint:?}: {} for {d}",
                    near.distance
                );
            }
        }
    }
    let whole = surface_deviation(&s, &points, None);
    assert!((whole.max / d - 1.0).abs() < 1e-6, "{}", whole.max);
    assert!((whole.rms / d - 1.0).abs() < 1e-6, "{}", whole.rms);
    let hints: Vec<(f64, f64)> = points.iter().map(|_| (0.0, 0.5)).collect();
    let near = surface_deviation_near(&s, &points, &hints);
    assert_eq!(near.points, points.len());
    assert!((near.max / d - 1.0).abs() < 1e-6, "{}", near.max);
}
