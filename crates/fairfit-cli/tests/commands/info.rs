//! `fairfit info` on curves and surfaces with known fairness, and on bad input (one-line error, exit 1).

use crate::common;
use common::file_with;

use assert_cmd::Command;
use serde_json::Value;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

fn circle_json(r: f64) -> String {
    let h = FRAC_1_SQRT_2;
    let pts: Vec<[f64; 3]> = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
    ]
    .iter()
    .map(|&(x, y)| [r * x, r * y, 0.0])
    .collect();
    serde_json::json!({
        "kind": "curve",
        "degree": 2,
        "knots": [0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0],
        "control_points": pts,
        "weights": [1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0],
    })
    .to_string()
}

fn info(args: &[&str]) -> (bool, String, String) {
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .arg("info")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn circle_summary() {
    let r = 2.5;
    let f = file_with(circle_json(r).as_bytes());
    let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["kind"], "curve");
    assert_eq!(v["degree"], 2);
    assert_eq!(v["control_points"], 9);
    assert_eq!(v["knots"], 12);
    assert_eq!(v["rational"], true);
    assert_eq!(v["regular"], true);
    assert_eq!(v["domain"], serde_json::json!([0.0, 1.0]));
    assert!((v["length"].as_f64().unwrap() - 2.0 * PI * r).abs() < 1e-10);
    assert!(v["fairness"].as_f64().unwrap() < 1e-12);
    assert!(v["max_span_fairness"].as_f64().unwrap() < 1e-12);
    assert_eq!(v["span_fairness"].as_array().unwrap().len(), 4);
    assert!((v["bending_energy"].as_f64().unwrap() - 2.0 * PI / r).abs() < 1e-10);
    assert_eq!(v["curvature_extrema"], 0);
    assert_eq!(v["curvature_extrema_exact"], 0);
    assert_eq!(v["inflections"], 0);
    assert_eq!(v["inflections_exact"], 0);
}

#[test]
fn s_curve_counts_and_span_sum() {
    // y = 3t(1-t)(1-2t) over x = 3t: one inflection, two curvature extrema
    let f = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0],[1,1,0],[2,-1,0],[3,0,0]]}"#,
    );
    let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["inflections"], 1);
    assert_eq!(v["inflections_exact"], 1);
    assert_eq!(v["curvature_extrema"], 2);
    assert_eq!(v["curvature_extrema_exact"], 2);
    assert_eq!(v["rational"], false);
    let fj: f64 = v["span_fairness"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .sum();
    let big_f = v["fairness"].as_f64().unwrap();
    assert!(big_f > 1.0);
    assert!((fj - big_f).abs() < 1e-12 * big_f);
}

#[test]
fn surface_summary_and_several_files() {
    // a ruled sheet: straight in v (u-iso curves have F = 0), a cubic graph in u
    let f = file_with(
        br#"{"kind": "surface", "degree_u": 3, "degree_v": 1,
            "knots_u": [0,0,0,0,1,1,1,1], "knots_v": [0,0,1,1],
            "control_points": [[[0,0,0],[0,0,1]], [[1,1,0],[1,1,1]], [[2,-1,0],[2,-1,1]], [[3,0,0],[3,0,1]]]}"#,
    );
    let c = file_with(circle_json(1.0).as_bytes());
    let (ok, stdout, stderr) = info(&["--iso", "3", f.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["kind"], "surface");
    assert_eq!(v["net_size"], serde_json::json!([4, 2]));
    assert_eq!(v["degree_u"], 3);
    assert_eq!(v["degree_v"], 1);
    assert_eq!(v["iso_curves_per_direction"], 3);
    assert_eq!(v["iso_curves"]["along_v"].as_array().unwrap().len(), 3);
    // along v (u fixed) the sheet is straight; along u every iso-curve is the cubic graph
    assert!(v["max_fairness_along_v"].as_f64().unwrap() < 1e-20);
    assert_eq!(v["iso_curves"]["along_u"][1]["inflections"], 1);
    assert_eq!(v["iso_curves"]["along_u"][1]["parameter"], 0.5);
    let cubic = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0.5],[1,1,0.5],[2,-1,0.5],[3,0,0.5]]}"#,
    );
    let (ok, stdout, stderr) = info(&[cubic.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let cf = serde_json::from_str::<Value>(&stdout).unwrap()["fairness"]
        .as_f64()
        .unwrap();
    assert!(cf > 1.0);
    for key in ["max_fairness_along_u", "iso_curves"] {
        let f = match key {
            "iso_curves" => v[key]["along_u"][2]["fairness"].as_f64().unwrap(),
            _ => v[key].as_f64().unwrap(),
        };
        assert!(
            (f - cf).abs() < 1e-12 * cf,
            "{key}: {f} vs the curve's {cf}"
        );
    }
    let (ok, stdout, _) = info(&[f.path().to_str().unwrap()]);
    assert!(ok);
    let v11: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v11["iso_curves_per_direction"], 11);
    assert_eq!(v11["iso_curves"]["along_u"].as_array().unwrap().len(), 11);

    let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap(), c.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    let arr = v.as_array().unwrap();
    assert_eq!(arr.len(), 2);
    assert_eq!(arr[1]["kind"], "curve");
    let name = c.path().file_name().unwrap().to_str().unwrap();
    assert!(arr[1]["file"].as_str().unwrap().ends_with(name));
}

