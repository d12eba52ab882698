//! `fairfit eval` end to end: numbers on the exact circle and a bilinear saddle, and every bad input
//! (missing, malformed, truncated, binary file; bad `--at` list; parameter outside the domain) giving a
//! one-line error with exit code 1 (2 for a usage error) and no panic.

use crate::common;
use crate::common::assert_success;
use common::{file_with, CIRCLE};

use assert_cmd::Command;
use serde_json::Value;

/// z = x y on [0,1]², bilinear.
const SADDLE: &str = r#"{"kind": "surface", "degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
  "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#;

fn eval(file: &std::path::Path, at: &str) -> std::process::Output {
    Command::cargo_bin("fairfit")
        .unwrap()
        .args(["eval", file.to_str().unwrap(), "--at", at])
        .output()
        .unwrap()
}

fn ok_json(file: &std::path::Path, at: &str) -> Vec<Value> {
    let out = eval(file, at);
    assert_success(&out);
    serde_json::from_slice::<Vec<Value>>(&out.stdout).unwrap()
}

/// Exit code 1 (a failure of the run), one stderr line starting with `error:` and containing
/// `needle`, no panic text.
fn assert_one_line_error(out: &std::process::Output, needle: &str) {
    assert_one_line_exit(out, 1, needle);
}

/// Exit code 2 (a malformed `--at`: a usage error), one line as [`assert_one_line_error`], pointing
/// at `fairfit eval --help`.
fn assert_usage_error(out: &std::process::Output, needle: &str) {
    assert_one_line_exit(out, 2, needle);
    assert_one_line_exit(out, 2, "see 'fairfit eval --help'");
}

fn assert_one_line_exit(out: &std::process::Output, code: i32, needle: &str) {
    assert_eq!(out.status.code(), Some(code));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains(needle), "expected `{needle}` in {err}");
    assert!(
        !err.contains("panicked") && !err.contains("internal error"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

fn vec3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|i| a[i].as_f64().unwrap())
}

#[test]
fn circle_points_curvature_and_derivatives() {
    let f = file_with(CIRCLE.as_bytes());
    let us = [0.0, 0.1, 0.3, 0.55, 0.8, 0.97, 1.0];
    let at = us.map(|u| u.to_string()).join(",");
    let out = ok_json(f.path(), &at);
    assert_eq!(out.len(), us.len());
    for (o, &u) in out.iter().zip(&us) {
        assert_eq!(o["u"].as_f64().unwrap(), u);
        let p = vec3(&o["point"]);
        let r = ((p[0] - 1.0).powi(2) + (p[1] + 1.0).powi(2)).sqrt();
        assert!((r - 2.0).abs() < 1e-12, "{r}");
        assert!((p[2] - 0.5).abs() < 1e-15);
        assert!((o["curvature"].as_f64().unwrap() - 0.5).abs() < 1e-10);
        assert!(o["torsion"].as_f64().unwrap().abs() < 1e-10);
        assert!(o["dkappa_ds"].as_f64().unwrap().abs() < 1e-8);
        let d = o["derivatives"].as_array().unwrap();
        assert_eq!(d.len(), 3);
        // C' is tangent: orthogonal to the radius
        let d1 = vec3(&d[0]);
        let dot = d1[0] * (p[0] - 1.0) + d1[1] * (p[1] + 1.0);
        assert!(dot.abs() < 1e-10 * (d1[0].hypot(d1[1])));
    }
    // the quarter point is exactly the control point (1, 1, 0.5)
    let q = ok_json(f.path(), "0.25");
    let p = vec3(&q[0]["point"]);
    assert!((p[0] - 1.0).abs() < 1e-15 && (p[1] - 1.0).abs() < 1e-15);
}

#[test]
fn saddle_partials_and_curvatures() {
    let f = file_with(SADDLE.as_bytes());
    let out = ok_json(f.path(), "0.5:0.25, 0:0");
    assert_eq!(out.len(), 2);
    let o = &out[0];
    assert_eq!(vec3(&o["point"]), [0.5, 0.25, 0.125]);
    assert_eq!(vec3(&o["du"]), [1.0, 0.0, 0.25]);
    assert_eq!(vec3(&o["dv"]), [0.0, 1.0, 0.5]);
    assert_eq!(vec3(&o["duv"]), [0.0, 0.0, 1.0]);
    assert_eq!(vec3(&o["duu"]), [0.0, 0.0, 0.0]);
    // z = xy: K = -1/(1 + x² + y²)², H = -xy/(1 + x² + y²)^{3/2}
    let (x, y) = (0.5f64, 0.25f64);
    let w = 1.0 + x * x + y * y;
    let k = o["gaussian_curvature"].as_f64().unwrap();
    let h = o["mean_curvature"].as_f64().unwrap();
    assert!((k + 1.0 / (w * w)).abs() < 1e-14, "{k}");
    assert!((h + x * y / w.powf(1.5)).abs() < 1e-14, "{h}");
    assert!((out[1]["gaussian_curvature"].as_f64().unwrap() + 1.0).abs() < 1e-14);
}

