//! Hostile input for every file reader and for what runs on the geometry they accept: arbitrary bytes,
//! lines of numbers mixed with garbage, and structured JSON with extreme values (degree 0 or huge,
//! NaN-like and 1e±300 coordinates, zero or negative weights, decreasing knots). Each reader must return
//! `Ok` or a typed error, never panic; geometry a reader accepts must evaluate, measure, tessellate,
//! export and plot without a panic as well. Case counts are capped so the file runs in seconds.

use fairfit::diffgeo::arc_length::arc_length;
use fairfit::fair::curve_fairness;
use fairfit::fair::surface::surface_fairness;
use fairfit::io::iges::{curve_to_iges, surface_to_iges, IgesOptions};
use fairfit::io::json::geometry_from_str;
use fairfit::io::mesh_read::read_mesh;
use fairfit::io::points::parse_points;
use fairfit::io::sections::parse_section_text;
use fairfit::io::step::{curve_to_step, surface_to_step, StepOptions};
use fairfit::io::tessellate::{tessellate_curve, tessellate_surface, TessellationOptions};
use fairfit::io::Geometry;
use fairfit::plot::curve_plots::{curvature_svg, curve_comb_svg, deviation_svg};
use fairfit::plot::surface_plots::{deviation_map_svg, iso_curvature_svg, IsoDirection};
use fairfit::plot::PlotSize;
use fairfit::{NurbsCurve, NurbsSurface, Vec3};
use proptest::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Number tokens that break naive parsers: signs, exponents at and past the f64 range, subnormals,
/// NaN/inf spellings, integers past u64, hex, empty exponents.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "3",
    "0.5",
    "1e300",
    "-1e300",
    "1e-300",
    "1e308",
    "1e309",
    "-1e309",
    "5e-324",
    "1e-400",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "infinity",
    "18446744073709551616",
    "99999999999999999999999",
    "0x10",
    "1e",
    "+",
    "-",
    ".",
    "1.2.3",
    "1,5",
    "3.14159",
];

/// Non-numeric tokens: separators, comments, Unicode, control characters.
const GARBAGE: &[&str] = &[
    ",",
    ";",
    "\t",
    " ",
    "#",
    "//",
    "x",
    "y,z",
    "é",
    "☃",
    "\u{feff}",
    "\r",
    "\0",
    "solid",
    "vertex",
    "endloop",
    "facet",
    "v",
    "f",
    "ply",
    "end_header",
    "element",
    "property",
];

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => prop::sample::select(NUMBERS).prop_map(str::to_string),
        1 => prop::sample::select(GARBAGE).prop_map(str::to_string),
        1 => any::<f64>().prop_map(|x| format!("{x:e}")),
    ]
}

/// Text made of lines of tokens separated by commas, spaces or semicolons.
fn numeric_text() -> impl Strategy<Value = String> {
    let line = prop::collection::vec(token(), 0..5).prop_flat_map(|toks| {
        prop::sample::select(vec![",", " ", ";", "\t"]).prop_map(move |sep| toks.join(sep))
    });
    prop::collection::vec(line, 0..12).prop_map(|lines| lines.join("\n"))
}

fn bytes() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(any::<u8>(), 0..400)
}

/// A unique temporary file holding `bytes` with extension `ext`; removed on drop.
struct TempFile(std::path::PathBuf);