fn assert_one_line_error(args: &[&str], needle: &str) {
    let (ok, stdout, stderr) = info(args);
    assert!(!ok, "should fail: {stdout}");
    assert!(stdout.is_empty());
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "one line expected: {stderr}");
    assert!(lines[0].starts_with("error: "), "{stderr}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains("internal error"),
        "{stderr}"
    );
    assert!(stderr.contains(needle), "`{needle}` not in: {stderr}");
}

#[test]
fn bad_input_gives_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.json");
    assert_one_line_error(&[missing.to_str().unwrap()], "nope.json");
    let cases: Vec<(&[u8], &str)> = vec![
        (b"{ this is not json", "invalid JSON"),
        (
            br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1"#,
            "invalid JSON",
        ),
        (&[0x89, 0x50, 0x4e, 0x47, 0x00, 0xff, 0xfe, 0x00], "UTF-8"),
        (
            br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,1,1,1], "control_points": [[0,0,0],[1,1,0],[2,-1,0],[3,0,0]]}"#,
            "knots",
        ),
        (
            br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1], "control_points": [[0,0,0],[1,1,0],[2,-1,0],[3,0,0]], "weights": [1, 0, 1, 1]}"#,
            "weights",
        ),
        (
            br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1], "control_points": [[0,0,0],[1,1,0],[2,-1,0],[3,0,0]], "weights": [1, -2, 1, 1]}"#,
            "weights",
        ),
        (
            br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,0.5,1,1], "control_points": [[0,0,0],[1,1,0],[2,-1,0],[3,0,0]]}"#,
            "knots",
        ),
        (br#"{"kind": "surface", "degree_u": 1}"#, "invalid JSON"),
        (b"", "invalid JSON"),
    ];
    for (content, needle) in cases {
        let f = file_with(content);
        assert_one_line_error(&[f.path().to_str().unwrap()], needle);
    }
    // a bad --iso value is a clap usage error, also without panic
    let c = file_with(circle_json(1.0).as_bytes());
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(["info", "--iso", "0", c.path().to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("--iso") && stderr.contains("fairfit info --help"));
    assert!(!stderr.contains("panicked"));
}

#[test]
fn degenerate_point_curve_prints_zeros_not_nan() {
    let f = file_with(
        br#"{"kind": "curve", "degree": 2, "knots": [0,0,0,1,1,1],
            "control_points": [[1,2,3],[1,2,3],[1,2,3]]}"#,
    );
    let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["fairness"].as_f64(), Some(0.0));
    assert_eq!(v["bending_energy"].as_f64(), Some(0.0));
    assert!(v["length"].as_f64().unwrap() < 1e-12);
    assert_eq!(v["inflections"], 0);
}

