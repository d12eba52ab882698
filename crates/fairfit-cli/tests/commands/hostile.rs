//! Hostile inputs and option combinations, one test per class of failure: an output over an input,
//! partial outputs, non-finite outputs, options a method ignores, and messages (one line, echoes cut,
//! control characters escaped, exit code 2 for option problems and 1 for input/output problems).
//! Every failing run is checked for its exact exit code, a single stderr line, no file left behind
//! (no output, no temporary) and every file of its folder unchanged, byte for byte.

use crate::common::{assert_success, data, fairfit};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

/// Every file under `dir` (recursively, hidden ones included) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                out.insert(p.clone(), b"<folder>".to_vec());
                stack.push(p);
            } else if meta.file_type().is_symlink() {
                let target = std::fs::read_link(&p).unwrap();
                out.insert(p, target.to_string_lossy().as_bytes().to_vec());
            } else if meta.is_file() {
                out.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// Runs `fairfit ARGS` in `dir` and asserts a failure with exit `code`, one stderr line starting
/// `error: ` with every needle, nothing on stdout, and `dir` exactly as before. Returns the line.
fn refused(dir: &Path, args: &[&str], code: i32, needles: &[&str]) -> String {
    let before = snapshot(dir);
    let out = fairfit().current_dir(dir).args(args).output().unwrap();
    let line = one_line(&out, code, args);
    for n in needles {
        assert!(line.contains(n), "{args:?}: expected `{n}` in {line}");
    }
    assert!(out.stdout.is_empty(), "{args:?}");
    assert_eq!(
        snapshot(dir),
        before,
        "{args:?}: files changed or left behind"
    );
    line
}

fn one_line(out: &Output, code: i32, args: &[&str]) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error: ") && err.ends_with('\n'), "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("internal error"),
        "{err}"
    );
    err.trim_end().to_string()
}

/// A folder with the points `p.csv` (naca4412) and three small sections `sec/a.csv`, `b.csv`,
/// `c.csv` (ellipses at z = 0, 1, 2).
fn workspace() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::copy(data("naca4412.csv"), d.join("p.csv")).unwrap();
    std::fs::create_dir(d.join("sec")).unwrap();
    for (k, name) in ["a", "b", "c"].iter().enumerate() {
        let z = k as f64;
        let text: String = (0..24)
            .map(|i| {
                let t = std::f64::consts::PI * i as f64 / 23.0;
                format!(
                    "{},{},{z}\n",
                    (2.0 + 0.2 * z) * t.cos(),
                    (1.0 + 0.1 * z) * t.sin()
                )
            })
            .collect();
        std::fs::write(d.join("sec").join(format!("{name}.csv")), text).unwrap();
    }
    dir
}

#[test]
fn an_output_over_an_input_is_refused_before_any_work() {
    let dir = workspace();
    let d = dir.path();
    // an output inside an input folder that is read
    refused(
        d,
        &["surface", "sec", "-o", "sec/a.csv"],
        2,
        &["input folder sec"],
    );
    refused(
        d,
        &["surface", "sec", "-o", "sec/new.csv"],
        2,
        &["input folder"],
    );
    // the input as --pareto, and one file for two outputs
    refused(
        d,
        &["curve", "p.csv", "-o", "out.json", "--pareto", "p.csv"],
        2,
        &["--pareto names the input file"],
    );
    refused(
        d,
        &["curve", "p.csv", "--pareto", "x.json", "-o", "x.json"],
        2,
        &["both name the file"],
    );
    // an output where --pareto-curves writes
    std::fs::create_dir(d.join("pc")).unwrap();
    refused(
        d,
        &[
            "curve",
            "p.csv",
            "-o",
            "pc/front_000.json",
            "--pareto",
            "f.csv",
            "--pareto-curves",
            "pc",
        ],
        2,
        &["--pareto-curves pc would overwrite -o"],
    );
    refused(
        d,
        &[
            "curve",
            "p.csv",
            "--pareto",
            "f.csv",
            "--pareto-curves",
            "p.csv",
        ],
        2,
        &["is a file"],
    );
    // the input through a symbolic link and a hard link
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("p.csv", d.join("link.json")).unwrap();
        std::fs::hard_link(d.join("p.csv"), d.join("hard.json")).unwrap();
        refused(
            d,
            &["curve", "p.csv", "-o", "link.json"],
            2,
            &["names the input file"],
        );
        refused(
            d,
            &["curve", "p.csv", "--report", "hard.json"],
            2,
            &["names the input file"],
        );
        refused(
            d,
            &["plot", "hard.json", "--points", "p.csv", "-o", "p.csv"],
            2,
            &["input file"],
        );
        // a link to nothing is refused (an input/output problem), not created
        std::os::unix::fs::symlink("nothing.json", d.join("dangling.json")).unwrap();
        refused(
            d,
            &["curve", "p.csv", "--method", "lsq", "-o", "dangling.json"],
            1,
            &["does not exist"],
        );
    }
    // two outputs on stdout
    refused(
        d,
        &["curve", "p.csv", "--report", "-"],
        2,
        &["both write to stdout"],
    );
}

