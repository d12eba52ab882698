//! `fairfit curve A B --chain g1|g2`: two arcs of the circle of radius 2 (split at angle 1) fitted
//! as a chain; the written pieces' join measured from their own derivatives (tangent and curvature
//! vector against each other and against the circle's `1/R`), the joined chain file, the report's
//! joins; and the usage errors (one line, exit 2).

use crate::common::{fairfit, file_with, one_line_failure, read_json};
use fairfit::io::{read_geometry, read_points, Geometry};
use fairfit::{NurbsCurve, Vec3};
use tempfile::{NamedTempFile, TempDir};

const R: f64 = 2.0;

/// A CSV of `n` points on the circle of radius `R` from angle `a0` to `a1`.
fn arc_file(a0: f64, a1: f64, n: usize) -> NamedTempFile {
    let mut s = String::from("x,y\n");
    for i in 0..n {
        let a = a0 + (a1 - a0) * i as f64 / (n - 1) as f64;
        s.push_str(&format!("{},{}\n", R * a.cos(), R * a.sin()));
    }
    file_with(s.as_bytes())
}

fn curve(p: &std::path::Path) -> NurbsCurve {
    match read_geometry(p).unwrap() {
        Geometry::Curve(c) => c,
        Geometry::Surface(_) => panic!("a surface"),
    }
}

/// Point, unit tangent and curvature vector at the start (`at_end` false) or end of `c`.
fn frame(c: &NurbsCurve, at_end: bool) -> (Vec3, Vec3, Vec3) {
    let (a, b) = c.domain();
    let d = c.derivatives(if at_end { b } else { a }, 2);
    let s = d[1].norm();
    (d[0], d[1] / s, d[1].cross(d[2]).cross(d[1]) / s.powi(4))
}

#[test]
fn a_g2_chain_of_two_arcs_joins_with_the_circles_curvature() {
    let (a, b) = (arc_file(0.0, 1.0, 40), arc_file(1.0, 2.3, 50));
    let dir = TempDir::new().unwrap();
    let out = dir.path().join("arc.json");
    let rep = dir.path().join("report.json");
    for (continuity, tol) in [("g1", 1e-4), ("g2", 1e-4)] {
        let run = fairfit()
            .args(["curve"])
            .arg(a.path())
            .arg(b.path())
            .args(["--chain", continuity, "--degree", "3", "--rel-tol"])
            .arg(tol.to_string())
            .arg("-o")
            .arg(&out)
            .arg("--report")
            .arg(&rep)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let (p1, p2) = (dir.path().join("arc_1.json"), dir.path().join("arc_2.json"));
        let (c1, c2) = (curve(&p1), curve(&p2));
        let (x1, t1, k1) = frame(&c1, true);
        let (x2, t2, k2) = frame(&c2, false);
        let report = read_json(&rep);
        let abs_tol = report["tolerance"].as_f64().unwrap();
        // relative to the whole chain's largest side: x from 2 cos 2.3 to 2
        let size = R - R * 2.3_f64.cos();
        assert!((abs_tol - tol * size).abs() < 1e-12 * size, "{abs_tol}");
        assert!((x1 - x2).norm() < 1e-12);
        assert!(t1.cross(t2).norm().atan2(t1.dot(t2)) <= 1e-9);
        // the join on the circle within the tolerance, its tangent the circle's
        assert!((x1.norm() - R).abs() <= abs_tol);
        let circle_t = Vec3::new(-x1[1], x1[0], 0.0) / x1.norm();
        assert!(t1.cross(circle_t).norm() < 1e-3);
        if continuity == "g2" {
            assert!((k1 - k2).norm() / k1.norm() <= 1e-9, "{k1:?} {k2:?}");
            assert!((k1.norm() * R - 1.0).abs() < 0.02, "{}", k1.norm() * R);
        }
        // every point of each piece within the tolerance
        for (file, c) in [(a.path(), &c1), (b.path(), &c2)] {
            let pts = read_points(file).unwrap().points;
            let d = fairfit::fit::max_orthogonal_deviation(c, &pts, &[]).max;
            assert!(d <= abs_tol * (1.0 + 1e-9), "{d} > {abs_tol}");
        }
        // the joined chain: one curve from the first piece's start to the second's end
        let joined = curve(&out);
        let (s, e) = joined.domain();
        assert!((joined.point(s) - frame(&c1, false).0).norm() < 1e-12);
        assert!((joined.point(e) - frame(&c2, true).0).norm() < 1e-12);
        // the report's join is the one measured here
        let j = &report["joins"][0];
        assert_eq!(j["pieces"], serde_json::json!([1, 2]));
        assert!(j["tangent_angle"].as_f64().unwrap() <= 1e-9);
        assert_eq!(report["chain"], continuity);
        assert_eq!(report["pieces"].as_array().unwrap().len(), 2);
        assert_eq!(report["tolerance_met"], true);
        if continuity == "g2" {
            assert!(j["curvature_relative"].as_f64().unwrap() <= 1e-9);
        }
    }
}

