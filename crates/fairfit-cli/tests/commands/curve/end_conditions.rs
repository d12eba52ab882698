//! End conditions on every method of `fairfit curve` (`--start`/`--end` point and curvature with
//! `lsq` and `fit-then-fair` too), and `--start-from`/`--end-from` with `--continuity`, measured on
//! the analytic quarter ellipse `x = cos t, y = 0.5 sin t` (curvature 4 at t = 0, 0.5 at t = π/2)
//! from the written curves' own derivatives.

use crate::common::{curve_run, data, polyline};
use assert_cmd::Command;
use fairfit::io::{read_geometry, read_points, Geometry};
use fairfit::{NurbsCurve, Vec3};
use serde_json::Value;
use tempfile::TempDir;

/// Runs `fairfit curve FILE ARGS -o dir/NAME.json --report dir/NAME-report.json`.
fn run(dir: &TempDir, name: &str, file: &str, extra: &[&str]) -> (NurbsCurve, Value) {
    let run = curve_run(dir.path(), name, file, extra);
    (run.curve, run.report)
}

/// Point, unit tangent and curvature vector at the start (`at_end` false) or end of `c`.
fn frame(c: &NurbsCurve, at_end: bool) -> (Vec3, Vec3, Vec3) {
    let (a, b) = c.domain();
    let d = c.derivatives(if at_end { b } else { a }, 2);
    let s = d[1].norm();
    (d[0], d[1] / s, d[1].cross(d[2]).cross(d[1]) / s.powi(4))
}

fn angle(a: Vec3, b: Vec3) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

#[test]
fn every_method_holds_curvature_ends_of_the_ellipse_within_the_tolerance() {
    let file = data("quarter_ellipse_200.csv");
    let pts = read_points(&file).unwrap().points;
    let dir = TempDir::new().unwrap();
    for method in ["lsq", "fit-then-fair", "integrated"] {
        let (curve, rep) = run(
            &dir,
            method,
            &file,
            &[
                "--method",
                method,
                "--start",
                "curvature:0,1:4",
                "--end",
                "curvature:-1,0:0.5",
                "--rel-tol",
                "1e-4",
            ],
        );
        let (_, t0, k0) = frame(&curve, false);
        let (_, t1, k1) = frame(&curve, true);
        assert!(
            angle(t0, Vec3::new(0.0, 1.0, 0.0)) <= 1e-9,
            "{method}: {t0:?}"
        );
        assert!(
            angle(t1, Vec3::new(-1.0, 0.0, 0.0)) <= 1e-9,
            "{method}: {t1:?}"
        );
        // towards the centre: −x at the start, −y at the end
        assert!(
            (k0 - Vec3::new(-4.0, 0.0, 0.0)).norm() <= 4e-9,
            "{method}: {k0:?}"
        );
        assert!(
            (k1 - Vec3::new(0.0, -0.5, 0.0)).norm() <= 0.5e-9,
            "{method}: {k1:?}"
        );
        let tol = rep["tolerance"].as_f64().unwrap();
        let worst = polyline::polyline_deviation(&curve, &pts, 50_000);
        assert!(worst <= tol * (1.0 + 1e-6), "{method}: {worst} > {tol}");
        let ec = &rep["end_conditions"];
        assert_eq!(ec["start"]["order"], "g2", "{method}");
        assert!(ec["end"]["curvature_relative"].as_f64().unwrap() <= 1e-9);
        let ratio = ec["fairness_cost_ratio"].as_f64().unwrap();
        assert!(ratio.is_finite() && ratio > 0.0, "{method}: {ratio}");
    }
}

#[test]
fn a_given_end_point_is_where_the_lsq_curve_starts() {
    let file = data("quarter_ellipse_200.csv");
    let dir = TempDir::new().unwrap();
    for method in ["lsq", "fit-then-fair"] {
        let (curve, rep) = run(
            &dir,
            method,
            &file,
            &[
                "--method",
                method,
                "--start",
                "point:1.00002,0.00001",
                "--tol",
                "1e-4",
            ],
        );
        let (p0, _, _) = frame(&curve, false);
        assert!(
            (p0 - Vec3::new(1.00002, 0.00001, 0.0)).norm() <= 1e-12,
            "{p0:?}"
        );
        assert!(
            rep["end_conditions"]["start"]["point_distance"]
                .as_f64()
                .unwrap()
                <= 1e-12
        );
    }
}

