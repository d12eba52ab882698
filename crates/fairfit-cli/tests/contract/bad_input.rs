//! Hostile command lines for every subcommand: 0, negative, huge, NaN and infinite option values, empty
//! and binary files, a folder where a file is expected, and unwritable output paths. Whatever the
//! outcome, `fairfit` must never panic or print a backtrace, and a failure is exactly one `error:` line
//! with a non-zero exit code. Inputs are tiny so the whole file runs in seconds.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

/// Count values that break naive integer option handling.
const COUNTS: &[&str] = &["0", "-1", "18446744073709551615", "18446744073709551616"];

struct Fixture {
    _dir: tempfile::TempDir,
    root: PathBuf,
}

impl Fixture {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().to_path_buf();
        let wavy: String = (0..14)
            .map(|i| {
                let x = i as f64 / 13.0;
                format!("{x},{}\n", 0.2 * (6.0 * x).sin())
            })
            .collect();
        std::fs::write(root.join("pts.csv"), wavy).unwrap();
        std::fs::write(
            root.join("curve.json"),
            r#"{"kind":"curve","degree":2,"knots":[0,0,0,0.5,1,1,1],
                "control_points":[[0,0,0],[1,1,0],[2,0,0],[3,1,0]]}"#,
        )
        .unwrap();
        std::fs::write(
            root.join("surface.json"),
            r#"{"kind":"surface","degree_u":1,"degree_v":1,"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],
                "control_points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#,
        )
        .unwrap();
        let sections = root.join("sections");
        std::fs::create_dir(&sections).unwrap();
        for k in 0..3 {
            let s: String = (0..10)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as f64 / 10.0;
                    format!("{} {} {k}\n", t.cos(), 0.5 * t.sin())
                })
                .collect();
            std::fs::write(sections.join(format!("s{k}.csv")), s).unwrap();
        }
        std::fs::write(root.join("empty.csv"), "").unwrap();
        let bin: Vec<u8> = (0..2048u32)
            .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
            .collect();
        std::fs::write(root.join("binary.dat"), &bin).unwrap();
        std::fs::write(root.join("binary.json"), &bin).unwrap();
        std::fs::create_dir(root.join("folder.json")).unwrap();
        // an open tube (8 around, 4 high) for slicing
        let mut obj = String::new();
        for j in 0..4 {
            for i in 0..8 {
                let t = std::f64::consts::TAU * i as f64 / 8.0;
                obj += &format!("v {} {} {j}\n", t.cos(), t.sin());
            }
        }
        for j in 0..3 {
            for i in 0..8 {
                let (a, b) = (j * 8 + i + 1, j * 8 + (i + 1) % 8 + 1);
                obj += &format!("f {a} {b} {}\nf {a} {} {}\n", b + 8, b + 8, a + 8);
            }
        }
        std::fs::write(root.join("tube.obj"), obj).unwrap();
        Fixture { _dir: dir, root }
    }

    fn path(&self, name: &str) -> String {
        self.root.join(name).display().to_string()
    }
}

/// Runs `fairfit args`; panics (failing the test) on a panic message, a backtrace, an exit code other
/// than 0, 1 or 2, or a failure that is not exactly one `error:` line. Returns the exit code.
fn run(args: &[String]) -> i32 {
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .timeout(std::time::Duration::from_secs(120))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let code = out.status.code();
    assert!(
        !err.contains("panicked")
            && !err.contains("internal error")
            && !err.contains("RUST_BACKTRACE")
            && !err.contains("stack backtrace"),
        "{args:?}: {err}"
    );
    assert!(
        matches!(code, Some(0..=2)),
        "{args:?}: exit {code:?}: {err}"
    );
    if code != Some(0) {
        let errors: Vec<&str> = err
            .lines()
            .filter(|l| !l.starts_with("warning: "))
            .collect();
        assert_eq!(errors.len(), 1, "{args:?}: {err}");
        assert!(errors[0].starts_with("error: "), "{args:?}: {err}");
    }
    code.unwrap_or(-1)
}

