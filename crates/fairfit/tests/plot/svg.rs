//! Plots rendered for real: SVG text parsed and rasterised by resvg to PNGs of the requested size that
//! are not blank; deviation numbers checked against points placed at known distances.

use fairfit::plot::curve_plots::{curvature_svg, curve_comb_svg, deviation_svg};
use fairfit::plot::png::{png_size, svg_to_png};
use fairfit::plot::surface_plots::{deviation_map_svg, iso_curvature_svg, IsoDirection};
use fairfit::plot::PlotSize;
use fairfit::{NurbsCurve, NurbsSurface, Vec3};

fn wavy_curve() -> NurbsCurve {
    let pts: Vec<Vec3> = (0..9)
        .map(|i| {
            let x = i as f64;
            Vec3::new(x, (x * 0.9).sin() * 2.0, 0.0)
        })
        .collect();
    let knots = fairfit::nurbs::knots::uniform_clamped(3, pts.len());
    NurbsCurve::bspline(3, knots, pts).unwrap()
}

fn wavy_surface() -> NurbsSurface {
    let net = (0..6)
        .map(|i| {
            (0..5)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    Vec3::new(x, y, (x * 0.8).sin() * (y * 0.6).cos())
                })
                .collect()
        })
        .collect();
    let ku = fairfit::nurbs::knots::uniform_clamped(3, 6);
    let kv = fairfit::nurbs::knots::uniform_clamped(3, 5);
    NurbsSurface::new(3, 3, ku, kv, net, None).unwrap()
}

/// Fraction of pixels that are not white, from a PNG re-rendered into an RGBA buffer.
fn ink(svg: &str, w: u32, h: u32) -> f64 {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default()).unwrap();
    let mut pm = resvg::tiny_skia::Pixmap::new(w, h).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::identity(),
        &mut pm.as_mut(),
    );
    let px = pm
        .data()
        .chunks(4)
        .filter(|p| p[0] < 250 || p[1] < 250 || p[2] < 250)
        .count();
    px as f64 / (w * h) as f64
}

fn out_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("fairfit-plots-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn curve_plots_render_to_png_of_the_requested_size() {
    let c = wavy_curve();
    let pts: Vec<Vec3> = (0..40)
        .map(|k| c.point(k as f64 / 39.0) + Vec3::new(0.0, 0.02, 0.0))
        .collect();
    let size = PlotSize::new(640, 420).unwrap();
    let dir = out_dir();
    for (name, svg) in [
        ("comb", curve_comb_svg(&c, Some(&pts), size).unwrap()),
        ("curvature", curvature_svg(&c, size).unwrap()),
        ("deviation", deviation_svg(&c, &pts, size).unwrap()),
    ] {
        assert!(svg.starts_with("<svg") && svg.contains(r#"width="640" height="420""#));
        let png = svg_to_png(&svg, 640, 420).unwrap();
        assert_eq!(png_size(&png), Some((640, 420)), "{name}");
        assert!(png.len() > 2000, "{name}: {} bytes", png.len());
        let f = ink(&svg, 640, 420);
        assert!(f > 0.01 && f < 0.8, "{name}: ink fraction {f}");
        std::fs::write(dir.join(format!("{name}.png")), png).unwrap();
    }
    // A different requested size is honoured (scaled rendering).
    let png = svg_to_png(&curvature_svg(&c, size).unwrap(), 320, 210).unwrap();
    assert_eq!(png_size(&png), Some((320, 210)));
}

#[test]
fn deviation_plot_reports_known_distances() {
    let c = NurbsCurve::bspline(
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)],
    )
    .unwrap();
    let pts = vec![
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(5.0, -0.25, 0.0),
        Vec3::new(9.0, 0.0, 0.0),
    ];
    let svg = deviation_svg(&c, &pts, PlotSize::default()).unwrap();
    // max 0.5, RMS sqrt((0.25 + 0.0625) / 3)
    assert!(svg.contains("max 5.000e-1"), "{svg}");
    assert!(svg.contains(&format!("RMS {:.3e}", (0.3125f64 / 3.0).sqrt())));
}

/// Beyond the marker cap (20,000) each marker stands for a run of points and shows its largest
/// deviation: a single spike between the thinned indices is still drawn.
#[test]
fn deviation_plot_thinning_keeps_the_worst_point() {
    let c = NurbsCurve::bspline(
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![Vec3::ZERO, Vec3::new(10.0, 0.0, 0.0)],
    )
    .unwrap();
    let n = 50_000; // a run of 3 points per marker
    let mut pts: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(10.0 * i as f64 / n as f64, 0.0, 0.0))
        .collect();
    pts[30_001] = Vec3::new(pts[30_001].x(), 0.5, 0.0); // not the first point of its run
    let svg = deviation_svg(&c, &pts, PlotSize::default()).unwrap();
    let ys: Vec<&str> = svg
        .split("<circle")
        .skip(1)
        .filter_map(|t| t.split("cy=\"").nth(1)?.split('"').next())
        .collect();
    assert!(ys.len() <= 20_000 && ys.len() >= 16_000, "{}", ys.len());
    let mut distinct = ys.clone();
    distinct.sort_unstable();
    distinct.dedup();
    // every marker at 0 but the spike's
    assert_eq!(distinct.len(), 2, "{distinct:?}");
    assert_eq!(ys.iter().filter(|&&y| y != ys[0]).count(), 1);
}

#[test]
fn surface_plots_render() {
    let s = wavy_surface();
    let pts: Vec<Vec3> = (0..15)
        .flat_map(|i| (0..15).map(move |j| (i as f64 / 14.0, j as f64 / 14.0)))
        .map(|(u, v)| s.point(u, v) + Vec3::new(0.0, 0.0, 0.01 * u))
        .collect();
    let size = PlotSize::new(700, 500).unwrap();
    let dir = out_dir();
    let map = deviation_map_svg(&s, &pts, size).unwrap();
    assert!(map.contains("max 1.000e-2"), "largest offset 0.01 at u = 1");
    let iso = iso_curvature_svg(&s, IsoDirection::FixedV, 5, size).unwrap();
    assert_eq!(iso.matches("v = ").count(), 5);
    for (name, svg) in [("devmap", map), ("iso", iso)] {
        let png = svg_to_png(&svg, 700, 500).unwrap();
        assert_eq!(png_size(&png), Some((700, 500)));
        assert!(ink(&svg, 700, 500) > 0.01, "{name}");
        std::fs::write(dir.join(format!("{name}.png")), png).unwrap();
    }
}
