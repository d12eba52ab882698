//! `fairfit export` and `fairfit plot` end to end: files written and checked (STEP/IGES structure, mesh
//! counts, PNG size), and bad input refused before any file exists.

use crate::common;
use common::fairfit;

use fairfit::io::cad_check::{check_iges, check_step};
use fairfit::plot::png::png_size;
use std::path::Path;

fn curve_json() -> String {
    serde_json::json!({
        "kind": "curve", "degree": 3,
        "knots": [0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
        "control_points": [[0, 0, 0], [10, 20, 0], [30, 25, 0], [45, 5, 0], [60, 15, 0]],
    })
    .to_string()
}

fn surface_json() -> String {
    let net: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| [i as f64 * 10.0, j as f64 * 10.0, ((i * j) % 3) as f64])
                .collect()
        })
        .collect();
    serde_json::json!({
        "kind": "surface", "degree_u": 3, "degree_v": 3,
        "knots_u": [0, 0, 0, 0, 1, 1, 1, 1], "knots_v": [0, 0, 0, 0, 1, 1, 1, 1],
        "control_points": net,
    })
    .to_string()
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn export_writes_checked_step_iges_and_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (name, json) in [("c.json", curve_json()), ("s.json", surface_json())] {
        let input = write(d, name, &json);
        let stem = &name[..1];
        let mesh = if stem == "c" { "obj" } else { "stl" };
        fairfit()
            .arg("export")
            .arg(&input)
            .args(["--step", &format!("{}/{stem}.step", d.display())])
            .args(["--iges", &format!("{}/{stem}.igs", d.display())])
            .args(["--mesh", &format!("{}/{stem}.{mesh}", d.display())])
            .args(["--chord-tol", "0.01", "--units", "m"])
            .args(["--samples", &format!("{}/{stem}.samples.json", d.display())])
            .assert()
            .success();
        let step = std::fs::read_to_string(d.join(format!("{stem}.step"))).unwrap();
        let entities = check_step(&step).unwrap().entities;
        assert!(step.contains("SI_UNIT($,.METRE.)"));
        let samples = std::fs::read_to_string(d.join(format!("{stem}.samples.json"))).unwrap();
        let samples: serde_json::Value = serde_json::from_str(&samples).unwrap();
        assert!(samples["points"].as_array().unwrap().len() >= 100);
        let iges = std::fs::read_to_string(d.join(format!("{stem}.igs"))).unwrap();
        let summary = check_iges(&iges).unwrap();
        assert!(iges.contains(",6,1HM,"), "unit flag metres");
        if stem == "c" {
            assert_eq!(entities.get("GEOMETRIC_CURVE_SET"), Some(&1));
            assert_eq!(summary.entity_types, vec![126]);
            let obj = std::fs::read_to_string(d.join("c.obj")).unwrap();
            assert_eq!(obj.lines().filter(|l| l.starts_with("l ")).count(), 1);
        } else {
            assert_eq!(entities.get("ADVANCED_FACE"), Some(&1));
            assert_eq!(summary.entity_types, vec![128]);
            let stl = std::fs::read(d.join("s.stl")).unwrap();
            let n = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
            assert!(n > 100 && stl.len() == 84 + 50 * n);
        }
    }
}

#[test]
fn bad_geometry_fails_before_any_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let decreasing = curve_json().replace("0.4,", "1.5,");
    let huge = curve_json().replace("[10,20,0]", "[1e999,20,0]");
    for (k, bad) in [decreasing, huge].iter().enumerate() {
        let input = write(d, &format!("bad{k}.json"), bad);
        let out = fairfit()
            .arg("export")
            .arg(&input)
            .args(["--step", &format!("{}/out{k}.step", d.display())])
            .args(["--iges", &format!("{}/out{k}.igs", d.display())])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: ") && err.lines().count() == 1,
            "{err}"
        );
        assert!(
            err.contains("knots") || err.contains("out of range"),
            "{err}"
        );
    }
    let left: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 2, "only the two inputs: {left:?}");
}

#[test]
fn unwritable_path_is_named_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "c.json", &curve_json());
    let target = dir.path().join("no_such_dir").join("out.step");
    let out = fairfit()
        .arg("export")
        .arg(&input)
        .arg("--step")
        .arg(&target)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no_such_dir/out.step"), "{err}");
    assert!(!target.exists());
    let out = fairfit().arg("export").arg(&input).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing to export"));
}

#[test]
fn plot_writes_png_of_the_requested_size_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = write(d, "c.json", &curve_json());
    let points = write(d, "p.csv", "x,y\n0,0\n15,18\n30,20\n45,8\n60,15\n");
    let png = d.join("comb.png");
    fairfit()
        .arg("plot")
        .arg(&input)
        .arg("--points")
        .arg(&points)
        .arg("-o")
        .arg(&png)
        .args(["--width", "500", "--height", "350"])
        .assert()
        .success();
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(png_size(&bytes), Some((500, 350)));
    assert!(bytes.len() > 2000);
    for kind in ["curvature", "deviation"] {
        let svg = d.join(format!("{kind}.svg"));
        fairfit()
            .arg("plot")
            .arg(&input)
            .arg("--points")
            .arg(&points)
            .args(["--kind", kind, "-o"])
            .arg(&svg)
            .assert()
            .success();
        assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    }
    let out = fairfit()
        .arg("plot")
        .arg(&input)
        .args(["--kind", "iso-u", "-o"])
        .arg(d.join("x.svg"))
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("--kind iso-u does not apply to a curve"));
    let surf = write(d, "s.json", &surface_json());
    let html = d.join("r.html");
    fairfit()
        .arg("export")
        .arg(&surf)
        .arg("--html")
        .arg(&html)
        .assert()
        .success();
    let page = std::fs::read_to_string(&html).unwrap();
    assert_eq!(page.matches("<svg").count(), 2, "two iso-curvature plots");
    assert!(page.contains("<td>4 x 4</td>"));
}
