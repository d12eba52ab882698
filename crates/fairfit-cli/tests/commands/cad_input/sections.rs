//! `fairfit surface` from a STEP or IGES file: OpenCASCADE writes blade-like B-spline sections (and a
//! surface) with known poles (`tests/python/occ_make_sections.py`, run with `$FAIRFIT_PYTHON`); the
//! skinned surface must pass within the tolerance of OpenCASCADE's own evaluation of every section (at
//! 41 parameters each, not the sampled ones), and at a tight tolerance the surface's iso-curve at every
//! section must hold OpenCASCADE's section at 3001 parameters within it (the exact-section check
//! refits where the first surface strays). Files with too few curves and misused options fail with
//! one line.

use assert_cmd::Command;
use fairfit::diffgeo::CurveProjector;
use fairfit::nurbs::SurfaceWorkspace;
use fairfit::surface::SurfaceProjector;
use fairfit::{NurbsSurface, Vec3};
use std::path::Path;

use crate::common::{python, surface_run};

fn fairfit() -> Command {
    Command::cargo_bin("fairfit").unwrap()
}

fn points(v: &serde_json::Value) -> Vec<Vec3> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|p| {
            Vec3::new(
                p[0].as_f64().unwrap(),
                p[1].as_f64().unwrap(),
                p[2].as_f64().unwrap(),
            )
        })
        .collect()
}

/// Largest distance of `pts` from `s`.
fn max_distance(s: &NurbsSurface, pts: &[Vec3]) -> f64 {
    let proj = SurfaceProjector::new(s, 12);
    let mut ws = SurfaceWorkspace::new(s, 2);
    pts.iter()
        .map(|&q| proj.project(q, None, &mut ws).distance)
        .fold(0.0, f64::max)
}

/// Runs `fairfit surface FILE EXTRA -o ... --report ...`; returns the surface, the report and stderr.
fn skin(file: &str, extra: &[&str], d: &Path) -> (NurbsSurface, serde_json::Value, String) {
    let r = surface_run(d, "s", file, extra);
    (r.surface, r.report, r.stderr)
}