/// `a` and `b` have the same structure and keys, and numbers equal to 1e-12 relative (1e-20 absolute
/// for round-off around zero).
fn assert_close(a: &Value, b: &Value, at: &str) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let (kx, ky): (Vec<_>, Vec<_>) = (x.keys().collect(), y.keys().collect());
            assert_eq!(kx, ky, "{at}");
            for k in x.keys() {
                assert_close(&x[k], &y[k], &format!("{at}.{k}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (i, (p, q)) in x.iter().zip(y).enumerate() {
                assert_close(p, q, &format!("{at}[{i}]"));
            }
        }
        (Value::Number(p), Value::Number(q)) => {
            let (p, q) = (p.as_f64().unwrap(), q.as_f64().unwrap());
            assert!(
                (p - q).abs() <= 1e-12 * p.abs().max(q.abs()) + 1e-20,
                "{at}: {p} vs {q}"
            );
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

#[test]
fn info_and_the_surface_report_agree_on_iso_curve_fairness() {
    // four half-ellipse sections at z = 0, 1, 2.5, 3 with growing semi-axes
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut cmd = Command::cargo_bin("fairfit").unwrap();
    cmd.arg("surface");
    for (k, z) in [0.0f64, 1.0, 2.5, 3.0].into_iter().enumerate() {
        let (a, b) = (2.0 + 0.3 * z, 1.0 + 0.1 * z * z);
        let mut s = String::from("x,y,z\n");
        for i in 0..40 {
            let t = std::f64::consts::PI * i as f64 / 39.0;
            s += &format!("{},{},{z}\n", a * t.cos(), b * t.sin());
        }
        let p = d.join(format!("sec_{k}.csv"));
        std::fs::write(&p, s).unwrap();
        cmd.arg(p);
    }
    let (json, rep) = (d.join("s.json"), d.join("r.json"));
    let out = cmd
        .args(["--tol", "1e-3", "-o"])
        .arg(&json)
        .arg("--report")
        .arg(&rep)
        .output()
        .unwrap();
    assert!(out.status.success());
    let summary = String::from_utf8_lossy(&out.stdout).into_owned();
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    let (ok, stdout, stderr) = info(&[json.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    // same curves, same keys, same numbers (to 1e-12: the report measures the surface before its
    // JSON round trip)
    assert_close(&v["iso_curves"], &report["iso_fairness"], "iso");
    let iso = &v["iso_curves"];
    assert_eq!(iso["along_u"].as_array().unwrap().len(), 11);
    assert_eq!(iso["along_v"].as_array().unwrap().len(), 11);
    let (fu, fv) = (
        v["max_fairness_along_u"].as_f64().unwrap(),
        v["max_fairness_along_v"].as_f64().unwrap(),
    );
    assert_eq!(fu, iso["max_fairness_along_u"].as_f64().unwrap());
    assert_eq!(fv, iso["max_fairness_along_v"].as_f64().unwrap());
    // along u run the sections (half ellipses, x from +a to -a); along v the rulings across them
    let first = &iso["along_u"][0];
    assert_eq!(first["parameter"], 0.0);
    let l0 = first["length"].as_f64().unwrap();
    // the z = 0 section: a half ellipse with semi-axes 2 and 1 (perimeter 9.68845 / 2)
    assert!((l0 - 9.688_448_220_547_675 / 2.0).abs() < 1e-3, "{l0}");
    // the printed summary names the directions the same way
    assert!(
        summary.contains(&format!("along u (the sections) {fu:.3e}"))
            && summary.contains(&format!("along v (across them) {fv:.3e}")),
        "{summary}"
    );
}

#[test]
fn an_ellipse_as_nurbs_has_its_interior_vertices_as_exact_extrema() {
    // the 9-point circle with y scaled by 0.4: an ellipse whose vertices are the arcs' joints, at
    // u = 0 (the start, not interior), 0.25, 0.5 and 0.75; κ is monotone between them and the
    // signed curvature never changes sign. The same ellipse lifted out of its plane by a tilt of
    // the y axis stays planar (the same counts).
    for (ty, tz) in [(0.4, 0.0), (0.24, 0.32)] {
        let mut v: Value = serde_json::from_str(&circle_json(3.0)).unwrap();
        for p in v["control_points"].as_array_mut().unwrap() {
            let y = p[1].as_f64().unwrap();
            p[1] = (ty * y).into();
            p[2] = (tz * y).into();
        }
        let f = file_with(v.to_string().as_bytes());
        let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
        assert!(ok, "{stderr}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["curvature_extrema_exact"], 3, "{stdout}");
        assert_eq!(v["inflections_exact"], 0, "{stdout}");
        assert_eq!(v["curvature_extrema"], 3, "{stdout}");
    }
}

#[test]
fn a_space_curve_has_exact_extrema_and_no_exact_inflection_count() {
    // (t, t², 3t³) on [−1, 1] as a cubic Bézier: not planar. Its curvature extrema are the roots of
    // f'g − 3fg' (f = |C'×C''|², g = |C'|²): t = 0 and t = ±0.1816 (tests/fair/exact_nurbs.rs), so 3.
    // A space curve has no signed curvature: its inflections are only sampled, so the exact field
    // is null rather than a sampled number under an exact name.
    let f = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [-1,-1,-1,-1,1,1,1,1],
            "control_points": [[-1,1,-3],[-0.3333333333333333,-0.3333333333333333,3],
                               [0.3333333333333333,-0.3333333333333333,-3],[1,1,3]]}"#,
    );
    let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["curvature_extrema_exact"], 3, "{stdout}");
    assert!(v["inflections_exact"].is_null(), "{stdout}");
    assert!(v["inflections"].is_u64(), "{stdout}");
}

#[test]
fn zero_speed_with_unbounded_curvature_gives_null_fairness() {
    // interior cusp: P1 and P2 crossed, C'(1/2) = 0 while C''(1/2) = (0, -6) and C''' = (24, 0) are
    // not parallel, so κ → ∞ there (F had printed as 5.1e23, a quadrature artefact)
    let cusp = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0],[1,1,0],[0,1,0],[1,0,0]]}"#,
    );
    // coinciding first two control points: C'(0) = 0 and κ ~ u^-1 near the start (F had been 1.0e22)
    let start = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0],[0,0,0],[1,1,0],[2,0,0]]}"#,
    );
    for (f, u) in [(&cusp, 0.5), (&start, 0.0)] {
        let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
        assert!(ok && stderr.is_empty(), "{stderr}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["regular"], false);
        for key in [
            "fairness",
            "energy",
            "max_span_fairness",
            "span_fairness",
            "bending_energy",
        ] {
            assert!(v[key].is_null(), "{key}: {}", v[key]);
        }
        let note = v["note"].as_str().unwrap();
        assert!(note.contains(&format!("not regular at u = {u}")), "{note}");
        assert!(v["length"].as_f64().unwrap() > 1.0);
    }
    // a straight line with a repeated control point is not regular at its start either, but its
    // curvature is 0 everywhere: F = 0 as before
    let line = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0],[0,0,0],[1,1,0],[3,3,0]]}"#,
    );
    let (ok, stdout, stderr) = info(&[line.path().to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["regular"], false);
    assert!(v.get("note").is_none());
    assert_eq!(v["fairness"].as_f64(), Some(0.0));
    assert!((v["length"].as_f64().unwrap() - 3.0 * 2f64.sqrt()).abs() < 1e-12);
}

