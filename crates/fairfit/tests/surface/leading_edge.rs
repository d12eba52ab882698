//! Airfoil sections split at their leading edges (`src/surface/leading_edge.rs`,
//! `CompatibleOptions::split_at_le`): every section's leading edge is pinned to u = 0.5, each section
//! curve passes through it there, and the surface's iso-curve u = 0.5 runs through all of them. The
//! leading edges here are found by the tests themselves (a brute-force farthest point on the
//! constructed airfoil, near its nose at chord position 0; an ellipse's vertex opposite its seam).

use super::corners::{blunt_airfoil, naca};
use fairfit::nurbs::Vec3;
use fairfit::surface::{
    reconstruct_surface, CompatibleOptions, Section, SurfaceOptions, SurfaceReconstruction,
};
use fairfit::Error;

const TOL: f64 = 1e-4;

/// Section `k` of a twisted, tapering loft of open NACA sections (sharp, slightly open trailing
/// edge): upper trailing edge round the nose to the lower one, `n + 1` cosine-spaced points per side.
/// Returns the section, its leading edge and its chord.
fn open_airfoil(k: usize, n: usize) -> (Section, Vec3, f64) {
    let (m, p, t) = [(0.04, 0.4, 0.12), (0.02, 0.3, 0.15), (0.0, 0.4, 0.18)][k];
    let (chord, twist, z) = (
        1.0 - 0.15 * k as f64,
        (8.0 * k as f64).to_radians(),
        0.7 * k as f64,
    );
    let x = |i: usize, up: bool| {
        let c = (std::f64::consts::PI * i as f64 / n as f64).cos();
        0.5 * if up { 1.0 + c } else { 1.0 - c }
    };
    let mut pts: Vec<Vec3> = (0..=n).map(|i| naca(m, p, t, x(i, true)).0).collect();
    pts.extend((1..=n).map(|i| naca(m, p, t, x(i, false)).1));
    let (c, s) = (twist.cos(), twist.sin());
    let place = |q: Vec3| {
        let (x, y) = ((q.x() - 0.25) * chord, q.y() * chord);
        Vec3::new(c * x - s * y, s * x + c * y, z)
    };
    let pts: Vec<Vec3> = pts.into_iter().map(place).collect();
    // the leading edge: the point farthest from the trailing edge (the midpoint of the two ends),
    // within 5e-3 chord of the nose at chord position 0 (cambered sections turn it slightly)
    let te = (pts[0] + pts[2 * n]) * 0.5;
    let le = pts
        .iter()
        .copied()
        .max_by(|a, b| a.distance(te).total_cmp(&b.distance(te)))
        .unwrap();
    assert!(le.distance(place(naca(m, p, t, 0.0).0)) < 5e-3 * chord);
    (Section::from_points(pts), le, chord)
}

fn options(split: bool) -> SurfaceOptions {
    SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: TOL,
            split_at_le: split,
            ..Default::default()
        },
        iso_curves: 5,
        ..Default::default()
    }
}

/// Each section's leading edge `noses[k]` (within 1e-12 of one of its points) keeps the parameter
/// 0.5, its curve passes through it at 0.5 within 1e-9 of the section's size, and so does the
/// surface's iso-curve u = 0.5 at the section's v; the report's distances say the same.
fn check_pinned(r: &SurfaceReconstruction, noses: &[Vec3], size: f64) {
    let le = r.compatible.leading_edges.as_ref().expect("split_at_le");
    assert_eq!(le.parameter, 0.5);
    assert_eq!(le.sections.len(), noses.len());
    for (k, ((row, fit), nose)) in le
        .sections
        .iter()
        .zip(&r.compatible.fits)
        .zip(noses)
        .enumerate()
    {
        assert_eq!(row.index, k);
        assert!(
            row.point.distance(*nose) < 1e-12,
            "section {k}: {:?} vs {nose:?}",
            row.point
        );
        assert_eq!(fit.params[row.point_index], 0.5, "section {k}");
        let on_curve = fit.curve.point(0.5).distance(*nose);
        let on_surface = r.surface.point(0.5, r.v_params[k]).distance(*nose);
        println!("section {k}: leading edge off the curve {on_curve:.2e}, off the surface {on_surface:.2e}");
        assert!(on_curve <= 1e-9 * size, "section {k}: {on_curve:e}");
        assert!(on_surface <= 1e-9 * size, "section {k}: {on_surface:e}");
        assert!(row.distance <= 1e-9 * size && row.surface_distance.unwrap() <= 1e-9 * size);
    }
    assert!(le.max_distance <= 1e-9 * size);
    assert!(le.surface_max_distance.unwrap() <= 1e-9 * size);
}

