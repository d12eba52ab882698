//! `fairfit surface` end to end: blade sections, sliced meshes with and without holes, and clear errors
//! (one line, exit code 1, no panic) for unusable inputs.

use crate::common;
use common::{fairfit, surface_run};

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn blade_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections")
}

/// A failure of the run (bad input): exit code 1, one `error:` line containing `needle`.
fn fails_with(cmd: &mut Command, needle: &str) {
    exits_with(cmd, 1, needle);
}

/// A usage error (an option value or combination `fairfit surface` does not accept): exit code 2, one
/// `error:` line containing `needle` and pointing at `fairfit surface --help`.
fn usage_fails(cmd: &mut Command, needle: &str) {
    let err = exits_with(cmd, 2, needle);
    assert!(err.contains("see 'fairfit surface --help'"), "{err}");
}

fn exits_with(cmd: &mut Command, code: i32, needle: &str) -> String {
    let out = cmd.output().unwrap();
    assert_eq!(out.status.code(), Some(code));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: ") && err.contains(needle), "{err}");
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    err.into_owned()
}

/// OBJ of an open cylinder (radius r, height 2), optionally without the triangles in an angular window
/// at mid height.
fn cylinder_obj(path: &Path, r: f64, hole: bool) {
    let (na, nz) = (96, 16);
    let mut s = String::new();
    for j in 0..=nz {
        for i in 0..na {
            let t = std::f64::consts::TAU * i as f64 / na as f64;
            s += &format!(
                "v {} {} {}\n",
                r * t.cos(),
                r * t.sin(),
                2.0 * j as f64 / nz as f64
            );
        }
    }
    for j in 0..nz {
        for i in 0..na {
            if hole && (7..9).contains(&j) && (10..20).contains(&i) {
                continue;
            }
            let (a, b) = (j * na + i + 1, j * na + (i + 1) % na + 1);
            let (c, d) = (a + na, b + na);
            s += &format!("f {a} {b} {d}\nf {a} {d} {c}\n");
        }
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn blade_sections_within_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let run = surface_run(dir.path(), "blade", blade_dir(), &["--tol", "0.0057"]);
    let r = run.report;
    assert_eq!(r["within_tolerance"], true);
    assert!(r["deviation"]["max"].as_f64().unwrap() <= 0.0057);
    assert_eq!(r["deviation"]["points"], 1916);
    let net = r["net"].as_array().unwrap();
    assert!(
        net[0].as_u64().unwrap() <= 24 && net[1].as_u64().unwrap() <= 10,
        "{net:?}"
    );
    assert_eq!(r["sections"].as_array().unwrap().len(), 10);
    // one section has an inner corner, the others none: nothing is held, and the report says why
    let c = &r["corners"];
    assert_eq!(c["held"], false);
    assert_eq!(c["per_section"][2], 1);
    assert!(c["reason"].as_str().unwrap().contains("different"), "{c}");
    assert!(r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["corners_held"] == 0));
    let s: serde_json::Value = serde_json::from_str(&run.json).unwrap();
    assert_eq!(s["kind"], "surface");
}

