//! Circles, ellipses and point-trimmed curves read from CAD files written by OpenCASCADE (fixtures in
//! `tests/data/conics`, made by `tests/python/occ_conics.py write`; see `tests/data/README.md`).
//!
//! Truths: OpenCASCADE's own reading of every fixture (`occ_truth.json`: 51 points per edge along its
//! orientation, and the length; re-checked against the installed OpenCASCADE when `$FAIRFIT_PYTHON` is
//! set), and analytic ones independent of OpenCASCADE: the rational weights give the exact radius
//! (`|P - C| = r` at 1000 samples), the radian and degree files give the same arc, and the section's
//! leading edge is the half circle of radius 5 about (5, 0, 0).

use crate::common::python;

use fairfit::diffgeo::{arc_length, CurveProjector};
use fairfit::fit::points::bounding_box_extent;
use fairfit::io::cad_read::{read_cad, read_cad_chain, read_contents, CadKind};
use fairfit::io::Geometry;
use fairfit::{NurbsCurve, Vec3};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/conics")
}

fn truth() -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(data().join("occ_truth.json")).unwrap()).unwrap()
}

fn ends(c: &NurbsCurve) -> (Vec3, Vec3) {
    let (a, b) = c.domain();
    (c.point(a), c.point(b))
}

/// Worst distances of one file's segments from OpenCASCADE's edges: (points off the segment, ends,
/// relative length difference), all relative to the size of the curve.
fn compare(file: &str, occ: &serde_json::Value) -> (f64, f64, f64) {
    let chain = read_cad_chain(data().join(file), 0).unwrap();
    let edges = occ["points"].as_array().unwrap();
    assert_eq!(chain.segments.len(), edges.len(), "{file}");
    let all: Vec<Vec3> = edges.iter().flat_map(python::json_points).collect();
    let size = bounding_box_extent(&all);
    let (mut off, mut end) = (0.0f64, 0.0f64);
    for (seg, e) in chain.segments.iter().zip(edges) {
        let pts = python::json_points(e);
        let proj = CurveProjector::new(seg, 16);
        for &p in &pts {
            off = off.max(proj.project(p).distance);
        }
        let (s, t) = ends(seg);
        end = end
            .max((s - pts[0]).norm())
            .max((t - pts[pts.len() - 1]).norm());
    }
    let ours: f64 = chain.segments.iter().map(arc_length).sum();
    let theirs = occ["length"].as_f64().unwrap();
    (off / size, end / size, (ours - theirs).abs() / theirs)
}

/// Every fixture against OpenCASCADE's reading of it: OpenCASCADE's points lie on fairfit's curves,
/// the ends agree and so do the lengths. STEP files carry 12 significant digits, IGES files 10; both
/// readers read the same digits, so they agree to rounding.
#[test]
fn every_fixture_agrees_with_opencascade() {
    let t = truth();
    let files = t.as_object().unwrap();
    assert_eq!(files.len(), 16);
    let mut bad = Vec::new();
    for (file, occ) in files {
        let (off, end, len) = compare(file, occ);
        println!("{file}: off {off:.2e}, ends {end:.2e}, length {len:.2e} (relative)");
        // OpenCASCADE projects the trimming points of a B-spline only to about 1e-9 (see
        // `a_bspline_trimmed_by_points_is_cut` for the exact ends)
        let tol = if file == "bspline_points.step" {
            1e-9
        } else {
            1e-12
        };
        if !(off < tol && end < tol && len < tol) {
            bad.push(file.clone());
        }
    }
    assert!(bad.is_empty(), "{bad:?}");
}

