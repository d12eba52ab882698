//! The curve report's `curvature_extrema` and `inflections` against the benchmark's independent
//! measurer (`bench/measure.py`, run with `$FAIRFIT_PYTHON`; skipped with a note when unset outside
//! CI): both count sign changes at 192 samples per knot span with the same hysteresis floor, so they
//! must agree exactly. The least-squares fits below have shallow curvature wiggles that the report's
//! former 32 samples per span stepped over (measured 2026-11-26: FFA-W3-241 7 against 9 extrema,
//! du84132v_noise1e-4 10 against 12).

use crate::common;
use common::{assert_success, data};

use crate::common::python;

use assert_cmd::Command;
use serde_json::Value;
use tempfile::TempDir;

/// `(extrema, inflections)` of the curve in `json` at `samples` per span, by bench/measure.py.
fn measured(python: &str, json: &std::path::Path, samples: usize) -> (u64, u64) {
    let bench = format!("{}/../../bench", env!("CARGO_MANIFEST_DIR"));
    let script = format!(
        "import json, sys, numpy as np\n\
         sys.path.insert(0, {bench:?})\n\
         import measure\n\
         js = json.load(open({json:?}))\n\
         c = measure.Curve(js['degree'], js['knots'], np.asarray(js['control_points'], float), js.get('weights'))\n\
         F, L = measure.fairness(c, True)\n\
         e, i = measure.shape_counts(c, True, L, {samples})\n\
         print(e, i)\n",
        json = json.to_str().unwrap()
    );
    let out = std::process::Command::new(python)
        .args(["-c", &script])
        .output()
        .unwrap();
    assert_success(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let v: Vec<u64> = text
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    (v[0], v[1])
}

#[test]
fn the_reported_extrema_are_the_measurers() {
    let Some(python) = python::python_or_skip("the report's extrema against bench/measure.py")
    else {
        return;
    };
    let dir = TempDir::new().unwrap();
    for (name, extrema, sparse) in [
        ("iea15mw_airfoils/FFA-W3-241.csv", 9, 7),
        ("du84132v_noise1e-4.csv", 12, 10),
    ] {
        let (out, rep) = (dir.path().join("c.json"), dir.path().join("r.json"));
        let run = Command::cargo_bin("fairfit")
            .unwrap()
            .args([
                "curve",
                &data(name),
                "--method",
                "lsq",
                "--rel-tol",
                "1e-3",
                "-o",
            ])
            .arg(&out)
            .arg("--report")
            .arg(&rep)
            .output()
            .unwrap();
        assert!(run.status.success(), "{name}");
        let report: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
        let (e, i) = measured(&python, &out, 192);
        assert_eq!(report["curvature_extrema"].as_u64(), Some(e), "{name}");
        assert_eq!(report["inflections"].as_u64(), Some(i), "{name}");
        // the numbers of 2026-11-26, and what 32 samples per span counted
        assert_eq!(e, extrema, "{name}");
        assert_eq!(measured(&python, &out, 32).0, sparse, "{name}");
        // the exact count (roots of dκ/ds) is the measurer's at 20 000 samples per span
        let (dense, dense_inflections) = measured(&python, &out, 20_000);
        assert_eq!(
            report["curvature_extrema_exact"].as_u64(),
            Some(dense),
            "{name}"
        );
        // and so are the exact inflections (roots of the signed curvature's numerator)
        assert_eq!(
            report["inflections_exact"].as_u64(),
            Some(dense_inflections),
            "{name}"
        );
        assert!(dense >= e, "{name}");
    }
}