/// Four closed D-shaped sections (a half-ellipse from (a, 0) over the top to (−a, 0), closed by the
/// straight segment back along y = 0): a corner at the seam and one inside, held as a C0 knot line.
#[test]
fn inner_corners_of_the_sections_are_held_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (k, z) in [0.0f64, 1.0, 2.5, 3.0].into_iter().enumerate() {
        let (a, b) = (2.0 + 0.3 * z, 1.0 + 0.1 * z * z);
        let mut s = String::new();
        for i in 0..=60 {
            let t = std::f64::consts::PI * i as f64 / 60.0;
            s += &format!("{},{},{z}\n", a * t.cos(), b * t.sin());
        }
        for i in 1..=20 {
            s += &format!("{},0,{z}\n", -a + 2.0 * a * i as f64 / 20.0);
        }
        std::fs::write(d.join(format!("sec_{k}.csv")), s).unwrap();
    }
    let r = surface_run(d, "s", d, &["--tol", "1e-3"]).report;
    assert_eq!(r["within_tolerance"], true);
    let c = &r["corners"];
    assert_eq!(c["held"], true, "{c}");
    assert_eq!(c["per_section"], serde_json::json!([1, 1, 1, 1]));
    assert!(r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["corners_held"] == 1));
    let tc = c["params"][0].as_f64().unwrap();
    let knots = r["knots_u"].as_array().unwrap();
    assert_eq!(knots.iter().filter(|k| k.as_f64() == Some(tc)).count(), 3);
    // --no-corners smooths them over; --corner-angle 100 finds none (the D's corners turn by 90°)
    let out = tempfile::tempdir().unwrap();
    for (flag, value, found) in [
        ("--no-corners", None, 1),
        ("--corner-angle", Some("100"), 0),
    ] {
        let extra: Vec<&str> = ["--tol", "1e-3", flag].into_iter().chain(value).collect();
        let c = surface_run(out.path(), "s2", d, &extra).report["corners"].clone();
        assert_eq!(c["held"], false, "{flag}: {c}");
        assert_eq!(
            c["per_section"],
            serde_json::json!(vec![found; 4]),
            "{flag}: {c}"
        );
    }
    let bad = fairfit()
        .arg("surface")
        .arg(d)
        .args(["--tol", "1e-3", "--corner-angle", "0", "-o"])
        .arg(out.path().join("s3.json"))
        .output()
        .unwrap();
    assert!(!bad.status.success() && !out.path().join("s3.json").exists());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("--corner-angle") && err.contains("(0, 180]"),
        "{err}"
    );
}

#[test]
fn sliced_cylinder_mesh_and_its_hole() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("cyl.obj");
    cylinder_obj(&mesh, 2.0, false);
    let sliced = ["--slices", "6", "--axis", "z", "--rel-tol", "1e-3"];
    let r = surface_run(dir.path(), "s", &mesh, &sliced).report;
    assert_eq!(r["gaps"].as_array().unwrap().len(), 0);
    assert_eq!(r["within_tolerance"], true);
    assert!(r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["closed"] == true));
    // smooth closed sections: periodic in u, no crease at the seam (tangent angle and relative
    // curvature jump at rounding level); --clamped-seam gives the clamped fit and its C0 edge
    // (about 0.014 rad and a 15 % curvature jump here)
    assert_eq!(r["periodic_u"], true);
    assert!(r["seam"]["max_tangent_angle"].as_f64().unwrap() < 1e-12);
    assert!(r["seam"]["max_curvature_jump"].as_f64().unwrap() < 1e-12);
    let clamped = [&sliced[..], &["--clamped-seam"]].concat();
    let r = surface_run(dir.path(), "c", &mesh, &clamped).report;
    assert_eq!(r["periodic_u"], false);
    assert_eq!(r["within_tolerance"], true);
    assert!(r["seam"]["max_tangent_angle"].as_f64().unwrap() > 1e-3);
    // 5 slices: the middle plane (z = 1) crosses the hole; it is reported with its size
    let holed = dir.path().join("holed.obj");
    cylinder_obj(&holed, 2.0, true);
    let r = surface_run(
        dir.path(),
        "h",
        &holed,
        &["--slices", "5", "--rel-tol", "1e-2"],
    )
    .report;
    let gaps = r["gaps"].as_array().unwrap();
    assert_eq!(gaps.len(), 1, "{gaps:?}");
    assert_eq!(gaps[0]["section"], 2);
    // 10 of 96 segments missing: chord 2 r sin(10 π / 96)
    let want = 4.0 * (10.0 * std::f64::consts::PI / 96.0).sin();
    let got = gaps[0]["length"].as_f64().unwrap();
    assert!((got - want).abs() < 0.05 * want, "{got} vs {want}");
}

