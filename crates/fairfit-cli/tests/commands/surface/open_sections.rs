//! `fairfit surface` on section files that stop one sampling step short of closing: closed across
//! that step at the tolerance's scale (the report's per-section `closed_by_gap`, a seamless periodic
//! surface), and kept open with `--open-sections`.

use crate::common;
use common::surface_run;

use std::path::Path;

/// Three wavy rings at z = 0, 1, 2 (ellipses 1 × (0.6 + 0.1k)), 200 points at equal angle steps of a
/// 200-step turn, the last point one step short of the first, as CSV files in `dir`. Returns the
/// steps from the last point to the first.
fn rings(dir: &Path) -> Vec<f64> {
    (0..3)
        .map(|k| {
            let b = 0.6 + 0.1 * k as f64;
            let p = |i: usize| {
                let t = std::f64::consts::TAU * i as f64 / 200.0;
                let r = 1.0 + 0.05 * (3.0 * t).cos();
                [r * t.cos(), b * r * t.sin(), k as f64]
            };
            let mut s = String::from("x,y,z\n");
            for i in 0..200 {
                let q = p(i);
                s += &format!("{:?},{:?},{:?}\n", q[0], q[1], q[2]);
            }
            std::fs::write(dir.join(format!("ring_{k}.csv")), s).unwrap();
            let (a, z) = (p(0), p(199));
            ((a[0] - z[0]).powi(2) + (a[1] - z[1]).powi(2)).sqrt()
        })
        .collect()
}

#[test]
fn section_files_one_step_short_of_closing_are_fitted_closed() {
    let (dir, out) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let steps = rings(dir.path());
    let tol = "0.04";
    let closed = surface_run(out.path(), "closed", dir.path(), &["--tol", tol]);
    let r = &closed.report;
    assert_eq!(r["within_tolerance"], true);
    assert_eq!(r["periodic_u"], true);
    for (s, step) in r["sections"].as_array().unwrap().iter().zip(&steps) {
        assert_eq!(s["closed"], true);
        assert_eq!(s["points"], 201);
        let g = s["closed_by_gap"].as_f64().unwrap();
        assert!((g - step).abs() <= 1e-12 * step, "{g} vs {step}");
    }
    assert!(r["seam"]["max_tangent_angle"].as_f64().unwrap() < 1e-9);

    let open = surface_run(
        out.path(),
        "open",
        dir.path(),
        &["--tol", tol, "--open-sections"],
    );
    let r = &open.report;
    assert_eq!(r["periodic_u"], false);
    for s in r["sections"].as_array().unwrap() {
        assert_eq!(s["closed"], false);
        assert_eq!(s["points"], 200);
        assert!(s.get("closed_by_gap").is_none());
    }
}
