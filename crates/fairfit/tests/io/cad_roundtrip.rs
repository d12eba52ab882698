//! The STEP and IGES files fairfit writes, read back by a real CAD kernel (OpenCASCADE through OCP).
//!
//! Writes a rational curve, a rational bicubic surface, a closed tube, a cone with a collapsed edge, a
//! periodic tube (checked closed in u with a C2 seam after reading) and the real IEA 15 MW blade
//! surface fitted by `fairfit surface` (fixture `tests/data/`) to STEP and IGES, each with a JSON of
//! 100+ sample parameters and fairfit's own points beside it, and runs
//! `tests/python/occ_roundtrip.py` with `$FAIRFIT_PYTHON`. Unset: the test is skipped with a note
//! (except under `CI=true`, where it fails); set but empty, pointing at no Python, or at one without
//! OCP: the test fails.

use crate::common::cad_fixtures;
use crate::common::python;

use cad_fixtures::{rational_curve, rational_surface};

use fairfit::io::iges::{write_curve_iges, write_surface_iges, IgesOptions};
use fairfit::io::samples::{curve_samples_json, surface_samples_json};
use fairfit::io::step::{write_curve_step, write_surface_step, StepOptions};
use fairfit::{NurbsSurface, Vec3};
use std::path::{Path, PathBuf};

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

/// A half cone: the boundary v = 1 collapses to the apex (a degenerate edge).
fn cone() -> NurbsSurface {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let arc = [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, h),
        (0.0, 1.0, 1.0),
        (-1.0, 1.0, h),
        (-1.0, 0.0, 1.0),
    ];
    let net = arc
        .iter()
        .map(|&(x, y, _)| {
            (0..3)
                .map(|j| {
                    let r = 20.0 * (1.0 - j as f64 / 2.0);
                    Vec3::new(r * x, r * y, 10.0 * j as f64)
                })
                .collect()
        })
        .collect();
    let w = arc.iter().map(|&(_, _, w)| vec![w; 3]).collect();
    let ku = vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
    NurbsSurface::new(2, 2, ku, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], net, Some(w)).unwrap()
}

/// A periodic bicubic tube (what `fairfit surface` makes of smooth closed sections): an unclamped
/// periodic u knot vector whose last 3 control rows repeat the first, so it is C2 across the u seam.
fn periodic_tube() -> NurbsSurface {
    let breaks = [0.0, 0.1, 0.25, 0.4, 0.5, 0.62, 0.75, 0.9, 1.0];
    let ku = fairfit::fit::lsq::periodic_knots(&breaks, 3);
    let ring: Vec<(f64, f64)> = (0..8)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 8.0;
            (12.0 * t.cos(), 7.0 * t.sin() + 0.5 * (2.0 * t).cos())
        })
        .collect();
    let net: Vec<Vec<Vec3>> = (0..11)
        .map(|i| {
            let (x, y) = ring[i % 8];
            (0..5)
                .map(|j| {
                    let z = 20.0 * j as f64;
                    let r = 1.0 + 0.1 * j as f64 + 0.02 * (j * j) as f64;
                    Vec3::new(r * x + 0.3 * z, r * y, z)
                })
                .collect()
        })
        .collect();
    let kv = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
    let s = NurbsSurface::new(3, 3, ku, kv, net, None).unwrap();
    assert!(s.is_periodic_u() && !s.is_periodic_v());
    s
}

/// The IEA 15 MW blade surface as fitted by `fairfit surface` (see `tests/data/README.md`).
fn blade() -> NurbsSurface {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/iea15mw_blade_surface.json");
    match fairfit::io::read_geometry(&path).unwrap() {
        fairfit::io::Geometry::Surface(s) => s,
        other => panic!("expected a surface, got {other:?}"),
    }
}

