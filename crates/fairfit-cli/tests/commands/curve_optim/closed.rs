//! `fairfit curve --method integrated` on closed data and on data with corners: periodic output,
//! `--control-points` shared among pieces, `--pareto` of the joined and of the periodic curve.

use crate::common;
use common::data;

use assert_cmd::Command;
use serde_json::Value;
use tempfile::TempDir;

fn run_report(args: &[&str], dir: &TempDir, tag: &str) -> (Value, Value) {
    let out = dir.path().join(format!("{tag}.json"));
    let rep = dir.path().join(format!("{tag}_report.json"));
    Command::cargo_bin("fairfit")
        .unwrap()
        .args(args)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&rep)
        .assert()
        .success();
    let read = |p| serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    (read(&out), read(&rep))
}

#[test]
fn closed_circle_is_periodic_and_its_pareto_front_is_periodic() {
    let dir = TempDir::new().unwrap();
    let f = dir.path().join("circle.csv");
    let mut s = String::from("x,y\n");
    for i in 0..=100 {
        let t = std::f64::consts::TAU * (i % 100) as f64 / 100.0;
        s.push_str(&format!("{},{}\n", 2.0 * t.cos(), 2.0 * t.sin()));
    }
    std::fs::write(&f, s).unwrap();
    let (c, r) = run_report(&["curve", f.to_str().unwrap()], &dir, "c");
    assert_eq!(r["closed"], true);
    assert_eq!(r["tolerance_met"], true);
    let n_u = r["control_points"].as_u64().unwrap() as usize;
    let ctrl = c["control_points"].as_array().unwrap();
    // periodic: n_u + p control points, the last p repeat the first p (p = 5: the default degree
    // search keeps the quintic on a circle)
    let p = c["degree"].as_u64().unwrap() as usize;
    assert_eq!(p, 5);
    assert_eq!(ctrl.len(), n_u + p);
    assert_eq!(ctrl[..p], ctrl[n_u..]);
    assert!(r["fairness"].as_f64().unwrap() < 200.0);
    // --pareto: the front of the periodic curve at its count, every member periodic
    let front = dir.path().join("front.csv");
    let curves = dir.path().join("front");
    let (_, r2) = run_report(
        &[
            "curve",
            f.to_str().unwrap(),
            "--pareto",
            front.to_str().unwrap(),
            "--pareto-curves",
            curves.to_str().unwrap(),
        ],
        &dir,
        "p",
    );
    let csv = std::fs::read_to_string(&front).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() >= 2, "{csv}");
    assert_eq!(r2["pareto_members"].as_u64().unwrap() as usize, rows.len());
    let tol = r["tolerance"].as_f64().unwrap();
    // sorted by deviation with falling F; the first member within the tolerance
    assert!(rows[0][2] <= tol, "{csv}");
    for w in rows.windows(2) {
        assert!(w[0][2] < w[1][2] && w[0][4] > w[1][4], "{csv}");
    }
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[1] as usize, n_u, "{csv}");
        let m: Value = serde_json::from_str(
            &std::fs::read_to_string(curves.join(format!("front_{i:03}.json"))).unwrap(),
        )
        .unwrap();
        let mc = m["control_points"].as_array().unwrap();
        assert_eq!(mc.len(), n_u + p);
        assert_eq!(mc[..p], mc[n_u..], "member {i} is periodic");
    }
}

#[test]
fn blunt_trailing_edge_fixed_count_and_pareto_keep_the_corners() {
    let dir = TempDir::new().unwrap();
    let fx = data("fx77w343.csv");
    let (c0, r0) = run_report(&["curve", &fx, "--closed"], &dir, "free");
    let n = r0["control_points"].as_u64().unwrap();
    assert_eq!(r0["closed"], true);
    assert_eq!(c0["control_points"].as_array().unwrap().len() as u64, n);
    let front = dir.path().join("front.csv");
    let curves = dir.path().join("front");
    let ns = n.to_string();
    let (c1, r1) = run_report(
        &[
            "curve",
            &fx,
            "--closed",
            "--control-points",
            &ns,
            "--pareto",
            front.to_str().unwrap(),
            "--pareto-curves",
            curves.to_str().unwrap(),
        ],
        &dir,
        "fixed",
    );
    assert_eq!(r1["control_points"].as_u64().unwrap(), n);
    assert_eq!(r1["tolerance_met"], true);
    assert_eq!(c1["knots"], c0["knots"]);
    let csv = std::fs::read_to_string(&front).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() >= 3, "{csv}");
    for w in rows.windows(2) {
        assert!(w[0][2] < w[1][2] && w[0][4] > w[1][4], "{csv}");
    }
    assert_eq!(r1["pareto_members"].as_u64().unwrap() as usize, rows.len());
    assert_eq!(std::fs::read_dir(&curves).unwrap().count(), rows.len());
    // too few control points for the pieces: a usage error, one line naming the range
    let o = Command::cargo_bin("fairfit")
        .unwrap()
        .args(["curve", &fx, "--closed", "--control-points", "5"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with("error: ") && err.contains("between 7 and"),
        "{err}"
    );
}

#[test]
fn periodic_fit_with_fairing_and_front_is_byte_identical_with_one_and_two_threads() {
    // a 3:1 ellipse: the periodic knot search, band fairing, polish and the periodic front
    let dir = TempDir::new().unwrap();
    let f = dir.path().join("ellipse.csv");
    let mut s = String::from("x,y\n");
    for i in 0..=150 {
        let t = std::f64::consts::TAU * (i % 150) as f64 / 150.0;
        s.push_str(&format!("{},{}\n", 3.0 * t.cos(), t.sin()));
    }
    std::fs::write(&f, s).unwrap();
    let run = |threads: &str| {
        let out = dir.path().join(format!("e{threads}.json"));
        let front = dir.path().join(format!("f{threads}.csv"));
        Command::cargo_bin("fairfit")
            .unwrap()
            .args([
                "curve",
                f.to_str().unwrap(),
                "--seed",
                "5",
                "--threads",
                threads,
            ])
            .arg("-o")
            .arg(&out)
            .arg("--pareto")
            .arg(&front)
            .assert()
            .success();
        (
            std::fs::read(out).unwrap(),
            std::fs::read_to_string(front).unwrap(),
        )
    };
    let (c1, f1) = run("1");
    let (c2, f2) = run("2");
    assert_eq!(c1, c2);
    assert_eq!(f1, f2);
    let c: Value = serde_json::from_slice(&c1).unwrap();
    let ctrl = c["control_points"].as_array().unwrap();
    let n_u = ctrl.len() - 3;
    assert_eq!(ctrl[..3], ctrl[n_u..], "periodic");
    assert!(f1.lines().count() >= 3, "{f1}");
}