#[test]
fn negative_parameter_is_parsed_and_rejected_as_outside_domain() {
    let f = file_with(CIRCLE.as_bytes());
    assert_one_line_error(&eval(f.path(), "-0.5"), "outside the domain");
    assert_one_line_error(
        &eval(f.path(), "0.5,1.2"),
        "--at: parameter u = 1.2 is outside the domain [0, 1] of u",
    );
    let s = file_with(SADDLE.as_bytes());
    assert_one_line_error(&eval(s.path(), "0.5:1.5"), "outside the domain");
    // the surface message names the direction; huge values print in exponent form, not 301 digits
    assert_one_line_error(
        &eval(s.path(), "0.5:1.5"),
        "parameter v = 1.5 is outside the domain [0, 1] of v",
    );
    assert_one_line_error(
        &eval(s.path(), "-1e300:0.5"),
        "parameter u = -1e300 is outside the domain [0, 1] of u",
    );
    assert_one_line_error(
        &eval(f.path(), "1e300"),
        "parameter u = 1e300 is outside the domain [0, 1] of u",
    );
}

#[test]
fn malformed_at_lists_are_errors() {
    let f = file_with(CIRCLE.as_bytes());
    assert_usage_error(&eval(f.path(), "0.1,,0.2"), "empty entry");
    assert_usage_error(&eval(f.path(), "abc"), "`abc` is not a finite number");
    assert_usage_error(&eval(f.path(), "0.1,NaN"), "not a finite number");
    assert_usage_error(&eval(f.path(), "inf"), "not a finite number");
    assert_usage_error(&eval(f.path(), "0.2:0.3"), "holds a curve");
    assert_usage_error(&eval(f.path(), ""), "empty entry");
    let s = file_with(SADDLE.as_bytes());
    assert_usage_error(&eval(s.path(), "0.5"), "not a U:V pair");
    assert_usage_error(&eval(s.path(), "0.1:0.2:0.3"), "not a U:V pair");
    assert_usage_error(&eval(s.path(), "0.1:x"), "`x` is not a finite number");
    assert_usage_error(&eval(s.path(), "0.5:"), "`0.5:` lacks its V value");
    assert_usage_error(&eval(s.path(), " :0.5"), "lacks its U value");
}

#[test]
fn bad_files_are_errors() {
    let missing = std::env::temp_dir().join("fairfit-eval-no-such-file.json");
    assert_one_line_error(&eval(&missing, "0.5"), "fairfit-eval-no-such-file.json");
    let truncated = file_with(&CIRCLE.as_bytes()[..120]);
    assert_one_line_error(&eval(truncated.path(), "0.5"), "EOF");
    let malformed = file_with(b"{\"kind\": \"curve\", \"degree\": 2, knots: []}");
    assert_one_line_error(&eval(malformed.path(), "0.5"), "invalid JSON");
    let binary = file_with(&[0xff, 0xfe, 0x00, 0x81, 0x9f, 0x00, 0x12]);
    assert_one_line_error(&eval(binary.path(), "0.5"), "not a UTF-8 text file");
    let wrong_knots = file_with(CIRCLE.replace("0.75, 0.75, 1", "0.75, 1").as_bytes());
    assert_one_line_error(&eval(wrong_knots.path(), "0.5"), "expected 12 knots");
    let zero_weight = file_with(
        CIRCLE
            .replace("[1, 0.7071067811865476, 1,", "[1, 0, 1,")
            .as_bytes(),
    );
    assert_one_line_error(&eval(zero_weight.path(), "0.5"), "weights");
    let empty = file_with(b"");
    assert_one_line_error(&eval(empty.path(), "0.5"), "the file is empty");
}

#[test]
fn missing_at_option_is_a_usage_error() {
    let f = file_with(CIRCLE.as_bytes());
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(["eval", f.path().to_str().unwrap()])
        .output()
        .unwrap();
    // a usage error: exit code 2, one line naming the option and the help to read
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("--at"), "{err}");
    assert!(
        err.trim_end().ends_with("see 'fairfit eval --help'"),
        "{err}"
    );
}