/// Three open NACA sections (4412, 2315, 0018; chord 1 to 0.7, twisted by 16°), 201 points each,
/// tolerance 1e-4 of the chord: clamped knots, every leading edge pinned, the tolerance met.
#[test]
fn open_airfoils_pin_their_noses_at_the_half() {
    let (secs, noses, _): (Vec<Section>, Vec<Vec3>, Vec<f64>) =
        itertools_unzip3((0..3).map(|k| open_airfoil(k, 100)));
    let r = reconstruct_surface(secs.clone(), &options(true)).unwrap();
    let free = reconstruct_surface(secs, &options(false)).unwrap();
    println!(
        "split: net {:?}, max deviation {:.4e} ({:.3} tol); free: net {:?}, {:.4e}",
        r.surface.net_size(),
        r.deviation.max,
        r.deviation.max / TOL,
        free.surface.net_size(),
        free.deviation.max
    );
    assert!(!r.compatible.periodic);
    assert!(r.deviation.max <= TOL && r.compatible.within_tolerance);
    check_pinned(&r, &noses, 1.0);
    // without the option the report has no leading edges
    assert!(free.compatible.leading_edges.is_none());
}

/// Closed smooth sections (ellipses, seam at the +x vertex) are fitted periodically: the leading
/// edge (the −x vertex, farthest from the seam) is pinned in the periodic solver too.
#[test]
fn periodic_sections_pin_the_point_opposite_the_seam() {
    let secs: Vec<Section> = (0..3)
        .map(|k| {
            let a = 1.0 + 0.3 * k as f64;
            Section::from_points(
                (0..=80)
                    .map(|i| {
                        let t = std::f64::consts::TAU * i as f64 / 80.0;
                        Vec3::new(a * t.cos(), 0.3 * t.sin(), k as f64)
                    })
                    .collect(),
            )
        })
        .collect();
    let noses: Vec<Vec3> = (0..3)
        .map(|k| Vec3::new(-(1.0 + 0.3 * k as f64), 0.0, k as f64))
        .collect();
    let r = reconstruct_surface(secs, &options(true)).unwrap();
    assert!(r.compatible.periodic);
    assert!(r.deviation.max <= TOL, "{}", r.deviation.max);
    check_pinned(&r, &noses, 2.6);
}

/// A round closed root (smooth seam, tied on the clamped knots the open sections need) lofted with
/// two open airfoils: the tied solver pins its leading edge too.
#[test]
fn tied_root_and_open_airfoils_pin_every_leading_edge() {
    let root = Section::from_points(
        (0..=80)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 80.0;
                Vec3::new(0.4 * t.cos() + 0.35, 0.3 * t.sin(), -0.7)
            })
            .collect(),
    );
    let mut secs = vec![root];
    let mut noses = vec![Vec3::new(-0.05, 0.0, -0.7)];
    for k in 0..2 {
        let (s, nose, _) = open_airfoil(k, 100);
        secs.push(s);
        noses.push(nose);
    }
    let r = reconstruct_surface(secs, &options(true)).unwrap();
    assert!(!r.compatible.periodic);
    assert!(r.deviation.max <= TOL, "{}", r.deviation.max);
    // the root's seam is tied (smooth), not a C0 crease
    let seam = r.seam.expect("a closed section");
    println!(
        "root seam: tangent angle {:.2e} rad",
        seam.max_tangent_angle
    );
    assert!(seam.max_tangent_angle < 1e-6, "{seam:?}");
    check_pinned(&r, &noses, 1.0);
}

