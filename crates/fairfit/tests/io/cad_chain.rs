//! Composite curves read from CAD files: a STEP `COMPOSITE_CURVE` (fixture `tests/data/occ_composite.step`:
//! a parameter-trimmed rational arc, a cubic stored backwards with `same_sense .F.`, a reparametrised
//! cubic segment) and an IGES 102 written by OpenCASCADE for a wire of three edges.
//!
//! Truths: analytic values of the segments (circle radius, Bernstein form of the backwards cubic), and,
//! with `$FAIRFIT_PYTHON`, OpenCASCADE's own reading of the STEP file (its edges sampled, its length)
//! and OpenCASCADE's evaluation of the wire's curves (`tests/python/occ_make_sections.py`).

use crate::common::python;

use fairfit::diffgeo::{arc_length, CurveProjector};
use fairfit::fit::sampling::{extent, sample_chain};
use fairfit::io::cad_chain::{join_segments, open_gaps};
use fairfit::io::cad_read::{parse_cad, read_cad, read_cad_chain, select, CadFormat, CadKind};
use fairfit::io::Geometry;
use fairfit::{NurbsCurve, Vec3};
use std::path::{Path, PathBuf};

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/occ_composite.step")
}

fn joined(path: &Path) -> NurbsCurve {
    match read_cad(path, CadKind::Curve, 0).unwrap().geometry {
        Geometry::Curve(c) => c,
        other => panic!("{other:?}"),
    }
}

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairfit-composite-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn bezier(p: &[Vec3; 4], t: f64) -> Vec3 {
    let s = 1.0 - t;
    p[0] * (s * s * s) + p[1] * (3.0 * s * s * t) + p[2] * (3.0 * s * t * t) + p[3] * (t * t * t)
}

/// The STEP composite against analytic truths: the first segment (the arc's parameters [0.2, 1]) lies
/// on the circle of radius 20 about (0, 20, 0) (to the 12 digits the file holds); the second runs the stored cubic backwards; the joined
/// curve is C0 at the joints (knots of multiplicity 3 at 1 and 2) and its domain is [0.2, 4] (the
/// reparametrised last segment spans its param_length 2, ISO 10303-42, not its parent's range [0, 1]).
#[test]
fn step_composite_reads_to_analytic_values() {
    let g = read_cad(fixture(), CadKind::Any, 0).unwrap();
    assert_eq!(
        (g.source.as_str(), g.count, g.segments),
        ("#49 (composite of 3 segments)", 1, 3)
    );
    let Geometry::Curve(c) = g.geometry else {
        panic!("a curve")
    };
    assert_eq!((c.degree(), c.domain()), (3, (0.2, 4.0)));
    assert!(c.is_rational());
    for joint in [1.0, 2.0] {
        assert_eq!(c.knots().iter().filter(|&&k| k == joint).count(), 3);
    }
    let centre = Vec3::new(0.0, 20.0, 0.0);
    for i in 0..=40 {
        let u = 0.2 + 0.8 * i as f64 / 40.0;
        // OpenCASCADE writes 12 significant digits (the weight 0.707106781187)
        assert!(((c.point(u) - centre).norm() - 20.0).abs() < 1e-10, "{u}");
    }
    let back = [
        Vec3::new(40.0, 10.0, 5.0),
        Vec3::new(30.0, 34.0, 3.0),
        Vec3::new(20.0, 30.0, 0.0),
        Vec3::new(20.0, 20.0, 0.0),
    ];
    for i in 0..=40 {
        let t = i as f64 / 40.0;
        let want = bezier(&back, 1.0 - t);
        assert!((c.point(1.0 + t) - want).norm() < 1e-12, "{t}");
    }
    assert!((c.point(4.0) - Vec3::new(70.0, 0.0, 0.0)).norm() < 1e-12);
    // the chain `fairfit curve` fits: every segment sampled, the two joint points once
    let chain = read_cad_chain(fixture(), 0).unwrap();
    assert_eq!(chain.segments.len(), 3);
    assert!(open_gaps(&chain.segments).is_empty());
    let pts = sample_chain(&chain.segments);
    let each: usize = chain
        .segments
        .iter()
        .map(|s| {
            let cap = fairfit::fit::sampling::MAX_CHORD * extent(&chain.segments);
            fairfit::fit::sampling::sample_curve_chord(s, cap).len()
        })
        .sum();
    assert_eq!(pts.len(), each - 2);
    let proj = CurveProjector::new(&c, 16);
    let off = pts
        .iter()
        .map(|&p| proj.project(p).distance)
        .fold(0.0, f64::max);
    assert!(off < 1e-11, "{off}");
    assert_eq!(pts[0], c.point(0.2));
    assert_eq!(*pts.last().unwrap(), c.point(4.0));
}

