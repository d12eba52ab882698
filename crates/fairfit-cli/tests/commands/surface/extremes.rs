//! Defects found by the session-13 product sweep, each pinned by the input that showed it: sections and
//! meshes at 1e±300 (misread as coincident points or empty planes), and the surface command's output
//! being the same whatever `--threads`.

use crate::common;
use common::{assert_success, fairfit, one_line_failure};

use std::path::Path;

/// Three ellipse sections (20 points each) of size `s`, as files in `dir`.
fn ellipse_sections(dir: &Path, s: f64) {
    for k in 0..3 {
        let text: String = (0..20)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 20.0;
                format!(
                    "{:e} {:e} {:e}\n",
                    s * t.cos(),
                    0.5 * s * t.sin(),
                    s * k as f64
                )
            })
            .collect();
        std::fs::write(dir.join(format!("s{k}.csv")), text).unwrap();
    }
}

/// OBJ of an open tube (radius s, 12 around, 4 high) with degenerate (zero-area) triangles mixed in.
fn tube_obj(path: &Path, s: f64) {
    let mut obj = String::new();
    for j in 0..5 {
        for i in 0..12 {
            let t = std::f64::consts::TAU * i as f64 / 12.0;
            obj += &format!("v {:e} {:e} {:e}\n", s * t.cos(), s * t.sin(), s * j as f64);
        }
    }
    for j in 0..4 {
        for i in 0..12 {
            let (a, b) = (j * 12 + i + 1, j * 12 + (i + 1) % 12 + 1);
            obj += &format!("f {a} {b} {}\nf {a} {} {}\n", b + 12, b + 12, a + 12);
            obj += &format!("f {a} {a} {b}\nf {a} {b} {a}\n");
        }
    }
    std::fs::write(path, obj).unwrap();
}

/// The arguments of `fairfit surface` on a folder of sections, or on an OBJ mesh sliced by 4 planes,
/// writing `out`.
fn surface_args<'a>(input: &'a Path, out: &'a str) -> Vec<&'a str> {
    let mut args = vec!["surface", input.to_str().unwrap()];
    if input.extension().is_some_and(|e| e == "obj") {
        args.extend(["--slices", "4"]);
    }
    args.extend(["-o", out]);
    args
}

#[test]
fn sections_and_meshes_at_extreme_scales_ask_for_rescaling() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let out = out.to_str().unwrap();
    for s in [1e300, 1e-300] {
        let secs = dir.path().join(format!("secs{s:e}"));
        std::fs::create_dir(&secs).unwrap();
        ellipse_sections(&secs, s);
        // was: "a section has zero length (all points coincide)"
        one_line_failure(
            &surface_args(&secs, out),
            1,
            &["section 0 is", "across", "rescale the points"],
        );
        let mesh = dir.path().join(format!("tube{s:e}.obj"));
        tube_obj(&mesh, s);
        // was (1e-300): "slicing gave 0 usable section(s) from 4 planes (4 empty)"
        one_line_failure(
            &surface_args(&mesh, out),
            1,
            &["the mesh is", "rescale the points"],
        );
    }
    assert!(!Path::new(out).exists());
    // at unit size the same files fit; the degenerate triangles change nothing
    let secs = dir.path().join("unit");
    std::fs::create_dir(&secs).unwrap();
    ellipse_sections(&secs, 1.0);
    let mesh = dir.path().join("tube.obj");
    tube_obj(&mesh, 1.0);
    for input in [&secs, &mesh] {
        assert_success(&fairfit().args(surface_args(input, out)).output().unwrap());
    }
}

/// The surface JSON and report of `fairfit surface ARGS --threads T` for T = 1, 2 and the default.
fn surface_outputs_per_thread_count(args: &[&str], dir: &Path) -> Vec<(Vec<u8>, Vec<u8>)> {
    [Some("1"), Some("2"), None]
        .iter()
        .map(|t| {
            let name = t.unwrap_or("default");
            let (o, r) = (
                dir.join(format!("s{name}.json")),
                dir.join(format!("r{name}.json")),
            );
            let mut cmd = fairfit();
            cmd.arg("surface")
                .args(args)
                .arg("-o")
                .arg(&o)
                .arg("--report")
                .arg(&r);
            if let Some(t) = t {
                cmd.args(["--threads", t]);
            }
            let out = cmd.output().unwrap();
            assert_success(&out);
            (std::fs::read(&o).unwrap(), std::fs::read(&r).unwrap())
        })
        .collect()
}

#[test]
fn surface_output_is_the_same_for_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let blade = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections");
    let mesh = dir.path().join("tube.obj");
    tube_obj(&mesh, 1.0);
    for args in [
        vec![blade.to_str().unwrap()],
        vec![mesh.to_str().unwrap(), "--slices", "5"],
    ] {
        let runs = surface_outputs_per_thread_count(&args, dir.path());
        let net = serde_json::from_slice::<serde_json::Value>(&runs[0].1).unwrap()["net"].clone();
        assert!(net[0].as_u64().unwrap() >= 4, "{net}");
        for r in &runs[1..] {
            assert!(
                r.0 == runs[0].0,
                "{args:?}: surface JSON differs between thread counts"
            );
            assert!(
                r.1 == runs[0].1,
                "{args:?}: report differs between thread counts"
            );
        }
    }
}

#[test]
fn outputs_naming_folders_fail_before_any_work_and_devices_are_written_into() {
    let dir = tempfile::tempdir().unwrap();
    let curve = dir.path().join("c.json");
    std::fs::write(
        &curve,
        r#"{"kind":"curve","degree":2,"knots":[0,0,0,0.5,1,1,1],
            "control_points":[[0,0,0],[1,1,0],[2,0,0],[3,1,0]]}"#,
    )
    .unwrap();
    let pts = dir.path().join("p.csv");
    std::fs::write(&pts, "0,0\n1,0.8\n2,0.1\n3,0.9\n4,0.2\n5,0.7\n6,0\n").unwrap();
    let folder = dir.path().join("folder.svg");
    std::fs::create_dir(&folder).unwrap();
    let (c, p, f) = (
        curve.to_str().unwrap(),
        pts.to_str().unwrap(),
        folder.to_str().unwrap(),
    );
    one_line_failure(&["plot", c, "-o", f], 1, &["names the folder", "-o"]);
    one_line_failure(
        &["export", c, "--plot", f],
        1,
        &["names the folder", "--plot"],
    );
    one_line_failure(&["export", c, "--samples", f], 1, &["names the folder"]);
    one_line_failure(&["curve", p, "-o", f], 1, &["names the folder"]);
    one_line_failure(&["curve", p, "--plot", f], 1, &["names the folder"]);
    // nothing was created beside them, and the folder is still a folder
    assert!(folder.is_dir());
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 3, "{names:?}");
    // a device is written into, not replaced: several outputs may name /dev/null
    let null = Path::new("/dev/null");
    if std::fs::metadata(null).is_ok_and(|m| !m.is_file()) {
        let out = fairfit()
            .args(["curve", p, "--method", "lsq", "-o", "/dev/null"])
            .args(["--report", "/dev/null"])
            .output()
            .unwrap();
        assert_success(&out);
        let meta = std::fs::metadata(null).unwrap();
        assert!(
            !meta.is_file() && !meta.is_dir(),
            "/dev/null is still a device"
        );
    }
}
