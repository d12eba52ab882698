//! The seam of surfaces skinned from closed sections: the tangent angle and the curvature jump of the
//! u iso-curves across `u = 0 ≡ 1`, on an analytic elliptic tube whose seam lies on a smooth part of
//! every section, on the IEA 15 MW blade's two circular root sections, and the open / cornered cases.

use fairfit::io::sections::read_section_file;
use fairfit::nurbs::{NurbsSurface, Vec3};
use fairfit::surface::{reconstruct_surface, CompatibleOptions, Section, SurfaceOptions};
use std::path::Path;

/// Worst seam discontinuity over `n + 1` iso-curves `v = const`: (largest angle in radians between
/// `S_u(0, v)` and `S_u(1, v)`, largest relative jump `|κ(0) − κ(1)| / max κ` of the curvature of the
/// u iso-curve), from the surface's exact derivatives.
fn seam_jump(s: &NurbsSurface, n: usize) -> (f64, f64) {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let (mut angle, mut jump) = (0.0f64, 0.0f64);
    for k in 0..=n {
        let v = v0 + (v1 - v0) * k as f64 / n as f64;
        let (a, b) = (s.derivatives(u0, v, 2), s.derivatives(u1, v, 2));
        // [k * 3 + l] = S_{u^k v^l}: S_u = [3], S_uu = [6]
        let (ta, tb) = (a[3], b[3]);
        let cos = ta.dot(tb) / (ta.norm() * tb.norm());
        let sin = ta.cross(tb).norm() / (ta.norm() * tb.norm());
        angle = angle.max(sin.atan2(cos).abs());
        let kappa = |d1: Vec3, d2: Vec3| d1.cross(d2).norm() / d1.norm().powi(3);
        let (ka, kb) = (kappa(a[3], a[6]), kappa(b[3], b[6]));
        jump = jump.max((ka - kb).abs() / ka.max(kb));
    }
    (angle, jump)
}

/// Semi-axes and centre of the tube's ellipse at height `z` (smooth in z, the ratio changes).
fn tube_at(z: f64) -> (f64, f64, Vec3) {
    let a = 2.0 + 0.3 * z;
    let b = 1.0 + 0.1 * z + 0.05 * z * z;
    (a, b, Vec3::new(0.2 * z, 0.1 * z * z, z))
}

/// Closed elliptic sections at z = 0, 0.5, ..., 5; the start (t = 0, the end of the long axis) is smooth.
fn tube_sections(points: usize) -> Vec<Section> {
    (0..11)
        .map(|k| {
            let z = 0.5 * k as f64;
            let (a, b, c) = tube_at(z);
            let pts: Vec<Vec3> = (0..=points)
                .map(|i| {
                    // uneven sampling so the parameters are not the design ones
                    let s = i as f64 / points as f64;
                    let t = std::f64::consts::TAU * (s + 0.03 * (std::f64::consts::TAU * s).sin());
                    c + Vec3::new(a * t.cos(), b * t.sin(), 0.0)
                })
                .collect();
            Section::from_points(pts)
        })
        .collect()
}

/// Upper bound of the distance of `p` from the analytic tube: the distance to the tube's ellipse in
/// the plane `z = p.z` (dense samples, then Newton on the ellipse parameter).
fn tube_distance(p: Vec3) -> f64 {
    let (a, b, c) = tube_at(p.z());
    let (x, y) = (p.x() - c.x(), p.y() - c.y());
    let d2 = |t: f64| (a * t.cos() - x).powi(2) + (b * t.sin() - y).powi(2);
    let mut t = (0..720)
        .map(|i| std::f64::consts::TAU * i as f64 / 720.0)
        .min_by(|&s, &t| d2(s).total_cmp(&d2(t)))
        .unwrap();
    for _ in 0..20 {
        let (ex, ey) = (a * t.cos() - x, b * t.sin() - y);
        let (dx, dy) = (-a * t.sin(), b * t.cos());
        let g = ex * dx + ey * dy;
        let h = dx * dx + dy * dy + ex * (-a * t.cos()) + ey * (-b * t.sin());
        if h <= 0.0 {
            break;
        }
        t -= g / h;
    }
    d2(t).sqrt()
}

