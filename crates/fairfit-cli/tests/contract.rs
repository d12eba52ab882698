//! The command-line contract shared by every subcommand: usage errors are one actionable line with exit
//! code 2, `--help`/`--version` print on stdout with exit 0, a closed stdout ends the run quietly with
//! exit 0, and two outputs naming one file (or an output naming an input) fail up front with exit 1.

use crate::common;
use common::{assert_success, fairfit, one_line_failure, CIRCLE};

use std::io::Read;
use std::path::Path;
use std::process::Stdio;

fn circle_file(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("circle.json");
    std::fs::write(&p, CIRCLE).unwrap();
    p
}

#[test]
fn usage_errors_are_one_line_with_the_help_to_read() {
    let dir = tempfile::tempdir().unwrap();
    let c = circle_file(dir.path());
    let c = c.to_str().unwrap();
    let line = one_line_failure(
        &["curve", "pts.csv", "--foo"],
        2,
        &["unexpected argument '--foo'", "see 'fairfit curve --help'"],
    );
    // clap's "use '-- --foo'" tip is dropped
    assert!(!line.contains("-- --foo"), "{line}");
    one_line_failure(
        &["eval", c],
        2,
        &["--at", "not provided", "see 'fairfit eval --help'"],
    );
    one_line_failure(
        &["export", c, "--stpe", "a.step"],
        2,
        &[
            "'--stpe'",
            "similar argument exists: '--step'",
            "fairfit export --help",
        ],
    );
    one_line_failure(
        &["info", "--iso", "0", c],
        2,
        &["'0'", "--iso", "1..=1000", "fairfit info --help"],
    );
    one_line_failure(
        &["curve", "pts.csv", "--method", "magic"],
        2,
        &[
            "'magic'",
            "lsq, integrated, fit-then-fair",
            "fairfit curve --help",
        ],
    );
    one_line_failure(
        &["bogus"],
        2,
        &["unrecognized subcommand 'bogus'", "see 'fairfit --help'"],
    );
}

#[test]
fn help_and_version_print_on_stdout_with_exit_zero() {
    for args in [
        vec!["--help"],
        vec!["--version"],
        vec!["curve", "--help"],
        vec!["help", "export"],
        vec!["eval", "-h"],
    ] {
        let out = fairfit().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(out.stderr.is_empty(), "{args:?}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("fairfit"), "{args:?}: {text}");
    }
    let out = fairfit().arg("--version").output().unwrap();
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).trim(),
        format!("fairfit {}", env!("CARGO_PKG_VERSION"))
    );
}

/// Starts `fairfit args`, reads `n` bytes of its stdout, closes the pipe and returns (exit code,
/// stderr, bytes read).
fn read_then_close(args: &[&str], n: usize) -> (Option<i32>, String, Vec<u8>) {
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("fairfit"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = vec![0u8; n];
    child.stdout.take().unwrap().read_exact(&mut head).unwrap(); // stdout dropped here
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        head,
    )
}

#[test]
fn a_closed_stdout_ends_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let c = circle_file(dir.path());
    // about 500 bytes per parameter: far more than a pipe buffer, so the writer meets the closed pipe
    let at: Vec<String> = (0..=4000)
        .map(|k| format!("{}", k as f64 / 4000.0))
        .collect();
    let at = at.join(",");
    let (code, err, head) = read_then_close(&["eval", c.to_str().unwrap(), "--at", &at], 10);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(err, "");
    assert_eq!(&head[..1], b"[");
    // several files to `info`: a large array, closed after 10 bytes
    let files: Vec<String> = (0..400).map(|_| c.to_str().unwrap().to_string()).collect();
    let mut args = vec!["info"];
    args.extend(files.iter().map(String::as_str));
    let (code, err, head) = read_then_close(&args, 10);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(err, "");
    assert_eq!(&head[..1], b"[");
}

#[test]
fn one_file_for_two_outputs_fails_up_front() {
    // a combination of options the command refuses: a usage error (exit 2)
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let c = circle_file(d);
    let c = c.to_str().unwrap();
    let a = d.join("a.out");
    let a = a.to_str().unwrap();
    one_line_failure(
        &["export", c, "--step", a, "--iges", a],
        2,
        &["--step and --iges both name the file", "a.out"],
    );
    // the same file spelled differently
    let same = format!("{}/sub/../a.out", d.display());
    std::fs::create_dir(d.join("sub")).unwrap();
    one_line_failure(
        &["export", c, "--mesh", a, "--html", &same],
        2,
        &["--mesh and --html both name the file"],
    );
    one_line_failure(
        &["export", c, "--step", a, "--samples", a],
        2,
        &["--step and --samples"],
    );
    // an output over the input
    one_line_failure(
        &["export", c, "--iges", c],
        2,
        &["--iges names the input file"],
    );
    one_line_failure(&["plot", c, "-o", c], 2, &["-o names the input file"]);
    // fitting commands check before any work
    let pts = d.join("pts.csv");
    std::fs::write(&pts, "0,0\n1,1\n2,0\n3,1\n4,0\n5,1\n").unwrap();
    let pts = pts.to_str().unwrap();
    one_line_failure(
        &["curve", pts, "-o", a, "--report", a],
        2,
        &["-o and --report both name the file"],
    );
    one_line_failure(
        &["surface", pts, pts, "-o", a, "--step", a],
        2,
        &["-o and --step both name the file"],
    );
    // nothing was written
    let mut names: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["circle.json", "pts.csv", "sub"]);
    // distinct files still work
    fairfit()
        .args(["export", c, "--step", a])
        .arg("--iges")
        .arg(d.join("b.out"))
        .assert()
        .success();
}

