//! `fit::outliers`: spikes recovered exactly, and no feature of a clean table taken for one.

use crate::common::example_data::read_csv;
use crate::common::rng;
use crate::common::scan_data::{extent, gauss, noisy_corner, noisy_spiral};
use fairfit::fit::noise::estimate_noise;
use fairfit::fit::outliers::find_outliers;
use fairfit::fit::screening::{screen, OutlierMode};
use fairfit::nurbs::Vec3;

/// A noisy spiral of `n` points with a 20-tolerance spike at every 200th point (0.5 %), in a random
/// direction; returns the points, the tolerance and the spike indices.
fn spiky(n: usize, seed: u64) -> (Vec<Vec3>, f64, Vec<usize>) {
    let tol = 1e-3 * extent(&noisy_spiral(n, 0.0, 1));
    let mut pts = noisy_spiral(n, tol / 10.0, seed);
    let mut g = rng(seed + 1);
    let idx: Vec<usize> = (100..n - 50).step_by(200).collect();
    for &i in &idx {
        let d = Vec3::new(gauss(&mut g), gauss(&mut g), 0.0);
        pts[i] += d / d.norm() * (20.0 * tol);
    }
    (pts, tol, idx)
}

#[test]
fn spike_indices_recovered_exactly_and_nothing_else_removed() {
    for n in [10_000, 50_000] {
        let (pts, tol, idx) = spiky(n, 3);
        let (s, kept) = screen(&pts, tol, OutlierMode::Auto);
        let found: Vec<usize> = s.outliers.iter().map(|o| o.index).collect();
        assert_eq!(found, idx, "{n} points");
        assert_eq!(kept.unwrap().len(), n - idx.len());
        // each spike's distance is its offset: 20 tol, less the noise
        assert!(s
            .outliers
            .iter()
            .all(|o| (o.distance / tol - 20.0).abs() < 2.0));
        // the noise is measured without them
        assert!((s.noise_sigma / (tol / 10.0) - 1.0).abs() < 0.25);
        // scaled by 1000: the same decisions
        let big: Vec<Vec3> = pts.iter().map(|&p| p * 1000.0).collect();
        let (sb, _) = screen(&big, 1000.0 * tol, OutlierMode::Auto);
        assert_eq!(sb.outliers.iter().map(|o| o.index).collect::<Vec<_>>(), idx);
    }
}

#[test]
fn features_are_not_spikes() {
    // clean tables: sharp and blunt trailing edges, leading edges, a quarter ellipse
    for name in [
        "naca4412.csv",
        "du84132v.csv",
        "e387.csv",
        "fx77w343.csv",
        "hq17.csv",
        "clarky.csv",
    ] {
        let pts = read_csv(name);
        let tol = 1e-3 * extent(&pts);
        assert_eq!(
            find_outliers(&pts, tol, estimate_noise(&pts)),
            vec![],
            "{name}"
        );
    }
    // a noisy corner, and a short straight piece of three points between two corners
    let c = noisy_corner(5000, 90.0, 2e-4, 2);
    assert!(find_outliers(&c, 2e-3, estimate_noise(&c)).is_empty());
    let mut steps: Vec<Vec3> = (0..=40)
        .map(|i| Vec3::new(i as f64 * 0.025, 0.0, 0.0))
        .collect();
    steps.extend((1..=2).map(|i| Vec3::new(1.0, i as f64 * 0.004, 0.0)));
    steps.extend((0..=40).map(|i| Vec3::new(1.0 + i as f64 * 0.025, 0.008, 0.0)));
    assert!(find_outliers(&steps, 2e-3, estimate_noise(&steps)).is_empty());
}