fn strings(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// `base` followed by `flag value` for every value; every run must fail cleanly.
fn rejects_all(base: &[String], flag: &str, values: &[&str]) {
    for v in values {
        let mut args = base.to_vec();
        args.push(format!("{flag}={v}"));
        assert_ne!(run(&args), 0, "{args:?} was accepted");
    }
}

/// `base` followed by `flag value` for every value; success is allowed, panics are not.
fn survives_all(base: &[String], flag: &str, values: &[&str]) {
    for v in values {
        let mut args = base.to_vec();
        args.push(format!("{flag}={v}"));
        run(&args);
    }
}

#[test]
fn curve_options_with_hostile_values() {
    let f = Fixture::new();
    let out = f.path("out.json");
    let lsq = strings(&["curve", &f.path("pts.csv"), "--method", "lsq", "-o", &out]);
    let integrated = strings(&["curve", &f.path("pts.csv"), "-o", &out]);
    for flag in ["--tol", "--rel-tol"] {
        rejects_all(&lsq, flag, &["nan", "inf", "-inf", "-1", "0", "1e400"]);
    }
    rejects_all(&lsq, "--corner-angle", &["nan", "inf", "-1", "0", "181"]);
    rejects_all(&lsq, "--smoothing", &["nan", "inf", "-inf", "-1", "1e400"]);
    rejects_all(&lsq, "--degree", &["0", "-1", "16", "18446744073709551616"]);
    rejects_all(&lsq, "--smoothing-order", &["0", "1", "4", "-1", "256"]);
    rejects_all(&lsq, "--correction-rounds", &["-1", "18446744073709551616"]);
    rejects_all(
        &lsq,
        "--start-tangent",
        &["nan,0", "inf,0", "0,0", "1", "1,2,3,4", "a,b"],
    );
    rejects_all(&lsq, "--chord-tol", &["nan", "inf", "-1", "0"]);
    rejects_all(&integrated, "--span-fairness", &["nan", "inf", "-1", "0"]);
    // end conditions: malformed, non-finite or degenerate values are refused
    rejects_all(&integrated, "--start-tangent", &["nan,0", "0,0"]);
    rejects_all(&integrated, "--end-tangent", &["inf,1"]);
    rejects_all(
        &integrated,
        "--start",
        &[
            "tangent:0,0",
            "tangent:nan,1",
            "curvature:1,0",
            "curvature:1,0:nan",
            "curvature:1,0:x",
            "bend:1,0",
            "tangent",
        ],
    );
    rejects_all(&lsq, "--end", &["curvature:1,0:2", "point:1,0"]);
    rejects_all(&integrated, "--control-points", COUNTS);
    rejects_all(&integrated, "--control-points", &["2", "15", "1000000"]);
    rejects_all(
        &integrated,
        "--seed",
        &["-1", "18446744073709551616", "nan"],
    );
    rejects_all(&integrated, "--threads", &["-1", "18446744073709551616"]);
    survives_all(&lsq, "--tol", &["1e-320", "1e308"]);
    survives_all(&lsq, "--correction-rounds", &["0", "1000"]);
    survives_all(&integrated, "--seed", &["0", "18446744073709551615"]);
    survives_all(&integrated, "--threads", &["0", "1000"]);
    survives_all(&integrated, "--control-points", &["4", "14"]);
}

#[test]
fn surface_options_with_hostile_values() {
    let f = Fixture::new();
    let base = strings(&["surface", &f.path("sections"), "-o", &f.path("out.json")]);
    for flag in ["--tol", "--rel-tol"] {
        rejects_all(&base, flag, &["nan", "inf", "-1", "0", "1e400"]);
    }
    rejects_all(
        &base,
        "--degree",
        &["0", "-1", "41", "18446744073709551615"],
    );
    rejects_all(&base, "--degree-v", &["0", "-1", "18446744073709551616"]);
    rejects_all(&base, "--max-ctrl", &["-1", "18446744073709551616"]);
    rejects_all(
        &base,
        "--normal",
        &["0,0,0", "nan,0,1", "inf,0,0", "1,2", "x"],
    );
    rejects_all(&base, "--smooth-v", &["nan", "inf", "-1"]);
    rejects_all(&base, "--gap-factor", &["nan", "inf", "-1", "0"]);
    rejects_all(&base, "--approximate-v", &["-1", "18446744073709551616"]);
    survives_all(&base, "--approximate-v", &["0", "1", "2", "3", "1000000"]);
    survives_all(
        &base,
        "--max-ctrl",
        &["0", "1", "2", "18446744073709551615"],
    );
    survives_all(&base, "--degree", &["1", "2", "9"]);
    survives_all(&base, "--degree-v", &["1", "2", "18446744073709551615"]);
    survives_all(&base, "--smooth-v", &["0", "1e308"]);
    // slicing a mesh
    let mesh = strings(&["surface", &f.path("tube.obj"), "-o", &f.path("out.json")]);
    rejects_all(
        &mesh,
        "--slices",
        &["0", "1", "-1", "10001", "18446744073709551615"],
    );
    rejects_all(&mesh, "--gap-factor", &["nan", "inf", "-1", "0"]);
    let sliced = strings(&[
        "surface",
        &f.path("tube.obj"),
        "--slices",
        "3",
        "-o",
        &f.path("out.json"),
    ]);
    rejects_all(
        &sliced,
        "--normal",
        &["0,0,0", "nan,0,1", "1e308,1e308,1e308"],
    );
    survives_all(&sliced, "--normal", &["1e-320,0,1", "0,1,1"]);
    survives_all(&sliced, "--gap-factor", &["1e-320", "1e308"]);
}

#[test]
fn eval_info_plot_export_with_hostile_values() {
    let f = Fixture::new();
    for geo in ["curve.json", "surface.json"] {
        let g = f.path(geo);
        let eval = strings(&["eval", &g]);
        rejects_all(
            &eval,
            "--at",
            &[
                "nan",
                "inf",
                "-1",
                "2",
                "",
                ",",
                "1e400",
                "0.5:nan",
                "0.5:0.5:0.5",
            ],
        );
        let info = strings(&["info", &g]);
        rejects_all(&info, "--iso", &["0", "-1", "1001", "18446744073709551616"]);
        let plot = strings(&["plot", &g, "-o", &f.path("p.svg")]);
        rejects_all(&plot, "--width", &["0", "-1", "99", "10001", "4294967296"]);
        rejects_all(&plot, "--height", &["0", "nan", "4294967296"]);
        rejects_all(&plot, "--iso", &["0", "-1", "18446744073709551616"]);
        survives_all(&plot, "--iso", &["1", "2", "1000"]);
        let export = strings(&["export", &g, "--mesh", &f.path("m.obj")]);
        rejects_all(&export, "--chord-tol", &["nan", "inf", "-1", "0"]);
        survives_all(&export, "--chord-tol", &["1e-320", "1e308", "1e-9"]);
        for (flag, ext) in [
            ("--step", "stp"),
            ("--iges", "igs"),
            ("--plot", "png"),
            ("--html", "html"),
        ] {
            run(&strings(&[
                "export",
                &g,
                flag,
                &f.path(&format!("o.{ext}")),
            ]));
        }
    }
}

#[test]
fn unusable_input_files_fail_cleanly() {
    let f = Fixture::new();
    let out = f.path("out.json");
    for input in [
        "empty.csv",
        "binary.dat",
        "folder.json",
        "missing.csv",
        "curve.json",
    ] {
        let p = f.path(input);
        assert_ne!(
            run(&strings(&["curve", &p, "--method", "lsq", "-o", &out])),
            0,
            "{input}"
        );
        assert_ne!(run(&strings(&["curve", &p, "-o", &out])), 0, "{input}");
        assert_ne!(run(&strings(&["surface", &p, "-o", &out])), 0, "{input}");
    }
    for input in [
        "empty.csv",
        "binary.json",
        "folder.json",
        "missing.json",
        "pts.csv",
    ] {
        let p = f.path(input);
        assert_ne!(run(&strings(&["eval", &p, "--at", "0.5"])), 0, "{input}");
        assert_ne!(run(&strings(&["info", &p])), 0, "{input}");
        assert_ne!(
            run(&strings(&["plot", &p, "-o", &f.path("p.svg")])),
            0,
            "{input}"
        );
        assert_ne!(
            run(&strings(&["export", &p, "--step", &f.path("o.stp")])),
            0,
            "{input}"
        );
    }
    // data points for plot and export that are not points
    for points in ["empty.csv", "binary.dat", "folder.json", "curve.json"] {
        let c = f.path("curve.json");
        let pts = f.path(points);
        assert_ne!(
            run(&strings(&[
                "plot",
                &c,
                "--points",
                &pts,
                "-o",
                &f.path("p.svg")
            ])),
            0
        );
        assert_ne!(
            run(&strings(&[
                "export",
                &c,
                "--points",
                &pts,
                "--html",
                &f.path("r.html")
            ])),
            0
        );
    }
}

#[test]
fn unwritable_outputs_fail_cleanly() {
    let f = Fixture::new();
    let folder = f.path("folder.json");
    let missing_dir = f.root.join("no/such/dir/out.json").display().to_string();
    let pts = f.path("pts.csv");
    let c = f.path("curve.json");
    for target in [folder.as_str(), missing_dir.as_str()] {
        assert_ne!(
            run(&strings(&["curve", &pts, "--method", "lsq", "-o", target])),
            0
        );
        assert_ne!(
            run(&strings(&[
                "curve", &pts, "--method", "lsq", "--report", target
            ])),
            0
        );
        assert_ne!(
            run(&strings(&["surface", &f.path("sections"), "-o", target])),
            0
        );
        assert_ne!(run(&strings(&["plot", &c, "-o", target])), 0);
        for flag in [
            "--step",
            "--iges",
            "--mesh",
            "--plot",
            "--html",
            "--samples",
        ] {
            assert_ne!(
                run(&strings(&["export", &c, flag, target])),
                0,
                "{flag} {target}"
            );
        }
    }
    // an output that names an input is refused before anything is written
    assert_ne!(
        run(&strings(&["curve", &pts, "--method", "lsq", "-o", &pts])),
        0
    );
    assert!(Path::new(&pts).exists());
}

/// Point files that parse but make fitting degenerate: all equal, two points, collinear, back and
/// forth, coordinates near 1e±300.
#[test]
fn degenerate_point_sets_fail_cleanly_or_fit() {
    let f = Fixture::new();
    let sets: Vec<(&str, String)> = vec![
        ("same.csv", "1,1\n".repeat(8)),
        ("two.csv", "0,0\n1,0\n".into()),
        ("three.csv", "0,0\n1,0\n2,1\n".into()),
        (
            "collinear.csv",
            (0..10).map(|i| format!("{i},{i}\n")).collect(),
        ),
        ("back.csv", "0,0\n1,0\n0,0\n1,0\n0,0\n".into()),
        (
            "huge.csv",
            (0..12)
                .map(|i| format!("{}e300,{}e300\n", i, (i * 7) % 5))
                .collect(),
        ),
        (
            "tiny.csv",
            (0..12)
                .map(|i| format!("{}e-300,{}e-300\n", i, (i * 7) % 5))
                .collect(),
        ),
    ];
    for (name, text) in &sets {
        std::fs::write(f.root.join(name), text).unwrap();
        let p = f.path(name);
        let o = f.path("o.json");
        for method in ["lsq", "integrated"] {
            run(&strings(&[
                "curve",
                &p,
                "--method",
                method,
                "-o",
                &o,
                "--plot",
                &f.path("o.svg"),
            ]));
        }
        run(&strings(&[
            "curve", &p, "--method", "lsq", "--closed", "-o", &o,
        ]));
    }
}

/// An unreachable per-span fairness target within the tolerance is reported as such, not as a missed
/// tolerance with a deviation below it.
#[test]
fn an_unmet_span_fairness_target_is_named_in_the_warning() {
    let f = Fixture::new();
    let args = strings(&[
        "curve",
        &f.path("pts.csv"),
        "--span-fairness",
        "1e-320",
        "-o",
        &f.path("o.json"),
    ]);
    let out = Command::cargo_bin("fairfit")
        .unwrap()
        .args(&args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("span fairness target 1.000e-320 was not met"),
        "{err}"
    );
    assert!(!err.contains("tolerance"), "{err}");
}

/// Coordinates near the floating-point limit overflow every length; the error says so (not "all points
/// coincide") and names the fix, with every method.
#[test]
fn overflowing_coordinates_ask_for_rescaling() {
    let f = Fixture::new();
    std::fs::write(
        f.root.join("limit.csv"),
        "0,0\n1,1e308\n2,-1e308\n3,1\n4,2\n",
    )
    .unwrap();
    for method in ["lsq", "integrated", "fit-then-fair"] {
        let out = Command::cargo_bin("fairfit")
            .unwrap()
            .args(strings(&[
                "curve",
                &f.path("limit.csv"),
                "--method",
                method,
                "-o",
                &f.path("o.json"),
            ]))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{method}: {err}");
        assert!(
            err.contains("too far apart") && err.contains("rescale"),
            "{method}: {err}"
        );
    }
}
