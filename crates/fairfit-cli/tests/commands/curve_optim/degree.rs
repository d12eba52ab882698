//! `fairfit curve --degree auto` (the integrated method's degree search, its default) and fixed
//! degrees 4 and 5: byte-identical output for 1 and 2 threads, every degree in the report, the chosen
//! one within the cubic's control points, `--degree 3` the cubic search alone, and a fixed count a
//! quintic cannot meet reported as a miss.

use crate::common;
use common::data;

use assert_cmd::Command;
use serde_json::Value;
use tempfile::TempDir;

fn fairfit(args: &[&str]) -> std::process::Output {
    Command::cargo_bin("fairfit")
        .unwrap()
        .args(args)
        .output()
        .unwrap()
}

fn run(args: &[&str]) -> String {
    let out = fairfit(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn report(path: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn auto_is_byte_identical_for_one_and_two_threads_and_reports_every_degree() {
    let dir = TempDir::new().unwrap();
    let input = data("iea15mw_airfoils/circular.csv");
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.path().join(format!("c{threads}.json"));
        let rep = dir.path().join(format!("r{threads}.json"));
        let (o, r) = (out.to_str().unwrap(), rep.to_str().unwrap());
        run(&[
            "curve",
            &input,
            "--degree",
            "auto",
            "--threads",
            threads,
            "-o",
            o,
            "--report",
            r,
        ]);
        outputs.push(std::fs::read(&out).unwrap());
        let v = report(&rep);
        let tried = v["optimizer"]["degrees_tried"].as_array().unwrap().clone();
        let degrees: Vec<u64> = tried
            .iter()
            .map(|t| t["degree"].as_u64().unwrap())
            .collect();
        assert_eq!(degrees, [3, 4, 5]);
        // the closed circular section: a higher degree, no more control points than the cubic,
        // and the report's curve is the chosen trial
        let chosen = v["degree"].as_u64().unwrap();
        assert!(chosen >= 4, "degree {chosen}");
        let n = v["control_points"].as_u64().unwrap();
        assert!(n <= tried[0]["control_points"].as_u64().unwrap());
        let t = &tried[(chosen - 3) as usize];
        assert_eq!(t["control_points"].as_u64().unwrap(), n);
        assert_eq!(t["fairness"], v["fairness"]);
        assert!(t["fairness"].as_f64().unwrap() < 0.1 * tried[0]["fairness"].as_f64().unwrap());
        assert_eq!(v["tolerance_met"], true);
        assert!(v["max_deviation"].as_f64().unwrap() <= v["tolerance"].as_f64().unwrap());
    }
    assert!(!outputs[0].is_empty());
    assert_eq!(outputs[0], outputs[1]);
}

#[test]
fn the_default_is_auto_and_degree_3_is_its_cubic_trial() {
    let dir = TempDir::new().unwrap();
    let input = data("iea15mw_airfoils/circular.csv");
    let mut reports = Vec::new();
    for degree in [None, Some("3")] {
        let rep = dir
            .path()
            .join(format!("r{}.json", degree.unwrap_or("default")));
        let out = dir.path().join("c.json");
        let mut args = vec![
            "curve",
            &input,
            "-o",
            out.to_str().unwrap(),
            "--report",
            rep.to_str().unwrap(),
        ];
        if let Some(d) = degree {
            args.extend(["--degree", d]);
        }
        run(&args);
        reports.push(report(&rep));
    }
    let (auto, cubic) = (&reports[0], &reports[1]);
    // the closed circular section: the quintic at the cubic's 7 distinct control points, F below 0.5
    // against the periodic cubic's polygon value 135.21 (docs/optim.md)
    assert_eq!(auto["degree"], 5);
    assert_eq!(auto["control_points"], 7);
    let f = auto["fairness"].as_f64().unwrap();
    assert!(f < 0.5, "F {f}");
    assert_eq!(auto["tolerance_met"], true);
    let tried = auto["optimizer"]["degrees_tried"].as_array().unwrap();
    let degrees: Vec<u64> = tried
        .iter()
        .map(|t| t["degree"].as_u64().unwrap())
        .collect();
    assert_eq!(degrees, [3, 4, 5]);
    // --degree 3: no search, the cubic trial of the default run
    assert_eq!(cubic["degree"], 3);
    assert!(cubic["optimizer"].get("degrees_tried").is_none());
    assert_eq!(cubic["control_points"], tried[0]["control_points"]);
    assert_eq!(cubic["fairness"], tried[0]["fairness"]);
    let f3 = cubic["fairness"].as_f64().unwrap();
    assert!((f3 - 135.21).abs() < 0.01, "cubic F {f3}");
}

#[test]
fn auto_needs_the_integrated_method_and_bad_degrees_are_refused() {
    let input = data("naca4412.csv");
    for method in ["lsq", "fit-then-fair"] {
        let out = fairfit(&["curve", &input, "--method", method, "--degree", "auto"]);
        assert_eq!(out.status.code(), Some(2), "{method}"); // a usage error
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--degree auto needs --method integrated"),
            "{err}"
        );
    }
    for bad in ["automatic", "0", "16", "3.5", ""] {
        let out = fairfit(&["curve", &input, "--degree", bad]);
        assert_eq!(out.status.code(), Some(2), "--degree {bad:?}");
    }
}

#[test]
fn a_fixed_count_a_quintic_cannot_meet_is_reported_as_a_miss() {
    // hq17: the quintic needs 15 control points (its count search), 12 leave the nose 1.6x tol out
    let dir = TempDir::new().unwrap();
    let rep = dir.path().join("r.json");
    let out = dir.path().join("c.json");
    let err = run(&[
        "curve",
        &data("hq17.csv"),
        "--degree",
        "5",
        "--control-points",
        "12",
        "--threads",
        "1",
        "-o",
        out.to_str().unwrap(),
        "--report",
        rep.to_str().unwrap(),
    ]);
    let v = report(&rep);
    assert_eq!(v["degree"], 5);
    assert_eq!(v["control_points"], 12);
    assert_eq!(v["tolerance_met"], false);
    let (dev, tol) = (
        v["max_deviation"].as_f64().unwrap(),
        v["tolerance"].as_f64().unwrap(),
    );
    assert!(dev > 1.2 * tol, "{dev} vs {tol}");
    assert!(err.contains("warning: the tolerance"), "{err}");
}

#[test]
fn the_front_and_the_cad_files_of_auto_have_the_chosen_degree() {
    let dir = TempDir::new().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    run(&[
        "curve",
        &data("iea15mw_airfoils/circular.csv"),
        "--degree",
        "auto",
        "--pareto",
        &path("front.csv"),
        "--pareto-curves",
        &path("front"),
        "--step",
        &path("c.step"),
        "--iges",
        &path("c.igs"),
        "-o",
        &path("c.json"),
    ]);
    let curve = report(&dir.path().join("c.json"));
    let p = curve["degree"].as_u64().unwrap();
    assert!(p >= 4, "degree {p}");
    let members: Vec<_> = std::fs::read_dir(dir.path().join("front"))
        .unwrap()
        .map(|e| report(&e.unwrap().path()))
        .collect();
    assert!(!members.is_empty());
    for m in &members {
        assert_eq!(m["degree"].as_u64().unwrap(), p);
    }
    let step = std::fs::read_to_string(dir.path().join("c.step")).unwrap();
    assert!(step.contains(&format!("B_SPLINE_CURVE_WITH_KNOTS('',{p},")));
    // IGES entity 126: K (upper control-point index), then the degree M
    let iges = std::fs::read_to_string(dir.path().join("c.igs")).unwrap();
    let n = curve["control_points"].as_array().unwrap().len();
    assert!(iges.contains(&format!("126,{},{p},", n - 1)), "{iges}");
}
