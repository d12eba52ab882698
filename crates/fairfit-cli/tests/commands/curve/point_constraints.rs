//! Per-point weights (`--weights`, a `w` column) and points to interpolate (`--interpolate`, an `i`
//! column) on every method of `fairfit curve`, measured on the written curve by an independent
//! projection (`CurveProjector`: dense samples, then Newton) against the bundled NACA 4412 airfoil.

use crate::common::{curve_run, data};
use assert_cmd::Command;
use fairfit::diffgeo::CurveProjector;
use fairfit::fit::points::bounding_box_extent;
use fairfit::io::read_points;
use fairfit::{NurbsCurve, Vec3};
use serde_json::Value;
use std::path::Path;
use tempfile::TempDir;

/// Runs `fairfit curve FILE ARGS -o dir/NAME.json --report dir/NAME-report.json`: the curve JSON
/// text, the curve and the report.
fn run(dir: &TempDir, name: &str, file: &Path, extra: &[&str]) -> (String, NurbsCurve, Value) {
    let run = curve_run(dir.path(), name, file, extra);
    (run.json, run.curve, run.report)
}

fn distance(curve: &NurbsCurve, q: Vec3) -> f64 {
    CurveProjector::new(curve, 64).project(q).distance
}

/// The points as an `x,y,w` file with weight `w(i)`.
fn with_weights(
    dir: &TempDir,
    name: &str,
    pts: &[Vec3],
    w: impl Fn(usize) -> f64,
) -> std::path::PathBuf {
    let mut s = String::from("x,y,w\n");
    for (i, p) in pts.iter().enumerate() {
        s.push_str(&format!("{:?},{:?},{:?}\n", p[0], p[1], w(i)));
    }
    let f = dir.path().join(name);
    std::fs::write(&f, s).unwrap();
    f
}

fn plain_file(dir: &TempDir, name: &str, pts: &[Vec3]) -> std::path::PathBuf {
    let s: String = pts
        .iter()
        .map(|p| format!("{:?},{:?}\n", p[0], p[1]))
        .collect();
    let f = dir.path().join(name);
    std::fs::write(&f, s).unwrap();
    f
}

fn naca() -> Vec<Vec3> {
    read_points(data("naca4412.csv")).unwrap().points
}

#[test]
fn a_weight_0_point_gives_the_json_of_the_data_without_it() {
    let pts = naca();
    let dir = TempDir::new().unwrap();
    let k = 37;
    let weighted = with_weights(&dir, "w.csv", &pts, |i| if i == k { 0.0 } else { 1.0 });
    let mut fewer = pts.clone();
    fewer.remove(k);
    let deleted = plain_file(&dir, "deleted.csv", &fewer);
    let weights = dir.path().join("weights.txt");
    let lines: String = (0..pts.len())
        .map(|i| if i == k { "0\n" } else { "1\n" })
        .collect();
    std::fs::write(&weights, lines).unwrap();
    let all = plain_file(&dir, "all.csv", &pts);
    for method in ["lsq", "integrated", "fit-then-fair"] {
        let m = ["--method", method];
        let (a, _, rep) = run(&dir, &format!("{method}-w"), &weighted, &m);
        let (b, _, _) = run(&dir, &format!("{method}-d"), &deleted, &m);
        let w = weights.to_str().unwrap();
        let (c, _, _) = run(
            &dir,
            &format!("{method}-f"),
            &all,
            &[m[0], m[1], "--weights", w],
        );
        assert_eq!(a, b, "{method}: the w column");
        assert_eq!(c, b, "{method}: --weights");
        assert_eq!(
            rep["point_constraint_fit"]["ignored"],
            serde_json::json!([k])
        );
    }
}