/// Two halves of the ellipse: B continues A from A's curve file, with the continuity asked for,
/// measured between the two written curves.
#[test]
fn start_from_a_fairfit_curve_gives_the_continuity_asked_for() {
    let text = std::fs::read_to_string(data("quarter_ellipse_200.csv")).unwrap();
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .collect();
    let dir = TempDir::new().unwrap();
    let a_csv = dir.path().join("a.csv");
    let b_csv = dir.path().join("b.csv");
    std::fs::write(&a_csv, lines[..100].join("\n")).unwrap();
    std::fs::write(&b_csv, lines[99..].join("\n")).unwrap();
    let (a, _) = run(&dir, "a", a_csv.to_str().unwrap(), &["--rel-tol", "1e-4"]);
    let a_json = dir.path().join("a.json");
    let (pa, ta, ka) = frame(&a, true);
    for (method, continuity) in [
        ("lsq", "g1"),
        ("lsq", "g2"),
        ("fit-then-fair", "g2"),
        ("integrated", "g2"),
    ] {
        let (b, rep) = run(
            &dir,
            "b",
            b_csv.to_str().unwrap(),
            &[
                "--method",
                method,
                "--start-from",
                a_json.to_str().unwrap(),
                "--continuity",
                continuity,
                "--rel-tol",
                "1e-4",
            ],
        );
        let (pb, tb, kb) = frame(&b, false);
        assert!(
            (pb - pa).norm() <= 1e-12,
            "{method} {continuity}: gap {}",
            (pb - pa).norm()
        );
        assert!(
            angle(ta, tb) <= 1e-9,
            "{method} {continuity}: angle {}",
            angle(ta, tb)
        );
        let dk = (kb - ka).norm() / ka.norm();
        if continuity == "g2" {
            assert!(dk <= 1e-9, "{method}: curvature differs by {dk:e}");
        }
        let ec = &rep["end_conditions"]["start"];
        assert_eq!(ec["order"], continuity);
        assert!(ec["tangent_angle"].as_f64().unwrap() <= 1e-9);
    }
    // A leads into B's start read from its end side: `--end-from B:start` (the default)
    let b_json = dir.path().join("b.json");
    let (a2, _) = run(
        &dir,
        "a2",
        a_csv.to_str().unwrap(),
        &[
            "--end-from",
            b_json.to_str().unwrap(),
            "--continuity",
            "g1",
            "--method",
            "lsq",
        ],
    );
    let Geometry::Curve(b) = read_geometry(&b_json).unwrap() else {
        panic!()
    };
    let (p1, t1, _) = frame(&a2, true);
    let (pb, tb, _) = frame(&b, false);
    assert!((p1 - pb).norm() <= 1e-12 && angle(t1, tb) <= 1e-9);
}

#[test]
fn a_missing_start_from_file_is_an_input_error() {
    let file = data("quarter_ellipse_200.csv");
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(["curve", &file, "--start-from", "/nonexistent/a.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("/nonexistent/a.json"), "{err}");
}

#[test]
fn closed_data_fitted_open_hold_g2_ends_at_the_seam() {
    // the whole ellipse `x = cos t, y = 0.5 sin t`, its last point repeating the first at t = 0:
    // closed data, so a condition is refused; with --open the curve starts and ends there, and both
    // ends hold the ellipse's tangent (0, 1) and curvature 4 towards −x
    let dir = TempDir::new().unwrap();
    let file = dir.path().join("ellipse.csv");
    let rows: Vec<String> = (0..=240)
        .map(|i| {
            let t = std::f64::consts::TAU * (i % 240) as f64 / 240.0;
            format!("{},{}", t.cos(), 0.5 * t.sin())
        })
        .collect();
    std::fs::write(&file, format!("x,y\n{}\n", rows.join("\n"))).unwrap();
    let ends = ["--start", "curvature:0,1:4", "--end", "curvature:0,1:4"];
    let refused = Command::cargo_bin("fairfit")
        .unwrap()
        .arg("curve")
        .arg(&file)
        .args(ends)
        .output()
        .unwrap();
    assert!(!refused.status.success());
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        err.contains("closed data have no ends") && err.contains("--open"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    let pts = read_points(&file).unwrap().points;
    let (curve, rep) = run(
        &dir,
        "open",
        file.to_str().unwrap(),
        &[&ends[..], &["--open"]].concat(),
    );
    assert_eq!(rep["closed"], false);
    for at_end in [false, true] {
        let (p, t, k) = frame(&curve, at_end);
        assert!((p - Vec3::new(1.0, 0.0, 0.0)).norm() <= 1e-12, "{p:?}");
        assert!(angle(t, Vec3::new(0.0, 1.0, 0.0)) <= 1e-9, "{t:?}");
        assert!((k - Vec3::new(-4.0, 0.0, 0.0)).norm() <= 4e-9, "{k:?}");
    }
    let tol = rep["tolerance"].as_f64().unwrap();
    let worst = polyline::polyline_deviation(&curve, &pts, 50_000);
    assert!(worst <= tol * (1.0 + 1e-6), "{worst} > {tol}");
    // --open and --closed contradict each other
    let both = Command::cargo_bin("fairfit")
        .unwrap()
        .arg("curve")
        .arg(&file)
        .args(["--open", "--closed"])
        .output()
        .unwrap();
    assert!(!both.status.success());
    assert!(String::from_utf8_lossy(&both.stderr).contains("cannot be used with"));
}
