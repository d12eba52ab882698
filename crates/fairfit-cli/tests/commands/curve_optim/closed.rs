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

/// A noisy ring of `n` points (ellipse 4 × 2, σ = tol/10, xorshift noise) whose last point is
/// `gap_tol · tol` from its first, as CSV scaled by `k`; `tol` is 4e-3 before scaling.
fn noisy_ring_csv(n: usize, gap_tol: f64, k: f64) -> String {
    let tol = 4e-3;
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut normal = || {
        let (a, b) = (uniform(), uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    };
    let mut pts: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            (
                2.0 * t.cos() + tol / 10.0 * normal(),
                t.sin() + tol / 10.0 * normal(),
            )
        })
        .collect();
    let (x0, y0) = pts[0];
    let (dx, dy) = (pts[n - 1].0 - x0, pts[n - 1].1 - y0);
    let s = gap_tol * tol / dx.hypot(dy);
    pts[n - 1] = (x0 + s * dx, y0 + s * dy);
    let mut csv = String::from("x,y\n");
    for (x, y) in pts {
        csv.push_str(&format!("{:.17e},{:.17e}\n", k * x, k * y));
    }
    csv
}

#[test]
fn a_noisy_ring_with_a_gap_under_the_tolerance_is_closed_and_says_so() {
    let dir = TempDir::new().unwrap();
    for (k, tag) in [(1.0, "unit"), (1e3, "scaled")] {
        let f = dir.path().join(format!("ring_{tag}.csv"));
        std::fs::write(&f, noisy_ring_csv(2000, 0.3, k)).unwrap();
        let tol = format!("{}", 4e-3 * k);
        let args = ["curve", f.to_str().unwrap(), "--tol", &tol, "--degree", "3"];
        let (c, r) = run_report(&args, &dir, tag);
        assert_eq!(r["closed"], true, "{tag}: {r}");
        let gap = r["closed_by_gap"].as_f64().unwrap();
        assert!((gap / (1.2e-3 * k) - 1.0).abs() < 1e-6, "{tag}: gap {gap}");
        assert_eq!(r["tolerance_met"], true, "{tag}");
        assert!(r["max_deviation"].as_f64().unwrap() <= 4e-3 * k, "{tag}");
        // periodic: the last p control points repeat the first p
        let n_u = r["control_points"].as_u64().unwrap() as usize;
        let ctrl = c["control_points"].as_array().unwrap();
        assert_eq!(ctrl.len(), n_u + 3, "{tag}");
        assert_eq!(ctrl[..3], ctrl[n_u..], "{tag}");
        eprintln!(
            "{tag}: gap {gap:.3e}, {n_u} control points, max deviation {:.3e}",
            r["max_deviation"].as_f64().unwrap()
        );
        if k == 1.0 {
            // --open keeps it open: two ends, no gap closed
            let mut open = args.to_vec();
            open.push("--open");
            let (_, r) = run_report(&open, &dir, "open");
            assert_eq!(r["closed"], false);
            assert!(r.get("closed_by_gap").is_none());
            // the least-squares method decides alike
            let mut lsq = args.to_vec();
            lsq.extend(["--method", "lsq"]);
            let (_, r) = run_report(&lsq, &dir, "lsq");
            assert_eq!(r["closed"], true);
            assert_eq!(r["closed_by_gap"].as_f64(), Some(gap));
            assert!(r["max_deviation"].as_f64().unwrap() <= 4e-3);
        }
    }
}

#[test]
fn a_ring_missing_an_arc_and_a_blunt_trailing_edge_stay_open() {
    let dir = TempDir::new().unwrap();
    let f = dir.path().join("cut.csv");
    std::fs::write(&f, noisy_ring_csv(2000, 5.0, 1.0)).unwrap();
    let (_, r) = run_report(
        &[
            "curve",
            f.to_str().unwrap(),
            "--tol",
            "4e-3",
            "--degree",
            "3",
        ],
        &dir,
        "cut",
    );
    assert_eq!(r["closed"], false);
    assert!(r.get("closed_by_gap").is_none());
    // naca4412's blunt trailing edge (2.5e-3 chord) at ten times its gap: open, tangents reversing
    let (_, r) = run_report(
        &[
            "curve",
            &data("naca4412.csv"),
            "--tol",
            "2.5e-2",
            "--degree",
            "3",
        ],
        &dir,
        "naca",
    );
    assert_eq!(r["closed"], false);
    assert!(r.get("closed_by_gap").is_none());
}