impl TempFile {
    fn new(ext: &str, bytes: &[u8]) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let p = std::env::temp_dir().join(format!(
            "fairfit_hostile_{}_{}.{ext}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::write(&p, bytes).unwrap();
        TempFile(p)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Everything the CLI does with an accepted curve: evaluation, measures, tessellation, exports, plots.
/// Results may be errors; only a panic fails the test.
fn exercise_curve(c: &NurbsCurve) {
    let (a, b) = c.domain();
    for u in [a, b, 0.5 * (a + b), a - 1.0, f64::NAN, f64::INFINITY] {
        let _ = c.point(u);
        let _ = c.derivatives(u, 3);
    }
    let _ = arc_length(c);
    let _ = curve_fairness(c);
    let opts = TessellationOptions {
        chord_tol: Some(1e-3),
        max_intervals: 256,
        ..Default::default()
    };
    let _ = tessellate_curve(c, &opts);
    let _ = curve_to_step(c, &StepOptions::default());
    let _ = curve_to_iges(c, &IgesOptions::default());
    let size = PlotSize::new(200, 150).unwrap();
    let pts = c.control_points().to_vec();
    let _ = curve_comb_svg(c, Some(&pts), size);
    let _ = curvature_svg(c, size);
    let _ = deviation_svg(c, &pts, size);
}

/// The surface counterpart of [`exercise_curve`].
fn exercise_surface(s: &NurbsSurface) {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    for (u, v) in [
        (u0, v0),
        (u1, v1),
        (0.5 * (u0 + u1), 0.5 * (v0 + v1)),
        (f64::NAN, v0),
    ] {
        let _ = s.point(u, v);
        let _ = s.derivatives(u, v, 2);
    }
    let _ = surface_fairness(s, 3);
    let opts = TessellationOptions {
        chord_tol: Some(1e-3),
        max_intervals: 64,
        ..Default::default()
    };
    let _ = tessellate_surface(s, &opts);
    let _ = surface_to_step(s, &StepOptions::default());
    let _ = surface_to_iges(s, &IgesOptions::default());
    let size = PlotSize::new(200, 150).unwrap();
    let pts = s.control_points_flat().to_vec();
    let _ = deviation_map_svg(s, &pts, size);
    let _ = iso_curvature_svg(s, IsoDirection::FixedU, 3, size);
}

fn exercise(g: &Geometry) {
    match g {
        Geometry::Curve(c) => exercise_curve(c),
        Geometry::Surface(s) => exercise_surface(s),
    }
}

/// A JSON number or an out-of-range literal.
fn json_number() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => prop::sample::select(vec![
            "0", "1", "2", "3", "-1", "0.5", "1e300", "-1e300", "1e-300", "1e308", "1e999", "5e-324",
            "18446744073709551615", "18446744073709551616", "1.5", "-0",
        ])
        .prop_map(str::to_string),
        1 => (-10.0..10.0f64).prop_map(|x| format!("{x}")),
    ]
}

fn json_list(item: BoxedStrategy<String>, max: usize) -> BoxedStrategy<String> {
    prop::collection::vec(item, 0..max)
        .prop_map(|v| format!("[{}]", v.join(",")))
        .boxed()
}

fn json_point() -> BoxedStrategy<String> {
    prop::collection::vec(json_number(), 3)
        .prop_map(|v| format!("[{}]", v.join(",")))
        .boxed()
}

/// Curve JSON: small degrees (and extreme ones), clamped-looking knots, extreme coordinates.
fn curve_json() -> impl Strategy<Value = String> {
    let degree = prop_oneof![
        4 => (0usize..5).prop_map(|d| d.to_string()),
        1 => prop::sample::select(vec!["18446744073709551615", "4294967296", "-1", "1.5", "1e3"])
            .prop_map(str::to_string),
    ];
    let knots = prop_oneof![
        3 => (1usize..4, 2usize..7).prop_map(|(p, n)| {
            let mut k = vec!["0".to_string(); p + 1];
            for i in 1..n.saturating_sub(p) {
                k.push(format!("{}", i as f64 / (n - p) as f64));
            }
            k.extend(std::iter::repeat_n("1".to_string(), p + 1));
            format!("[{}]", k.join(","))
        }),
        1 => json_list(json_number().boxed(), 12),
    ];
    let weights = prop_oneof![
        Just(String::new()),
        json_list(json_number().boxed(), 8).prop_map(|w| format!(",\"weights\":{w}")),
    ];
    (degree, knots, json_list(json_point(), 8), weights).prop_map(|(d, k, cp, w)| {
        format!("{{\"kind\":\"curve\",\"degree\":{d},\"knots\":{k},\"control_points\":{cp}{w}}}")
    })
}

/// Surface JSON: a bilinear-to-biquadratic net with extreme values mixed in.
fn surface_json() -> impl Strategy<Value = String> {
    (1usize..3, 1usize..3, 0usize..2, 0usize..2).prop_flat_map(|(p, q, eu, ev)| {
        let (nu, nv) = (p + 1 + eu, q + 1 + ev);
        let clamped = |deg: usize, n: usize| {
            let mut k = vec!["0".to_string(); deg + 1];
            for i in 1..(n - deg) {
                k.push(format!("{}", i as f64 / (n - deg) as f64));
            }
            k.extend(std::iter::repeat_n("1".to_string(), deg + 1));
            format!("[{}]", k.join(","))
        };
        let (ku, kv) = (clamped(p, nu), clamped(q, nv));
        let row =
            prop::collection::vec(json_point(), nv).prop_map(|r| format!("[{}]", r.join(",")));
        let net = prop::collection::vec(row, nu).prop_map(|rows| format!("[{}]", rows.join(",")));
        let wrow =
            prop::collection::vec(json_number(), nv).prop_map(|r| format!("[{}]", r.join(",")));
        let weights = prop_oneof![
            Just(String::new()),
            prop::collection::vec(wrow, nu)
                .prop_map(|rows| format!(",\"weights\":[{}]", rows.join(","))),
        ];
        (net, weights).prop_map(move |(net, w)| {
            format!(
                "{{\"kind\":\"surface\",\"degree_u\":{p},\"degree_v\":{q},\"knots_u\":{ku},\
                 \"knots_v\":{kv},\"control_points\":{net}{w}}}"
            )
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, rng_seed: proptest::test_runner::RngSeed::Fixed(0x00FA_1AF1), ..ProptestConfig::default() })]

    #[test]
    fn point_files_never_panic(text in numeric_text(), raw in bytes()) {
        let _ = parse_points(&text, "fuzz.csv");
        let _ = parse_points(&String::from_utf8_lossy(&raw), "fuzz.csv");
    }

    #[test]
    fn section_files_never_panic(text in numeric_text(), raw in bytes()) {
        let _ = parse_section_text(&text, "fuzz.csv");
        let _ = parse_section_text(&String::from_utf8_lossy(&raw), "fuzz.csv");
    }

    #[test]
    fn json_files_never_panic(raw in bytes(), text in numeric_text()) {
        let _ = geometry_from_str(&String::from_utf8_lossy(&raw));
        let _ = geometry_from_str(&text);
    }

    #[test]
    fn accepted_curves_never_panic(text in curve_json()) {
        if let Ok(g) = geometry_from_str(&text) {
            exercise(&g);
        }
    }

    #[test]
    fn accepted_surfaces_never_panic(text in surface_json()) {
        if let Ok(g) = geometry_from_str(&text) {
            exercise(&g);
        }
    }

    #[test]
    fn mesh_files_never_panic(raw in bytes(), text in numeric_text(), ext in prop::sample::select(vec!["ply", "stl", "obj", "xyz"])) {
        for content in [raw.clone(), text.clone().into_bytes()] {
            let f = TempFile::new(ext, &content);
            let _ = read_mesh(&f.0);
        }
    }
}

/// Mesh headers with a hostile body: the header is valid, the counts and data are not.
#[test]
fn mesh_headers_with_hostile_counts_are_errors() {
    let cases: &[(&str, &[u8])] = &[
        ("ply", b"ply\nformat ascii 1.0\nelement vertex 99999999999999\nend_header\n"),
        ("ply", b"ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nend_header\n1\n"),
        ("ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"),
        ("ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 7\n"),
        ("ply", b"ply\nformat ascii 1.0\nelement face 1\nproperty list int int vertex_indices\nend_header\n-5 1 2 3\n"),
        ("ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\nnan 0 0\n"),
        ("obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n"),
        ("obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9223372036854775807\n"),
        ("obj", b"v 0 0 0\nf 1 1\n"),
        ("stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0\nendloop\n"),
        ("stl", &[0u8; 84]),
        ("xyz", b"1e400 0 0\n"),
    ];
    for (ext, bytes) in cases {
        let f = TempFile::new(ext, bytes);
        let r = read_mesh(&f.0);
        // a one-vertex point cloud without faces may be read; everything else here must be an error
        if let Ok(m) = &r {
            assert!(m.vertices.iter().all(|p| p.is_finite()), "{ext}: {m:?}");
            assert!(m.triangles.iter().flatten().all(|&i| i < m.vertices.len()));
        }
    }
}

/// Directories, missing files and binary files given where a text file is expected are typed errors.
#[test]
fn unreadable_paths_are_typed_errors() {
    let dir = std::env::temp_dir();
    assert!(fairfit::io::read_points(&dir).is_err());
    assert!(fairfit::io::read_geometry(&dir).is_err());
    assert!(read_mesh(&dir).is_err());
    assert!(fairfit::io::sections::read_section_file(&dir).is_err());
    let missing = dir.join("fairfit_hostile_missing_file.csv");
    assert!(fairfit::io::read_points(&missing).is_err());
    let bin = TempFile::new("json", &[0xff, 0xfe, 0, 1, 2, 3]);
    assert!(fairfit::io::read_geometry(&bin.0).is_err());
    assert!(fairfit::io::read_points(&bin.0).is_err());
    assert!(fairfit::io::sections::read_section_file(&bin.0).is_err());
}

/// A curve with coordinates near 1e±300 and the degree/knot extremes the JSON format allows.
#[test]
fn extreme_json_curves_are_ok_or_typed_errors() {
    for (degree, scale) in [(1, 1e300), (2, 1e-300), (3, 1e300), (2, 1e-320)] {
        let n = degree + 3;
        let knots = fairfit::nurbs::knots::uniform_clamped(degree, n);
        let pts: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64 * scale, ((i * i) % 3) as f64 * scale, 0.0))
            .collect();
        if let Ok(c) = NurbsCurve::bspline(degree, knots, pts) {
            exercise_curve(&c);
        }
    }
    for text in [
        r#"{"kind":"curve","degree":18446744073709551615,"knots":[0,1],"control_points":[[0,0,0]]}"#,
        r#"{"kind":"curve","degree":18446744073709551614,"knots":[0,1],"control_points":[[0,0,0]]}"#,
        r#"{"kind":"curve","degree":1,"knots":[0,0,1e999,1],"control_points":[[0,0,0],[1,1,1]]}"#,
        r#"{"kind":"curve","degree":1,"knots":[0,0,1,1],"control_points":[[0,0,0],[1,1,1]],"weights":[0,1]}"#,
        r#"{"kind":"curve","degree":1,"knots":[0,0,1,1],"control_points":[[0,0,0],[1,1,1]],"weights":[-1,1]}"#,
        r#"{"kind":"surface","degree_u":18446744073709551615,"degree_v":1,"knots_u":[0,1],"knots_v":[0,0,1,1],"control_points":[[[0,0,0],[0,1,0]]]}"#,
        r#"{"kind":"surface","degree_u":1,"degree_v":1,"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],"control_points":[[[0,0,0],[0,1,0]],[[1,0,0]]]}"#,
    ] {
        assert!(geometry_from_str(text).is_err(), "{text}");
    }
}