#[test]
fn unusable_inputs_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o.json");
    let one = blade_dir().join("sec_03_s0.245.csv");
    // one section
    fails_with(
        fairfit().arg("surface").arg(&one).arg("-o").arg(&o),
        "at least 2 sections",
    );
    // a section of 2 points
    let two = dir.path().join("two.csv");
    std::fs::write(&two, "x,y,z\n0,0,1\n1,0,1\n").unwrap();
    fails_with(
        fairfit()
            .arg("surface")
            .arg(&one)
            .arg(&two)
            .arg("-o")
            .arg(&o),
        "at least 3 points",
    );
    // an empty folder, a missing file, a malformed file
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    std::fs::write(empty.join("INDEX.md"), "nothing").unwrap();
    fails_with(
        fairfit().arg("surface").arg(&empty).arg("-o").arg(&o),
        "no .csv",
    );
    fails_with(
        fairfit()
            .arg("surface")
            .arg(&one)
            .arg(dir.path().join("nope.csv"))
            .arg("-o")
            .arg(&o),
        "nope.csv",
    );
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "1,2,3\n1,x,3\n").unwrap();
    fails_with(
        fairfit()
            .arg("surface")
            .arg(&one)
            .arg(&bad)
            .arg("-o")
            .arg(&o),
        "bad.csv:2",
    );
    // a mesh without --slices, and slices that cut nothing (two far-apart rings of points)
    let mesh = dir.path().join("c.obj");
    cylinder_obj(&mesh, 1.0, false);
    usage_fails(
        fairfit().arg("surface").arg(&mesh).arg("-o").arg(&o),
        "--slices",
    );
    let rings = dir.path().join("rings.xyz");
    let mut s = String::new();
    for z in [0.0, 10.0] {
        for i in 0..50 {
            let t = std::f64::consts::TAU * i as f64 / 50.0;
            s += &format!("{} {} {z}\n", t.cos(), t.sin());
        }
    }
    std::fs::write(&rings, s).unwrap();
    fails_with(
        fairfit()
            .arg("surface")
            .arg(&rings)
            .args(["--slices", "8"])
            .arg("-o")
            .arg(&o),
        "usable section",
    );
    usage_fails(
        fairfit()
            .arg("surface")
            .arg(&mesh)
            .args(["--slices", "1"])
            .arg("-o")
            .arg(&o),
        "at least 2 slices",
    );
    usage_fails(
        fairfit()
            .arg("surface")
            .arg(blade_dir())
            .arg("--tol=-1")
            .arg("-o")
            .arg(&o),
        "invalid value '-1' for '--tol <TOL>': expected a finite number > 0",
    );
    assert!(!o.exists());
}

#[test]
fn impossible_counts_and_negative_numbers_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o.json");
    let with = |extra: &[&str]| {
        let mut c = fairfit();
        c.arg("surface")
            .arg(blade_dir())
            .args(extra)
            .arg("-o")
            .arg(&o);
        c
    };
    // was: accepted, the fit lifted the count to degree + 1 and only warned that the tolerance failed
    for (n, p, need) in [("0", "3", "4"), ("3", "3", "4"), ("2", "2", "3")] {
        usage_fails(
            &mut with(&["--max-ctrl", n, "--degree", p]),
            &format!(
                "--max-ctrl {n} is below the {need} control points a degree-{p} section needs"
            ),
        );
    }
    usage_fails(
        &mut with(&["--approximate-v", "1"]),
        "at least 2 control points",
    );
    // was: "unexpected argument '-1' found" for every negative number
    usage_fails(
        &mut with(&["--max-ctrl", "-1"]),
        "invalid value '-1' for '--max-ctrl <MAX_CTRL>': expected a whole number >= 0",
    );
    usage_fails(
        &mut with(&["--threads", "-2"]),
        "expected a whole number >= 0, got -2",
    );
    usage_fails(
        &mut with(&["--degree", "2.5"]),
        "expected a whole number >= 0, got 2.5",
    );
    usage_fails(
        &mut with(&["--smooth-v", "-1"]),
        "invalid value '-1' for '--smooth-v <SMOOTH_V>': expected a finite number >= 0",
    );
    usage_fails(
        &mut with(&["--gap-factor", "-3"]),
        "expected a finite number > 0, got -3",
    );
    assert!(!o.exists());
}