fn section_names(r: &serde_json::Value) -> Vec<String> {
    r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn sections_written_by_opencascade_are_skinned_within_the_tolerance() {
    let Some(python) = python::python_or_skip("the OpenCASCADE-written section files") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_make_sections.py");
    let out = std::process::Command::new(&python)
        .arg(&script)
        .arg(d)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cases: Vec<serde_json::Value> = stdout
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let case = |name: &str| -> &serde_json::Value {
        cases
            .iter()
            .find(|c| c["file"].as_str().unwrap().ends_with(name))
            .unwrap_or_else(|| panic!("{name} not written: {stdout}"))
    };
    for name in ["sections_mm.step", "sections_mm.igs", "sections_inch.step"] {
        let c = case(name);
        let file = c["file"].as_str().unwrap();
        let (s, r, stderr) = skin(file, &[], d);
        assert!(
            stderr.contains("5 sections from its B-spline curves in file order"),
            "{stderr}"
        );
        assert_eq!(
            stderr.contains("converted from inch to mm"),
            name.contains("inch")
        );
        assert_eq!(r["sections"].as_array().unwrap().len(), 5);
        assert_eq!(r["within_tolerance"], true);
        let tol = r["tolerance"].as_f64().unwrap();
        let mut worst = 0.0f64;
        for sec in c["curves"].as_array().unwrap() {
            worst = worst.max(max_distance(&s, &points(sec)));
        }
        println!(
            "{name}: worst OCC section point {worst:.3e} from the surface, tolerance {tol:.3e}"
        );
        assert!(worst <= tol, "{name}: {worst} > {tol}");
        // the exact sections at the default tolerance: within at once
        let e = &r["exact_sections"];
        let exact = e["max_deviation"].as_f64().unwrap();
        println!(
            "{name}: exact sections within {:.4} of the tolerance",
            exact / tol
        );
        assert_eq!(
            (e["refits"].as_u64(), &e["within_tolerance"]),
            (Some(0), &serde_json::json!(true))
        );
        assert!(exact >= worst && exact <= tol, "{exact} vs {worst}, {tol}");
    }
    // held to the exact sections: at 1e-5 of the size the first surface lets OpenCASCADE's sections
    // stray beyond the tolerance between the samples; the refit holds all 3001 x 5 of OpenCASCADE's
    // points within it, measured from the surface's iso-curve at each section's v
    let c = case("sections_mm.step");
    let file = c["file"].as_str().unwrap();
    let (s, r, stderr) = skin(file, &["--rel-tol", "1e-5"], d);
    let tol = r["tolerance"].as_f64().unwrap();
    let e = &r["exact_sections"];
    let first = e["first_max_deviation"].as_f64().unwrap();
    let kept = e["max_deviation"].as_f64().unwrap();
    let mut truth = 0.0f64;
    for (k, sec) in c["dense"].as_array().unwrap().iter().enumerate() {
        let v = r["sections"][k]["v"].as_f64().unwrap();
        let iso = s.iso_curve_v(v).unwrap();
        let proj = CurveProjector::new(&iso, 64);
        let worst = points(sec)
            .iter()
            .map(|&p| proj.project(p).distance)
            .fold(0.0, f64::max);
        let reported = r["sections"][k]["exact_max_deviation"].as_f64().unwrap();
        assert!(
            reported >= worst * (1.0 - 1e-4),
            "{k}: {reported} < {worst}"
        );
        truth = truth.max(worst);
    }
    println!(
        "--rel-tol 1e-5: exact sections first {:.4}, kept {:.4} of the tolerance ({} refits, {} points \
         added); OpenCASCADE's 3001 points per section within {:.4}",
        first / tol,
        kept / tol,
        e["refits"],
        e["added_points"],
        truth / tol
    );
    assert!(first > tol, "{first} <= {tol}: the case no longer strays");
    assert!(e["refits"].as_u64().unwrap() >= 1);
    assert_eq!(e["within_tolerance"], true);
    assert_eq!(r["within_tolerance"], true);
    assert!(kept <= tol && truth <= tol, "{kept} {truth} > {tol}");
    assert!(
        stderr.contains("the exact sections lie within") && stderr.contains("refit(s) with"),
        "{stderr}"
    );
    // the shuffled file in file order, and sorted along z
    let c = case("shuffled_mm.step");
    let file = c["file"].as_str().unwrap();
    let (_, r, _) = skin(file, &[], d);
    let names = section_names(&r);
    let (s, r, _) = skin(file, &["--order", "axis"], d);
    // written at z = 30, 0, 60, 12, 45
    let by_z: Vec<String> = [1, 3, 0, 4, 2].iter().map(|&i| names[i].clone()).collect();
    assert_eq!(section_names(&r), by_z);
    // each exact section went along with its samples: measured against its own iso-curve
    assert_eq!(r["exact_sections"]["within_tolerance"], true);
    assert!(
        r["exact_sections"]["max_deviation"].as_f64().unwrap()
            < 0.8 * r["tolerance"].as_f64().unwrap()
    );
    let tol = r["tolerance"].as_f64().unwrap();
    let all: Vec<Vec3> = c["curves"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(points)
        .collect();
    let dev = max_distance(&s, &all);
    println!("shuffled, --order axis: {dev:.3e} (tolerance {tol:.3e})");
    assert!(dev <= tol, "{dev} > {tol}");
    // a face is re-faired through its v-iso-curves: OpenCASCADE's 9 x 9 grid on the original surface
    // stays near the re-faired one also between the sections
    let c = case("face_mm.step");
    let (s, r, stderr) = skin(c["file"].as_str().unwrap(), &[], d);
    assert!(
        stderr.contains("re-fairing B-spline surface #")
            && stderr.contains("9 of its v-iso-curves"),
        "{stderr}"
    );
    assert_eq!(r["within_tolerance"], true);
    assert!(r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["reversed"] == false));
    let tol = r["tolerance"].as_f64().unwrap();
    let dev = max_distance(&s, &points(&c["curves"][0]));
    println!("face re-faired: OCC grid {dev:.3e} from it (tolerance {tol:.3e})");
    assert!(dev <= tol, "{dev} > {tol}");
    // a wire of three edges is one composite curve (IGES 102): one section, too few
    let o = d.join("o.json");
    fails(
        &[
            "surface",
            case("wire_mm.igs")["file"].as_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
        ],
        1,
        "holds 1 composite curve: a surface needs at least 2 sections",
    );
}

fn fails(args: &[&str], code: i32, needle: &str) {
    let out = fairfit().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.starts_with("error: ") && err.contains(needle), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn too_few_curves_and_misused_options_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let json = d.join("c.json");
    std::fs::write(
        &json,
        r#"{"kind": "curve", "degree": 2, "knots": [0, 0, 0, 1, 1, 1],
            "control_points": [[0, 0, 0], [1, 2, 0], [3, 0, 0]]}"#,
    )
    .unwrap();
    let step = d.join("one.step");
    fairfit()
        .arg("export")
        .arg(&json)
        .arg("--step")
        .arg(&step)
        .assert()
        .success();
    let s = step.to_str().unwrap();
    let o = d.join("o.json");
    let o = o.to_str().unwrap();
    fails(
        &["surface", s, "-o", o],
        1,
        "one.step holds 1 B-spline curve: a surface needs at least 2 sections",
    );
    fails(
        &["surface", s, "--index", "1", "-o", o],
        2,
        "--index chooses a B-spline surface to re-fair",
    );
    fails(
        &["surface", s, "--entity", "surface", "-o", o],
        1,
        "has no B-spline surface (found: 1 B-spline curve)",
    );
    fails(
        &["surface", s, json.to_str().unwrap(), "-o", o],
        2,
        "give it as the only input",
    );
    fails(
        &[
            "surface",
            json.to_str().unwrap(),
            "--entity",
            "curve",
            "-o",
            o,
        ],
        2,
        "--index and --entity choose an entity of a STEP or IGES file",
    );
}