/// The truth file is OpenCASCADE's reading of the committed fixtures (re-read now, to 1e-13).
#[test]
fn truth_file_is_current() {
    let Some(python) = python::python_or_skip("OpenCASCADE's reading of the conic fixtures") else {
        return;
    };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_conics.py");
    let t = truth();
    for file in ["arc_deg.step", "arc_points_reversed.step", "section.igs"] {
        let out = std::process::Command::new(&python)
            .arg(&script)
            .arg("read")
            .arg(data().join(file))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{stdout}");
        let now: serde_json::Value =
            serde_json::from_str(stdout.lines().rfind(|l| l.starts_with('{')).unwrap()).unwrap();
        let (a, b) = (&now["points"], &t[file]["points"]);
        for (ea, eb) in a.as_array().unwrap().iter().zip(b.as_array().unwrap()) {
            for (p, q) in ea.as_array().unwrap().iter().zip(eb.as_array().unwrap()) {
                assert!(
                    (python::json_point(p) - python::json_point(q)).norm() < 1e-13 * 100.0,
                    "{file}"
                );
            }
        }
    }
}

/// The exact radius (an analytic truth): every STEP circle and arc of radius 7.5 about (1, 2, 3), at
/// 1000 samples, and the section's leading edge (radius 5 about (5, 0, 0)); the IGES circles too, to
/// the 10 digits their transformation matrices hold.
#[test]
fn rational_weights_give_the_exact_radius() {
    let check = |c: &NurbsCurve, centre: Vec3, r: f64, tol: f64| {
        let (a, b) = c.domain();
        let mut worst = 0.0f64;
        for i in 0..1000 {
            let p = c.point(a + (b - a) * i as f64 / 999.0);
            worst = worst.max(((p - centre).norm() - r).abs() / r);
        }
        assert!(worst < tol, "{worst}");
        worst
    };
    let centre = Vec3::new(1.0, 2.0, 3.0);
    for file in [
        "circle.step",
        "arc_rad.step",
        "arc_deg.step",
        "arc_points.step",
        "arc_points_reversed.step",
    ] {
        let chain = read_cad_chain(data().join(file), 0).unwrap();
        let w = check(&chain.segments[0], centre, 7.5, 1e-12);
        println!("{file}: |P - C| / r - 1 at most {w:.2e}");
    }
    for file in ["circle.igs", "arc.igs"] {
        let chain = read_cad_chain(data().join(file), 0).unwrap();
        let w = check(&chain.segments[0], centre, 7.5, 1e-9);
        println!("{file}: |P - C| / r - 1 at most {w:.2e}");
    }
    for file in ["section.step", "section.igs"] {
        let chain = read_cad_chain(data().join(file), 0).unwrap();
        check(&chain.segments[1], Vec3::new(5.0, 0.0, 0.0), 5.0, 1e-12);
        let (s, e) = ends(&chain.segments[1]);
        assert!(
            (s - Vec3::new(5.0, 5.0, 0.0)).norm() < 1e-11,
            "{file} {s:?}"
        );
        assert!(
            (e - Vec3::new(5.0, -5.0, 0.0)).norm() < 1e-11,
            "{file} {e:?}"
        );
        // the leading edge passes through the origin
        let le = CurveProjector::new(&chain.segments[1], 16).project(Vec3::ZERO);
        assert!(le.distance < 1e-11, "{file}");
    }
}

