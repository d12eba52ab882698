//! Helpers shared by the CLI integration tests: running the binary, the example data, one-line failure
//! checks and small geometry files; in submodules an independent deviation check and the Python
//! peers.
#![allow(dead_code)]

pub mod polyline;
/// The Python peers (`$FAIRFIT_PYTHON`), shared with the other crates' tests.
pub use fairfit_testkit as python;

use assert_cmd::Command;
use std::io::Write;
use tempfile::NamedTempFile;

/// The `fairfit` binary under test.
pub fn fairfit() -> Command {
    Command::cargo_bin("fairfit").unwrap()
}

/// The path of `examples/data/NAME`.
pub fn data(name: &str) -> String {
    format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A temporary file holding `content`.
pub fn file_with(content: &[u8]) -> NamedTempFile {
    let mut f = NamedTempFile::new().unwrap();
    f.write_all(content).unwrap();
    f.flush().unwrap();
    f
}

/// The JSON in file `p`.
pub fn read_json(p: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The exact rational quadratic circle of radius 2 around (1, -1, 0.5) (a small valid curve file).
pub const CIRCLE: &str = r#"{"kind": "curve", "degree": 2,
  "knots": [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1],
  "control_points": [[3,-1,0.5],[3,1,0.5],[1,1,0.5],[-1,1,0.5],[-1,-1,0.5],[-1,-3,0.5],[1,-3,0.5],[3,-3,0.5],[3,-1,0.5]],
  "weights": [1, 0.7071067811865476, 1, 0.7071067811865476, 1, 0.7071067811865476, 1, 0.7071067811865476, 1]}"#;

/// Runs `fairfit ARGS`, expects exit `code`, empty stdout and exactly one stderr line starting
/// `error: ` and containing every needle, with no panic text; returns that line.
pub fn one_line_failure(args: &[&str], code: i32, needles: &[&str]) -> String {
    let out = fairfit().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: expected `{n}` in {err}");
    }
    assert!(!err.contains("panicked") && !err.contains("internal error"));
    err
}

/// A successful `fairfit curve` run: the curve file's text, the curve and the report.
pub struct CurveRun {
    pub json: String,
    pub curve: fairfit::NurbsCurve,
    pub report: serde_json::Value,
}

/// Runs `fairfit SUBCOMMAND INPUT EXTRA -o DIR/NAME.json --report DIR/NAME-report.json` and asserts
/// that it succeeded; returns the output file, the report file and the run.
fn run_writing(
    subcommand: &str,
    dir: &std::path::Path,
    name: &str,
    input: impl AsRef<std::ffi::OsStr>,
    extra: &[&str],
) -> (
    std::path::PathBuf,
    std::path::PathBuf,
    assert_cmd::assert::Assert,
) {
    let out = dir.join(format!("{name}.json"));
    let report = dir.join(format!("{name}-report.json"));
    let run = fairfit()
        .arg(subcommand)
        .arg(input)
        .args(extra)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .assert()
        .success();
    (out, report, run)
}

/// Runs `fairfit curve FILE EXTRA -o DIR/NAME.json --report DIR/NAME-report.json`, asserts that it
/// succeeded and reads what it wrote.
pub fn curve_run(
    dir: &std::path::Path,
    name: &str,
    file: impl AsRef<std::ffi::OsStr>,
    extra: &[&str],
) -> CurveRun {
    let (c, r, _) = run_writing("curve", dir, name, file, extra);
    let fairfit::io::Geometry::Curve(curve) = fairfit::io::read_geometry(&c).unwrap() else {
        panic!("{}: not a curve", c.display())
    };
    CurveRun {
        json: std::fs::read_to_string(&c).unwrap(),
        curve,
        report: read_json(&r),
    }
}

/// A successful `fairfit surface` run: the surface file's text, the surface, the report and stderr.
pub struct SurfaceRun {
    pub json: String,
    pub surface: fairfit::NurbsSurface,
    pub report: serde_json::Value,
    pub stderr: String,
}

/// Runs `fairfit surface INPUT EXTRA -o DIR/NAME.json --report DIR/NAME-report.json`, asserts that it
/// succeeded and reads what it wrote.
pub fn surface_run(
    dir: &std::path::Path,
    name: &str,
    input: impl AsRef<std::ffi::OsStr>,
    extra: &[&str],
) -> SurfaceRun {
    let (s, r, run) = run_writing("surface", dir, name, input, extra);
    let fairfit::io::Geometry::Surface(surface) = fairfit::io::read_geometry(&s).unwrap() else {
        panic!("{}: not a surface", s.display())
    };
    SurfaceRun {
        json: std::fs::read_to_string(&s).unwrap(),
        surface,
        report: read_json(&r),
        stderr: String::from_utf8_lossy(&run.get_output().stderr).into_owned(),
    }
}

/// Asserts that a finished run succeeded, showing its stderr otherwise.
pub fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
