//! Slicing dense point clouds (`src/surface/slicing.rs`, with its slab thinning): with the fit's
//! tolerance, each slab's points become tolerance-sized clusters, so a noisy cloud's sections are
//! closed, lie within half the tolerance of the true cross-section, and have a size set by the shape
//! and the tolerance, not by the point count; thin parts (a sharp trailing edge) are not merged
//! across beyond that.

use crate::common::xorshift::Xorshift;
use fairfit::nurbs::Vec3;
use fairfit::surface::slicing::{slice_mesh, SliceOptions, Slices, CLUSTER_TOLERANCES};
use fairfit::surface::Mesh;
use fairfit::Tolerance;
use std::f64::consts::TAU;

const TOL: f64 = 1e-2;

/// `n` points of the cylinder of radius 1 around the z axis, z in [0, 2], with radial noise
/// `sigma`, in random order.
fn noisy_cylinder(n: usize, sigma: f64, seed: u64) -> Mesh {
    let mut rng = Xorshift(seed);
    let vertices = (0..n)
        .map(|_| {
            let (t, z) = (TAU * rng.uniform(), 2.0 * rng.uniform());
            let r = 1.0 + sigma * rng.normal();
            Vec3::new(r * t.cos(), r * t.sin(), z)
        })
        .collect();
    Mesh {
        vertices,
        triangles: vec![],
    }
}

fn slice(cloud: &Mesh, slices: usize, tolerance: Option<Tolerance>) -> Slices {
    slice_mesh(
        cloud,
        &SliceOptions {
            slices,
            tolerance,
            ..Default::default()
        },
    )
    .unwrap()
}

#[test]
fn a_dense_noisy_cylinder_gives_closed_sections_within_half_the_tolerance_whatever_its_density() {
    let sizes = |n: usize| -> Vec<usize> {
        let cloud = noisy_cylinder(n, TOL / 10.0, 0x2545_f491_4f6c_dd1d);
        let s = slice(&cloud, 4, Some(Tolerance::Absolute(TOL)));
        assert_eq!(s.sections.len(), 4);
        assert!(s.gaps.is_empty(), "{n} points: {:?}", s.gaps);
        for sec in &s.sections {
            assert!(sec.closed);
            for p in &sec.points {
                let rho = (p.x() * p.x() + p.y() * p.y()).sqrt();
                assert!((rho - 1.0).abs() <= TOL / 2.0, "{n} points: radius {rho}");
            }
        }
        s.sections.iter().map(|s| s.points.len()).collect()
    };
    // a slab holds 5 % of the cloud: about 5,000 and 20,000 points
    let (few, many) = (sizes(100_000), sizes(400_000));
    // cluster seeds are more than r apart along a band narrower than r: at most 2π / r of them
    let r = CLUSTER_TOLERANCES * TOL;
    let bound = (TAU / r).ceil() as usize + 1;
    for (&a, &b) in few.iter().zip(&many) {
        assert!(a <= bound && b <= bound, "{a}, {b} > {bound}");
        // four times the points, about the same section: within 15 %
        assert!(
            (a as f64 - b as f64).abs() <= 0.15 * a as f64,
            "{few:?} vs {many:?}"
        );
        assert!(a >= bound / 3, "{a}");
    }
    // without a tolerance every slab point is a section point (the former behaviour)
    let cloud = noisy_cylinder(100_000, TOL / 10.0, 0x2545_f491_4f6c_dd1d);
    let all = slice(&cloud, 4, None);
    let points: usize = all.sections.iter().map(|s| s.points.len()).sum();
    assert!(points > 4 * 4_500, "{points}");
}

#[test]
fn a_relative_tolerance_is_a_fraction_of_the_largest_slab() {
    let cloud = noisy_cylinder(100_000, TOL / 10.0, 7);
    // the slabs are 2 across: 5e-3 of that is the absolute 1e-2
    let rel = slice(&cloud, 4, Some(Tolerance::Relative(5e-3)));
    let abs = slice(&cloud, 4, Some(Tolerance::Absolute(TOL)));
    let counts = |s: &Slices| {
        s.sections
            .iter()
            .map(|s| s.points.len())
            .collect::<Vec<_>>()
    };
    let (a, b) = (counts(&rel), counts(&abs));
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (*x as f64 - *y as f64).abs() <= 0.02 * *y as f64,
            "{a:?} vs {b:?}"
        );
    }
    let bad = slice_mesh(
        &cloud,
        &SliceOptions {
            slices: 4,
            tolerance: Some(Tolerance::Absolute(-1.0)),
            ..Default::default()
        },
    );
    assert!(bad.is_err());
}

