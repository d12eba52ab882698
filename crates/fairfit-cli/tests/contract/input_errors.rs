//! Defects found by the session-15 fuzz pass, each pinned by the input that showed it and the exact
//! line (and exit code) the user now gets.

use crate::common;
use common::{file_with, one_line_failure, CIRCLE};

/// A one-line fairfit surface JSON (a bilinear patch).
const PATCH: &str = r#"{"kind": "surface", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#;

#[test]
fn geometry_json_given_as_points_is_named_not_dumped() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.json");
    let out = out.to_str().unwrap();
    let curve = file_with(CIRCLE.as_bytes());
    let surface = file_with(PATCH.as_bytes());
    let other = file_with(br#"{"points": [[0, 0], [1, 1]]}"#);
    for (f, kind) in [(&curve, "curve"), (&surface, "surface")] {
        let p = f.path().to_str().unwrap();
        let expected = format!(
            "error: invalid input data: {p}: already a fairfit {kind} (JSON), not a point file; \
             `fairfit info|eval|plot|export` take it (to re-fit it, write it as STEP with \
             `fairfit export --step` first)\n"
        );
        // was (surface): "...:1: expected 2 or 3 numbers, got `{...the whole file...}`"; (curve): "no
        // points found (empty file?)" or the file's second line
        for cmd in ["surface", "curve"] {
            assert_eq!(one_line_failure(&[cmd, p, "-o", out], 1, &[]), expected);
        }
    }
    let p = other.path().to_str().unwrap();
    let expected = format!(
        "error: invalid input data: {p}: a JSON file, not a point file (points are 2 or 3 numbers per \
         line)\n"
    );
    assert_eq!(one_line_failure(&["curve", p, "-o", out], 1, &[]), expected);
}

#[test]
fn unknown_plot_extension_is_a_usage_error_like_the_other_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let curve = file_with(CIRCLE.as_bytes());
    let c = curve.path().to_str().unwrap();
    for name in ["x.xyz", "x"] {
        let out = dir.path().join(name);
        let out = out.to_str().unwrap();
        // was: exit 1, "x.xyz: unknown plot format, expected a .svg or .png file name"
        let line = one_line_failure(&["plot", c, "-o", out], 2, &[]);
        assert_eq!(
            line,
            format!(
                "error: -o {out}: unknown format, expected a .svg or .png file name; see 'fairfit \
                 plot --help'\n"
            )
        );
        assert!(!std::path::Path::new(out).exists());
        // the same option error through export's --plot and --mesh
        let line = one_line_failure(&["export", c, "--plot", out], 2, &[]);
        assert_eq!(
            line,
            format!(
                "error: --plot {out}: unknown format, expected a .svg or .png file name; see \
                 'fairfit export --help'\n"
            )
        );
        let line = one_line_failure(&["export", c, "--mesh", out], 2, &[]);
        assert_eq!(
            line,
            format!(
                "error: --mesh {out}: unknown format, expected a .obj, .stl or .ply file name; \
                 see 'fairfit export --help'\n"
            )
        );
    }
}

#[test]
fn subnormal_knot_range_is_refused_alike_by_plot_info_and_eval() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("p.svg");
    let svg = svg.to_str().unwrap();
    // 1 / 5e-309 overflows; 6e-309 (the smallest range whose reciprocal is finite) still plots
    for range in ["1e-320", "5e-309"] {
        let curve = file_with(
            format!(
                r#"{{"kind": "curve", "degree": 2, "knots": [0, 0, 0, {range}, {range}, {range}],
                "control_points": [[0,0,0],[1,1,0],[2,0,0]]}}"#
            )
            .as_bytes(),
        );
        let c = curve.path().to_str().unwrap();
        let expected = format!(
            "error: invalid JSON: {c}: field `knots`: invalid knot vector: curve: the knots run from \
             0e0 to {range}, a range below the floating-point limit; rescale the parameters\n"
        );
        // was: plot "invalid input data: nothing finite to plot"; info length 0 and not regular;
        // eval null points
        for args in [
            vec!["plot", c, "-o", svg],
            vec!["info", c],
            vec!["eval", c, "--at", "0"],
        ] {
            assert_eq!(one_line_failure(&args, 1, &[]), expected, "{args:?}");
        }
    }
    let curve = file_with(
        br#"{"kind": "curve", "degree": 2, "knots": [0, 0, 0, 6e-309, 6e-309, 6e-309],
        "control_points": [[0,0,0],[1,1,0],[2,0,0]]}"#,
    );
    // 6e-309 is accepted, but its curvature comb is not finite (the teeth's ends were NaN in the
    // SVG): the plot fails with one line and writes nothing
    one_line_failure(
        &["plot", curve.path().to_str().unwrap(), "-o", svg],
        1,
        &["cannot be computed as a finite number", "NaN"],
    );
    assert!(!std::path::Path::new(svg).exists());
}