/// Degrees and radians, parameters and points, both senses: the same arc (to rounding), named as an
/// arc; the full circle is closed and named a circle.
#[test]
fn the_arc_is_the_same_however_it_is_trimmed() {
    let read = |f: &str| read_cad_chain(data().join(f), 0).unwrap();
    let rad = read("arc_rad.step");
    assert_eq!(rad.source, "#16 (circular arc, trimmed #17)");
    let (a, b) = rad.segments[0].domain();
    assert!(
        (a - 0.4).abs() < 1e-15 && (b - 2.9).abs() < 1e-15,
        "{a} {b}"
    );
    for f in ["arc_deg.step", "arc_points.step"] {
        let c = &read(f).segments[0];
        let (a2, b2) = c.domain();
        assert!(
            (a2 - a).abs() < 1e-12 && (b2 - b).abs() < 1e-12,
            "{f}: {a2} {b2}"
        );
        for i in 0..=100 {
            let u = a + (b - a) * i as f64 / 100.0;
            let v = a2 + (b2 - a2) * i as f64 / 100.0;
            assert!(
                (c.point(v) - rad.segments[0].point(u)).norm() < 1e-12 * 7.5,
                "{f}"
            );
        }
    }
    let back = &read("arc_points_reversed.step").segments[0];
    let (s, e) = ends(back);
    let (s0, e0) = ends(&rad.segments[0]);
    assert!((s - e0).norm() < 1e-11 && (e - s0).norm() < 1e-11);
    let circle = read("circle.step");
    assert_eq!(circle.source, "#16 (circle, trimmed #17)");
    let (s, e) = ends(&circle.segments[0]);
    assert!((s - e).norm() < 1e-14);
    let g = read_cad(data().join("circle.igs"), CadKind::Any, 0).unwrap();
    assert_eq!(g.source, "DE 1 (circle)");
    assert_eq!(
        read("ellipse_arc.igs").source,
        "DE 1 (elliptical arc)".to_string()
    );
    assert_eq!(read("parabola_arc.igs").source, "DE 1 (parabolic arc)");
    assert_eq!(read("hyperbola_arc.igs").source, "DE 1 (hyperbolic arc)");
    assert_eq!(
        read("ellipse_arc.step").source,
        "#16 (elliptical arc, trimmed #17)"
    );
    assert_eq!(
        read("parabola_arc.step").source,
        "#16 (parabolic arc, trimmed #17)"
    );
    assert_eq!(
        read("hyperbola_arc.step").source,
        "#16 (hyperbolic arc, trimmed #17)"
    );
}

/// STEP `PARABOLA` and `HYPERBOLA` arcs (OpenCASCADE's, placed at (1, 2, 3) with axis (0.2, 0.3, 1)):
/// one exact rational quadratic Bezier each, on the analytic conic `y² = 4 f x` (f = 2) and
/// `x²/36 - y²/9 = 1` in the placement's frame to 1e-10 (the file's 12 digits) at 1001 parameters, from the first trim to the
/// second; trimmed by ISO parameters alone (`f (t² x + 2 t y)`, `(a cosh t, b sinh t)`), by points
/// alone and reversed, and OpenCASCADE's reading (every fixture above) within 1e-12.
#[test]
fn parabola_and_hyperbola_arcs_read_exactly() {
    let origin = Vec3::new(1.0, 2.0, 3.0);
    let z = Vec3::new(0.2, 0.3, 1.0);
    let z = z * (1.0 / z.norm());
    // the placement's ref_direction: (5, 0, -1), across the axis
    let x0 = Vec3::new(5.0, 0.0, -1.0);
    let x = x0 - z * x0.dot(z);
    let x = x * (1.0 / x.norm());
    let y = z.cross(x);
    let local = |p: Vec3| {
        let d = p - origin;
        (d.dot(x), d.dot(y), d.dot(z))
    };
    let text = |f: &str| std::fs::read_to_string(data().join(f)).unwrap();
    let parse = |t: &str| {
        let g = fairfit::io::cad_read::select(
            fairfit::io::cad_read::parse_cad(t, fairfit::io::cad_read::CadFormat::Step).unwrap(),
            CadKind::Curve,
            0,
            "x",
        )
        .unwrap();
        match g.geometry {
            fairfit::io::Geometry::Curve(c) => c,
            other => panic!("{other:?}"),
        }
    };
    for (file, on, at) in [
        (
            "parabola_arc.step",
            Box::new(|u: f64, v: f64| (v * v - 8.0 * u) / 8.0) as Box<dyn Fn(f64, f64) -> f64>,
            Box::new(|t: f64| (2.0 * t * t, 4.0 * t)) as Box<dyn Fn(f64) -> (f64, f64)>,
        ),
        (
            "hyperbola_arc.step",
            Box::new(|u: f64, v: f64| u * u / 36.0 - v * v / 9.0 - 1.0),
            Box::new(|t: f64| (6.0 * t.cosh(), 3.0 * t.sinh())),
        ),
    ] {
        let t = text(file);
        let c = parse(&t);
        assert_eq!((c.degree(), c.n_control_points()), (2, 3), "{file}");
        let (a, b) = c.domain();
        for i in 0..=1000 {
            let (u, v, w) = local(c.point(a + (b - a) * i as f64 / 1000.0));
            // the file's placement has 12 digits
            assert!(
                on(u, v).abs() < 1e-10 && w.abs() < 1e-10,
                "{file}: {i}: {} {w}",
                on(u, v)
            );
        }
        // OpenCASCADE's trims: its parabola parameter U = 2 f t from -3 to 2, its hyperbola t from
        // -1 to 1.5 (the points given with them)
        let (t0, t1) = if file.starts_with("parabola") {
            (-0.75, 0.5)
        } else {
            (-1.0, 1.5)
        };
        let (s, e) = ends(&c);
        let want = |t: f64| {
            let (u, v) = at(t);
            origin + x * u + y * v
        };
        assert!(
            (s - want(t0)).norm() < 1e-10 && (e - want(t1)).norm() < 1e-10,
            "{file}"
        );
        // ISO parameters alone, the points dropped: the same arc
        let m = regex_lite_trims(&t);
        let iso = t.replace(
            &m,
            &format!("(PARAMETER_VALUE({t0:?})),(PARAMETER_VALUE({t1:?})),.T.,.PARAMETER.)"),
        );
        let c2 = parse(&iso);
        let (s2, e2) = ends(&c2);
        assert!((s2 - s).norm() < 1e-10 && (e2 - e).norm() < 1e-10, "{file}");
        // points alone, reversed
        let back = t.replace(&m, "(#23),(#22),.F.,.CARTESIAN.)");
        let (s3, e3) = ends(&parse(&back));
        assert!((s3 - e).norm() < 1e-10 && (e3 - s).norm() < 1e-10, "{file}");
    }
}