/// Table `name` densified to `n` points by a centripetal Catmull-Rom spline through its points,
/// evenly in each segment's parameter with counts by chord, started at its middle point (the
/// leading edge): the trailing edge (a sharp wedge, or a thin open gap) is inside the sequence.
/// Gaussian noise of `sigma_tols` tolerances along the normal, and the points `spikes` moved 20
/// tolerances outwards. Returns the points and the tolerance (`1e-3 ×` the clean extent).
fn dense_foil(
    name: &str,
    n: usize,
    sigma_tols: f64,
    spikes: &[usize],
    seed: u64,
) -> (Vec<Vec3>, f64) {
    let mut t = read_csv(name);
    if (t[0] - t[t.len() - 1]).norm() == 0.0 {
        t.pop();
    }
    let m = t.len();
    t.rotate_left(m / 2);
    let at = |i: isize| -> Vec3 {
        if i < 0 {
            t[0] * 2.0 - t[1]
        } else if i as usize >= m {
            t[m - 1] * 2.0 - t[m - 2]
        } else {
            t[i as usize]
        }
    };
    let total: f64 = t.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let mut clean = Vec::with_capacity(n);
    for s in 0..m - 1 {
        let (p0, p1, p2, p3) = (at(s as isize - 1), t[s], t[s + 1], at(s as isize + 2));
        let k = (((n - 1) as f64 * (p2 - p1).norm() / total).round() as usize).max(1);
        let (t0, t1) = (0.0, (p1 - p0).norm().sqrt());
        let t2 = t1 + (p2 - p1).norm().sqrt();
        let t3 = t2 + (p3 - p2).norm().sqrt();
        let lerp = |a: Vec3, b: Vec3, ta: f64, tb: f64, u: f64| {
            a * ((tb - u) / (tb - ta)) + b * ((u - ta) / (tb - ta))
        };
        for j in 0..k {
            let u = t1 + (t2 - t1) * j as f64 / k as f64;
            let a1 = lerp(p0, p1, t0, t1, u);
            let a2 = lerp(p1, p2, t1, t2, u);
            let a3 = lerp(p2, p3, t2, t3, u);
            let b1 = lerp(a1, a2, t0, t2, u);
            let b2 = lerp(a2, a3, t1, t3, u);
            clean.push(lerp(b1, b2, t1, t2, u));
        }
    }
    clean.push(t[m - 1]);
    let tol = 1e-3 * extent(&clean);
    let mut g = rng(seed);
    let nc = clean.len();
    let pts = (0..nc)
        .map(|i| {
            let d = clean[(i + 1).min(nc - 1)] - clean[i.saturating_sub(1)];
            // counter-clockwise tables: the outward normal is the tangent turned clockwise
            let out = Vec3::new(d[1], -d[0], 0.0) / d.norm();
            let spike = if spikes.contains(&i) { 20.0 * tol } else { 0.0 };
            clean[i] + out * (sigma_tols * tol * gauss(&mut g) + spike)
        })
        .collect();
    (pts, tol)
}

#[test]
fn thin_trailing_edges_of_dense_airfoils_are_kept_and_their_spikes_found_exactly() {
    // naca4412: an open trailing edge 2.5 tolerances thick; e387: a sharp closed one
    for name in ["naca4412.csv", "e387.csv"] {
        for n in [10_000, 100_000] {
            for (k, noise) in [0.0, 0.01, 0.1].into_iter().enumerate() {
                let (pts, tol) = dense_foil(name, n, noise, &[], 11 + k as u64);
                let (s, kept) = screen(&pts, tol, OutlierMode::Auto);
                assert_eq!(s.outliers, vec![], "{name}, {n} points, noise {noise} tol");
                assert!(kept.is_none());
                let idx: Vec<usize> = (100..pts.len() - 50).step_by(200).collect();
                let (pts, tol) = dense_foil(name, n, noise, &idx, 11 + k as u64);
                let (s, kept) = screen(&pts, tol, OutlierMode::Auto);
                let found: Vec<usize> = s.outliers.iter().map(|o| o.index).collect();
                assert_eq!(found, idx, "{name}, {n} points, noise {noise} tol, spiked");
                assert_eq!(kept.unwrap().len(), pts.len() - idx.len());
            }
        }
    }
}

#[test]
fn dense_corners_and_short_straight_pieces_are_not_spikes() {
    // 90°, 45° and 30° corners (each with a point on it) at 10^4 and 10^5 points, noise tol/10
    for turns in [&[90.0, -45.0][..], &[30.0]] {
        for n in [10_000, 100_000] {
            let (pts, tol, _) =
                crate::fit::corners::arcs(&[1.0, 0.8, 1.0], &[0.6, -0.8, 0.5], turns, n, 0.1, 5);
            let (s, _) = screen(&pts, tol, OutlierMode::Auto);
            assert_eq!(s.outliers, vec![], "{turns:?} at {n} points");
        }
    }
    // a step 3 tolerances high between two 90° corners, sampled every tol/10 with noise tol/10
    let tol = 2e-3;
    let h = tol / 10.0;
    let mut g = rng(17);
    let mut steps: Vec<Vec3> = (0..=5000)
        .map(|i| Vec3::new(i as f64 * h, 0.0, 0.0))
        .collect();
    steps.extend((1..=30).map(|i| Vec3::new(1.0, i as f64 * h, 0.0)));
    steps.extend((1..=5000).map(|i| Vec3::new(1.0 + i as f64 * h, 3.0 * tol, 0.0)));
    for p in &mut steps {
        *p += Vec3::new(gauss(&mut g), gauss(&mut g), 0.0) * (tol / 10.0);
    }
    let (s, _) = screen(&steps, tol, OutlierMode::Auto);
    assert_eq!(s.outliers, vec![]);
}