#[test]
fn batch_refuses_an_outdir_at_or_inside_its_input_folder() {
    let dir = workspace();
    let d = dir.path();
    let lsq = ["--method", "lsq", "--rel-tol", "1e-2"];
    for (out, place) in [
        ("sec", "is the input folder sec"),
        ("./sec/", "is the input folder"),
        ("sec/out", "lies inside the input folder sec"),
        ("sec/new/deeper", "lies inside the input folder"),
        ("out/../sec/x", "lies inside the input folder"),
    ] {
        let mut args = vec!["batch", "sec", "-o", out];
        args.extend(lsq);
        refused(d, &args, 2, &[place, "--help"]);
    }
    #[cfg(unix)]
    {
        // through a link to the input folder, made beside it
        std::os::unix::fs::symlink("sec", d.join("alias")).unwrap();
        let mut args = vec!["batch", "sec", "-o", "alias/out"];
        args.extend(lsq);
        refused(d, &args, 2, &["lies inside the input folder sec"]);
    }
    // a sibling whose name starts like the input folder's is outside it, and is written
    let mut args = vec!["batch", "sec", "-o", "sec2"];
    args.extend(lsq);
    let out = fairfit().current_dir(d).args(&args).output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["a.json", "b.report.json", "c.json", "summary.jsonl"] {
        assert!(d.join("sec2").join(f).is_file(), "{f}");
    }
}

#[test]
#[cfg(unix)]
fn links_and_stdout_are_written_through_never_replaced() {
    let dir = workspace();
    let d = dir.path();
    // -o /dev/stdout and -o - write to stdout (here a pipe)
    for o in ["/dev/stdout", "-"] {
        let out = fairfit()
            .current_dir(d)
            .args(["curve", "p.csv", "--method", "lsq", "-o", o])
            .output()
            .unwrap();
        assert_success(&out);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["kind"], "curve");
    }
    assert!(std::fs::symlink_metadata("/dev/stdout").map_or(true, |m| !m.is_file()));
    // a link to a regular file elsewhere: the file is replaced, the link kept
    std::fs::create_dir(d.join("real")).unwrap();
    std::fs::write(d.join("real/c.json"), "old").unwrap();
    std::os::unix::fs::symlink("real/c.json", d.join("c.json")).unwrap();
    let out = fairfit()
        .current_dir(d)
        .args(["curve", "p.csv", "--method", "lsq", "-o", "c.json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(std::fs::symlink_metadata(d.join("c.json"))
        .unwrap()
        .file_type()
        .is_symlink());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("real/c.json")).unwrap()).unwrap();
    assert_eq!(v["kind"], "curve");
    let names: Vec<_> = std::fs::read_dir(d.join("real")).unwrap().collect();
    assert_eq!(names.len(), 1, "no temporary left");
}

#[test]
#[cfg(unix)]
fn a_failing_output_leaves_none_of_the_others() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let dir = workspace();
    let d = dir.path();
    refused(
        d,
        &["curve", "p.csv", "-o", "out.json", "--report", "/dev/full"],
        1,
        &["/dev/full"],
    );
    std::fs::write(d.join("c.json"), crate::common::CIRCLE).unwrap();
    refused(
        d,
        &[
            "export",
            "c.json",
            "--step",
            "a.step",
            "--iges",
            "/dev/full",
        ],
        1,
        &["/dev/full"],
    );
    // the front and its curves are written with the rest, so a failing -o leaves none of them
    // (nor the folder made for the curves)
    refused(
        d,
        &[
            "curve",
            "p.csv",
            "--pareto",
            "front.csv",
            "--pareto-curves",
            "pc",
            "-o",
            "/dev/full",
        ],
        1,
        &["/dev/full"],
    );
    // the mesh fails after the fit: the surface JSON is not written either
    refused(
        d,
        &[
            "surface",
            "sec",
            "-o",
            "out.json",
            "--mesh",
            "m.stl",
            "--chord-tol",
            "1e-12",
        ],
        2,
        &["chord tolerance"],
    );
}

