//! Dense sections (`src/surface/dense.rs`): noisy sections of thousands of points fit within the
//! tolerance at every point with the control points of the clean sparse sections, the noise is
//! measured, spikes are excluded by index, and a sliced cloud gives the same bytes on 1 and 2 threads.

use crate::common::xorshift::Xorshift;
use fairfit::io::surface_to_json;
use fairfit::nurbs::Vec3;
use fairfit::surface::slicing::{slice_mesh, SliceOptions};
use fairfit::surface::{reconstruct_surface, Mesh, Section, SurfaceOptions, SurfaceReconstruction};

/// The true section at height `z`: a closed three-lobed curve of size ~2.
fn truth(t: f64, z: f64) -> Vec3 {
    let r =
        (1.0 + 0.08 * (1.5 * z).sin()) * (1.0 + 0.06 * (3.0 * t).cos() + 0.03 * (2.0 * t).sin());
    Vec3::new(r * t.cos(), 0.7 * r * t.sin(), z)
}

/// `k` closed sections of `n` points each (the last repeats the first), with in-plane normal noise
/// `sigma`.
fn sections(k: usize, n: usize, sigma: f64) -> Vec<Section> {
    let mut noise = Xorshift(0x9e37_79b9_7f4a_7c15);
    (0..k)
        .map(|j| {
            let z = 2.0 * j as f64 / (k - 1) as f64;
            let mut pts: Vec<Vec3> = (0..n)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as f64 / n as f64;
                    let (p, h) = (truth(t, z), 1e-6);
                    let d = truth(t + h, z) - truth(t - h, z);
                    let normal = Vec3::new(d.y(), -d.x(), 0.0) / d.norm();
                    p + normal * (sigma * noise.normal())
                })
                .collect();
            pts.push(pts[0]);
            Section::from_points(pts)
        })
        .collect()
}

fn options(tol: f64) -> SurfaceOptions {
    let mut o = SurfaceOptions::default();
    o.sections.tolerance = tol;
    o.sections.max_control_points = 120;
    o.iso_curves = 5;
    o
}

/// Largest distance of the surface's section iso-curves (2,000 points each, at the sections' `v`)
/// from the noise-free section curves (a 4,000-segment polyline of each, point-to-segment distance).
fn distance_to_truth(r: &SurfaceReconstruction, k: usize) -> f64 {
    let (u0, u1) = r.surface.domain_u();
    let mut worst = 0.0f64;
    for (j, &v) in r.v_params.iter().enumerate().take(k) {
        let z = 2.0 * j as f64 / (k - 1) as f64;
        let poly: Vec<Vec3> = (0..=4000)
            .map(|i| truth(std::f64::consts::TAU * i as f64 / 4000.0, z))
            .collect();
        for i in 0..2000 {
            let q = r.surface.point(u0 + (u1 - u0) * i as f64 / 1999.0, v);
            let d = poly
                .windows(2)
                .map(|w| {
                    let (a, e) = (w[0], w[1] - w[0]);
                    let t = ((q - a).dot(e) / e.dot(e)).clamp(0.0, 1.0);
                    (a + e * t - q).norm()
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

#[test]
fn dense_noisy_sections_fit_within_tol_at_every_point_with_the_sparse_count() {
    let (k, tol) = (6, 2e-3);
    let sigma = tol / 10.0;
    // the clean sparse sections (150 points, spacing ~ 5 tol) take the plain pipeline
    let sparse = reconstruct_surface(sections(k, 150, 0.0), &options(tol)).unwrap();
    assert!(sparse.dense.is_none());
    let dense = reconstruct_surface(sections(k, 20_000, sigma), &options(tol)).unwrap();
    let d = dense
        .dense
        .as_ref()
        .expect("20,000-point sections are dense");
    // every one of the 6 x 20,001 points is measured and within the tolerance
    assert_eq!(dense.deviation.points, k * 20_001);
    assert!(
        dense.deviation.max <= tol,
        "{} > {tol}",
        dense.deviation.max
    );
    assert!(dense.section_deviation.iter().all(|&x| x <= tol));
    // the representatives are ~ perimeter / (4 tol) ~ 690 per section, not 20,000
    for s in &d.sections {
        assert!(s.representatives < 1_500, "{}", s.representatives);
        assert!(s.outliers.is_empty(), "{:?}", s.outliers);
        // the measured noise is within 25 % of the true sigma
        assert!(
            (s.noise_sigma / sigma - 1.0).abs() < 0.25,
            "{} vs {sigma}",
            s.noise_sigma
        );
    }
    // few control points: at most 3 more per section than the clean sparse sections need (18 vs 15
    // measured: the representatives are fitted within tol less their spread, 3-4 sigma)
    let (nu_dense, nu_sparse) = (dense.surface.net_size().0, sparse.surface.net_size().0);
    assert!(nu_dense <= nu_sparse + 3, "{nu_dense} vs {nu_sparse}");
    // the fit averages the noise: within the tolerance of the noise-free sections
    let t = distance_to_truth(&dense, k);
    println!("dense sections: distance to the noise-free sections {t:.3e} (tol {tol:e})");
    assert!(t <= tol, "{t} > {tol}");
}

#[test]
fn spikes_of_dense_sections_are_excluded_by_index() {
    let (k, tol) = (4, 2e-3);
    let mut secs = sections(k, 10_000, tol / 20.0);
    // 3 spikes of 20 tol on section 1, outward along the normal (radially, roughly)
    let spikes = [1_234, 5_000, 8_765];
    for &i in &spikes {
        let p = secs[1].points[i];
        let radial = Vec3::new(p.x(), p.y(), 0.0);
        secs[1].points[i] = p + radial / radial.norm() * (20.0 * tol);
    }
    let r = reconstruct_surface(secs, &options(tol)).unwrap();
    let d = r.dense.as_ref().unwrap();
    let found: Vec<usize> = d.sections[1].outliers.iter().map(|o| o.index).collect();
    // the alignment keeps closed sections' order when the seam stays (checked: no shift, no reversal)
    assert_eq!(r.alignment[1], (false, 0));
    assert_eq!(found, spikes);
    assert!(d
        .sections
        .iter()
        .enumerate()
        .all(|(j, s)| j == 1 || s.outliers.is_empty()));
    assert_eq!(r.sections[1].points.len(), 10_001 - 3);
    assert!(r.deviation.max <= tol, "{}", r.deviation.max);
}

#[test]
fn a_sliced_dense_cloud_gives_the_same_surface_on_1_and_2_threads() {
    // 200,000 points of a prism on the section at z = 0, between z = 0 and 2, sliced into 8 planes
    // (slab 0.1 of the spacing: ~5,000 points per section, exactly on the section curve)
    let mut noise = Xorshift(7);
    let vertices: Vec<Vec3> = (0..200_000)
        .map(|_| {
            let (t, z) = (
                std::f64::consts::TAU * noise.uniform(),
                2.0 * noise.uniform(),
            );
            let p = truth(t, 0.0);
            Vec3::new(p.x(), p.y(), z)
        })
        .collect();
    let slices = slice_mesh(
        &Mesh {
            vertices,
            triangles: vec![],
        },
        &SliceOptions {
            slices: 8,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(slices.sections.len(), 8);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| reconstruct_surface(slices.sections.clone(), &options(2e-3)).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert!(one.dense.is_some());
    assert_eq!(surface_to_json(&one.surface), surface_to_json(&two.surface));
    assert_eq!(one.deviation, two.deviation);
    assert_eq!(one.dense, two.dense);
    assert!(one.deviation.max <= 2e-3, "{}", one.deviation.max);
}
