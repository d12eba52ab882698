//! Sections (`src/surface/orient.rs`): open sections whose ends meet at the tolerance's scale are
//! closed before the fit ([`Section::close_at_tolerance`]), so scanned rings whose last point stops
//! one step short of the first give a closed, seamless surface.

use fairfit::nurbs::Vec3;
use fairfit::surface::{reconstruct_surface, CompatibleOptions, Section, SurfaceOptions};

/// Section `k` of a lofted ring (an ellipse 1.0 × (0.6 + 0.1k) with a third-harmonic wave, at
/// z = 0.5k): `n` points at equal angle steps from angle 0, the last `missing` steps short of a full
/// turn (1: the ring stops one step before its first point).
fn ring(k: usize, n: usize, missing: usize) -> Section {
    let b = 0.6 + 0.1 * k as f64;
    let pts = (0..n - missing)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / (n - 1) as f64;
            let r = 1.0 + 0.05 * (3.0 * t).cos();
            Vec3::new(r * t.cos(), b * r * t.sin(), 0.5 * k as f64)
        })
        .collect();
    Section::from_points(pts)
}

fn options(tol: f64, open_sections: bool) -> SurfaceOptions {
    SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: tol,
            ..Default::default()
        },
        iso_curves: 5,
        open_sections,
        ..Default::default()
    }
}

/// The largest distance between the surface's iso-curves u = 0 and u = 1 at 21 values of v.
fn edge_gap(r: &fairfit::surface::SurfaceReconstruction) -> f64 {
    let s = &r.surface;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    (0..=20)
        .map(|j| {
            let v = v0 + (v1 - v0) * j as f64 / 20.0;
            s.point(u0, v).distance(s.point(u1, v))
        })
        .fold(0.0, f64::max)
}

/// Four rings of 300 points, each stopping one angle step (0.013 to 0.020 long) short of closing, at
/// the tolerance 0.025: closed across that step and fitted periodically, the surface has no seam;
/// kept open, its u ends stay a step apart.
#[test]
fn rings_one_step_short_of_closing_are_closed_at_the_tolerance() {
    let tol = 2.5e-2;
    let secs: Vec<Section> = (0..4).map(|k| ring(k, 301, 1)).collect();
    assert!(secs.iter().all(|s| !s.closed));
    let steps: Vec<f64> = secs
        .iter()
        .map(|s| s.points[0].distance(s.points[s.points.len() - 1]))
        .collect();

    let r = reconstruct_surface(secs.clone(), &options(tol, false)).unwrap();
    println!(
        "closed: net {:?}, periodic {}, gaps {:?}, seam {:?}, edge gap {:.3e}, dev {:.3e}",
        r.surface.net_size(),
        r.compatible.periodic,
        r.closed_by_gap,
        r.seam,
        edge_gap(&r),
        r.deviation.max
    );
    for (g, step) in r.closed_by_gap.iter().zip(&steps) {
        assert_eq!(*g, Some(*step));
    }
    assert!(r.sections.iter().all(|s| s.closed && s.points.len() == 301));
    assert!(r.compatible.periodic);
    let seam = r.seam.unwrap();
    assert!(seam.max_tangent_angle < 1e-9, "{seam:?}");
    assert!(seam.max_curvature_jump < 1e-6, "{seam:?}");
    assert!(edge_gap(&r) < 1e-12, "{}", edge_gap(&r));
    assert!(r.deviation.max <= tol, "{}", r.deviation.max);

    let open = reconstruct_surface(secs, &options(tol, true)).unwrap();
    println!(
        "open: net {:?}, edge gap {:.3e}",
        open.surface.net_size(),
        edge_gap(&open)
    );
    assert!(open.closed_by_gap.iter().all(Option::is_none));
    assert!(open.sections.iter().all(|s| !s.closed) && open.seam.is_none());
    assert!(!open.compatible.periodic);
    // the open surface's u ends are near the rings' end points, about a step apart
    assert!(edge_gap(&open) > 0.5 * steps[0], "{}", edge_gap(&open));
}

/// Rings with ten steps missing (a 0.2-wide opening, within 0.25 but ten spacings wide) and rings
/// one step short at a tolerance below the step stay open.
#[test]
fn openings_wider_than_the_tolerance_or_the_spacing_stay_open() {
    let secs: Vec<Section> = (0..4).map(|k| ring(k, 301, 10)).collect();
    let r = reconstruct_surface(secs, &options(0.25, false)).unwrap();
    assert!(r.closed_by_gap.iter().all(Option::is_none));
    assert!(r.sections.iter().all(|s| !s.closed));

    let secs: Vec<Section> = (0..4).map(|k| ring(k, 301, 1)).collect();
    let step = secs[0].points[0].distance(secs[0].points[299]);
    let r = reconstruct_surface(secs, &options(0.5 * step, false)).unwrap();
    assert!(r.closed_by_gap.iter().all(Option::is_none));
    assert!(r.sections.iter().all(|s| !s.closed));
}
