//! Agreement with the independent `curvo` crate (0.3) on random rational curves and surfaces: points
//! and derivatives (curves up to order 3, surfaces up to order 2) to 1e-10 relative.

use crate::common;
use common::*;
use curvo::prelude::{NurbsCurve3D, NurbsSurface3D};
use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use nalgebra::{Point4, Vector3};
use rand::Rng;

fn to_curvo_curve(c: &NurbsCurve) -> NurbsCurve3D<f64> {
    let pts = c
        .homogeneous_points()
        .iter()
        .map(|q| Point4::new(q[0], q[1], q[2], q[3]))
        .collect();
    NurbsCurve3D::try_new(c.degree(), pts, c.knots().to_vec()).expect("curvo accepts the curve")
}

fn to_curvo_surface(s: &NurbsSurface) -> NurbsSurface3D<f64> {
    let (_, n_v) = s.net_size();
    let net = s
        .homogeneous_points()
        .chunks(n_v)
        .map(|row| {
            row.iter()
                .map(|q| Point4::new(q[0], q[1], q[2], q[3]))
                .collect()
        })
        .collect();
    NurbsSurface3D::new(
        s.degree_u(),
        s.degree_v(),
        s.knots_u().to_vec(),
        s.knots_v().to_vec(),
        net,
    )
}

fn close(a: Vec3, b: Vector3<f64>, scale: f64) -> bool {
    let d = Vec3::new(a.x() - b.x, a.y() - b.y, a.z() - b.z).norm();
    d <= 1e-10 * scale.max(b.norm()).max(a.norm())
}

#[test]
fn curves_agree_with_curvo() {
    let mut r = rng(21);
    for case in 0..100 {
        let p = 1 + case % 6;
        let c = random_curve(&mut r, p, p + 1 + case % 9, true, p);
        let cc = to_curvo_curve(&c);
        let (a, b) = c.domain();
        let sc = scale(&c);
        for i in 0..50 {
            let u = if i == 0 {
                a
            } else if i == 1 {
                b
            } else {
                r.random_range(a..b)
            };
            let p0 = c.point(u);
            let q0 = cc.point_at(u);
            assert!(
                close(p0, q0.coords, sc),
                "case {case} u={u}: {p0:?} vs {q0:?}"
            );
            let d = c.derivatives(u, 3);
            let e = cc.rational_derivatives(u, 3);
            for k in 0..=3 {
                assert!(
                    close(d[k], e[k], sc),
                    "case {case} p={p} k={k} u={u}: {:?} vs {:?}",
                    d[k],
                    e[k]
                );
            }
        }
    }
}

#[test]
fn surfaces_agree_with_curvo() {
    let mut r = rng(22);
    for case in 0..40 {
        let (p, q) = (1 + case % 4, 1 + (case / 4) % 4);
        let s = random_surface(&mut r, p, q, p + 1 + case % 4, q + 2, true);
        let cs = to_curvo_surface(&s);
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let sc = s
            .control_points_flat()
            .iter()
            .fold(1.0f64, |m, x| m.max(x.max_abs()));
        for _ in 0..30 {
            let (u, v) = (r.random_range(u0..u1), r.random_range(v0..v1));
            let pt = s.point(u, v);
            assert!(close(pt, cs.point_at(u, v).coords, sc), "case {case}");
            let d = s.derivatives(u, v, 2);
            let e = cs.rational_derivatives(u, v, 2);
            for k in 0..=2 {
                for l in 0..=(2 - k) {
                    assert!(
                        close(d[k * 3 + l], e[k][l], sc),
                        "case {case} ({k},{l}) at ({u},{v}): {:?} vs {:?}",
                        d[k * 3 + l],
                        e[k][l]
                    );
                }
            }
        }
    }
}
