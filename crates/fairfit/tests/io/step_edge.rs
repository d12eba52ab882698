//! STEP `EDGE_CURVE`s cut their curves at their vertices (`io/step_edge.rs`): OpenCASCADE-written
//! faces (`tests/data/edges`, `tests/python/occ_edges.py`) whose curved edge is an untrimmed `CIRCLE`,
//! `ELLIPSE` or B-spline inside a `SURFACE_CURVE`. Truths: the analytic circle and ellipse (radius,
//! ends at the vertices' angles, length `r Δθ`), ISO 10303-42's sense (the edge runs from its start
//! vertex to its end vertex; `same_sense .F.` against the curve), and OpenCASCADE's reading of every
//! file (its points on the edge, its length; run with `$FAIRFIT_PYTHON`).

use fairfit::diffgeo::{arc_length, CurveProjector};
use fairfit::io::cad_read::{read_cad, CadKind};
use fairfit::io::Geometry;
use fairfit::{NurbsCurve, Vec3};
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use crate::common::python;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/edges")
        .join(name)
}

/// The one curve fairfit reads from the fixture (the face's straight edge is no curve it reads), and
/// its source.
fn edge(name: &str) -> (NurbsCurve, String) {
    let g = read_cad(fixture(name), CadKind::Curve, 0).unwrap();
    assert_eq!(g.count, 1, "{name}");
    match g.geometry {
        Geometry::Curve(c) => (c, g.source),
        other => panic!("{other:?}"),
    }
}

fn ends(c: &NurbsCurve) -> (Vec3, Vec3) {
    let (a, b) = c.domain();
    (c.point(a), c.point(b))
}

/// The circle of the arc fixtures at angle `t`.
fn on_circle(t: f64) -> Vec3 {
    Vec3::new(1.0 + 10.0 * t.cos(), 2.0 + 10.0 * t.sin(), 3.0)
}

#[test]
fn circle_edges_are_the_arcs_between_their_vertices() {
    // (file, start angle, end angle, length): arc_reversed swaps the vertices and runs against the
    // circle (the same arc, backwards); arc_long runs against it from 0.5 to 2.0 (the long way)
    let cases = [
        ("arc.step", 0.5, 2.0, 15.0),
        ("arc_reversed.step", 2.0, 0.5, 15.0),
        ("arc_long.step", 0.5, 2.0, 10.0 * (TAU - 1.5)),
    ];
    for (name, t0, t1, length) in cases {
        let (c, source) = edge(name);
        assert_eq!(source, "#21 (circular arc, edge of #27)", "{name}");
        let (s, e) = ends(&c);
        assert!((s - on_circle(t0)).norm() < 1e-11, "{name}: {s:?}");
        assert!((e - on_circle(t1)).norm() < 1e-11, "{name}: {e:?}");
        let (a, b) = c.domain();
        let mut worst = 0.0f64;
        for i in 0..=1000 {
            let p = c.point(a + (b - a) * i as f64 / 1000.0);
            let r = Vec3::new(p.x() - 1.0, p.y() - 2.0, 0.0).norm();
            worst = worst.max((r - 10.0).abs()).max((p.z() - 3.0).abs());
        }
        assert!(worst < 1e-13 * 10.0, "{name}: {worst}");
        let l = arc_length(&c);
        assert!(
            (l - length).abs() < 1e-12 * length,
            "{name}: {l} vs {length}"
        );
        // the long arc passes through the angle opposite the short one's middle, not through it
        let proj = CurveProjector::new(&c, 16);
        let short_mid = proj.project(on_circle(1.25)).distance;
        let long_mid = proj.project(on_circle(1.25 + 0.5 * TAU)).distance;
        if name == "arc_long.step" {
            assert!(
                short_mid > 1.0 && long_mid < 1e-12,
                "{short_mid} {long_mid}"
            );
        } else {
            assert!(
                short_mid < 1e-12 && long_mid > 1.0,
                "{short_mid} {long_mid}"
            );
        }
    }
}

#[test]
fn ellipse_and_bspline_edges_are_cut_at_their_vertices() {
    // the ellipse about (0, 0, 1), x along (1, 0, 0), y along (0, 0.6, 0.8) x ... in its tilted plane:
    // from angle 5.5 to 7.0, across its angle 0
    let (c, source) = edge("ellipse.step");
    assert_eq!(source, "#21 (elliptical arc, edge of #27)");
    let z = Vec3::new(0.0, 0.6, 0.8);
    let x = Vec3::new(1.0, 0.0, 0.0);
    let y = z.cross(x);
    let at = |t: f64| Vec3::new(0.0, 0.0, 1.0) + x * (12.0 * t.cos()) + y * (5.0 * t.sin());
    let (s, e) = ends(&c);
    assert!((s - at(5.5)).norm() < 1e-11 && (e - at(7.0)).norm() < 1e-11);
    let proj = CurveProjector::new(&c, 16);
    for t in [5.6, 6.0, TAU, 6.5, 6.9] {
        assert!(proj.project(at(t)).distance < 1e-11, "{t}");
    }
    assert!(proj.project(at(3.0)).distance > 1.0);
    // the flattened wiggly cubic from 0.1 to 0.8 of its domain
    let (c, source) = edge("bspline.step");
    assert_eq!(source, "#21 (edge of #27)");
    let (s, e) = ends(&c);
    // the vertices as OpenCASCADE wrote them (12 decimals)
    let v0 = Vec3::new(14.429012345679, 22.979938271605, 0.0);
    let v1 = Vec3::new(88.647633358377, 11.848234410218, 0.0);
    assert!(
        (s - v0).norm() < 1e-9 && (e - v1).norm() < 1e-9,
        "{s:?} {e:?}"
    );
}

#[test]
fn opencascade_reads_the_same_edges() {
    let Some(python) = python::python_or_skip("OpenCASCADE's reading of the edge fixtures") else {
        return;
    };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_edges.py");
    for name in [
        "arc.step",
        "arc_reversed.step",
        "arc_long.step",
        "ellipse.step",
        "bspline.step",
    ] {
        let out = std::process::Command::new(&python)
            .arg(&script)
            .arg("read")
            .arg(fixture(name))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{name}: {stdout}");
        let v: serde_json::Value =
            serde_json::from_str(stdout.lines().rfind(|l| l.starts_with('{')).unwrap()).unwrap();
        let pts = python::json_points(&v["points"]);
        let (c, _) = edge(name);
        let size = fairfit::fit::sampling::extent(std::slice::from_ref(&c));
        let proj = CurveProjector::new(&c, 16);
        let worst = pts
            .iter()
            .map(|&p| proj.project(p).distance)
            .fold(0.0, f64::max);
        // the same piece: its ends are OpenCASCADE's (in either order: OpenCASCADE orients the edge
        // as the face's loop uses it) and its length is OpenCASCADE's
        let (s, e) = ends(&c);
        let (o0, o1) = (pts[0], pts[pts.len() - 1]);
        let ends_apart = ((s - o0).norm() + (e - o1).norm()).min((s - o1).norm() + (e - o0).norm());
        let (ours, theirs) = (arc_length(&c), v["length"].as_f64().unwrap());
        println!(
            "{name}: OCC's points within {worst:.2e} of fairfit's edge, ends {ends_apart:.2e} apart, \
             length {ours} vs OCC {theirs}"
        );
        assert!(worst < 1e-9 * size, "{name}: {worst}");
        assert!(ends_apart < 1e-7 * size, "{name}: {ends_apart}");
        assert!(
            (ours - theirs).abs() < 1e-9 * theirs,
            "{name}: {ours} vs {theirs}"
        );
    }
}
