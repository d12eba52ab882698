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
