//! `fairfit surface --outliers auto|off` on dense noisy sections with three spikes: `auto` excludes
//! exactly the spikes (by index, listed per section in the report) and meets the tolerance on every
//! other point; `off` keeps every point, misses the tolerance by the spikes' distance and names
//! them, by section, on stderr.

use crate::common;
use common::surface_run;

use std::path::Path;

const TOL: f64 = 1e-3;
const SPIKES: [usize; 3] = [1_234, 5_000, 8_765];

/// Four open half-ellipse sections of 10,000 points (about 4 per tolerance-sized bin: dense) with
/// Gaussian noise of tol/20 along the normal, and spikes of 20 tol along it on section 1, as files
/// in `dir`.
fn sections(dir: &Path) {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    for (k, z) in [0.0f64, 1.0, 2.5, 3.0].into_iter().enumerate() {
        let (a, b) = (2.0 + 0.3 * z, 1.0 + 0.1 * z * z);
        let mut s = String::from("x,y,z\n");
        for i in 0..10_000 {
            let t = std::f64::consts::PI * i as f64 / 9_999.0;
            let (nx, ny) = (b * t.cos(), a * t.sin());
            let len = nx.hypot(ny);
            let (u, v) = (uniform(), uniform());
            let mut off = TOL / 20.0 * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
            if k == 1 && SPIKES.contains(&i) {
                off = 20.0 * TOL;
            }
            let (x, y) = (a * t.cos() + off * nx / len, b * t.sin() + off * ny / len);
            s += &format!("{x:.17e},{y:.17e},{z}\n");
        }
        std::fs::write(dir.join(format!("sec_{k}.csv")), s).unwrap();
    }
}

#[test]
fn auto_excludes_exactly_the_spikes_and_off_names_them() {
    let dir = tempfile::tempdir().unwrap();
    let secs = dir.path().join("secs");
    std::fs::create_dir(&secs).unwrap();
    sections(&secs);
    let run = |mode: &str| {
        let extra = ["--tol", "1e-3", "--outliers", mode];
        let r = surface_run(dir.path(), &format!("s_{mode}"), &secs, &extra);
        (r.report, r.stderr)
    };
    let outliers = |r: &serde_json::Value, k: usize| -> Vec<u64> {
        r["dense"]["sections"][k]["outliers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| o["index"].as_u64().unwrap())
            .collect()
    };
    let (auto, err) = run("auto");
    assert_eq!(outliers(&auto, 1), SPIKES.map(|i| i as u64));
    for k in [0, 2, 3] {
        assert!(outliers(&auto, k).is_empty(), "section {k}");
    }
    assert_eq!(auto["deviation"]["points"], 40_000 - 3);
    let max = auto["deviation"]["max"].as_f64().unwrap();
    assert!(max <= TOL, "{max}");
    assert_eq!(auto["within_tolerance"], true);
    assert!(!err.contains("spikes"), "{err}");

    let (off, err) = run("off");
    for k in 0..4 {
        assert!(outliers(&off, k).is_empty(), "section {k}");
    }
    assert_eq!(off["deviation"]["points"], 40_000);
    // a spike is 20 tol off the shape: the fit stays on the shape and misses it by most of that
    let max = off["deviation"]["max"].as_f64().unwrap();
    assert!(max > 10.0 * TOL, "{max}");
    assert_eq!(off["within_tolerance"], false);
    let line = err
        .lines()
        .find(|l| l.contains("section 1: isolated spikes"))
        .unwrap_or_else(|| panic!("{err}"));
    for i in SPIKES {
        assert!(line.contains(&format!("point {i} (")), "{line}");
    }
    assert!(line.ends_with("--outliers auto excludes them"), "{line}");
    assert!(
        !err.contains("section 0:") && !err.contains("section 2:"),
        "{err}"
    );
}