/// The thin symmetric "blade" section: y = ±h(x), h(x) = 0.06 (1 − x²) (sharp edges at x = ±1),
/// as a point at arc fraction `s` in [0, 1) (upper side from x = 1 to −1, lower side back).
fn blade(s: f64) -> (Vec3, Vec3) {
    let (x, side) = if s < 0.5 {
        (1.0 - 4.0 * s, 1.0)
    } else {
        (-1.0 + 4.0 * (s - 0.5), -1.0)
    };
    // a parameter even in x is near enough even in arc length for this test (slope at most 0.12)
    let y = side * 0.06 * (1.0 - x * x);
    let slope = side * -0.12 * x;
    let normal = Vec3::new(-slope, 1.0, 0.0) * side;
    (Vec3::new(x, y, 0.0), normal / normal.norm())
}

/// Distance from `p` (in the plane z = const) to the blade section.
fn distance_to_blade(p: Vec3) -> f64 {
    let (x, y) = (p.x(), p.y());
    let side = if y >= 0.0 { 1.0 } else { -1.0 };
    // the nearest point on one side: a fine search over x (the curve is nearly flat)
    (0..=4000)
        .map(|i| -1.0 + 2.0 * i as f64 / 4000.0)
        .map(|u| {
            let q = side * 0.06 * (1.0 - u * u);
            ((x - u).powi(2) + (y - q).powi(2)).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_thin_blade_cloud_is_sliced_closed_and_not_merged_across_its_edge() {
    let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
    let vertices: Vec<Vec3> = (0..200_000)
        .map(|_| {
            let (p, normal) = blade(rng.uniform());
            let z = 2.0 * rng.uniform();
            p + normal * (TOL / 10.0 * rng.normal()) + Vec3::new(0.0, 0.0, z)
        })
        .collect();
    let cloud = Mesh {
        vertices,
        triangles: vec![],
    };
    let s = slice(&cloud, 4, Some(Tolerance::Absolute(TOL)));
    assert_eq!(s.sections.len(), 4);
    assert!(s.gaps.is_empty(), "{:?}", s.gaps);
    let r = CLUSTER_TOLERANCES * TOL;
    for sec in &s.sections {
        assert!(sec.closed);
        for p in &sec.points {
            let d = distance_to_blade(*p);
            assert!(d <= TOL / 2.0, "{p:?}: {d}");
        }
        // both sides kept: where the blade is thicker than 2r, each station has points on both
        for x in [-0.9, -0.5, 0.0, 0.5, 0.9] {
            for side in [1.0, -1.0] {
                let y = side * 0.06 * (1.0 - x * x);
                assert!(
                    sec.points
                        .iter()
                        .any(|p| (p.x() - x).abs() < 4.0 * r && (p.y() - y).abs() < TOL / 2.0),
                    "no point near ({x}, {y})"
                );
            }
        }
        // the tour never crosses the blade except at its edges: consecutive points on opposite
        // sides only where the blade is thinner than 2r + the noise band
        for w in sec.points.windows(2) {
            if w[0].y() * w[1].y() < 0.0 {
                let x = 0.5 * (w[0].x() + w[1].x());
                let h = 0.06 * (1.0 - x * x);
                assert!(2.0 * h <= 2.0 * r + TOL / 2.0, "a crossing at x = {x}");
            }
        }
    }
}

/// A sparse cloud of the same cylinder (4,000 points: a slab holds about 200, thinned to about 100
/// on a ring 628 tolerances long): its random holes make 20 gaps of several spacings over the 8
/// sections, up to 44 tolerances long. None stands out (`surface::chain::OPENING_RATIO`), so every gap is
/// bridged and every section stays closed; opened at its largest hole, each section would start at
/// a random place round the ring (the surface twisted between sections).
#[test]
fn a_sparse_cloud_with_random_holes_keeps_its_sections_closed() {
    let cloud = noisy_cylinder(4_000, TOL / 10.0, 0x2545_f491_4f6c_dd1d);
    let s = slice(&cloud, 8, Some(Tolerance::Absolute(TOL)));
    eprintln!(
        "gaps {} (longest {:.3e}), section points {:?}",
        s.gaps.len(),
        s.gaps.iter().map(|g| g.length).fold(0.0, f64::max),
        s.sections
            .iter()
            .map(|s| s.points.len())
            .collect::<Vec<_>>()
    );
    assert_eq!(s.sections.len(), 8);
    assert!(s.gaps.len() >= 8, "{:?}", s.gaps);
    assert!(s.gaps.iter().all(|g| g.handling == "bridged"));
    assert!(s.sections.iter().all(|sec| sec.closed));
}