fn tube_options(tol: f64, periodic: bool) -> SurfaceOptions {
    SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: tol,
            max_control_points: 60,
            periodic_closed: periodic,
            ..Default::default()
        },
        iso_curves: 5,
        ..Default::default()
    }
}

#[test]
fn analytic_tube_seam_and_deviation() {
    for periodic in [false, true] {
        tube_case(periodic);
    }
}

fn tube_case(periodic: bool) {
    let tol = 1e-4;
    let r = reconstruct_surface(tube_sections(80), &tube_options(tol, periodic)).unwrap();
    assert!(
        r.compatible.within_tolerance,
        "{}",
        r.compatible.max_deviation
    );
    assert!(r.deviation.max <= tol, "{}", r.deviation.max);
    // the whole surface between the sections stays near the analytic tube
    let mut worst = 0.0f64;
    for i in 0..=60 {
        for j in 0..=25 {
            let p = r.surface.point(i as f64 / 60.0, j as f64 / 25.0);
            worst = worst.max(tube_distance(p));
        }
    }
    let (angle, jump) = seam_jump(&r.surface, 40);
    println!(
        "tube periodic={periodic}: net {:?}, deviation {:.3e}, analytic {:.3e}, seam angle {:.3e} rad, curvature jump {:.3e}",
        r.surface.net_size(),
        r.deviation.max,
        worst,
        angle,
        jump
    );
    // between the sections the cubic interpolation across them adds a little (1.3e-4 measured)
    assert!(worst <= 2.0 * tol, "{worst:e}");
    assert_eq!(r.compatible.periodic, periodic);
    let seam = r.seam.expect("closed sections report their seam");
    // the pipeline's seam measure agrees with this file's own
    assert!((seam.max_tangent_angle - angle).abs() <= 1e-12 + 1e-9 * angle);
    assert!((seam.max_curvature_jump - jump).abs() <= 1e-12 + 1e-9 * jump);
    if periodic {
        // C2 across the seam: the wrapped control rows make both ends one and the same curve
        assert!(angle < 1e-9 && jump < 1e-9, "{angle:e} {jump:e}");
        let (n_u, n_v) = r.surface.net_size();
        for j in 0..n_v {
            for i in 0..3 {
                assert_eq!(
                    r.surface.control_point(i, j),
                    r.surface.control_point(n_u - 3 + i, j)
                );
            }
        }
    } else {
        // the clamped fit's crease: 5.5e-2 rad (3.2°) and the curvature nearly doubles
        assert!(angle > 1e-2 && jump > 0.5, "{angle:e} {jump:e}");
    }
}

fn iea_root_sections() -> Vec<Section> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections");
    ["sec_00_s0.000.csv", "sec_01_s0.020.csv"]
        .iter()
        .map(|f| Section::from_points(read_section_file(dir.join(f)).unwrap()))
        .collect()
}

#[test]
fn iea_root_sections_seam() {
    for periodic in [false, true] {
        root_case(periodic);
    }
}

fn root_case(periodic: bool) {
    let secs = iea_root_sections();
    assert!(secs.iter().all(|s| s.closed));
    let r = reconstruct_surface(secs, &tube_options(0.0057, periodic)).unwrap();
    assert!(r.deviation.max <= 0.0057, "{}", r.deviation.max);
    let (angle, jump) = seam_jump(&r.surface, 10);
    println!(
        "iea root periodic={periodic}: net {:?}, deviation {:.3e}, seam angle {:.3e} rad, curvature jump {:.3e}",
        r.surface.net_size(),
        r.deviation.max,
        angle,
        jump
    );
    assert_eq!(r.compatible.periodic, periodic);
    if periodic {
        assert!(angle < 1e-9 && jump < 1e-9, "{angle:e} {jump:e}");
    } else {
        // the clamped fit's crease at the circular root: 2.0e-2 rad (1.2°)
        assert!(angle > 1e-2, "{angle:e}");
    }
}