/// OpenCASCADE reads the same file as a wire: its edges, sampled along their orientation, lie on
/// fairfit's joined curve (to 1e-12 of the size), start and end where it does, and the lengths agree.
#[test]
fn step_composite_agrees_with_opencascade() {
    let Some(python) = python::python_or_skip("OpenCASCADE's reading of the composite") else {
        return;
    };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_composite.py");
    let out = std::process::Command::new(&python)
        .arg(&script)
        .arg("read")
        .arg(fixture())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let v: serde_json::Value =
        serde_json::from_str(stdout.lines().rfind(|l| l.starts_with('{')).unwrap()).unwrap();
    let c = joined(&fixture());
    let proj = CurveProjector::new(&c, 16);
    let edges = v["points"].as_array().unwrap();
    assert_eq!(edges.len(), 3);
    let mut worst = 0.0f64;
    let mut all = Vec::new();
    for e in edges {
        for q in python::json_points(e) {
            worst = worst.max(proj.project(q).distance);
            all.push(q);
        }
    }
    let length = v["length"].as_f64().unwrap();
    let ours = arc_length(&c);
    println!("OCC edges: {worst:.2e} from the joined curve; length {length} vs {ours}");
    assert!(worst < 1e-12 * 70.0, "{worst}");
    assert!((all[0] - c.point(0.2)).norm() < 1e-12 * 70.0);
    assert!((all[all.len() - 1] - c.point(4.0)).norm() < 1e-12 * 70.0);
    assert!((length - ours).abs() < 1e-9 * length, "{length} {ours}");
}

/// OpenCASCADE writes a wire of three edges as one IGES 102 of three 126s: the chain's segments
/// evaluate to OpenCASCADE's points of each curve, and the joined curve too (each segment shifted).
#[test]
fn iges_composite_from_opencascade_matches_its_curves() {
    let Some(python) = python::python_or_skip("the OpenCASCADE-written wire") else {
        return;
    };
    let d = dir("occ");
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_make_sections.py");
    let out = std::process::Command::new(&python)
        .arg(&script)
        .arg(&d)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let case: serde_json::Value = stdout
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .find(|c| c["kind"] == "composite")
        .unwrap();
    let file = case["file"].as_str().unwrap();
    let chain = read_cad_chain(file, 0).unwrap();
    assert_eq!(chain.segments.len(), 3);
    assert_eq!(chain.source, "DE 1 (composite of 3 segments)");
    let j = joined(Path::new(file));
    let mut offset = chain.segments[0].domain().0;
    let mut worst = 0.0f64;
    for (seg, pts) in chain
        .segments
        .iter()
        .zip(case["curves"].as_array().unwrap())
    {
        let (a, b) = seg.domain();
        for (k, want) in python::json_points(pts).into_iter().enumerate() {
            let u = a + (b - a) * k as f64 / 40.0;
            worst = worst.max((seg.point(u) - want).norm());
            worst = worst.max((j.point(offset + (u - a)) - want).norm());
        }
        offset += b - a;
    }
    println!("IGES 102 segments and joined curve vs OpenCASCADE: {worst:.2e} mm");
    assert!(worst < 1e-9 * 70.0, "{worst}");
    let _ = std::fs::remove_dir_all(&d);
}

