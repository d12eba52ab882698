//! STEP and IGES files as input of `fairfit info`, `eval`, `plot`, `export` and `curve`, end to end.
//!
//! A curve written by fairfit's own writers reads back bit for bit, so `info` and `eval` of the STEP and
//! IGES files must print exactly what they print for the JSON; `fairfit curve part.igs` re-fairs the
//! CAD curve: the result is checked against the original curve itself (densely, at parameters other
//! than the sampled ones) and must be fairer. Broken files fail with exit code 1 and one line.

use assert_cmd::Command;
use fairfit::diffgeo::projection::CurveProjector;
use fairfit::io::{read_geometry, Geometry};
use fairfit::NurbsCurve;
use std::path::{Path, PathBuf};

fn fairfit() -> Command {
    Command::cargo_bin("fairfit").unwrap()
}

/// A wiggly spatial cubic (7 poles, an interior knot of multiplicity 2), in millimetres.
fn curve_json() -> String {
    serde_json::json!({
        "kind": "curve", "degree": 3,
        "knots": [0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.45, 1.0, 1.0, 1.0, 1.0],
        "control_points": [[0, 0, 0], [10, 25, 2], [30, 32, -4], [55, 5, 3], [70, -10, 0],
                           [90, 15, 6], [110, 30, 1]],
    })
    .to_string()
}

fn stdout_of(args: &[&str]) -> String {
    let out = fairfit().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "fairfit {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn setup(d: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let json = d.join("part.json");
    std::fs::write(&json, curve_json()).unwrap();
    let (step, iges) = (d.join("part.stp"), d.join("part.igs"));
    fairfit()
        .arg("export")
        .arg(&json)
        .arg("--step")
        .arg(&step)
        .arg("--iges")
        .arg(&iges)
        .assert()
        .success();
    (json, step, iges)
}

#[test]
fn info_eval_plot_and_export_read_step_and_iges() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (json, step, iges) = setup(d);
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let info = stdout_of(&["info", &s(&json)]);
    assert!(!info.contains("\"source\""), "{info}");
    // the CAD files' info is the JSON's plus where the curve came from
    let without_source = |p: &Path| -> (String, serde_json::Value) {
        let mut v: serde_json::Value = serde_json::from_str(&stdout_of(&["info", &s(p)])).unwrap();
        let src = v.as_object_mut().unwrap().remove("source").unwrap();
        (serde_json::to_string_pretty(&v).unwrap(), src)
    };
    let (step_info, src) = without_source(&step);
    assert_eq!(step_info, info.trim_end());
    assert_eq!(
        src,
        serde_json::json!({"format": "STEP", "entity": src["entity"], "kind": "B-spline curve",
            "segments": 1, "index": 0, "count": 1, "unit": "mm", "unit_declared": true,
            "mm_per_unit": 1.0})
    );
    assert!(src["entity"].as_str().unwrap().starts_with('#'), "{src}");
    let (iges_info, src) = without_source(&iges);
    assert_eq!(iges_info, info.trim_end());
    assert_eq!(
        (src["format"].as_str(), src["entity"].as_str()),
        (Some("IGES"), Some("DE 1"))
    );
    let eval = stdout_of(&["eval", &s(&json), "--at", "0,0.3,0.5,1"]);
    assert_eq!(stdout_of(&["eval", &s(&step), "--at", "0,0.3,0.5,1"]), eval);
    assert_eq!(stdout_of(&["eval", &s(&iges), "--at", "0,0.3,0.5,1"]), eval);
    let svg = d.join("comb.svg");
    stdout_of(&["plot", &s(&iges), "-o", &s(&svg)]);
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let again = d.join("again.step");
    stdout_of(&["export", &s(&iges), "--step", &s(&again)]);
    assert_eq!(without_source(&again).0, info.trim_end());
}