/// Closed symmetric airfoils (NACA 00xx thickness with a closed, sharp trailing edge) from the
/// trailing edge round the upper side to the leading edge and back: a corner at every seam.
fn sharp_airfoils(open: bool) -> Vec<Section> {
    (0..4)
        .map(|k| {
            let (chord, z) = (1.0 - 0.15 * k as f64, k as f64);
            let half = |x: f64| {
                0.6 * (0.2969 * x.sqrt() - 0.126 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
                    - 0.1036 * x.powi(4))
            };
            let n = 50;
            let mut pts: Vec<Vec3> = (0..=2 * n)
                .map(|i| {
                    let (s, sign) = if i <= n {
                        (i as f64 / n as f64, 1.0)
                    } else {
                        ((2 * n - i) as f64 / n as f64, -1.0)
                    };
                    // cosine spacing from the trailing edge (x = 1) to the leading edge (x = 0)
                    let x = 0.5 * (1.0 + (std::f64::consts::PI * s).cos());
                    Vec3::new(chord * x, sign * chord * half(x), z)
                })
                .collect();
            if open {
                pts.pop();
            }
            Section::from_points(pts)
        })
        .collect()
}

#[test]
fn corner_at_the_seam_and_open_sections_keep_the_clamped_fit() {
    for open in [false, true] {
        let secs = sharp_airfoils(open);
        assert!(secs.iter().all(|s| s.closed != open));
        let on = reconstruct_surface(secs.clone(), &tube_options(1e-4, true)).unwrap();
        let off = reconstruct_surface(secs, &tube_options(1e-4, false)).unwrap();
        assert!(!on.compatible.periodic);
        // bit for bit the surface of the clamped fit
        assert_eq!(on.surface, off.surface);
        assert!(on.deviation.max <= 1e-4, "{}", on.deviation.max);
        let k = on.surface.knots_u();
        assert!(k[..4].iter().all(|&x| x == 0.0) && k[k.len() - 4..].iter().all(|&x| x == 1.0));
        if !open {
            // the ends meet at the trailing edge: a deliberate C0 edge with the wedge's angle
            let seam = on.seam.expect("closed sections report their seam");
            let (p0, p1) = (on.surface.point(0.0, 0.5), on.surface.point(1.0, 0.5));
            assert!((p0 - p1).norm() < 1e-12, "{p0:?} {p1:?}");
            assert!(seam.max_tangent_angle > 2.5, "{seam:?}");
        } else {
            assert!(on.seam.is_none());
        }
    }
}

/// The whole IEA blade: the two circular root sections are closed and smooth at the seam, the outer
/// sections are open (blunt trailing edges), so the shared knot vector stays clamped. The root circles'
/// seams are tied (C2, see `surface::seam_tie`): the surface's iso-curves at the root are smooth across
/// the trailing-edge line instead of creased by 4.4° (`periodic_closed = false` keeps that crease).
#[test]
fn mixed_blade_ties_the_seam_of_its_closed_root() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    files.sort();
    let secs: Vec<Section> = files
        .iter()
        .map(|f| Section::from_points(read_section_file(f).unwrap()))
        .collect();
    assert!(secs[0].closed && secs[1].closed && !secs[9].closed);
    // the root's iso-curve angle at the seam, from the exact surface derivatives
    let root_angle = |s: &NurbsSurface| {
        let (a, b) = (s.derivatives(0.0, 0.0, 1), s.derivatives(1.0, 0.0, 1));
        let (ta, tb) = (a[2], b[2]);
        ta.cross(tb).norm().atan2(ta.dot(tb))
    };
    let tied = reconstruct_surface(secs.clone(), &tube_options(0.0057, true)).unwrap();
    let plain = reconstruct_surface(secs, &tube_options(0.0057, false)).unwrap();
    for r in [&tied, &plain] {
        assert!(!r.compatible.periodic);
        assert!(r.deviation.max <= 0.0057, "{}", r.deviation.max);
        let (p0, p1) = (r.surface.point(0.0, 0.0), r.surface.point(1.0, 0.0));
        assert!((p0 - p1).norm() < 1e-12, "{p0:?} {p1:?}");
    }
    let (a_tied, a_plain) = (root_angle(&tied.surface), root_angle(&plain.surface));
    println!("blade root seam angle: tied {a_tied:.3e} rad, plain {a_plain:.3e} rad");
    assert!(a_tied < 1e-9, "{a_tied:e}");
    assert!(a_plain > 0.05, "{a_plain:e}");
    // the tie costs no control points
    assert_eq!(tied.surface.net_size(), plain.surface.net_size());
}