/// The trims of the fixture's one `TRIMMED_CURVE`, from the first `(` after the basis to `);`.
fn regex_lite_trims(text: &str) -> String {
    let start = text.find("TRIMMED_CURVE('',#17,").unwrap() + "TRIMMED_CURVE('',#17,".len();
    let end = start + text[start..].find(");").unwrap() + 1;
    text[start..end].to_string()
}

/// A B-spline trimmed by points only is cut at their projections: its ends are the trimming points,
/// which are the basis at 0.15 and 0.85 (OpenCASCADE's edge), not the basis's ends.
#[test]
fn a_bspline_trimmed_by_points_is_cut() {
    let c = read_cad_chain(data().join("bspline_points.step"), 0).unwrap();
    assert_eq!(c.source, "#16 (trimmed #17)");
    let (a, b) = c.segments[0].domain();
    assert!(
        (a - 0.15).abs() < 1e-10 && (b - 0.85).abs() < 1e-10,
        "{a} {b}"
    );
    // the generator's cubic (poles and knots of tests/python/occ_conics.py) at 0.15 and 0.85
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(10.0, 8.0, 1.0),
        Vec3::new(25.0, -4.0, 2.0),
        Vec3::new(40.0, 6.0, 0.0),
        Vec3::new(50.0, 0.0, -1.0),
    ];
    let cubic = NurbsCurve::bspline(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
        pts.to_vec(),
    )
    .unwrap();
    let (s, e) = ends(&c.segments[0]);
    let (ds, de) = (
        (s - cubic.point(0.15)).norm(),
        (e - cubic.point(0.85)).norm(),
    );
    let occ = truth()["bspline_points.step"]["points"][0].clone();
    let occ_end = python::json_point(&occ[occ.as_array().unwrap().len() - 1]);
    println!(
        "ends off the generator's C(0.15), C(0.85): {ds:.2e}, {de:.2e}; OpenCASCADE's end: {:.2e}",
        (occ_end - cubic.point(0.85)).norm()
    );
    // the file holds the points to 12 digits
    assert!(ds < 1e-12 * 50.0 && de < 1e-12 * 50.0, "{ds} {de}");
}