#[test]
fn degenerate_normal_gives_null_curvatures() {
    // the edge u = 0 collapses to one point, so S_v = 0 there
    let tri = r#"{"kind": "surface", "degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
      "control_points": [[[0,0,0],[0,0,0]],[[1,0,0],[1,1,0]]]}"#;
    let f = file_with(tri.as_bytes());
    let out = ok_json(f.path(), "0:0.5,0.5:0.5");
    assert!(out[0]["gaussian_curvature"].is_null());
    assert!(out[0]["mean_curvature"].is_null());
    assert_eq!(vec3(&out[0]["dv"]), [0.0, 0.0, 0.0]);
    // a planar triangle: zero curvature away from the collapsed edge
    assert_eq!(out[1]["gaussian_curvature"].as_f64().unwrap(), 0.0);
    assert_eq!(out[1]["mean_curvature"].as_f64().unwrap(), 0.0);
}

/// A cubic Bézier `(P0, P1, P2, P3)` on [0, 1] as curve JSON, every coordinate times `s`.
fn bezier_json(p: [[f64; 2]; 4], s: f64) -> String {
    let pts: Vec<String> = p
        .iter()
        .map(|q| format!("[{:e},{:e},0]", q[0] * s, q[1] * s))
        .collect();
    format!(
        r#"{{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1], "control_points": [{}]}}"#,
        pts.join(",")
    )
}

#[test]
fn zero_speed_gives_null_curvature_with_a_note_at_any_scale() {
    // P0 = P1: C'(0) = 3 (P1 - P0) = 0. At u = 1/2 (by hand): C' = (9/4, 3/4), C'' = (3, -3),
    // κ = |C' × C''| / |C'|³ = 9 / (45/8)^(3/2).
    let kappa_half = 9.0 / (45.0f64 / 8.0).powf(1.5);
    // at 1e-300, dκ/ds at u = 1/2 (about 1e600) is beyond f64: one line, no output
    let f = file_with(bezier_json([[0., 0.], [0., 0.], [1., 1.], [2., 0.]], 1e-300).as_bytes());
    assert_one_line_error(&eval(f.path(), "0,0.5"), "dκ/ds at u = 0.5");
    let out = ok_json(f.path(), "0");
    assert!(out[0]["curvature"].is_null() && out[0]["note"].is_string());
    for s in [1.0, 1e300] {
        let f = file_with(bezier_json([[0., 0.], [0., 0.], [1., 1.], [2., 0.]], s).as_bytes());
        let out = ok_json(f.path(), "0,0.5");
        assert_eq!(out[0]["regular"], Value::Bool(false), "{s:e}");
        for key in ["curvature", "torsion", "dkappa_ds"] {
            assert!(out[0][key].is_null(), "{s:e} {key}: {}", out[0][key]);
        }
        assert!(out[0]["note"].as_str().unwrap().contains("not regular"));
        // the point and derivatives are still there: C(0) = P0, C'(0) = 0
        assert_eq!(vec3(&out[0]["point"]), [0.0, 0.0, 0.0]);
        assert_eq!(vec3(&out[0]["derivatives"][0]), [0.0, 0.0, 0.0]);
        assert_eq!(out[1]["regular"], Value::Bool(true));
        assert!(out[1].get("note").is_none());
        let k = out[1]["curvature"].as_f64().unwrap();
        assert!((k * s / kappa_half - 1.0).abs() < 1e-12, "{s:e}: {k}");
    }
    // an interior cusp: P1 and P2 crossed, C'(1/2) = 3 [(P1-P0)/4 + (P2-P1)/2 + (P3-P2)/4] = 0
    let f = file_with(bezier_json([[0., 0.], [1., 1.], [0., 1.], [1., 0.]], 1.0).as_bytes());
    let out = ok_json(f.path(), "0.5,0.25");
    assert!(out[0]["curvature"].is_null() && out[0]["regular"] == Value::Bool(false));
    assert!(out[1]["curvature"].as_f64().unwrap() > 0.0);
}

