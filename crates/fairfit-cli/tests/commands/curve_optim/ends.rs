//! `fairfit curve --ends pinned|free`: the report says which end condition was used, free ends
//! give the same bytes with 1 and 2 threads, and `--ends free` needs the integrated method.

use crate::common;
use common::data;

use assert_cmd::Command;
use serde_json::Value;
use tempfile::TempDir;

fn run(args: &[&str]) -> std::process::Output {
    Command::cargo_bin("fairfit")
        .unwrap()
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn free_ends_are_thread_count_independent_and_reported() {
    let dir = TempDir::new().unwrap();
    let input = data("quarter_ellipse_200_noise1e-4.csv");
    let mut outputs = Vec::new();
    let mut reports = Vec::new();
    for (threads, ends) in [("1", "free"), ("2", "free"), ("1", "pinned")] {
        let out = dir.path().join(format!("c{threads}{ends}.json"));
        let rep = dir.path().join(format!("r{threads}{ends}.json"));
        let o = run(&[
            "curve",
            &input,
            "--ends",
            ends,
            "--threads",
            threads,
            "-o",
            out.to_str().unwrap(),
            "--report",
            rep.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        outputs.push(std::fs::read(&out).unwrap());
        let r: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
        reports.push(r);
    }
    assert!(!outputs[0].is_empty());
    assert_eq!(outputs[0], outputs[1]);
    assert_ne!(outputs[0], outputs[2]);
    assert_eq!(reports[0]["ends"], "free");
    assert_eq!(reports[2]["ends"], "pinned");
    for r in &reports {
        assert_eq!(r["tolerance_met"], true);
        assert!(r["max_deviation"].as_f64().unwrap() <= r["tolerance"].as_f64().unwrap());
    }
    // measured: F 28.68 pinned, 25.28 free (ratio 0.882; splprep's 33.9), 5 control points each
    let (ff, fp) = (
        reports[0]["fairness"].as_f64().unwrap(),
        reports[2]["fairness"].as_f64().unwrap(),
    );
    assert!(ff < 0.9 * fp, "{ff} vs {fp}");
}

#[test]
fn free_ends_need_the_integrated_method() {
    for method in ["lsq", "fit-then-fair"] {
        let o = run(&[
            "curve",
            &data("quarter_ellipse_200.csv"),
            "--method",
            method,
            "--ends",
            "free",
        ]);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--ends free needs --method integrated"),
            "{err}"
        );
    }
    // a closed curve has no ends: the report says so
    let dir = TempDir::new().unwrap();
    let pts = dir.path().join("circle.csv");
    let text: String = (0..=40)
        .map(|i| {
            let t = std::f64::consts::TAU * (i % 40) as f64 / 40.0;
            format!("{},{}\n", t.cos(), t.sin())
        })
        .collect();
    std::fs::write(&pts, text).unwrap();
    let rep = dir.path().join("r.json");
    let o = run(&[
        "curve",
        pts.to_str().unwrap(),
        "--ends",
        "free",
        "-o",
        dir.path().join("c.json").to_str().unwrap(),
        "--report",
        rep.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(r["closed"], true);
    assert_eq!(r["ends"], Value::Null);
    // a curve with a corner keeps its ends pinned: two quarter arcs meeting at a right angle
    let text: String = (0..=80)
        .map(|i| {
            if i <= 40 {
                let t = std::f64::consts::FRAC_PI_2 * i as f64 / 40.0;
                format!("{},{}\n", 1.0 - t.cos(), t.sin())
            } else {
                // from (1, 1) downwards: the tangent turns from (1, 0) to (0, −1)
                let t = std::f64::consts::FRAC_PI_2 * (i - 40) as f64 / 40.0;
                format!("{},{}\n", 2.0 - t.cos(), 1.0 - t.sin())
            }
        })
        .collect();
    std::fs::write(&pts, text).unwrap();
    let o = run(&[
        "curve",
        pts.to_str().unwrap(),
        "--ends",
        "free",
        "-o",
        dir.path().join("c.json").to_str().unwrap(),
        "--report",
        rep.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(r["closed"], false);
    assert_eq!(r["ends"], "pinned");
}