fn write_files(dir: &Path) -> Vec<PathBuf> {
    let (c, s) = (rational_curve(), rational_surface(3));
    let curve_samples = dir.join("curve.samples.json");
    std::fs::write(&curve_samples, curve_samples_json(&c, 120)).unwrap();
    let surface_samples = dir.join("surface.samples.json");
    std::fs::write(&surface_samples, surface_samples_json(&s, 12, 10)).unwrap();
    let cone_samples = dir.join("cone.samples.json");
    std::fs::write(&cone_samples, surface_samples_json(&cone(), 12, 10)).unwrap();
    let tube_samples = dir.join("tube.samples.json");
    std::fs::write(&tube_samples, surface_samples_json(&tube(), 12, 10)).unwrap();
    let periodic_samples = dir.join("periodic.samples.json");
    let mut samples: serde_json::Value =
        serde_json::from_str(&surface_samples_json(&periodic_tube(), 12, 10)).unwrap();
    samples["seam"] = "u".into();
    std::fs::write(&periodic_samples, samples.to_string()).unwrap();
    let blade_samples = dir.join("blade.samples.json");
    // The blade is in metres and written as such: OpenCASCADE reads it back in millimetres.
    let mut samples: serde_json::Value =
        serde_json::from_str(&surface_samples_json(&blade(), 24, 12)).unwrap();
    samples["unit"] = "m".into();
    std::fs::write(&blade_samples, samples.to_string()).unwrap();
    let (so, io) = (StepOptions::default(), IgesOptions::default());
    let metres = StepOptions {
        unit: fairfit::io::LengthUnit::Metre,
        ..Default::default()
    };
    let metres_iges = IgesOptions {
        unit: fairfit::io::LengthUnit::Metre,
        ..Default::default()
    };
    write_surface_step(dir.join("blade.step"), &blade(), &metres).unwrap();
    write_surface_iges(dir.join("blade.igs"), &blade(), &metres_iges).unwrap();
    write_curve_step(dir.join("curve.step"), &c, &so).unwrap();
    write_curve_iges(dir.join("curve.igs"), &c, &io).unwrap();
    write_surface_step(dir.join("surface.step"), &s, &so).unwrap();
    write_surface_iges(dir.join("surface.igs"), &s, &io).unwrap();
    write_surface_step(dir.join("tube.step"), &tube(), &so).unwrap();
    write_surface_iges(dir.join("tube.igs"), &tube(), &io).unwrap();
    write_surface_step(dir.join("periodic.step"), &periodic_tube(), &so).unwrap();
    write_surface_iges(dir.join("periodic.igs"), &periodic_tube(), &io).unwrap();
    write_surface_step(dir.join("cone.step"), &cone(), &so).unwrap();
    write_surface_iges(dir.join("cone.igs"), &cone(), &io).unwrap();
    let names = [
        "curve.step",
        "curve.igs",
        "surface.step",
        "surface.igs",
        "tube.step",
        "tube.igs",
        "cone.step",
        "cone.igs",
        "periodic.step",
        "periodic.igs",
        "blade.step",
        "blade.igs",
    ];
    names
        .iter()
        .flat_map(|f| {
            let samples = match &f[..4] {
                "curv" => &curve_samples,
                "surf" => &surface_samples,
                "cone" => &cone_samples,
                "blad" => &blade_samples,
                "peri" => &periodic_samples,
                _ => &tube_samples,
            };
            [dir.join(f), samples.clone()]
        })
        .collect()
}

#[test]
fn opencascade_reads_back_fairfit_step_and_iges() {
    let Some(python) = python::python_or_skip("the OpenCASCADE round trip") else {
        return;
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
    assert_eq!(reports.len(), args.len() / 2);
    for (r, file) in reports.iter().zip(args.iter().step_by(2)) {
        assert_eq!(r["file"].as_str(), file.to_str(), "{r}");
        assert!(r.get("error").is_none(), "{r}");
        assert!(r["samples"].as_u64().unwrap() >= 100, "{r}");
        assert!(r["relative_error"].as_f64().unwrap() <= 1e-9, "{r}");
    }
    assert_eq!(reports[0]["kind"], "curve");
    assert_eq!(reports[1]["kind"], "curve");
    for r in &reports[2..] {
        assert_eq!(r["kind"], "surface", "{r}");
        assert_eq!(r["valid_faces"], 1, "{r}");
    }
    let blade = blade();
    let (n_u, n_v) = blade.net_size();
    for r in &reports[8..10] {
        // the closed / periodic flags make OpenCASCADE rebuild it periodic on the 8 distinct rows
        assert_eq!(r["u_closed"], true, "{r}");
        assert_eq!(r["u_periodic"], true, "{r}");
        assert_eq!(r["poles"], serde_json::json!([8, 5]), "{r}");
        assert!(r["seam_tangent_angle"].as_f64().unwrap() <= 1e-9, "{r}");
        assert!(r["seam_curvature_jump"].as_f64().unwrap() <= 1e-9, "{r}");
    }
    for r in &reports[10..] {
        assert_eq!(r["poles"], serde_json::json!([n_u, n_v]), "{r}");
        assert!(r["samples"].as_u64().unwrap() >= 300, "{r}");
        assert_eq!(r["unit_factor"], 1000.0, "{r}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
