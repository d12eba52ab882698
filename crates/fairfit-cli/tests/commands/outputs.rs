//! `fairfit curve ... --step --iges --mesh --plot --html` end to end: all five files written with the
//! content a CAD system, a mesh viewer and a browser expect; bad input and unwritable paths fail before
//! any file (the curve JSON included) is written.

use crate::common;
use common::fairfit;

use fairfit::io::cad_check::{check_iges, check_step};
use std::path::{Path, PathBuf};

fn naca() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/naca4412.csv")
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn one_line_error(out: &std::process::Output) -> String {
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "{err}"
    );
    err
}

#[test]
fn lsq_fit_writes_step_iges_mesh_plot_and_html() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fairfit()
        .current_dir(d)
        .arg("curve")
        .arg(naca())
        .args(["--method", "lsq", "-o", "c.json"])
        .args(["--step", "a.stp", "--iges", "a.igs", "--mesh", "a.obj"])
        .args(["--plot", "a.svg", "--html", "a.html"])
        .assert()
        .success();
    assert_eq!(
        files_in(d),
        ["a.html", "a.igs", "a.obj", "a.stp", "a.svg", "c.json"],
        "the five outputs and the curve, no temporary files"
    );
    let curve = match fairfit::io::read_geometry(d.join("c.json")).unwrap() {
        fairfit::io::Geometry::Curve(c) => c,
        g => panic!("not a curve: {g:?}"),
    };
    let n = curve.n_control_points();

    let step = std::fs::read_to_string(d.join("a.stp")).unwrap();
    assert!(
        step.starts_with("ISO-10303-21;\nHEADER;"),
        "{}",
        &step[..40]
    );
    assert!(step.contains("FILE_SCHEMA(("));
    assert!(step.trim_end().ends_with("END-ISO-10303-21;"));
    check_step(&step).unwrap();
    assert_eq!(step.matches("B_SPLINE_CURVE_WITH_KNOTS(").count(), 1);
    assert_eq!(step.matches("GEOMETRIC_CURVE_SET(").count(), 1);
    assert_eq!(
        step.matches("CARTESIAN_POINT(").count(),
        n + 1,
        "the control points and the placement origin"
    );
    assert!(step.contains("SI_UNIT(.MILLI.,.METRE.)"));

    let iges = std::fs::read_to_string(d.join("a.igs")).unwrap();
    for (k, line) in iges.lines().enumerate() {
        assert_eq!(line.len(), 80, "IGES line {k} is not 80 columns: {line:?}");
    }
    let sections: String = iges.lines().map(|l| &l[72..73]).collect();
    let order: String = sections.chars().fold(String::new(), |mut acc, c| {
        if !acc.ends_with(c) {
            acc.push(c);
        }
        acc
    });
    assert_eq!(
        order, "SGDPT",
        "start, global, directory, parameter, terminate"
    );
    assert_eq!(check_iges(&iges).unwrap().entity_types, vec![126]);

    let obj = std::fs::read_to_string(d.join("a.obj")).unwrap();
    let vertices = obj.lines().filter(|l| l.starts_with("v ")).count();
    assert!(vertices > n, "polyline denser than the control polygon");
    let line = obj.lines().find(|l| l.starts_with("l ")).unwrap();
    assert_eq!(line.split_whitespace().count(), vertices + 1);

    let svg = std::fs::read_to_string(d.join("a.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("curvature comb") && svg.contains("<polyline"));

    let html = std::fs::read_to_string(d.join("a.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert_eq!(
        html.matches("<svg").count(),
        3,
        "comb, curvature, deviation"
    );
    for external in ["<script", "<link", "src=", "href=", "url("] {
        assert!(!html.contains(external), "not self-contained: {external}");
    }
    assert!(html.contains("max_deviation") || html.contains("max deviation"));
}

#[test]
fn nan_points_and_bad_geometry_fail_before_any_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("nan.csv"), "x,y\n0,0\n1,0.2\n2,NaN\n3,0.1\n4,0\n").unwrap();
    let knots_short = r#"{"kind":"curve","degree":3,"knots":[0,0,0,0,1,1,1],
        "control_points":[[0,0,0],[1,1,0],[2,1,0],[3,0,0]]}"#;
    let nan_json = r#"{"kind":"curve","degree":1,"knots":[0,0,1,1],
        "control_points":[[0,0,0],[NaN,1,0]]}"#;
    let zero_weight = r#"{"kind":"curve","degree":1,"knots":[0,0,1,1],
        "control_points":[[0,0,0],[1,1,0]],"weights":[1,0]}"#;
    std::fs::write(d.join("short.json"), knots_short).unwrap();
    std::fs::write(d.join("nan.json"), nan_json).unwrap();
    std::fs::write(d.join("w.json"), zero_weight).unwrap();
    let inputs = files_in(d);
    let outputs = [
        "--step", "o.stp", "--iges", "o.igs", "--mesh", "o.obj", "--plot", "o.svg", "--html",
        "o.html",
    ];
    let out = fairfit()
        .current_dir(d)
        .args(["curve", "nan.csv", "--method", "lsq", "-o", "o.json"])
        .args(outputs)
        .output()
        .unwrap();
    let err = one_line_error(&out);
    assert!(err.contains("nan.csv") && err.contains("finite"), "{err}");
    for (file, needle) in [
        ("short.json", "knots"),
        ("nan.json", "nan.json"),
        ("w.json", "weight"),
    ] {
        let out = fairfit()
            .current_dir(d)
            .args(["export", file])
            .args(outputs)
            .output()
            .unwrap();
        let err = one_line_error(&out);
        assert!(err.contains(needle), "{file}: {err}");
    }
    assert_eq!(files_in(d), inputs, "no output written");
}

#[test]
fn unwritable_output_is_named_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = fairfit()
        .current_dir(d)
        .arg("curve")
        .arg(naca())
        .args(["--method", "lsq", "-o", "c.json", "--report", "r.json"])
        .args([
            "--step",
            "a.stp",
            "--iges",
            "no_such_dir/a.igs",
            "--html",
            "a.html",
        ])
        .output()
        .unwrap();
    let err = one_line_error(&out);
    assert!(err.contains("no_such_dir/a.igs"), "{err}");
    assert!(
        files_in(d).is_empty(),
        "all or nothing, no temporary files: {:?}",
        files_in(d)
    );
}