#[test]
fn unknown_plot_and_mesh_formats_are_usage_errors_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pts = d.join("pts.csv");
    std::fs::write(&pts, "0,0\n1,1\n2,0\n3,1\n4,0\n5,1\n").unwrap();
    let pts = pts.to_str().unwrap();
    let o = d.join("o.json");
    let o = o.to_str().unwrap();
    let jpg = d.join("p.jpg");
    let jpg = jpg.to_str().unwrap();
    // was: exit 1 after the fit ("unknown plot format")
    one_line_failure(
        &["curve", pts, "-o", o, "--plot", jpg],
        2,
        &[
            "--plot",
            "p.jpg: unknown format, expected a .svg or .png file name",
        ],
    );
    one_line_failure(
        &["curve", pts, "-o", o, "--mesh", "m.xyz"],
        2,
        &["--mesh m.xyz: unknown format, expected a .obj, .stl or .ply file name"],
    );
    // two copies of one section cannot make a surface, but the format is refused before they are read
    one_line_failure(
        &["surface", pts, pts, "-o", o, "--plot", "plot"],
        2,
        &[
            "--plot plot: unknown format",
            "see 'fairfit surface --help'",
        ],
    );
    one_line_failure(
        &[
            "export",
            &circle_file(d).to_string_lossy(),
            "--mesh",
            "m.STEP",
        ],
        2,
        &["--mesh m.STEP: unknown format"],
    );
    assert!(!Path::new(o).exists());
}

#[test]
fn coordinates_near_the_ends_of_the_f64_range_give_numbers_or_clear_messages() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // unit-size reference: the exact circle of radius 2 has κ = 0.5 and length 4π
    for s in [1e-300f64, 1e300] {
        let scaled: serde_json::Value = {
            let mut v: serde_json::Value = serde_json::from_str(CIRCLE).unwrap();
            for p in v["control_points"].as_array_mut().unwrap() {
                for x in p.as_array_mut().unwrap() {
                    *x = serde_json::json!(x.as_f64().unwrap() * s);
                }
            }
            v
        };
        let f = d.join(format!("c{s:e}.json"));
        std::fs::write(&f, scaled.to_string()).unwrap();
        let f = f.to_str().unwrap();
        let out = fairfit().args(["info", f]).output().unwrap();
        if s < 1.0 {
            // E = F/L³ of the circle at 1e-300 is about 1e900, beyond f64: one line, no output
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{err}");
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(
                err.contains("energy cannot be computed as a finite number"),
                "{err}"
            );
            assert!(out.stdout.is_empty());
        } else {
            assert!(out.status.success());
            let info: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            let len = info["length"].as_f64().unwrap();
            assert!((len / s - 4.0 * std::f64::consts::PI).abs() < 1e-9, "{len}");
            assert!(info["fairness"].as_f64().unwrap() < 1e-12);
        }
        let out = fairfit()
            .args(["eval", f, "--at", "0.1,0.6"])
            .output()
            .unwrap();
        // dκ/ds of the circle is 0 up to round-off, which at 1e-300 is scaled by 1e600 past f64:
        // then the run fails with one line (no output holds a non-finite number), never a panic
        let err = String::from_utf8_lossy(&out.stderr);
        if out.status.success() {
            let ev: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            let k = ev[0]["curvature"].as_f64().unwrap();
            assert!((k * s - 0.5).abs() < 1e-9, "{k}");
            let text = String::from_utf8_lossy(&out.stdout);
            assert!(!text.contains("NaN") && !text.contains("nan") && !text.contains("null"));
            assert!(err.is_empty(), "{err}");
        } else {
            assert_eq!(out.status.code(), Some(1), "{err}");
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(
                err.contains("cannot be computed as a finite number"),
                "{err}"
            );
            assert!(out.stdout.is_empty());
        }
        // exports are written (or refused with one line), never a panic
        let step = d.join(format!("c{s:e}.step"));
        let out = fairfit()
            .args(["export", f, "--step"])
            .arg(&step)
            .arg("--mesh")
            .arg(d.join(format!("c{s:e}.obj")))
            .output()
            .unwrap();
        assert_success(&out);
        let text = std::fs::read_to_string(&step).unwrap();
        fairfit::io::cad_check::check_step(&text).unwrap();
    }
    // a spatial curve 1e-300 long: E = F/L³ and dκ/ds are about 1e900 and 1e600, beyond f64: the run
    // fails with one line rather than print null
    let tiny = r#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,0.5,1,1,1,1],
      "control_points": [[0,0,0],[1e-300,2e-300,0],[3e-300,1e-300,5e-301],[4e-300,-1e-300,0],[6e-300,5e-301,2e-301]]}"#;
    let f = d.join("tiny.json");
    std::fs::write(&f, tiny).unwrap();
    let f = f.to_str().unwrap();
    for args in [vec!["info", f], vec!["eval", f, "--at", "0.3"]] {
        one_line_failure(&args, 1, &["cannot be computed as a finite number"]);
    }
}

/// Hostile option values and files for every subcommand.
mod bad_input;
/// Input errors that name the problem, pinned by the inputs that showed them.
mod input_errors;
/// Bounded reading and bounded work: refusals that name their limit.
mod limits;
