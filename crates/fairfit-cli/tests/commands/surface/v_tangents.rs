//! `fairfit surface --start-tangent-v / --end-tangent-v` on sections sampled from a translational
//! surface `S(u, t) = C(u) + γ(t)` (its `∂S/∂t = γ'(t)`, one direction along a whole section): the
//! written surface's `∂S/∂v`, by finite differences of surface points, follows the analytic `γ'` at
//! both ends; the report says so; bad values are one-line usage errors with no output written.

use crate::common;
use common::{fairfit, surface_run};

use fairfit::{NurbsSurface, Vec3};
use std::path::Path;

fn gamma(t: f64) -> Vec3 {
    Vec3::new(0.4 * (1.5 * t).sin(), 0.2 * (1.0 - t.cos()), 2.0 * t)
}

fn gamma_d(t: f64) -> Vec3 {
    Vec3::new(0.6 * (1.5 * t).cos(), 0.2 * t.sin(), 2.0)
}

const SPINE: [f64; 5] = [0.0, 0.3, 0.7, 1.0, 1.3];

/// Five open wavy sections (60 points each) translated along γ, as CSV files in `dir`.
fn sections(dir: &Path) {
    for (k, &t) in SPINE.iter().enumerate() {
        let mut s = String::from("x,y,z\n");
        for i in 0..60 {
            let x = 4.0 * i as f64 / 59.0;
            let p = Vec3::new(x, 0.5 * (1.2 * x).sin() + 0.1 * x, 0.0) + gamma(t);
            s += &format!("{:?},{:?},{:?}\n", p.x(), p.y(), p.z());
        }
        std::fs::write(dir.join(format!("sec_{k}.csv")), s).unwrap();
    }
}

fn arg(d: Vec3) -> String {
    format!("{:?},{:?},{:?}", d.x(), d.y(), d.z())
}

/// `∂S/∂v` at an end by a one-sided 5-point difference inside the end knot span.
fn sv_fd(s: &NurbsSurface, u: f64, at_start: bool) -> Vec3 {
    let kv = s.knots_v();
    let q = s.degree_v();
    let span = if at_start {
        kv[q + 1] - kv[q]
    } else {
        kv[kv.len() - q - 1] - kv[kv.len() - q - 2]
    };
    let (v, h) = if at_start {
        (kv[0], 1e-3 * span)
    } else {
        (kv[kv.len() - 1], -1e-3 * span)
    };
    let f = |k: f64| s.point(u, v + k * h);
    (f(0.0) * -25.0 + f(1.0) * 48.0 - f(2.0) * 36.0 + f(3.0) * 16.0 - f(4.0) * 3.0) / (12.0 * h)
}

fn angle(a: Vec3, b: Vec3) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

#[test]
fn the_surface_leaves_its_end_sections_along_the_asked_directions() {
    let dir = tempfile::tempdir().unwrap();
    sections(dir.path());
    let (d0, d1) = (gamma_d(SPINE[0]), gamma_d(SPINE[4]));
    let (start, end) = (arg(d0 * 5.0), arg(d1));
    let tangents = ["--start-tangent-v", &start, "--end-tangent-v", &end];
    let extra = [&["--tol", "1e-4"][..], &tangents].concat();
    let run = surface_run(dir.path(), "s", dir.path(), &extra);
    let (s, r) = (run.surface, run.report);
    assert_eq!(r["within_tolerance"], true);
    let t = &r["v_end_tangents"];
    for (end, d) in [("start", d0), ("end", d1)] {
        let a = t[end]["max_angle"].as_f64().unwrap();
        assert!(a <= 1e-9, "{end}: {a:e}");
        let asked: Vec<f64> = t[end]["direction"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let u = d / d.norm();
        assert!((Vec3::new(asked[0], asked[1], asked[2]) - u).norm() < 1e-15);
    }
    assert_eq!(t["u_samples"], 1001);
    // the written surface, measured independently: 5 sections + 2 legs across
    assert_eq!(s.net_size().1, 7);
    let mut worst = 0.0f64;
    for i in 0..=300 {
        let u = i as f64 / 300.0;
        worst = worst.max(angle(sv_fd(&s, u, true), d0));
        worst = worst.max(angle(sv_fd(&s, u, false), d1));
    }
    assert!(worst <= 1e-9, "{worst:e}");
    // without the options the report has no such key and the net has 5 columns across
    let pr = surface_run(dir.path(), "p", dir.path(), &["--tol", "1e-4"]).report;
    assert!(pr.get("v_end_tangents").is_none());
    assert_eq!(pr["net"][1], 5);
    assert_eq!(pr["net"][0], r["net"][0]);
}

/// A usage error: exit 2, one `error:` line with `needle`, no output written.
fn refused(dir: &Path, extra: &[&str], needle: &str) {
    let out = dir.join("o.json");
    let o = fairfit()
        .arg("surface")
        .arg(dir)
        .args(["--tol", "1e-4"])
        .args(extra)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(needle),
        "{extra:?}: {err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!out.exists(), "{extra:?}");
}

#[test]
fn bad_tangent_values_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    sections(dir.path());
    let d = dir.path();
    for flag in ["--start-tangent-v", "--end-tangent-v"] {
        refused(d, &[flag, "0,0,0"], "non-zero");
        refused(d, &[flag, "nan,0,1"], "finite");
        refused(d, &[flag, "1,inf,1"], "finite");
        refused(d, &[flag, "1,2"], "got 2 values");
        refused(d, &[flag, "1,2,3,4"], "got 4 values");
        refused(d, &[flag, "a,b,c"], "expected three numbers");
        refused(
            d,
            &[flag, "-1,0,0", "--degree-v", "1"],
            "--degree-v 2 or more",
        );
    }
    refused(
        d,
        &[
            "--start-tangent-v",
            "0,0,1",
            "--end-tangent-v",
            "0,0,1",
            "--approximate-v",
            "3",
        ],
        "at least 4 control points",
    );
}