#[test]
#[cfg(unix)]
fn a_signal_removes_the_temporaries_and_the_next_run_removes_stale_ones() {
    let dir = workspace();
    let d = dir.path();
    // a FIFO output blocks the commit (no reader) after every temporary is written: SIGTERM then
    let fifo = d.join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return; // no mkfifo here
    }
    let bin = assert_cmd::cargo::cargo_bin("fairfit");
    let child = std::process::Command::new(bin)
        .current_dir(d)
        .args([
            "curve", "p.csv", "--method", "lsq", "-o", "out.json", "--report", "fifo",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let tmp = d.join(format!(".out.json.fairfit-{}.tmp", child.id()));
    let start = std::time::Instant::now();
    while !tmp.exists() {
        assert!(start.elapsed().as_secs() < 60, "no temporary file appeared");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    let line = one_line(&out, 143, &["SIGTERM"]);
    assert!(line.contains("interrupted by SIGTERM"), "{line}");
    assert!(!tmp.exists() && !d.join("out.json").exists());
    // a temporary of a killed run (PIDs above 2^22 are never alive) goes with the next write there
    let stale = d.join(".out.json.fairfit-4999999.tmp");
    let foreign = d.join(".out.json.tmp4999999");
    std::fs::write(&stale, "x").unwrap();
    std::fs::write(&foreign, "x").unwrap();
    let ok = fairfit()
        .current_dir(d)
        .args(["curve", "p.csv", "--method", "lsq", "-o", "out.json"])
        .output()
        .unwrap();
    assert!(ok.status.success());
    if Path::new("/proc/self").exists() {
        assert!(!stale.exists(), "the stale temporary is removed");
    }
    assert!(foreign.exists(), "a file of another naming is kept");
}

#[test]
fn a_value_that_is_not_finite_fails_the_run_and_writes_nothing() {
    let dir = workspace();
    let d = dir.path();
    let huge = r#"{"kind": "curve", "degree": 2, "knots": [0,0,0,1,1,1],
        "control_points": [[0,0,0],[1e308,1e308,0],[-1e308,0,0]]}"#;
    std::fs::write(d.join("huge.json"), huge).unwrap();
    refused(
        d,
        &[
            "export",
            "huge.json",
            "--plot",
            "h.svg",
            "--mesh",
            "h.ply",
            "--step",
            "h.step",
        ],
        1,
        &["finite"],
    );
    refused(d, &["plot", "huge.json", "-o", "h.svg"], 1, &["finite"]);
    // a curve 1e-300 long: its fairness integrals are beyond f64
    let tiny = r#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,0.5,1,1,1,1],
      "control_points": [[0,0,0],[1e-300,2e-300,0],[3e-300,1e-300,5e-301],[4e-300,-1e-300,0],[6e-300,5e-301,2e-301]]}"#;
    std::fs::write(d.join("tiny.json"), tiny).unwrap();
    refused(
        d,
        &["info", "tiny.json"],
        1,
        &["cannot be computed as a finite number"],
    );
    // a point (every control point the same) has no inflections: 0, not null
    let point = r#"{"kind": "curve", "degree": 2, "knots": [0,0,0,1,1,1],
        "control_points": [[1,1,0],[1,1,0],[1,1,0]]}"#;
    std::fs::write(d.join("point.json"), point).unwrap();
    let out = fairfit()
        .current_dir(d)
        .args(["info", "point.json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["inflections_exact"], 0);
    assert_eq!(v["curvature_extrema_exact"], 0);
}

#[test]
fn an_option_the_method_ignores_is_a_usage_error() {
    let dir = workspace();
    let d = dir.path();
    for (args, flag) in [
        (vec!["--knots", "averaging"], "--knots"),
        (vec!["--param", "chord"], "--param"),
        (vec!["--smoothing", "0.1"], "--smoothing"),
        (vec!["--correction-rounds", "2"], "--correction-rounds"),
    ] {
        let mut a = vec!["curve", "p.csv", "-o", "c.json"];
        a.extend(args);
        refused(d, &a, 2, &[flag, "--method integrated"]);
    }
    for method in ["lsq", "fit-then-fair"] {
        for (args, flag) in [
            (vec!["--span-fairness", "10"], "--span-fairness"),
            (vec!["--pareto", "f.csv"], "--pareto"),
            (vec!["--no-band-fairing"], "--no-band-fairing"),
        ] {
            let mut a = vec!["curve", "p.csv", "--method", method, "-o", "c.json"];
            a.extend(args);
            refused(d, &a, 2, &[flag, "has no effect"]);
        }
    }
    refused(d, &["curve", "p.csv", "--degree", "1"], 2, &["--degree"]);
    refused(d, &["curve", "p.csv", "--degree", "15"], 2, &["--degree"]);
}

#[test]
fn a_failed_run_prints_one_line_with_echoes_cut_and_controls_escaped() {
    let dir = workspace();
    let d = dir.path();
    // a warning before the error is folded into its line
    std::fs::write(d.join("dup.csv"), "0,0\n".repeat(199) + "1,1\n").unwrap();
    let line = refused(d, &["curve", "dup.csv", "-o", "c.json"], 1, &["too few"]);
    assert!(
        line.contains("earlier warning: dup.csv: dropped 198 consecutive duplicate"),
        "{line}"
    );
    // a 1 MB token is cut
    std::fs::write(
        d.join("long.csv"),
        format!("0,0\n1,{}\n", "x".repeat(1 << 20)),
    )
    .unwrap();
    let line = refused(d, &["curve", "long.csv", "-o", "c.json"], 1, &["long.csv"]);
    assert!(line.len() < 400, "{} characters", line.len());
    // a newline in a file name is escaped
    let line = refused(
        d,
        &["curve", "no\nsuch.csv", "-o", "c.json"],
        1,
        &["no\\nsuch.csv"],
    );
    assert!(!line.contains('\n'));
    // --slices on a CAD file names the rule
    std::fs::write(d.join("c.json"), crate::common::CIRCLE).unwrap();
    let step = d.join("c.step");
    let out = fairfit()
        .current_dir(d)
        .args(["export", "c.json", "--step"])
        .arg(&step)
        .output()
        .unwrap();
    assert!(out.status.success());
    refused(
        d,
        &["surface", "c.step", "--slices", "4", "-o", "s.json"],
        2,
        &["--slices takes a mesh or point cloud"],
    );
}

/// A clamped uniform knot vector of degree 3 for `n` control points, as JSON.
fn cubic_knots_json(n: usize) -> String {
    let spans = n - 3;
    let mut k = vec!["0".to_string(); 4];
    k.extend((1..spans).map(|i| format!("{}", i as f64 / spans as f64)));
    k.extend(std::iter::repeat_n("1".to_string(), 4));
    format!("[{}]", k.join(","))
}

/// Runs `fairfit ARGS` in `dir` under an address-space limit of `kib` KiB (`ulimit -v` in `sh -c`)
/// and asserts what [`refused`] asserts: exit 1, one line naming the memory, nothing written.
fn refused_under_ulimit(dir: &Path, kib: u64, args: &[&str], needles: &[&str]) {
    let before = snapshot(dir);
    let out = std::process::Command::new("sh")
        .current_dir(dir)
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(assert_cmd::cargo::cargo_bin("fairfit"))
        .args(args)
        .output()
        .unwrap();
    let line = one_line(&out, 1, args);
    for n in needles {
        assert!(line.contains(n), "{args:?}: expected `{n}` in {line}");
    }
    assert!(out.stdout.is_empty(), "{args:?}");
    assert_eq!(
        snapshot(dir),
        before,
        "{args:?}: files changed or left behind"
    );
}

/// The buffers that grow with the span count (info's extrema samples, a plot's samples and SVG text,
/// a mesh's vertices) are reserved fallibly: under `ulimit -v` 1 GiB a curve of 2·10^5 spans and a
/// surface of 700 × 700 spans (limits raised by `--max-spans`) end with one line, exit 1 and no
/// file, where they used to abort ("memory allocation of N bytes failed", a backtrace, exit 134).
#[test]
#[cfg(target_os = "linux")]
fn a_run_short_of_memory_fails_with_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 200_003;
    let pts: Vec<String> = (0..n)
        .map(|i| format!("[{},{},0]", i as f64 * 1e-3, (i as f64 * 0.01).sin()))
        .collect();
    let curve = format!(
        r#"{{"kind":"curve","degree":3,"knots":{},"control_points":[{}]}}"#,
        cubic_knots_json(n),
        pts.join(",")
    );
    std::fs::write(d.join("c.json"), curve).unwrap();
    let m = 703;
    let rows: Vec<String> = (0..m)
        .map(|i| {
            let row: Vec<String> = (0..m)
                .map(|j| {
                    format!(
                        "[{},{},{}]",
                        i as f64,
                        j as f64,
                        ((i * 7 + j * 3) % 11) as f64
                    )
                })
                .collect();
            format!("[{}]", row.join(","))
        })
        .collect();
    let knots = cubic_knots_json(m);
    let surface = format!(
        r#"{{"kind":"surface","degree_u":3,"degree_v":3,"knots_u":{knots},"knots_v":{knots},"control_points":[{}]}}"#,
        rows.join(",")
    );
    std::fs::write(d.join("s.json"), surface).unwrap();
    let gib = 1 << 20;
    let spans = ["--max-spans", "1000000"];
    let mut info = vec!["info", "c.json"];
    info.extend(spans);
    refused_under_ulimit(d, gib, &info, &["extrema's samples: not enough memory for"]);
    let mut plot = vec!["plot", "c.json", "-o", "p.svg"];
    plot.extend(spans);
    refused_under_ulimit(d, gib, &plot, &["plot", "not enough memory for"]);
    let mut mesh = vec!["export", "s.json", "--mesh", "m.obj"];
    mesh.extend(spans);
    refused_under_ulimit(d, gib, &mesh, &["the mesh", "not enough memory for"]);
}