/// Four open half-ellipse sections at z = 0, 1, 2.5, 3 (semi-axes growing with z), as CSV files.
fn half_ellipse_sections(dir: &Path) -> Vec<PathBuf> {
    [0.0f64, 1.0, 2.5, 3.0]
        .iter()
        .enumerate()
        .map(|(k, &z)| {
            let (a, b) = (2.0 + 0.3 * z, 1.0 + 0.1 * z * z);
            let mut s = String::from("x,y,z\n");
            for i in 0..40 {
                let t = std::f64::consts::PI * i as f64 / 39.0;
                s += &format!("{},{},{z}\n", a * t.cos(), b * t.sin());
            }
            let p = dir.join(format!("sec_{k}.csv"));
            std::fs::write(&p, s).unwrap();
            p
        })
        .collect()
}

#[test]
fn surface_writes_checked_step_and_html() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let secs = d.join("secs");
    std::fs::create_dir(&secs).unwrap();
    half_ellipse_sections(&secs);
    let (step, html) = (d.join("s.step"), d.join("s.html"));
    let (step_arg, html_arg) = (step.to_str().unwrap(), html.to_str().unwrap());
    let extra = ["--tol", "1e-3", "--step", step_arg, "--html", html_arg];
    let r = surface_run(d, "s", &secs, &extra).report;
    assert_eq!(r["within_tolerance"], true);
    assert_eq!(r["deviation"]["points"], 160);
    let (nu, nv) = (r["net"][0].as_u64().unwrap(), r["net"][1].as_u64().unwrap());
    // four sections are interpolated: four control points across them
    assert_eq!(nv, 4);
    let text = std::fs::read_to_string(&step).unwrap();
    let entities = fairfit::io::cad_check::check_step(&text).unwrap().entities;
    assert_eq!(entities.get("ADVANCED_FACE"), Some(&1), "{entities:?}");
    assert_eq!(text.matches("B_SPLINE_SURFACE_WITH_KNOTS").count(), 1);
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("<svg"), "the page carries its plots");
    assert!(
        page.contains(&format!("{nu} x {nv}")),
        "the page names the net"
    );
}

#[test]
fn sections_ordered_by_position_along_an_axis() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let secs = d.join("secs");
    std::fs::create_dir(&secs).unwrap();
    // names in the wrong order: z = 0, 1, 2.5, 3 become files d, b, a, c
    for (p, name) in half_ellipse_sections(&secs)
        .iter()
        .zip(["d", "b", "a", "c"])
    {
        std::fs::rename(p, secs.join(format!("{name}.csv"))).unwrap();
    }
    let run = |order: &str| {
        let extra = ["--tol", "1e-3", "--order", order, "--axis", "z"];
        surface_run(d, &format!("s_{order}"), &secs, &extra).report
    };
    let r = run("axis");
    let names: Vec<String> = r["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let n = s["name"].as_str().unwrap();
            Path::new(n)
                .file_stem()
                .unwrap()
                .to_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(names, ["d", "b", "a", "c"]);
    assert_eq!(r["within_tolerance"], true);
    // chord-length v parameters of stacked sections 1, 1.5, 0.5 apart (plus the growing ellipses)
    let v: Vec<f64> = r["v_params"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(v.windows(2).all(|w| w[1] > w[0]), "{v:?}");
    assert!(
        v[1] > 0.2 && v[1] < 0.45 && v[2] > 0.7 && v[2] < 0.9,
        "{v:?}"
    );
    // by name (a, b, c, d = z 2.5, 1, 3, 0) the surface zig-zags: much less fair across the sections
    let by_name = run("name");
    let f = |r: &serde_json::Value| r["iso_fairness"]["max_fairness_along_v"].as_f64().unwrap();
    assert!(f(&by_name) > 10.0 * f(&r), "{} vs {}", f(&by_name), f(&r));
}

/// Sections and meshes at extreme scales, thread counts and output paths.
mod extremes;
mod open_sections;
mod outliers;
mod split_at_le;
mod v_tangents;