/// Blunt-trailing-edge sections closed by a trailing-edge segment: the inner trailing-edge corner
/// stays a held C0 knot line, the leading edge (farthest from the seam corner) is pinned beside it.
#[test]
fn held_corners_and_the_pinned_leading_edge_combine() {
    let secs: Vec<Section> = (0..4).map(|k| blunt_airfoil(k, 6).0).collect();
    let r = reconstruct_surface(secs, &options(true)).unwrap();
    let c = &r.compatible.corners;
    println!(
        "blunt, split: net {:?}, max deviation {:.4e} ({:.3} tol), corners {:?}",
        r.surface.net_size(),
        r.deviation.max,
        r.deviation.max / TOL,
        c.params
    );
    assert!(c.held && c.params.len() == 1 && c.params[0] > 0.5, "{c:?}");
    assert!(r.deviation.max <= TOL, "{}", r.deviation.max);
    let le = r.compatible.leading_edges.as_ref().unwrap();
    let noses: Vec<Vec3> = le.sections.iter().map(|s| s.point).collect();
    // the point pinned is the one farthest from the seam point (the closed section's trailing edge)
    for (s, nose) in r.sections.iter().zip(&noses) {
        let far = s
            .points
            .iter()
            .map(|q| q.distance(s.points[0]))
            .fold(0.0, f64::max);
        assert_eq!(nose.distance(s.points[0]), far);
    }
    check_pinned(&r, &noses, 1.0);
}

/// A section whose farthest point from the midpoint of its ends is an end point (a parabola arc) has
/// no leading edge: a one-line `InvalidData` naming it; so is a leading edge that is a held corner.
/// Given section parameters conflict.
#[test]
fn sections_without_a_leading_edge_are_refused() {
    let (a, _, _) = open_airfoil(0, 40);
    let arc = Section::from_points(
        (0..=40)
            .map(|i| {
                let x = i as f64 / 40.0;
                Vec3::new(x, x * x, 1.0)
            })
            .collect(),
    );
    let e = reconstruct_surface(vec![a.clone(), arc], &options(true)).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, Error::InvalidData(_)), "{e:?}");
    assert!(msg.contains("section 1") && !msg.contains('\n'), "{msg}");
    // D-shaped sections (a half-ellipse closed by its chord): the point farthest from the seam
    // corner is the other, held, corner
    let d: Vec<Section> = (0..3)
        .map(|k| {
            let (a, z) = (2.0 + 0.3 * k as f64, k as f64);
            let mut pts: Vec<Vec3> = (0..=60)
                .map(|i| {
                    let t = std::f64::consts::PI * i as f64 / 60.0;
                    Vec3::new(a * t.cos(), t.sin(), z)
                })
                .collect();
            pts.extend((1..=20).map(|i| Vec3::new(-a + 2.0 * a * i as f64 / 20.0, 0.0, z)));
            Section::from_points(pts)
        })
        .collect();
    let e = reconstruct_surface(d, &options(true))
        .unwrap_err()
        .to_string();
    assert!(e.contains("section 0") && e.contains("held corner"), "{e}");
    let mut o = options(true);
    o.sections.section_params = Some(vec![vec![0.0; 81]; 2]);
    let e = reconstruct_surface(vec![a.clone(), a], &o).unwrap_err();
    assert!(matches!(e, Error::InvalidOption(_)), "{e:?}");
}

/// Unzips triples (the sections, their noses and chords).
fn itertools_unzip3<A, B, C>(it: impl Iterator<Item = (A, B, C)>) -> (Vec<A>, Vec<B>, Vec<C>) {
    let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
    for (x, y, z) in it {
        a.push(x);
        b.push(y);
        c.push(z);
    }
    (a, b, c)
}

/// Dense sections (6,001 points each, tolerance 1e-3: fitted through their representatives,
/// `src/surface/dense.rs`): the leading edge pinned is the data point itself, not the centroid of
/// its tolerance-sized arc, and every kept point meets the tolerance.
#[test]
fn dense_sections_pin_the_data_leading_edge() {
    let (secs, noses, _): (Vec<Section>, Vec<Vec3>, Vec<f64>) =
        itertools_unzip3((0..3).map(|k| open_airfoil(k, 3000)));
    let mut o = options(true);
    o.sections.tolerance = 1e-3;
    let r = reconstruct_surface(secs, &o).unwrap();
    assert!(r.dense.is_some());
    println!(
        "dense, split: net {:?}, max deviation {:.4e}",
        r.surface.net_size(),
        r.deviation.max
    );
    assert!(r.deviation.max <= 1e-3, "{}", r.deviation.max);
    check_pinned(&r, &noses, 1.0);
}
