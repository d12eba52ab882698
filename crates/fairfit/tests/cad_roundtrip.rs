//! The STEP and IGES files fairfit writes, read back by a real CAD kernel (OpenCASCADE through OCP).
//!
//! Writes a rational curve and a rational bicubic surface to STEP and IGES, each with a JSON of 100+
//! sample parameters and fairfit's own points beside it, and runs `tests/python/occ_roundtrip.py` with
//! `$FAIRFIT_PYTHON`. Unset: the test is skipped with a note, except under `CI=true`, where it fails.

use fairfit::io::iges::{write_curve_iges, write_surface_iges, IgesOptions};
use fairfit::io::step::{write_curve_step, write_surface_step, StepOptions};
use fairfit::{NurbsCurve, NurbsSurface, Vec3};
use std::path::{Path, PathBuf};

fn curve() -> NurbsCurve {
    let pts = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(12.5, 30.0, 1.0),
        Vec3::new(40.0, 35.0, -2.0),
        Vec3::new(70.0, 5.0, 3.0),
        Vec3::new(95.0, 20.0, 0.5),
        Vec3::new(120.0, 60.0, 8.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.55, 1.0, 1.0, 1.0, 1.0];
    NurbsCurve::new(3, knots, pts, Some(vec![1.0, 0.8, 1.3, 1.0, 0.6, 1.0])).unwrap()
}

fn surface() -> NurbsSurface {
    let ku = vec![0.0, 0.0, 0.0, 0.0, 0.35, 0.7, 1.0, 1.0, 1.0, 1.0];
    let kv = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
    let net = (0..6)
        .map(|i| {
            (0..5)
                .map(|j| {
                    let (x, y) = (i as f64 * 20.0, j as f64 * 15.0);
                    Vec3::new(x + 0.1 * y, y, 8.0 * (x / 50.0).sin() * (y / 40.0).cos())
                })
                .collect()
        })
        .collect();
    let w = (0..6)
        .map(|i| (0..5).map(|j| 1.0 + 0.2 * ((i + j) % 3) as f64).collect())
        .collect();
    NurbsSurface::new(3, 3, ku, kv, net, Some(w)).unwrap()
}

/// A rational quadratic full circle (9 points) swept along z and flared: closed in u (seam edge).
fn tube() -> NurbsSurface {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let ring = [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, h),
        (0.0, 1.0, 1.0),
        (-1.0, 1.0, h),
        (-1.0, 0.0, 1.0),
        (-1.0, -1.0, h),
        (0.0, -1.0, 1.0),
        (1.0, -1.0, h),
        (1.0, 0.0, 1.0),
    ];
    let net = ring
        .iter()
        .map(|&(x, y, _)| {
            (0..4)
                .map(|j| {
                    let r = 10.0 + 2.0 * (j as f64).powi(2);
                    Vec3::new(r * x, r * y, 15.0 * j as f64)
                })
                .collect()
        })
        .collect();
    let w = ring.iter().map(|&(_, _, w)| vec![w; 4]).collect();
    let ku = vec![
        0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
    ];
    let kv = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    NurbsSurface::new(2, 3, ku, kv, net, Some(w)).unwrap()
}

fn samples_json(kind: &str, params: &[Vec<f64>], points: &[Vec3]) -> String {
    serde_json::json!({
        "kind": kind,
        "params": params,
        "points": points.iter().map(|p| p.0).collect::<Vec<_>>(),
    })
    .to_string()
}

fn surface_samples_json(s: &NurbsSurface) -> String {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut sp = Vec::new();
    for i in 0..=12 {
        for j in 0..=10 {
            sp.push(vec![
                u0 + (u1 - u0) * i as f64 / 12.0,
                v0 + (v1 - v0) * j as f64 / 10.0,
            ]);
        }
    }
    let spts: Vec<Vec3> = sp.iter().map(|p| s.point(p[0], p[1])).collect();
    samples_json("surface", &sp, &spts)
}

fn write_files(dir: &Path) -> Vec<PathBuf> {
    let (c, s) = (curve(), surface());
    let (a, b) = c.domain();
    let params: Vec<Vec<f64>> = (0..=120)
        .map(|k| vec![a + (b - a) * k as f64 / 120.0])
        .collect();
    let pts: Vec<Vec3> = params.iter().map(|u| c.point(u[0])).collect();
    let curve_samples = dir.join("curve.samples.json");
    std::fs::write(&curve_samples, samples_json("curve", &params, &pts)).unwrap();
    let surface_samples = dir.join("surface.samples.json");
    std::fs::write(&surface_samples, surface_samples_json(&s)).unwrap();
    let tube_samples = dir.join("tube.samples.json");
    std::fs::write(&tube_samples, surface_samples_json(&tube())).unwrap();
    let (so, io) = (StepOptions::default(), IgesOptions::default());
    write_curve_step(dir.join("curve.step"), &c, &so).unwrap();
    write_curve_iges(dir.join("curve.igs"), &c, &io).unwrap();
    write_surface_step(dir.join("surface.step"), &s, &so).unwrap();
    write_surface_iges(dir.join("surface.igs"), &s, &io).unwrap();
    write_surface_step(dir.join("tube.step"), &tube(), &so).unwrap();
    write_surface_iges(dir.join("tube.igs"), &tube(), &io).unwrap();
    let names = [
        "curve.step",
        "curve.igs",
        "surface.step",
        "surface.igs",
        "tube.step",
        "tube.igs",
    ];
    names
        .iter()
        .flat_map(|f| {
            let samples = match &f[..4] {
                "curv" => &curve_samples,
                "surf" => &surface_samples,
                _ => &tube_samples,
            };
            [dir.join(f), samples.clone()]
        })
        .collect()
}

#[test]
fn opencascade_reads_back_fairfit_step_and_iges() {
    let python = match std::env::var("FAIRFIT_PYTHON") {
        Ok(p) if !p.is_empty() => p,
        _ => {
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!(
                    "FAIRFIT_PYTHON is not set under CI=true: the CAD round trip must run in CI"
                );
            }
            println!("note: FAIRFIT_PYTHON unset, skipping the OpenCASCADE round trip");
            return;
        }
    };
    let dir = std::env::temp_dir().join(format!("fairfit-occ-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let args = write_files(&dir);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/occ_roundtrip.py");
    let out = std::process::Command::new(&python)
        .arg(&script)
        .args(&args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "OpenCASCADE round trip failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let reports: Vec<serde_json::Value> = stdout
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(reports.len(), 6);
    for r in &reports {
        assert!(r["samples"].as_u64().unwrap() >= 100, "{r}");
        assert!(r["relative_error"].as_f64().unwrap() <= 1e-9, "{r}");
    }
    assert_eq!(reports[2]["valid_faces"], 1);
    for r in &reports[2..] {
        assert_eq!(r["valid_faces"], 1, "{r}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