/// Tessellation, curvature samples and surface projection near 1e±300 work on an exactly rescaled
/// copy: the results are the unit-scale results scaled by the same power of two, to the bit.
#[test]
fn extreme_scales_tessellate_plot_and_project_like_unit_scale() {
    let net = |s: f64| -> Vec<Vec<Vec3>> {
        (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| Vec3::new(i as f64 * s, j as f64 * s, ((i * j) % 3) as f64 * s))
                    .collect()
            })
            .collect()
    };
    let k = fairfit::nurbs::knots::uniform_clamped(3, 4);
    let surf = |s: f64| NurbsSurface::new(3, 3, k.clone(), k.clone(), net(s), None).unwrap();
    let unit = surf(1.0);
    let opts = |t: f64| TessellationOptions {
        chord_tol: Some(t),
        ..Default::default()
    };
    let m1 = tessellate_surface(&unit, &opts(1e-3)).unwrap();
    let curve1 = unit.iso_curve_u(0.3).unwrap();
    let (c1, _) = fairfit::plot::curve_plots::curvature_samples(&curve1).unwrap();
    let q1: Vec<Vec3> = vec![Vec3::new(1.0, 1.0, 2.0), Vec3::new(2.5, 0.5, -1.0)];
    let feet1 = fairfit::plot::surface_projection::project_points(&unit, &q1);
    for e in [997, -997, 700] {
        let s = 2f64.powi(e);
        let big = surf(s);
        let m = tessellate_surface(&big, &opts(1e-3 * s)).unwrap();
        assert_eq!(m.vertices.len(), m1.vertices.len(), "2^{e}");
        assert_eq!(m.triangles, m1.triangles);
        for (a, b) in m.vertices.iter().zip(&m1.vertices) {
            assert_eq!(*a, *b * s, "2^{e}");
        }
        let (c, _) =
            fairfit::plot::curve_plots::curvature_samples(&big.iso_curve_u(0.3).unwrap()).unwrap();
        for (a, b) in c.iter().zip(&c1) {
            assert!(
                (a.kappa * s - b.kappa).abs() <= 1e-12 * b.kappa.abs().max(1.0),
                "2^{e}"
            );
        }
        let q: Vec<Vec3> = q1.iter().map(|&p| p * s).collect();
        let feet = fairfit::plot::surface_projection::project_points(&big, &q);
        for (a, b) in feet.iter().zip(&feet1) {
            assert!(
                (a.distance / s - b.distance).abs() <= 1e-12 * b.distance,
                "2^{e}"
            );
        }
    }
}

/// A key or value holding a control character (a `\n` escape in the document) is quoted in the error
/// escaped: the message stays one line (found by the `json` libFuzzer target).
#[test]
fn a_json_error_quoting_a_control_character_is_one_line() {
    let doc = r#"{"kind": "curve", "degree": 3, "knots": [0,0,0,0,1,1,1,1],
        "con\ntrol\u001b_points": [[0,0,0],[1,0,0],[2,1,0],[3,0,0]]}"#;
    let e = geometry_from_str(doc).unwrap_err().to_string();
    assert!(!e.contains('\n') && !e.contains('\u{1b}'), "{e}");
    assert!(e.contains(r"con\ntrol\u{1b}_points"), "{e}");
}