#[test]
fn more_sections_than_the_limit_are_refused_with_its_option() {
    let dir = workspace();
    let d = dir.path();
    // the three section files against a limit of 2: refused after reading, before any fit
    refused(
        d,
        &[
            "surface",
            "sec/a.csv",
            "sec/b.csv",
            "sec/c.csv",
            "--max-sections",
            "2",
            "-o",
            "s.json",
        ],
        1,
        &["3 sections", "limit of 2", "--max-sections"],
    );
    // planes asked for above the limit: a usage error before the cloud is read
    std::fs::write(d.join("cloud.xyz"), "0 0 0\n1 0 0\n0 1 1\n").unwrap();
    refused(
        d,
        &["surface", "cloud.xyz", "--slices", "1001", "-o", "s.json"],
        2,
        &["--slices 1001", "limit of 1000", "--max-sections"],
    );
    // at the limit the same files fit
    let out = fairfit()
        .current_dir(d)
        .args(["surface", "sec/a.csv", "sec/b.csv", "sec/c.csv"])
        .args(["--max-sections", "3", "-o", "s.json"])
        .output()
        .unwrap();
    assert_success(&out);
    assert!(d.join("s.json").exists());
}

/// Every method fits the same half ellipse at unit size and at 1e±200 and 1e300 (beyond 2^±64 a fit
/// and its measures work on an exactly rescaled copy): the same control-point count, deviation over
/// tolerance, fairness and exact shape counts (squared distances and the numerators' powers of
/// lengths would otherwise overflow or underflow).
#[test]
fn every_method_fits_the_same_shape_at_any_scale() {
    let dir = workspace();
    let d = dir.path();
    let csv = |s: f64| {
        (0..40)
            .map(|i| {
                let t = i as f64 / 39.0 * std::f64::consts::PI;
                format!("{:e},{:e}\n", s * t.cos(), 0.5 * s * t.sin())
            })
            .collect::<String>()
    };
    let measures = |r: &serde_json::Value| {
        let f = |k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k}: {r}"));
        let ratio = f("max_deviation") / f("tolerance");
        let counts = [
            "control_points",
            "curvature_extrema_exact",
            "inflections_exact",
        ]
        .map(|k| r[k].as_u64().unwrap_or_else(|| panic!("{k}: {r}")));
        (counts, ratio, f("fairness"))
    };
    for method in ["lsq", "integrated", "fit-then-fair"] {
        let mut unit = None;
        for s in [1.0, 1e-200, 1e200, 1e300] {
            let name = format!("{method}-{s:e}");
            std::fs::write(d.join(format!("{name}.csv")), csv(s)).unwrap();
            let run = crate::common::curve_run(
                d,
                &name,
                d.join(format!("{name}.csv")),
                &["--method", method],
            );
            let (counts, ratio, fairness) = measures(&run.report);
            assert!(ratio <= 1.0 && ratio > 0.5, "{name}: {ratio}");
            let (c0, r0, f0): ([u64; 3], f64, f64) = *unit.get_or_insert((counts, ratio, fairness));
            assert_eq!(counts, c0, "{name}");
            assert_eq!(
                counts[1], 3,
                "{name}: a half ellipse has three curvature extrema"
            );
            assert!((ratio - r0).abs() < 1e-9, "{name}: {ratio} vs {r0}");
            assert!(
                (fairness / f0 - 1.0).abs() < 1e-9,
                "{name}: {fairness} vs {f0}"
            );
        }
    }
}
