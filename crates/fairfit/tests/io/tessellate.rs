//! Tessellation and mesh files against an exact rational cylinder: every vertex on the cylinder,
//! chord heights within the tolerance, radial normals, and the triangle count the sagitta formula
//! predicts; OBJ/STL/PLY parsed back.

use fairfit::io::mesh_write::{mesh_bytes, to_obj, to_ply, write_curve_mesh, MeshFormat};
use fairfit::io::tessellate::{tessellate_curve, tessellate_surface, TessellationOptions};
use fairfit::{NurbsCurve, NurbsSurface, Vec3};

const R: f64 = 25.0;

/// Half cylinder of radius R (two exact rational quarter circles), height 40, along z.
fn half_cylinder() -> NurbsSurface {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let arc = [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, h),
        (0.0, 1.0, 1.0),
        (-1.0, 1.0, h),
        (-1.0, 0.0, 1.0),
    ];
    let net = arc
        .iter()
        .map(|&(x, y, _)| vec![Vec3::new(R * x, R * y, 0.0), Vec3::new(R * x, R * y, 40.0)])
        .collect();
    let w = arc.iter().map(|&(_, _, w)| vec![w, w]).collect();
    let ku = vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
    NurbsSurface::new(2, 1, ku, vec![0.0, 0.0, 1.0, 1.0], net, Some(w)).unwrap()
}

fn radius(p: Vec3) -> f64 {
    (p.x() * p.x() + p.y() * p.y()).sqrt()
}

#[test]
fn cylinder_mesh_meets_the_chord_tolerance() {
    let s = half_cylinder();
    for tol in [0.1, 0.01] {
        let opts = TessellationOptions {
            chord_tol: Some(tol),
            min_per_span: 1,
            ..Default::default()
        };
        let m = tessellate_surface(&s, &opts).unwrap();
        for (&p, &n) in m.vertices.iter().zip(&m.normals) {
            assert!((radius(p) - R).abs() < 1e-10 * R);
            let radial = Vec3::new(p.x(), p.y(), 0.0) / radius(p);
            assert!(
                (n.dot(radial).abs() - 1.0).abs() < 1e-12,
                "normal {n:?} at {p:?}"
            );
        }
        let mut worst: f64 = 0.0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.vertices[i as usize]);
            for q in [
                (a + b) * 0.5,
                (b + c) * 0.5,
                (a + c) * 0.5,
                (a + b + c) / 3.0,
            ] {
                worst = worst.max(R - radius(q));
            }
        }
        assert!(worst <= tol, "chord height {worst} > {tol}");
        // Sagitta: an arc of angle θ has chord height R(1 - cos(θ/2)); π needs at least this many segments.
        let min_segments = (std::f64::consts::PI / (2.0 * (1.0 - tol / R).acos())).ceil() as usize;
        let segments = m.vertices.iter().filter(|p| p.z() == 0.0).count() - 1;
        assert!(
            segments >= min_segments && segments <= 4 * min_segments,
            "{segments} vs {min_segments}"
        );
        assert!(worst > tol / 16.0, "not over-refined: {worst}");
    }
}

#[test]
fn curve_polyline_meets_the_chord_tolerance() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let c = NurbsCurve::new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![
            Vec3::new(R, 0.0, 0.0),
            Vec3::new(R, R, 0.0),
            Vec3::new(0.0, R, 0.0),
        ],
        Some(vec![1.0, h, 1.0]),
    )
    .unwrap();
    let opts = TessellationOptions {
        chord_tol: Some(1e-3),
        min_per_span: 1,
        ..Default::default()
    };
    let m = tessellate_curve(&c, &opts).unwrap();
    assert_eq!(m.polylines.len(), 1);
    let line = &m.polylines[0];
    assert_eq!(line.len(), m.vertices.len());
    for w in line.windows(2) {
        let mid = (m.vertices[w[0] as usize] + m.vertices[w[1] as usize]) * 0.5;
        assert!(R - radius(mid) <= 1e-3);
    }
    let obj = to_obj(&m);
    assert_eq!(obj.lines().filter(|l| l.starts_with("l ")).count(), 1);
    let ply = to_ply(&m);
    assert!(ply.contains(&format!("element edge {}", line.len() - 1)));
    assert!(
        mesh_bytes(&m, MeshFormat::Stl).is_err(),
        "a curve is not an STL"
    );
}

#[test]
fn mesh_files_parse_back() {
    let m = tessellate_surface(&half_cylinder(), &TessellationOptions::default()).unwrap();
    let stl = mesh_bytes(&m, MeshFormat::Stl).unwrap();
    let n = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
    assert_eq!(n, m.triangles.len());
    assert_eq!(stl.len(), 84 + 50 * n);
    let f = |k: usize| f32::from_le_bytes(stl[k..k + 4].try_into().unwrap()) as f64;
    let first = m.vertices[m.triangles[0][0] as usize];
    assert!((f(84 + 12) - first.x()).abs() < 1e-5 * R);
    let obj = to_obj(&m);
    let count = |p: &str| obj.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!(
        (count("v "), count("vn "), count("f ")),
        (m.vertices.len(), m.vertices.len(), n)
    );
    for l in obj.lines().filter(|l| l.starts_with("f ")) {
        for idx in l[2..]
            .split(' ')
            .map(|t| t.split("//").next().unwrap().parse::<usize>().unwrap())
        {
            assert!((1..=m.vertices.len()).contains(&idx));
        }
    }
    let ply = to_ply(&m);
    let body: Vec<&str> = ply.split("end_header\n").nth(1).unwrap().lines().collect();
    assert_eq!(body.len(), m.vertices.len() + n);
    let v0: Vec<f64> = body[0].split(' ').map(|t| t.parse().unwrap()).collect();
    assert_eq!(v0.len(), 6);
    assert_eq!(v0[0], m.vertices[0].x());
}

#[test]
fn bad_paths_and_tolerances_are_errors() {
    let c = NurbsCurve::bspline(
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)],
    )
    .unwrap();
    let e = write_curve_mesh("out.xyz", &c, &TessellationOptions::default()).unwrap_err();
    assert!(e.to_string().contains("out.xyz"), "{e}");
    let bad = TessellationOptions {
        chord_tol: Some(-1.0),
        ..Default::default()
    };
    assert!(tessellate_curve(&c, &bad).is_err());
    let tiny = TessellationOptions {
        chord_tol: Some(1e-9),
        max_intervals: 8,
        ..Default::default()
    };
    let e = tessellate_surface(&half_cylinder(), &tiny)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not reached"), "{e}");
    assert!(
        e.contains("chord tolerance 1e-9 not reached with 8 intervals"),
        "{e}"
    );
    // a tolerance far below the geometry in scientific notation (had been 300 digits, one line of
    // 400 characters)
    let tinier = TessellationOptions {
        chord_tol: Some(1e-300),
        ..Default::default()
    };
    let e = tessellate_surface(&half_cylinder(), &tinier)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("chord tolerance 1e-300 not reached with 4096 intervals"),
        "{e}"
    );
    assert!(e.len() < 150, "{e}");
    let e = tessellate_curve(
        &c,
        &TessellationOptions {
            chord_tol: Some(f64::INFINITY),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("must be positive and finite, got inf"), "{e}");
}
