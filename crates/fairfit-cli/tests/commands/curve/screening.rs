//! `fairfit curve` screening: spikes excluded with `--outliers auto` (the default) and listed in the
//! report, named on stderr with `--outliers off`; the one-line noise warning below the noise.

use crate::common::{assert_success, file_with};
use assert_cmd::Command;
use serde_json::Value;
use tempfile::TempDir;

/// A clean circle arc of `n` points (radius 1, 3 rad), with points `spikes` pushed out by 5 %
/// (50 tolerances at `--rel-tol 1e-3`), and Gaussian-like noise `sigma` along the radius.
fn arc_csv(n: usize, spikes: &[usize], sigma: f64) -> String {
    let mut s = String::from("x,y\n");
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    for i in 0..n {
        // a sum of 12 uniforms: a deterministic near-normal sample
        let g: f64 = (0..12)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            })
            .sum::<f64>()
            - 6.0;
        let a = i as f64 / (n - 1) as f64 * 3.0;
        let r = if spikes.contains(&i) { 1.05 } else { 1.0 } + sigma * g;
        s += &format!("{},{}\n", r * a.cos(), r * a.sin());
    }
    s
}

fn run(csv: &str, extra: &[&str]) -> (Value, String) {
    let input = file_with(csv.as_bytes());
    let dir = TempDir::new().unwrap();
    let report = dir.path().join("r.json");
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args([
            "curve",
            input.path().to_str().unwrap(),
            "--rel-tol",
            "1e-3",
            "--method",
            "lsq",
        ])
        .args(["-o", dir.path().join("c.json").to_str().unwrap()])
        .args(["--report", report.to_str().unwrap()])
        .args(extra)
        .output()
        .unwrap();
    assert_success(&out);
    let r: Value = serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    (r, String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn spikes_excluded_by_default_and_named_when_off() {
    let csv = arc_csv(2000, &[300, 1234], 0.0);
    let (r, err) = run(&csv, &[]);
    let idx: Vec<u64> = r["outliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["index"].as_u64().unwrap())
        .collect();
    assert_eq!(idx, vec![300, 1234]);
    let d = r["outliers"][0]["distance"].as_f64().unwrap();
    assert!((d - 0.05).abs() < 0.005, "distance {d}");
    assert_eq!(
        (r["points"].as_u64(), r["outliers_mode"].as_str()),
        (Some(1998), Some("auto"))
    );
    assert!(r["max_deviation"].as_f64().unwrap() <= r["tolerance"].as_f64().unwrap());
    assert!(err.is_empty(), "{err}");
    let (r, err) = run(&csv, &["--outliers", "off"]);
    assert_eq!(r["outliers"].as_array().unwrap().len(), 0);
    if r["max_deviation"].as_f64().unwrap() > r["tolerance"].as_f64().unwrap() {
        let line = err
            .lines()
            .find(|l| l.contains("isolated spikes"))
            .expect(&err);
        assert!(
            line.contains("point 300") && line.contains("point 1234"),
            "{line}"
        );
    }
}

#[test]
fn noise_warning_in_one_line_when_the_tolerance_is_below_the_noise() {
    // σ ≈ 0.3 tol (tol = 2e-3 of the arc's 2-wide box)
    let (r, err) = run(&arc_csv(4000, &[], 6e-4), &[]);
    let sigma = r["noise_sigma"].as_f64().unwrap();
    assert!((sigma / 6e-4 - 1.0).abs() < 0.25, "σ {sigma}");
    assert_eq!(r["noise_limited"], Value::Bool(true));
    assert!((r["meaningful_tolerance"].as_f64().unwrap() / (5.0 * sigma) - 1.0).abs() < 1e-12);
    // fitted to the meaningful tolerance, the asked one kept in the report
    let used = r["tolerance_used"].as_f64().unwrap();
    assert_eq!(Some(used), r["meaningful_tolerance"].as_f64());
    assert!(r["tolerance"].as_f64().unwrap() < used);
    assert!(r["max_deviation"].as_f64().unwrap() <= used);
    assert!(
        r["control_points"].as_u64().unwrap() < 30,
        "{}",
        r["control_points"]
    );
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("below the noise"))
        .collect();
    assert_eq!(lines.len(), 1, "{err}");
    // at a tenth of the tolerance: no warning
    let (r, err) = run(&arc_csv(4000, &[], 2e-4), &[]);
    assert_eq!(r["noise_limited"], Value::Bool(false));
    assert_eq!(r["tolerance_used"], r["tolerance"]);
    assert!(!err.contains("below the noise"), "{err}");
}