#[test]
fn a_weight_2_point_is_held_to_half_the_tolerance_on_every_method() {
    let pts = naca();
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    let dir = TempDir::new().unwrap();
    let all = plain_file(&dir, "all.csv", &pts);
    for method in ["lsq", "integrated", "fit-then-fair"] {
        let m = ["--method", method];
        let (_, plain, _) = run(&dir, &format!("{method}-plain"), &all, &m);
        // the point the plain fit leaves farthest, beyond tol / 2
        let (k, d0) = pts
            .iter()
            .map(|&q| distance(&plain, q))
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert!(d0 > 0.5 * tol, "{method}: {d0:e}");
        let f = with_weights(&dir, &format!("{method}.csv"), &pts, |i| {
            if i == k {
                2.0
            } else {
                1.0
            }
        });
        let (_, curve, rep) = run(&dir, method, &f, &m);
        let d = distance(&curve, pts[k]);
        eprintln!(
            "{method}: point {k} {d0:.3e} -> {d:.3e} (tol/2 {:.3e})",
            0.5 * tol
        );
        assert!(d <= 0.5 * tol * (1.0 + 1e-9), "{method}: {d:e}");
        let worst = pts.iter().map(|&q| distance(&curve, q)).fold(0.0, f64::max);
        assert!(worst <= tol * (1.0 + 1e-9), "{method}: {worst:e}");
        let ratio = rep["point_constraint_fit"]["weighted_ratio"]
            .as_f64()
            .unwrap();
        assert!(ratio <= 1.0 + 1e-9, "{method}: {ratio}");
    }
}

#[test]
fn interpolated_airfoil_points_lie_on_the_curve_within_1e_9_of_its_size() {
    let pts = naca();
    let size = bounding_box_extent(&pts);
    let tol = 1e-3 * size;
    // the leading edge (least x) and two points on each surface
    let le = (0..pts.len())
        .min_by(|&a, &b| pts[a][0].total_cmp(&pts[b][0]))
        .unwrap();
    let idx = [20, 55, le, le + 30, pts.len() - 25];
    let list = idx.map(|i| i.to_string()).join(",");
    let dir = TempDir::new().unwrap();
    let all = plain_file(&dir, "all.csv", &pts);
    for method in ["integrated", "lsq", "fit-then-fair"] {
        let (_, curve, rep) = run(
            &dir,
            method,
            &all,
            &["--method", method, "--interpolate", &list],
        );
        for &k in &idx {
            let d = distance(&curve, pts[k]);
            assert!(d <= 1e-9 * size, "{method}: point {k} {d:e}");
        }
        let worst = pts.iter().map(|&q| distance(&curve, q)).fold(0.0, f64::max);
        assert!(worst <= tol * (1.0 + 1e-9), "{method}: {worst:e}");
        let listed = rep["point_constraints"].as_array().unwrap();
        assert_eq!(listed.len(), idx.len());
        let mut sorted = idx.to_vec();
        sorted.sort();
        for (e, &k) in listed.iter().zip(&sorted) {
            assert_eq!(e["index"], k);
            assert!(e["distance"].as_f64().unwrap() <= 1e-9 * size);
        }
    }
    // the same points as an `i` column
    let mut s = String::from("x y i\n");
    for (i, p) in pts.iter().enumerate() {
        s.push_str(&format!(
            "{:?} {:?} {}\n",
            p[0],
            p[1],
            u8::from(idx.contains(&i))
        ));
    }
    let f = dir.path().join("flags.txt");
    std::fs::write(&f, s).unwrap();
    let (a, _, _) = run(&dir, "col", &f, &[]);
    let (b, _, _) = run(&dir, "flag", &all, &["--interpolate", &list]);
    assert_eq!(a, b);
}

/// Exit code `code` and one `error:` line containing `needle`.
fn fails(code: i32, args: &[&std::ffi::OsStr], needle: &str) {
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .arg("curve")
        .args(args)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(code), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].starts_with("error: ") && lines[0].contains(needle),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_weights_and_indices_are_one_line_errors() {
    let pts = naca();
    let dir = TempDir::new().unwrap();
    let all = plain_file(&dir, "all.csv", &pts);
    let n = pts.len();
    let os = |s: &str| std::ffi::OsString::from(s);
    let neg = with_weights(&dir, "neg.csv", &pts, |i| if i == 3 { -1.0 } else { 1.0 });
    fails(1, &[neg.as_os_str()], ">= 0");
    let zero = with_weights(&dir, "zero.csv", &pts, |_| 0.0);
    fails(1, &[zero.as_os_str()], "every weight is 0");
    for (name, body, needle) in [
        (
            "nan.txt",
            "1\n".repeat(n - 1) + "NaN\n",
            "expected a finite weight",
        ),
        ("short.txt", "1\n".repeat(n - 1), "weights for"),
    ] {
        let f = dir.path().join(name);
        std::fs::write(&f, body).unwrap();
        fails(
            1,
            &[all.as_os_str(), &os("--weights"), f.as_os_str()],
            needle,
        );
    }
    let out_of_range = format!("3,{n}");
    fails(
        2,
        &[all.as_os_str(), &os("--interpolate"), &os(&out_of_range)],
        "--interpolate",
    );
}
