//! `fairfit curve` on dense noisy data (12,000 points of a spiral, noise tol/20, generated here):
//! the same JSON bytes with 1 and 2 threads, the tolerance met on every point, a handful of control
//! points (the reduction stage, `optim/stages/reduce.rs`).

use assert_cmd::Command;
use serde_json::Value;
use std::fmt::Write;
use tempfile::TempDir;

/// The noisy spiral as CSV text (xorshift noise, uniform of the same variance as σ = 1.1e-4).
fn spiral_csv(n: usize) -> String {
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut noise = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let u = (s >> 11) as f64 / (1u64 << 53) as f64;
        1.1e-4 * 3f64.sqrt() * (2.0 * u - 1.0)
    };
    let mut out = String::from("x,y\n");
    for i in 0..n {
        let t = i as f64 / (n - 1) as f64;
        let (a, r) = (7.2 * t, 0.4 + 1.125 * t);
        writeln!(
            out,
            "{:.9},{:.9}",
            r * a.cos() + noise(),
            r * a.sin() + noise()
        )
        .unwrap();
    }
    out
}

#[test]
fn dense_noisy_data_give_the_same_bytes_with_one_and_two_threads() {
    let dir = TempDir::new().unwrap();
    let input = dir.path().join("spiral.csv");
    std::fs::write(&input, spiral_csv(12_000)).unwrap();
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.path().join(format!("c{threads}.json"));
        let rep = dir.path().join(format!("r{threads}.json"));
        let o = Command::cargo_bin("fairfit")
            .unwrap()
            .args([
                "curve",
                input.to_str().unwrap(),
                "--no-corners",
                "--threads",
                threads,
            ])
            .arg("-o")
            .arg(&out)
            .arg("--report")
            .arg(&rep)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&std::fs::read(&rep).unwrap()).unwrap();
        assert_eq!(r["points"], 12_000);
        assert_eq!(r["tolerance_met"], true);
        assert!(r["max_deviation"].as_f64().unwrap() <= r["tolerance"].as_f64().unwrap());
        let n = r["control_points"].as_u64().unwrap();
        assert!((8..40).contains(&n), "{n} control points");
        outputs.push(std::fs::read(&out).unwrap());
    }
    assert!(!outputs[0].is_empty());
    assert_eq!(outputs[0], outputs[1]);
}