#[test]
fn curve_refairs_a_cad_curve_within_its_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (json, _, iges) = setup(d);
    let (faired, faired_step, report) = (
        d.join("faired.json"),
        d.join("faired.step"),
        d.join("r.json"),
    );
    let out = fairfit()
        .arg("curve")
        .arg(&iges)
        .args(["--rel-tol", "1e-3", "-o"])
        .arg(&faired)
        .arg("--step")
        .arg(&faired_step)
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("points sampled on DE 1 (degree 3, 7 control points; 20 per knot span)"),
        "{stderr}"
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["tolerance_met"], true, "{r}");
    let tol = r["tolerance"].as_f64().unwrap();
    let curve = |p: &Path| -> NurbsCurve {
        match read_geometry(p).unwrap() {
            Geometry::Curve(c) => c,
            other => panic!("{other:?}"),
        }
    };
    let (original, refit) = (curve(&json), curve(&faired));
    // the STEP written beside the JSON holds the same curve
    assert_eq!(curve(&faired_step), refit);
    // the original curve, at 3001 parameters (not the sampled ones), stays within the tolerance of the
    // re-fit: the fit was checked against the exact curve between its samples and refitted (the first
    // fit, on the samples alone, let it stray 1.0002 of the tolerance)
    let projector = CurveProjector::new(&refit, 16);
    let worst = (0..3001)
        .map(|i| {
            projector
                .project(original.point((i as f64 + 0.37) / 3001.37))
                .distance
        })
        .fold(0.0f64, f64::max);
    assert!(worst <= tol, "{worst} > {tol}");
    let exact = &r["exact_curve"];
    assert_eq!(exact["within_tolerance"], true, "{r}");
    let reported = exact["max_deviation"].as_f64().unwrap();
    assert!(worst <= reported * (1.0 + 1e-4), "{worst} > {reported}");
    assert!(stderr.contains("the exact curve lies within"), "{stderr}");
    let fairness = |p: &Path| -> f64 {
        let v: serde_json::Value =
            serde_json::from_str(&stdout_of(&["info", p.to_str().unwrap()])).unwrap();
        v["fairness"].as_f64().unwrap()
    };
    let (f0, f1) = (fairness(&json), fairness(&faired));
    println!(
        "F {f0:.1} -> {f1:.1}, worst deviation {worst:.4} (tolerance {tol:.4}, {:.4} of it)",
        worst / tol
    );
    assert!(f1 < 0.8 * f0, "F {f0} -> {f1}");
}

fn failure(args: &[&str], code: i32) -> String {
    let out = fairfit().args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(code), "fairfit {args:?}");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    stderr
}

#[test]
fn broken_unsupported_and_empty_cad_files_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (json, step, iges) = setup(d);
    let text = std::fs::read_to_string(&step).unwrap();
    let truncated = d.join("truncated.step");
    std::fs::write(&truncated, &text[..text.len() * 2 / 3]).unwrap();
    let e = failure(&["info", truncated.to_str().unwrap()], 1);
    assert!(
        e.contains("truncated.step") && e.contains("truncated?"),
        "{e}"
    );
    let igs = std::fs::read_to_string(&iges).unwrap();
    let cut = d.join("cut.igs");
    std::fs::write(&cut, &igs[..igs.len() - 200]).unwrap();
    let e = failure(&["eval", cut.to_str().unwrap(), "--at", "0.5"], 1);
    assert!(e.contains("cut.igs") && e.contains("truncated"), "{e}");
    let unsupported = d.join("json.step");
    std::fs::write(&unsupported, curve_json()).unwrap();
    let e = failure(&["plot", unsupported.to_str().unwrap(), "-o", "x.svg"], 1);
    assert!(e.contains("not a STEP file"), "{e}");
    let lines = d.join("lines.step");
    let only_lines = {
        let a = text.find("B_SPLINE_CURVE_WITH_KNOTS").unwrap();
        let b = a + text[a..].find(';').unwrap();
        format!("{}LINE('',#1,#2){}", &text[..a], &text[b..])
    };
    std::fs::write(&lines, only_lines).unwrap();
    let e = failure(&["curve", lines.to_str().unwrap(), "-o", "x.json"], 1);
    assert!(
        e.contains("lines.step has no B-spline curve (found: LINE); export the edge as a B-spline"),
        "{e}"
    );
    let e = failure(&["info", json.to_str().unwrap(), "--index", "1"], 2);
    assert!(
        e.contains("--index and --entity choose an entity of a STEP or IGES file"),
        "{e}"
    );
    let e = failure(&["info", step.to_str().unwrap(), "--index", "3"], 2);
    assert!(
        e.contains("holds 1 B-spline curve; index 3 is out of range (0 to 0)"),
        "{e}"
    );
    let e = failure(&["curve", step.to_str().unwrap(), "--entity", "surface"], 2);
    assert!(e.contains("--entity surface"), "{e}");
}
