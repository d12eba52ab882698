//! Bounded reading and bounded work: every refusal is one line naming its limit and the option that
//! raises it, and a hostile input (a device, a sparse file, a huge claim) is refused before it costs
//! memory (checked under a small address-space limit where a shell is at hand).

use crate::common::{assert_success, data, fairfit, file_with, one_line_failure, CIRCLE};

/// Runs `fairfit ARGS` under `ulimit -v KB` (a child shell): exit code and stderr.
fn under_memory_limit(kb: u64, args: &str) -> (Option<i32>, String) {
    let bin = assert_cmd::cargo::cargo_bin("fairfit");
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kb}; exec '{}' {args}", bin.display()))
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn devices_are_refused_at_once_within_100_mb() {
    for (args, needle) in [
        (
            "curve /dev/zero",
            "/dev/zero: not a text file (contains NUL bytes)",
        ),
        (
            "info /dev/zero",
            "/dev/zero: not a UTF-8 text file (expected fairfit JSON)",
        ),
        (
            "surface /dev/zero /dev/zero -o /tmp/fairfit_limits_test_never_written.json",
            "/dev/zero: not a text file (contains NUL bytes)",
        ),
        ("curve /dev/urandom", "/dev/urandom: not a text file"),
    ] {
        let (code, err) = under_memory_limit(100_000, args);
        assert_eq!(code, Some(1), "{args}: {err}");
        assert_eq!(err.lines().count(), 1, "{args}: {err}");
        assert!(err.contains(needle), "{args}: {err}");
    }
}

#[test]
fn a_sparse_cad_file_over_the_size_limit_is_refused_by_its_length() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("big.igs");
    std::fs::File::create(&f).unwrap().set_len(1 << 30).unwrap();
    let (code, err) = under_memory_limit(100_000, &format!("info '{}'", f.display()));
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("larger than the file size limit of 512 MiB (raise it with --max-file-mb N"),
        "{err}"
    );
    let circle = file_with(CIRCLE.as_bytes());
    let p = circle.path().to_str().unwrap();
    one_line_failure(
        &["info", p, "--max-file-mb", "0"],
        1,
        &[
            "larger than the file size limit of 0 MiB",
            "--max-file-mb N",
        ],
    );
}

#[test]
fn the_point_limit_names_its_option() {
    let foil = data("fx77w343.csv");
    one_line_failure(
        &["curve", &foil, "--max-points", "10"],
        1,
        &["fx77w343.csv: more points than the limit of 10 (raise it with --max-points N"],
    );
    // a JSON whose arrays hold more elements than 6 per allowed control point
    let circle = file_with(CIRCLE.as_bytes());
    one_line_failure(
        &["info", circle.path().to_str().unwrap(), "--max-points", "2"],
        1,
        &["array elements, over the limit of 12 (6 per allowed control point; raise it with --max-points N"],
    );
    let out = fairfit()
        .args([
            "info",
            circle.path().to_str().unwrap(),
            "--max-points",
            "1000",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
}

#[test]
fn a_curve_json_claiming_10_to_the_8_knots_is_refused_before_it_is_parsed() {
    let mut text = String::from(r#"{"kind":"curve","degree":3,"knots":["#);
    // parsed as a JSON value this would take over 320 MB; refused, the run stays under 400 MB
    text.push_str(&"0,".repeat(10_000_000));
    text.push_str("0]}");
    let f = file_with(text.as_bytes());
    let (code, err) = under_memory_limit(
        400_000,
        &format!("info '{}' --max-points 100000", f.path().display()),
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("10000003 array elements, over the limit of 600000"),
        "{err}"
    );
}

#[test]
fn info_and_plot_refuse_more_spans_than_allowed() {
    let circle = file_with(CIRCLE.as_bytes());
    let p = circle.path().to_str().unwrap();
    one_line_failure(
        &["info", p, "--max-spans", "3"],
        1,
        &[
            "4 knot spans, over the limit of 3 for this command",
            "--max-spans N",
        ],
    );
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("c.svg");
    one_line_failure(
        &["plot", p, "-o", svg.to_str().unwrap(), "--max-spans", "3"],
        1,
        &["4 knot spans, over the limit of 3", "--max-spans N"],
    );
    assert!(!svg.exists());
}

#[test]
fn a_huge_thread_count_from_the_environment_is_clamped() {
    let foil = data("fx77w343.csv");
    let out = fairfit()
        .env("RAYON_NUM_THREADS", "100000")
        .args(["curve", &foil, "--method", "lsq"])
        .output()
        .unwrap();
    assert_success(&out);
}