#[test]
fn tiny_regular_circle_keeps_its_curvature() {
    // the exact circle of radius 2 scaled by 1e-300: κ = 0.5e300 at every u, regular everywhere
    let mut v: Value = serde_json::from_str(CIRCLE).unwrap();
    for p in v["control_points"].as_array_mut().unwrap() {
        for x in p.as_array_mut().unwrap() {
            *x = serde_json::json!(x.as_f64().unwrap() * 1e-300);
        }
    }
    let f = file_with(v.to_string().as_bytes());
    // dκ/ds is 0 up to round-off, which at this scale is multiplied by 1e600, past f64: the run
    // fails with one line naming it (outputs hold finite numbers or are not written)
    assert_one_line_error(
        &eval(f.path(), "0,0.3,0.9"),
        "the dκ/ds at u = 0 cannot be computed",
    );
    // the same circle at unit size: κ = 0.5 and dκ/ds = 0 (round-off)
    let f = file_with(CIRCLE.as_bytes());
    for o in ok_json(f.path(), "0,0.3,0.9") {
        assert_eq!(o["regular"], Value::Bool(true));
        let k = o["curvature"].as_f64().unwrap();
        assert!((k - 0.5).abs() < 1e-9, "{k}");
        assert!(o["dkappa_ds"].as_f64().unwrap().abs() < 1e-9);
    }
}

#[test]
fn no_negative_zero_in_the_output() {
    // a quarter cylinder of radius 1 whose normal points outward: K = 0 exactly, H = -1/2; the
    // curvature formula gives K = 0·N − M² = −0.0 here, which printed as "-0.0"
    let cyl = r#"{"kind": "surface", "degree_u": 1, "degree_v": 2, "knots_u": [0,0,1,1], "knots_v": [0,0,0,1,1,1],
      "control_points": [[[1,0,1],[1,1,1],[0,1,1]],[[1,0,0],[1,1,0],[0,1,0]]],
      "weights": [[1,0.7071067811865476,1],[1,0.7071067811865476,1]]}"#;
    let f = file_with(cyl.as_bytes());
    let out = eval(f.path(), "0:0,0.5:0.5");
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!text.contains("-0.0"), "{text}");
    let v: Vec<Value> = serde_json::from_str(&text).unwrap();
    for o in &v {
        let k = o["gaussian_curvature"].as_f64().unwrap();
        assert!(k == 0.0 && k.is_sign_positive());
        assert!((o["mean_curvature"].as_f64().unwrap() + 0.5).abs() < 1e-12);
    }
    // a planar curve's torsion (c·C''' with c along -z and C''' in the plane) was "-0.0" too
    let f = file_with(
        br#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
            "control_points": [[0,0,0],[0,0,0],[1,1,0],[2,0,0]]}"#,
    );
    let out = eval(f.path(), "0.3");
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!text.contains("-0.0"), "{text}");
    let v: Vec<Value> = serde_json::from_str(&text).unwrap();
    assert!(v[0]["torsion"].as_f64().unwrap().is_sign_positive());
    // negative numbers other than zero are kept
    assert_eq!(v[0]["derivatives"][2][0].as_f64().unwrap(), -6.0);
}

#[test]
fn knots_whose_range_overflows_are_refused() {
    // finite knots from -1e308 to 1e308: the range is infinite in f64, every basis function came out
    // 0 and eval printed the point (0, 0, 0) for a curve through (0,0,0)..(2,0,0)
    let f = file_with(
        br#"{"kind": "curve", "degree": 2, "knots": [-1e308,-1e308,-1e308,1e308,1e308,1e308],
            "control_points": [[0,0,0],[1,1,0],[2,0,0]]}"#,
    );
    assert_one_line_error(&eval(f.path(), "0"), "beyond the floating-point limit");
    // a range of 1e308 is still fine: the midpoint of the quadratic Bézier is (1, 0.5, 0)
    let f = file_with(
        br#"{"kind": "curve", "degree": 2, "knots": [0,0,0,1e308,1e308,1e308],
            "control_points": [[0,0,0],[1,1,0],[2,0,0]]}"#,
    );
    let out = ok_json(f.path(), "5e307");
    let p = vec3(&out[0]["point"]);
    assert!(
        (p[0] - 1.0).abs() < 1e-12 && (p[1] - 0.5).abs() < 1e-12,
        "{p:?}"
    );
    // there the speed is about 2e-308 (|C'|³ underflows), yet the curve is regular with κ = |C'×C''|/|C'|³
    // = 1 in the Bézier parameter t: C'(1/2) = (2, 0), C''(1/2) = (0, -4)
    assert_eq!(out[0]["regular"], Value::Bool(true));
    let k = out[0]["curvature"].as_f64().unwrap();
    assert!((k - 1.0).abs() < 1e-12, "{k}");
}