/// The section joins into one curve (a composite of a B-spline, an arc and a line) whose length is
/// OpenCASCADE's, and its kind is a composite.
#[test]
fn the_section_joins_into_one_curve() {
    let t = truth();
    for file in ["section.step", "section.igs"] {
        let g = read_cad(data().join(file), CadKind::Curve, 0).unwrap();
        assert_eq!(g.segments, 3, "{file}");
        let Geometry::Curve(c) = g.geometry else {
            panic!("a curve")
        };
        assert!(c.is_rational());
        let len = arc_length(&c);
        let occ = t[file]["length"].as_f64().unwrap();
        assert!((len - occ).abs() < 1e-12 * occ, "{file}: {len} {occ}");
        let (s, e) = ends(&c);
        assert!((s - Vec3::new(100.0, 0.5, 0.0)).norm() < 1e-10);
        assert!((e - Vec3::new(100.0, -0.5, 0.0)).norm() < 1e-10);
    }
    let contents = read_contents(data().join("section.step")).unwrap();
    assert_eq!(contents.composites.len(), 1);
    assert!(contents.curves.is_empty());
}

/// Every prefix (100 cut points), 300 single-character corruptions and 60 deletions of each STEP and
/// IGES conic fixture give a curve or a typed one-line error: never a panic.
#[test]
fn corrupted_conic_files_never_panic() {
    use fairfit::io::cad_read::{parse_cad, select, CadFormat};
    let (mut errors, mut read) = (0, 0);
    for file in [
        "arc_deg.step",
        "arc_points_reversed.step",
        "ellipse_arc.step",
        "parabola_arc.step",
        "hyperbola_arc.step",
        "section.step",
        "arc.igs",
        "ellipse_arc.igs",
        "section.igs",
    ] {
        let bytes = std::fs::read(data().join(file)).unwrap();
        let format = CadFormat::from_path(file).unwrap();
        let mut variants: Vec<Vec<u8>> = (0..100)
            .map(|k| bytes[..bytes.len() * k / 100].to_vec())
            .collect();
        for k in 0..300 {
            let mut v = bytes.clone();
            let at = (k * 7919) % v.len();
            v[at] = b"()#,;9H'./ EF-0"[k % 15];
            variants.push(v);
        }
        for k in 0..60 {
            let mut v = bytes.clone();
            v.remove((k * 15_485_863) % v.len());
            variants.push(v);
        }
        for v in &variants {
            let text = String::from_utf8_lossy(v);
            match parse_cad(&text, format).and_then(|c| select(c, CadKind::Any, 0, "x")) {
                Ok(_) => read += 1,
                Err(e) => {
                    errors += 1;
                    let m = e.to_string();
                    assert!(!m.contains('\n') && !m.is_empty(), "{file}: {m}");
                }
            }
        }
    }
    println!("{errors} errors, {read} read");
    assert!(errors > 500 && read > 500, "{errors} {read}");
}