#[test]
fn chain_usage_errors_are_one_line_with_exit_2() {
    let (a, b) = (arc_file(0.0, 1.0, 20), arc_file(1.0, 2.0, 20));
    let dir = TempDir::new().unwrap();
    let out = dir.path().join("o.json");
    let (a, b, out) = (
        a.path().to_str().unwrap(),
        b.path().to_str().unwrap(),
        out.to_str().unwrap(),
    );
    one_line_failure(
        &["curve", a, "--chain", "g2", "-o", out],
        2,
        &["at least two"],
    );
    one_line_failure(&["curve", a, b, "-o", out], 2, &["--chain"]);
    one_line_failure(&["curve", a, b, "--chain", "g2"], 2, &["-o"]);
    one_line_failure(
        &["curve", a, b, "--split-at-le", "-o", out],
        2,
        &["--split-at-le", "one airfoil file"],
    );
    one_line_failure(
        &["curve", a, b, "--chain", "g1", "--method", "lsq", "-o", out],
        2,
        &["--method", "--chain"],
    );
    one_line_failure(
        &[
            "curve",
            a,
            b,
            "--chain",
            "g2",
            "--control-points",
            "6",
            "-o",
            out,
        ],
        2,
        &["--control-points"],
    );
}

#[test]
fn pieces_that_do_not_meet_are_an_input_error() {
    let (a, b) = (arc_file(0.0, 1.0, 20), arc_file(1.2, 2.0, 20));
    refused_chain(&a, &b, "g2", &["do not meet", "pieces 1 and 2"]);
}

#[test]
fn split_at_le_pins_the_airfoils_leading_edge_at_the_parameter_half() {
    let file = crate::common::data("naca4412.csv");
    let dir = TempDir::new().unwrap();
    let (out, rep) = (
        dir.path().join("af.json"),
        dir.path().join("af-report.json"),
    );
    let run = fairfit()
        .args(["curve", &file, "--split-at-le", "-o"])
        .arg(&out)
        .arg("--report")
        .arg(&rep)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let c = curve(&out);
    let report = read_json(&rep);
    assert_eq!(c.domain(), (0.0, 1.0));
    let p = c.degree();
    assert_eq!(c.knots().iter().filter(|&&k| k == 0.5).count(), p);
    // the leading edge of NACA 4412 is its point (0, 0), the farthest from the trailing edge
    let pts = read_points(&file).unwrap().points;
    let le = report["split_at_le"]["index"].as_u64().unwrap() as usize;
    assert_eq!((pts[le][0], pts[le][1]), (0.0, 0.0));
    let tol = report["tolerance"].as_f64().unwrap();
    assert!((c.point(0.5) - pts[le]).norm() <= tol);
    // G2 at the leading edge: the two sides of the knot 0.5, measured on the joined curve
    let below = 0.5 - f64::EPSILON / 4.0; // the float just below 0.5: the span on the left
    let (left, right) = (c.derivatives(below, 2), c.derivatives(0.5, 2));
    let t = |d: &[Vec3]| d[1] / d[1].norm();
    assert!(t(&left).cross(t(&right)).norm() < 1e-6);
    let j = &report["joins"][0];
    assert!(j["tangent_angle"].as_f64().unwrap() <= 1e-9);
    assert!(j["curvature_relative"].as_f64().unwrap() <= 1e-9);
    // within the tolerance everywhere; F within 10 % of the single curve's
    let d = fairfit::fit::max_orthogonal_deviation(&c, &pts, &[]).max;
    assert!(d <= tol * (1.0 + 1e-9), "{d}");
    let ratio = report["fairness_ratio"].as_f64().unwrap();
    assert!(ratio <= 1.10, "{ratio}");
}

#[test]
fn a_g1_chain_across_a_corner_is_refused_not_written_with_a_kink() {
    // two straight pieces meeting at a right angle: the corner is named (no tangent is within the
    // tolerance of both)
    let line = |f: &dyn Fn(f64) -> (f64, f64)| {
        let mut s = String::from("x,y\n");
        for i in 0..=20 {
            let (x, y) = f(i as f64 / 20.0);
            s.push_str(&format!("{x},{y}\n"));
        }
        file_with(s.as_bytes())
    };
    let (a, b) = (line(&|t| (t, 0.0)), line(&|t| (1.0, t)));
    refused_chain(
        &a,
        &b,
        "g1",
        &["chain pieces 1 and 2 meet at a corner", "90.0 degrees"],
    );
}

/// `fairfit curve A B --chain CONTINUITY -o o.json` fails as an input error (exit 1, one line with
/// `needles`) and writes neither the chain nor a piece.
fn refused_chain(a: &NamedTempFile, b: &NamedTempFile, continuity: &str, needles: &[&str]) {
    let dir = TempDir::new().unwrap();
    let out = dir.path().join("o.json");
    one_line_failure(
        &[
            "curve",
            a.path().to_str().unwrap(),
            b.path().to_str().unwrap(),
            "--chain",
            continuity,
            "-o",
            out.to_str().unwrap(),
        ],
        1,
        needles,
    );
    assert!(!out.exists() && !dir.path().join("o_1.json").exists());
}
