//! `fairfit batch`: every input's curve is the bytes `fairfit curve --seed S` writes for it, whatever
//! `--jobs`; a failed input is an error row that stops nothing; the exit code says whether any
//! failed; shards of a list cover it once.

use crate::common::{assert_success, data, fairfit, one_line_failure};
use std::path::Path;

/// A folder with two airfoils and a file of two points (which cannot be fitted).
fn inputs() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["e387.csv", "naca4412.csv"] {
        std::fs::copy(data(name), dir.path().join(name)).unwrap();
    }
    std::fs::write(dir.path().join("two.csv"), "0,0\n1,1\n").unwrap();
    dir
}

/// The summary's rows, as JSON values.
fn rows(path: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn each_curve_is_the_curve_commands_bytes_whatever_the_jobs() {
    let dir = inputs();
    let mut outs = Vec::new();
    for jobs in ["1", "2"] {
        let out = tempfile::tempdir().unwrap();
        let run = fairfit()
            .args(["batch", dir.path().to_str().unwrap(), "-o"])
            .arg(out.path())
            .args(["--jobs", jobs, "--seed", "3"])
            .output()
            .unwrap();
        // one input failed: exit 1 and one line naming the count
        assert_eq!(run.status.code(), Some(1), "{run:?}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains("1 of 3 input(s) failed"), "{err}");
        outs.push(out);
    }
    for name in ["e387", "naca4412"] {
        let single = tempfile::tempdir().unwrap();
        let (curve, report) = (single.path().join("c.json"), single.path().join("r.json"));
        let run = fairfit()
            .args(["curve", &data(&format!("{name}.csv")), "--seed", "3", "-o"])
            .arg(&curve)
            .arg("--report")
            .arg(&report)
            .output()
            .unwrap();
        assert_success(&run);
        let want = std::fs::read(&curve).unwrap();
        let want_report = crate::common::read_json(&report);
        for out in &outs {
            let got = std::fs::read(out.path().join(format!("{name}.json"))).unwrap();
            assert_eq!(
                got, want,
                "{name}: batch curve differs from `fairfit curve`"
            );
            let r = crate::common::read_json(&out.path().join(format!("{name}.report.json")));
            for key in [
                "control_points",
                "fairness",
                "max_deviation",
                "degree",
                "curvature_extrema",
            ] {
                assert_eq!(r[key], want_report[key], "{name}: {key}");
            }
        }
        for out in &outs {
            let row = rows(&out.path().join("summary.jsonl"))
                .into_iter()
                .find(|r| r["name"] == name)
                .unwrap();
            assert_eq!(row["status"], "ok");
            assert_eq!(row["error"], serde_json::Value::Null);
            assert_eq!(row["control_points"], want_report["control_points"]);
            assert_eq!(row["fairness"], want_report["fairness"]);
            assert_eq!(row["max_deviation"], want_report["max_deviation"]);
            assert!(row["seconds"].as_f64().unwrap() > 0.0);
        }
    }
    for out in &outs {
        let all = rows(&out.path().join("summary.jsonl"));
        let names: Vec<&str> = all.iter().map(|r| r["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["e387", "naca4412", "two"], "input order");
        assert_eq!(all[2]["status"], "error");
        let msg = all[2]["error"].as_str().unwrap();
        assert!(msg.contains("2 points are too few"), "{msg}");
        assert_eq!(all[2]["control_points"], serde_json::Value::Null);
        assert!(
            !out.path().join("two.json").exists(),
            "no file for a failed input"
        );
    }
}

#[test]
fn shards_of_a_list_cover_it_once_and_an_all_ok_run_exits_zero() {
    let dir = inputs();
    let list = dir.path().join("list.txt");
    let e387 = dir.path().join("e387.csv");
    let naca = dir.path().join("naca4412.csv");
    std::fs::write(
        &list,
        format!("# two airfoils\n{}\n\n{}\n", e387.display(), naca.display()),
    )
    .unwrap();
    let out = tempfile::tempdir().unwrap();
    for k in ["1/2", "2/2"] {
        let run = fairfit()
            .args(["batch", list.to_str().unwrap(), "-o"])
            .arg(out.path())
            .args(["--shard", k, "--method", "lsq"])
            .output()
            .unwrap();
        assert_success(&run);
    }
    let first = rows(&out.path().join("summary.1-of-2.jsonl"));
    let second = rows(&out.path().join("summary.2-of-2.jsonl"));
    assert_eq!((first.len(), second.len()), (1, 1));
    assert_eq!(
        (first[0]["name"].as_str(), second[0]["name"].as_str()),
        (Some("e387"), Some("naca4412"))
    );
    for name in ["e387", "naca4412"] {
        let report = crate::common::read_json(&out.path().join(format!("{name}.report.json")));
        assert_eq!(report["method"], "lsq");
        assert!(report["max_deviation"].as_f64().unwrap() <= report["tolerance"].as_f64().unwrap());
    }
}

#[test]
fn single_file_outputs_and_bad_shards_are_usage_errors() {
    let dir = inputs();
    let d = dir.path().to_str().unwrap();
    one_line_failure(
        &["batch", d, "-o", d, "--step", "x.step"],
        2,
        &["--step", "batch"],
    );
    one_line_failure(
        &["batch", d, "-o", d, "--report", "r.json"],
        2,
        &["--report"],
    );
    one_line_failure(&["batch", d, "-o", d, "--shard", "3/2"], 2, &["--shard"]);
    one_line_failure(&["batch", d, "-o", d, "--jobs", "0"], 2, &["--jobs"]);
    one_line_failure(&["batch", d], 2, &["OUTDIR"]);
}

#[test]
fn a_huge_jobs_count_is_capped_not_started() {
    // before: `--jobs 99999999999` asked rayon for that many threads and had not fitted anything
    // after 30 s; now the pool is capped like `--threads` and the result is the one of `--jobs 1`
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("e387.csv"), dir.path().join("e387.csv")).unwrap();
    let mut curves = Vec::new();
    for jobs in ["1", "99999999999"] {
        let out = tempfile::tempdir().unwrap();
        let start = std::time::Instant::now();
        let run = fairfit()
            .args(["batch", dir.path().to_str().unwrap(), "-o"])
            .arg(out.path())
            .args(["--jobs", jobs, "--method", "lsq"])
            .output()
            .unwrap();
        assert_success(&run);
        assert!(
            start.elapsed().as_secs() < 30,
            "--jobs {jobs}: {:?}",
            start.elapsed()
        );
        curves.push(std::fs::read(out.path().join("e387.json")).unwrap());
    }
    assert_eq!(curves[0], curves[1]);
}