/// Hostile numbers in the conic entities (zero, negative, NaN-like and huge radii, degenerate axes,
/// trims out of range, points off the curve, no plane-angle unit fairfit knows): one-line errors
/// naming the entity, never a panic.
#[test]
fn hostile_conic_data_gives_one_line_errors() {
    use fairfit::io::cad_read::{parse_cad, select, CadFormat};
    let step = std::fs::read_to_string(data().join("arc_rad.step")).unwrap();
    let iges = std::fs::read_to_string(data().join("arc.igs")).unwrap();
    let ell = std::fs::read_to_string(data().join("ellipse_arc.igs")).unwrap();
    let cases: Vec<(String, CadFormat, &str)> = vec![
        (
            step.replace("CIRCLE('',#18,7.5)", "CIRCLE('',#18,0.)"),
            CadFormat::Step,
            "#17",
        ),
        (
            step.replace("CIRCLE('',#18,7.5)", "CIRCLE('',#18,-7.5)"),
            CadFormat::Step,
            "not a finite positive length",
        ),
        (
            step.replace("CIRCLE('',#18,7.5)", "CIRCLE('',#18,1.E309)"),
            CadFormat::Step,
            "line",
        ),
        (
            step.replace("CIRCLE('',#18,7.5)", "CIRCLE('',#18,'r')"),
            CadFormat::Step,
            "not a finite positive length",
        ),
        (
            step.replace(
                "#21 = DIRECTION('',(0.980580675691,-6.938893903907E-18,-0.196116135138)",
                "#21 = DIRECTION('',(0.188144173677,0.282216260515,0.940720868384)",
            ),
            CadFormat::Step,
            "degenerate",
        ),
        (
            step.replace("PARAMETER_VALUE(0.4)", "PARAMETER_VALUE(1.E200)"),
            CadFormat::Step,
            "not usable angles",
        ),
        (
            step.replace("(#22,PARAMETER_VALUE(0.4))", "(PARAMETER_VALUE(0.4),#22)")
                .replace(".T.,.PARAMETER.", ".T.,.CARTESIAN.")
                .replace(
                    "#22 = CARTESIAN_POINT('',(7.612160587474",
                    "#22 = CARTESIAN_POINT('',(70.612160587474",
                ),
            CadFormat::Step,
            "off the circle",
        ),
        (
            step.replace("SI_UNIT($,.RADIAN.)", "SI_UNIT($,.STERADIAN.)"),
            CadFormat::Step,
            "plane-angle unit",
        ),
        (
            iges.replace(
                "100,0.,0.,0.,6.907957455,2.920637567",
                "100,0.,0.,0.,0.000000000,0.000000000",
            ),
            CadFormat::Iges,
            "DE 1",
        ),
        (
            iges.replace("-7.282186239,1.794369969;", "-9.282186239,1.794369969;"),
            CadFormat::Iges,
            "not one circle",
        ),
        (
            ell.replacen("104,1.234567901E-02,", "104,-1.23456790E-02,", 1),
            CadFormat::Iges,
            "hyperbolic arc: the start point",
        ),
    ];
    for (k, (text, format, want)) in cases.iter().enumerate() {
        assert_ne!(
            text,
            if *format == CadFormat::Step {
                &step
            } else if text.contains("104,") {
                &ell
            } else {
                &iges
            },
            "case {k} changes nothing"
        );
        let e = parse_cad(text, *format)
            .and_then(|c| select(c, CadKind::Curve, 0, "f"))
            .map(|g| g.source)
            .unwrap_err()
            .to_string();
        println!("case {k}: {e}");
        assert!(e.contains(want) && !e.contains('\n'), "case {k}: {e}");
    }
}

/// Extreme but finite conic data (radius 1e300, tiny radius, a far-away centre) reads or fails with one
/// line; it never panics, and a read circle is still exact where it is finite.
#[test]
fn extreme_conic_sizes_never_panic() {
    use fairfit::io::cad_read::{parse_cad, select, CadFormat};
    let step = std::fs::read_to_string(data().join("circle.step")).unwrap();
    for (from, to) in [
        ("CIRCLE('',#18,7.5)", "CIRCLE('',#18,1.E300)"),
        ("CIRCLE('',#18,7.5)", "CIRCLE('',#18,1.E-300)"),
        (
            "#19 = CARTESIAN_POINT('',(1.,2.,3.))",
            "#19 = CARTESIAN_POINT('',(1.E308,2.,3.))",
        ),
    ] {
        let text = step.replace(from, to);
        assert_ne!(text, step, "{to}");
        match parse_cad(&text, CadFormat::Step).and_then(|c| select(c, CadKind::Curve, 0, "f")) {
            Ok(g) => {
                let Geometry::Curve(c) = g.geometry else {
                    panic!("a curve")
                };
                let (a, b) = c.domain();
                let _ = c.point(0.5 * (a + b));
            }
            Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
        }
    }
}
