//! `fairfit surface --split-at-le` on the IEA-15MW blade sections: every section's leading edge (the
//! point farthest from the midpoint of its first and last points, found here from the files) is on
//! the written surface's iso-curve u = 0.5 at the section's v, the report's `split_at_le` says so, the
//! tolerance is met; a section without a leading edge is refused in one line with nothing written.

use crate::common;
use common::{fairfit, surface_run};

use fairfit::Vec3;
use std::path::{Path, PathBuf};

fn blade_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections")
}

/// The points of a section file (comment lines and the `x,y,z` header skipped).
fn section_points(path: &Path) -> Vec<Vec3> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#') && !l.starts_with('x'))
        .map(|l| {
            let v: Vec<f64> = l
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect();
            Vec3::new(v[0], v[1], v[2])
        })
        .collect()
}

#[test]
fn blade_leading_edges_lie_on_the_iso_curve_u_half() {
    let dir = tempfile::tempdir().unwrap();
    let extra = ["--tol", "0.0057", "--split-at-le"];
    let run = surface_run(dir.path(), "blade", blade_dir(), &extra);
    let (s, r) = (run.surface, run.report);
    assert_eq!(r["within_tolerance"], true);
    let le = &r["split_at_le"];
    assert_eq!(le["parameter"], 0.5);
    let rows = le["sections"].as_array().unwrap();
    assert_eq!(rows.len(), 10);
    let mut files: Vec<PathBuf> = std::fs::read_dir(blade_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    let size = 6.0; // the largest chord is 5.7
    let mut checked = 0;
    for (k, (row, file)) in rows.iter().zip(&files).enumerate() {
        let p: Vec<f64> = serde_json::from_value(row["point"].clone()).unwrap();
        let q = Vec3::new(p[0], p[1], p[2]);
        // the leading edge from the file itself (an open section's ends, a closed one's start, are
        // unchanged by the orientation unless its seam was shifted)
        if r["sections"][k]["seam_shift"] == 0 {
            let pts = section_points(file);
            let te = (pts[0] + pts[pts.len() - 1]) * 0.5;
            let far = pts
                .iter()
                .copied()
                .max_by(|a, b| a.distance(te).total_cmp(&b.distance(te)))
                .unwrap();
            assert_eq!(q, far, "section {k}");
            checked += 1;
        }
        let v = r["v_params"][k].as_f64().unwrap();
        let miss = s.point(0.5, v).distance(q);
        assert!(miss <= 1e-9 * size, "section {k}: {miss:e}");
        assert!(row["distance"].as_f64().unwrap() <= 1e-9 * size, "{row}");
        assert!(
            row["surface_distance"].as_f64().unwrap() <= 1e-9 * size,
            "{row}"
        );
    }
    assert!(checked >= 8, "{checked}");
    assert!(le["max_distance"].as_f64().unwrap() <= 1e-9 * size);
    assert!(le["surface_max_distance"].as_f64().unwrap() <= 1e-9 * size);
    // without the option the report has no such key
    let plain = surface_run(dir.path(), "plain", blade_dir(), &["--tol", "0.0057"]).report;
    assert!(plain.get("split_at_le").is_none());
}

/// A section whose farthest point from the midpoint of its ends is an end point (a parabola arc):
/// exit 1, one line naming the section, no output file.
#[test]
fn a_section_without_a_leading_edge_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let files = blade_dir();
    std::fs::copy(files.join("sec_05_s0.439.csv"), d.join("a.csv")).unwrap();
    let arc: String = (0..=40)
        .map(|i| {
            let x = i as f64 / 40.0;
            format!("{x},{},60\n", x * x)
        })
        .collect();
    std::fs::write(d.join("b.csv"), arc).unwrap();
    let out = d.join("s.json");
    let res = fairfit()
        .arg("surface")
        .arg(d.join("a.csv"))
        .arg(d.join("b.csv"))
        .args(["--tol", "0.005", "--split-at-le", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(res.status.code(), Some(1));
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(
        err.starts_with("error: ") && err.contains("section 1") && err.contains("leading edge"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!out.exists());
}