/// A cubic Bézier on [0, 1] with `C'(t) = (t − s)(1, t) + (0, eps)`, `s = 1/√2`, scaled by `scale`:
/// for `eps = 0` a cusp at the irrational `s`, strictly between the 64 samples per span the search
/// had used (45/64 is 0.004 away); `C''(s) = (1, s)` and `C''' = (0, 2)` are not parallel, so κ is
/// unbounded there.
fn cusp_between_samples(eps: f64, scale: f64) -> tempfile::NamedTempFile {
    let s = FRAC_1_SQRT_2;
    // the Bernstein coefficients of C' (power coefficients c0 + c1 t + c2 t² per coordinate)
    let bern = |c0: f64, c1: f64, c2: f64| [c0, c0 + 0.5 * c1, c0 + c1 + c2];
    let (dx, dy) = (bern(-s, 1.0, 0.0), bern(eps, -s, 1.0));
    let mut pts = vec![[0.0, 0.0, 0.0]];
    for i in 0..3 {
        let [x, y, _] = pts[i];
        pts.push([x + dx[i] / 3.0, y + dy[i] / 3.0, 0.0]);
    }
    let pts: Vec<[f64; 3]> = pts.iter().map(|p| p.map(|x| x * scale)).collect();
    file_with(
        serde_json::json!({"kind": "curve", "degree": 3, "knots": [0, 0, 0, 0, 1, 1, 1, 1],
            "control_points": pts})
        .to_string()
        .as_bytes(),
    )
}

#[test]
fn a_cusp_between_samples_is_found_exactly_and_scale_free() {
    for scale in [1.0, 1e-200, 1e200] {
        let f = cusp_between_samples(0.0, scale);
        let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
        assert!(ok && stderr.is_empty(), "{stderr}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["regular"], false, "{scale}: {stdout}");
        assert!(v["fairness"].is_null() && v["energy"].is_null(), "{stdout}");
        let note = v["note"].as_str().unwrap();
        let u: f64 = note
            .split("not regular at u = ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|u| u.parse().ok())
            .unwrap_or_else(|| panic!("{note}"));
        assert!((u - FRAC_1_SQRT_2).abs() < 1e-12, "{scale}: {u}");
        // a near-cusp, its least speed 1e-7 of |C'(0)|: regular (at unit size with a large finite
        // F; at 1e-200 its energy F/L³ leaves the floating-point range: one error line, no output)
        let f = cusp_between_samples(1e-7, scale);
        let (ok, stdout, stderr) = info(&[f.path().to_str().unwrap()]);
        if scale < 1.0 {
            assert!(!ok && stdout.is_empty(), "{scale}: {stdout}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(
                stderr.contains("cannot be computed as a finite number"),
                "{stderr}"
            );
            continue;
        }
        assert!(ok, "{stderr}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["regular"], true, "{scale}: {stdout}");
        assert!(v.get("note").is_none(), "{stdout}");
        if scale == 1.0 {
            assert!(stderr.is_empty(), "{stderr}");
            assert!(v["fairness"].as_f64().is_some_and(|x| x > 1e6), "{stdout}");
        }
    }
}
