//! `fairfit curve`: a tolerance fit with its report checked against an independent projection, and
//! ill-posed inputs (one-line error, exit 1, no panic).

use assert_cmd::Command;
use fairfit::diffgeo::CurveProjector;
use fairfit::io::{read_geometry, read_points, Geometry};
use serde_json::Value;
use std::io::Write;
use tempfile::{NamedTempFile, TempDir};

fn data(name: &str) -> String {
    format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn file_with(content: &[u8]) -> NamedTempFile {
    let mut f = NamedTempFile::new().unwrap();
    f.write_all(content).unwrap();
    f.flush().unwrap();
    f
}

fn fails_cleanly(args: &[&str], needle: &str) {
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(args)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
    assert_eq!(lines.len(), 1, "one line expected: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("internal error"),
        "{err}"
    );
    assert!(
        err.to_lowercase().contains(needle),
        "'{needle}' not in: {err}"
    );
}

#[test]
fn quarter_ellipse_within_rel_tol_and_report_agrees() {
    let dir = TempDir::new().unwrap();
    let (c, r) = (dir.path().join("c.json"), dir.path().join("r.json"));
    Command::cargo_bin("fairfit")
        .unwrap()
        .args([
            "curve",
            &data("quarter_ellipse_200.csv"),
            "--method",
            "lsq",
            "--rel-tol",
            "1e-3",
        ])
        .arg("-o")
        .arg(&c)
        .arg("--report")
        .arg(&r)
        .assert()
        .success();
    let Geometry::Curve(curve) = read_geometry(&c).unwrap() else {
        panic!("not a curve")
    };
    let pts = read_points(data("quarter_ellipse_200.csv")).unwrap().points;
    let proj = CurveProjector::new(&curve, 64);
    let worst = pts
        .iter()
        .map(|&q| proj.project(q).distance)
        .fold(0.0, f64::max);
    assert!(worst <= 1e-3, "{worst}");
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(&r).unwrap()).unwrap();
    assert_eq!(
        rep["control_points"].as_u64().unwrap() as usize,
        curve.n_control_points()
    );
    assert!((rep["max_deviation"].as_f64().unwrap() - worst).abs() < 1e-9);
    assert!(rep["fairness"].as_f64().unwrap() >= 0.0);
    assert!(rep["fit_seconds"].as_f64().unwrap() > 0.0);
}

#[test]
fn blunt_trailing_edge_closed_reports_two_corners() {
    let dir = TempDir::new().unwrap();
    let r = dir.path().join("r.json");
    Command::cargo_bin("fairfit")
        .unwrap()
        .args([
            "curve",
            &data("fx77w343.csv"),
            "--method",
            "lsq",
            "--closed",
            "-o",
        ])
        .arg(dir.path().join("c.json"))
        .arg("--report")
        .arg(&r)
        .assert()
        .success();
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(&r).unwrap()).unwrap();
    assert_eq!(rep["corners"].as_array().unwrap().len(), 2);
    assert!(rep["max_deviation"].as_f64().unwrap() <= rep["tolerance"].as_f64().unwrap());
    // corners disabled: a periodic closed fit, no corners
    Command::cargo_bin("fairfit")
        .unwrap()
        .args([
            "curve",
            &data("fx77w343.csv"),
            "--method",
            "lsq",
            "--closed",
            "--no-corners",
            "--rel-tol",
            "5e-3",
            "-o",
        ])
        .arg(dir.path().join("c2.json"))
        .arg("--report")
        .arg(&r)
        .assert()
        .success();
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(&r).unwrap()).unwrap();
    assert_eq!(rep["corners"].as_array().unwrap().len(), 0);
}

#[test]
fn collinear_points_fit_a_line() {
    let f = file_with(b"x,y\n0,0\n1,1\n2,2\n3,3\n4,4\n5,5\n");
    let dir = TempDir::new().unwrap();
    let r = dir.path().join("r.json");
    Command::cargo_bin("fairfit")
        .unwrap()
        .arg("curve")
        .arg(f.path())
        .arg("--report")
        .arg(&r)
        .assert()
        .success();
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(&r).unwrap()).unwrap();
    assert_eq!(rep["control_points"], 4);
    assert!(rep["max_deviation"].as_f64().unwrap() < 1e-9);
}

#[test]
fn duplicates_warn_on_stderr() {
    let f = file_with(b"0,0\n1,1\n1,1\n2,0\n3,1\n4,0\n");
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .arg("curve")
        .arg(f.path())
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("dropped 1 consecutive duplicate"));
}

#[test]
fn ill_posed_inputs_fail_with_one_line() {
    let two = file_with(b"0,0\n1,1\n");
    fails_cleanly(&["curve", two.path().to_str().unwrap()], "at least 4");
    let same = file_with(b"1,1\n1,1\n1,1\n1,1\n1,1\n");
    fails_cleanly(&["curve", same.path().to_str().unwrap()], "distinct points");
    let nan = file_with(b"x,y\n0,0\n1,nan\n2,2\n3,1\n");
    fails_cleanly(&["curve", nan.path().to_str().unwrap()], ":3:");
    let empty = file_with(b"");
    fails_cleanly(&["curve", empty.path().to_str().unwrap()], "no points");
    let binary = file_with(&[0u8, 159, 146, 150, 255, 0, 1, 2, 3]);
    fails_cleanly(
        &["curve", binary.path().to_str().unwrap()],
        "not a text file",
    );
    fails_cleanly(&["curve", "/nonexistent/points.csv"], "nonexistent");
    let ok = data("quarter_ellipse_200.csv");
    fails_cleanly(
        &["curve", &ok, "--method", "integrated", "--span-fairness=-1"],
        "span fairness",
    );
    fails_cleanly(&["curve", &ok, "--pareto-curves", "/tmp/x"], "--pareto");
    fails_cleanly(&["curve", &ok, "--tol=-1"], "tolerance");
    fails_cleanly(&["curve", &ok, "--corner-angle", "0"], "corner-angle");
}