/// A segment moved 1 mm away: the composite is no longer one curve (one-line error naming the gap),
/// while its chain still reads; a segment of a kind fairfit does not read is named.
#[test]
fn gaps_and_unsupported_segments_give_one_line_errors() {
    let text = std::fs::read_to_string(fixture()).unwrap();
    let d = dir("gap");
    let gap = d.join("gap.step");
    // the backwards cubic's last pole (the joint with the arc) moved by 1 mm in y
    let moved = text.replace(
        "#28 = CARTESIAN_POINT('',(20.,20.,0.));",
        "#28 = CARTESIAN_POINT('',(20.,21.,0.));",
    );
    assert_ne!(moved, text);
    std::fs::write(&gap, moved).unwrap();
    let e = read_cad(&gap, CadKind::Curve, 0).unwrap_err().to_string();
    assert!(
        e.contains("gap.step: the composite curve #49 (composite of 3 segments): segments 1 and 2 are 1.000e0 apart")
            && e.contains("`fairfit curve` re-fits it as one chain of points"),
        "{e}"
    );
    assert!(!e.contains('\n'));
    let chain = read_cad_chain(&gap, 0).unwrap();
    assert_eq!(open_gaps(&chain.segments), vec![(0, 1.0)]);
    assert!(join_segments(&chain.segments).is_err());
    // the last segment's parent a LINE: the composite is named, its B-spline members read alone
    let line = text.replace(
        "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#31,2.)",
        "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#900,2.)",
    ) + "";
    let line = line.replace(
        "ENDSEC;\nEND-ISO-10303-21;",
        "#900 = LINE('',#39,#901);\n#901 = VECTOR('',#14,1.);\nENDSEC;\nEND-ISO-10303-21;",
    );
    let c = parse_cad(&line, CadFormat::Step).unwrap();
    assert!(c.composites.is_empty());
    assert!(
        c.other_curves
            .contains("COMPOSITE_CURVE (with a LINE segment)"),
        "{:?}",
        c.other_curves
    );
    assert_eq!(c.curves.len(), 3);
    // a param_length that is no positive number
    for bad in ["0.", "-2.", "$"] {
        let t = text.replace(
            "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#31,2.)",
            &format!("REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#31,{bad})"),
        );
        let e = parse_cad(&t, CadFormat::Step).unwrap_err().to_string();
        assert!(
            e.contains("(#48): the param_length of a REPARAMETRISED_COMPOSITE_CURVE_SEGMENT must be a positive number"),
            "{bad}: {e}"
        );
        assert!(!e.contains('\n'));
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Straight segments: the last segment a `TRIMMED_CURVE` of a `LINE` (by parameter values, and by its
/// trimming points) or a `POLYLINE`: the joined curve runs straight along them (degree 1 raised to 3).
#[test]
fn trimmed_lines_and_polylines_are_straight_segments() {
    let text = std::fs::read_to_string(fixture()).unwrap();
    let with = |parent: &str, extra: &str| {
        let t = text.replace(
            "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#31,2.)",
            &format!("REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,{parent},2.)"),
        );
        let t = t.replace(
            "ENDSEC;\nEND-ISO-10303-21;",
            &format!(
                "#900 = CARTESIAN_POINT('',(40.,10.,5.));#901 = CARTESIAN_POINT('',(70.,0.,0.));\
                 #902 = DIRECTION('',(6.,-2.,-1.));#903 = VECTOR('',#902,15.);\
                 #904 = LINE('',#900,#903);\
                 #905 = CARTESIAN_POINT('',(55.,10.,2.));\n{extra}\nENDSEC;\nEND-ISO-10303-21;"
            ),
        );
        let c = parse_cad(&t, CadFormat::Step).unwrap();
        // the third B-spline (#31) is no member any more: it comes first, the composite second
        let g = select(c, CadKind::Curve, 1, "x").unwrap();
        assert_eq!(
            (g.source.as_str(), g.count),
            ("#49 (composite of 3 segments)", 2)
        );
        match g.geometry {
            Geometry::Curve(c) => c,
            other => panic!("{other:?}"),
        }
    };
    // |(6, -2, -1)| = sqrt(41); magnitude 15: parameter sqrt(41) / 3 moves by 5 (6, -2, -1) to (70, 0, 0)
    let u1 = 41f64.sqrt() / 3.0;
    for trims in [
        format!("(PARAMETER_VALUE(0.)),(PARAMETER_VALUE({u1:?}))"),
        "(#900),(#901)".to_string(),
    ] {
        let c = with(
            "#906",
            &format!("#906 = TRIMMED_CURVE('',#904,{trims},.T.,.PARAMETER.);"),
        );
        assert_eq!((c.degree(), c.domain()), (3, (0.2, 4.0)), "{trims}");
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let want = Vec3::new(40.0 + 30.0 * t, 10.0 - 10.0 * t, 5.0 - 5.0 * t);
            assert!(
                (c.point(2.0 + 2.0 * t) - want).norm() < 1e-12,
                "{trims} {t}"
            );
        }
    }
    let c = with("#906", "#906 = POLYLINE('',(#900,#905,#901));");
    assert_eq!(c.domain(), (0.2, 4.0));
    assert!((c.point(2.5) - Vec3::new(47.5, 10.0, 3.5)).norm() < 1e-12);
    assert!((c.point(3.0) - Vec3::new(55.0, 10.0, 2.0)).norm() < 1e-12);
    assert!((c.point(3.5) - Vec3::new(62.5, 5.0, 1.0)).norm() < 1e-12);
}

/// A trimmed `LINE` reads its `DIRECTION` and trims with the conics' code: `.CARTESIAN.` prefers the
/// trimming points over the parameters, and a zero or one-ratio `DIRECTION` or a non-finite parameter
/// is a one-line error naming the instance.
#[test]
fn trimmed_lines_share_the_conic_direction_and_trims() {
    let text = std::fs::read_to_string(fixture()).unwrap();
    let with = |dir: &str, line: &str| {
        let t = text.replace(
            "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#31,2.)",
            "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,#906,2.)",
        );
        let t = t.replace(
            "ENDSEC;\nEND-ISO-10303-21;",
            &format!(
                "#900 = CARTESIAN_POINT('',(40.,10.,5.));#901 = CARTESIAN_POINT('',(70.,0.,0.));\
                 #902 = DIRECTION('',{dir});#903 = VECTOR('',#902,15.);\
                 #904 = LINE('',#900,#903);\n{line}\nENDSEC;\nEND-ISO-10303-21;"
            ),
        );
        parse_cad(&t, CadFormat::Step)
            .and_then(|c| select(c, CadKind::Curve, 1, "x"))
            .map(|g| match g.geometry {
                Geometry::Curve(c) => c,
                other => panic!("{other:?}"),
            })
    };
    // both trims given, the parameters pointing elsewhere: the points win under .CARTESIAN.
    let both = "#906 = TRIMMED_CURVE('',#904,(#900,PARAMETER_VALUE(0.)),(#901,PARAMETER_VALUE(2.)),.T.,.CARTESIAN.);";
    let c = with("(6.,-2.,-1.)", both).unwrap();
    assert!((c.point(4.0) - Vec3::new(70.0, 0.0, 0.0)).norm() < 1e-12);
    assert!((c.point(3.0) - Vec3::new(55.0, 5.0, 2.5)).norm() < 1e-12);
    // ... and the parameters under .PARAMETER.: 15 (6, -2, -1) / sqrt(41) per unit from (40, 10, 5)
    let c = with("(6.,-2.,-1.)", &both.replace("CARTESIAN.)", "PARAMETER.)")).unwrap();
    let step = Vec3::new(6.0, -2.0, -1.0) * (15.0 / 41f64.sqrt());
    assert!((c.point(4.0) - (Vec3::new(40.0, 10.0, 5.0) + step * 2.0)).norm() < 1e-12);
    let by_params = "#906 = TRIMMED_CURVE('',#904,(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(1.)),.T.,.PARAMETER.);";
    for (dir, line, want) in [
        ("(0.,0.,0.)", by_params, "the DIRECTION #902 is zero or not finite"),
        ("(1.)", by_params, "the DIRECTION #902 needs 2 or 3 ratios"),
        (
            "(6.,-2.,-1.)",
            "#906 = TRIMMED_CURVE('',#904,(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(1.E999)),.T.,.PARAMETER.);",
            "a PARAMETER_VALUE trim is not a finite number",
        ),
        (
            "(6.,-2.,-1.)",
            "#906 = TRIMMED_CURVE('',#904,(PARAMETER_VALUE(0.)),(),.T.,.PARAMETER.);",
            "neither a PARAMETER_VALUE nor a CARTESIAN_POINT",
        ),
    ] {
        let e = with(dir, line).unwrap_err().to_string();
        assert!(e.contains(want) && e.contains("(#906)"), "{dir} {line}: {e}");
        assert_eq!(e.lines().count(), 1);
    }
}

/// Every prefix (200 cut points), 400 single-character corruptions and 100 deletions of the composite
/// fixture give a curve or a typed one-line error: never a panic.
#[test]
fn corrupted_composites_never_panic() {
    let bytes = std::fs::read(fixture()).unwrap();
    let mut variants: Vec<Vec<u8>> = (0..200)
        .map(|k| bytes[..bytes.len() * k / 200].to_vec())
        .collect();
    for k in 0..400 {
        let mut v = bytes.clone();
        let at = (k * 7919) % v.len();
        v[at] = b"()#,;9H'./ EF"[k % 13];
        variants.push(v);
    }
    for k in 0..100 {
        let mut v = bytes.clone();
        v.remove((k * 15_485_863) % v.len());
        variants.push(v);
    }
    let (mut errors, mut chains) = (0, 0);
    for v in &variants {
        let text = String::from_utf8_lossy(v);
        let read = parse_cad(&text, CadFormat::Step).and_then(|c| {
            let n = c.composites.len();
            select(c, CadKind::Any, 0, "x").map(|_| n)
        });
        match read {
            Ok(n) => chains += n,
            Err(e) => {
                errors += 1;
                let m = e.to_string();
                assert!(!m.contains('\n') && !m.is_empty(), "{m}");
            }
        }
    }
    println!(
        "{} variants, {errors} errors, {chains} composites read",
        variants.len()
    );
    assert!(errors > 100 && chains > 100, "{errors} {chains}");
}
