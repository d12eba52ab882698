//! `fit::screening`: the noise warning when the tolerance is below the noise, and only then.

use crate::common::example_data::read_csv;
use crate::common::rng;
use crate::common::scan_data::{extent, gauss, noisy_spiral};
use fairfit::fit::screening::{meaningful_tolerance, screen, OutlierMode};
use fairfit::nurbs::Vec3;

#[test]
fn noise_warning_only_when_the_tolerance_is_below_the_noise() {
    let n = 20_000;
    let tol = 1e-3 * extent(&noisy_spiral(n, 0.0, 1));
    for (rel, warned) in [(1.0 / 3.0, true), (0.1, false), (0.01, false)] {
        let (s, kept) = screen(&noisy_spiral(n, rel * tol, 4), tol, OutlierMode::Auto);
        assert_eq!(s.noise_limited.is_some(), warned, "σ = tol · {rel}");
        assert!(kept.is_none() && s.outliers.is_empty(), "σ = tol · {rel}");
        if let Some(t) = s.noise_limited {
            assert_eq!(t, meaningful_tolerance(s.noise_sigma, n));
            let line = s.noise_warning(tol).unwrap();
            assert!(!line.contains('\n') && line.contains("below the noise"));
        }
    }
}

/// The clean, sparse fx77w343 table measures a σ of shape (about 0.4 tol, unresolved): no warning at
/// `--rel-tol 1e-3`. The same airfoil densified to 30 points per interval (uniform Catmull–Rom
/// through the table) with Gaussian noise of tol / 3 still warns, and measures that σ.
#[test]
fn sparse_clean_table_gets_no_warning_but_its_noisy_dense_version_does() {
    let pts = read_csv("fx77w343.csv");
    let tol = 1e-3 * extent(&pts);
    let (s, _) = screen(&pts, tol, OutlierMode::Off);
    assert!(!s.noise_resolved && s.noise_limited.is_none(), "{s:?}");
    assert!(s.noise_warning(tol).is_none());

    let sigma = tol / 3.0;
    let mut g = rng(9);
    let per = 30;
    let mut dense = Vec::new();
    for i in 0..pts.len() - 1 {
        let p = |k: isize| pts[(i as isize + k).clamp(0, pts.len() as isize - 1) as usize];
        let (p0, p1, p2, p3) = (p(-1), p(0), p(1), p(2));
        for j in 0..per {
            let t = j as f64 / per as f64;
            let (t2, t3) = (t * t, t * t * t);
            let c = (p1 * 2.0
                + (p2 - p0) * t
                + (p0 * 2.0 - p1 * 5.0 + p2 * 4.0 - p3) * t2
                + (p1 * 3.0 - p0 - p2 * 3.0 + p3) * t3)
                * 0.5;
            let noise = Vec3::new(gauss(&mut g), gauss(&mut g), 0.0) * sigma;
            dense.push(c + noise);
        }
    }
    let (s, _) = screen(&dense, tol, OutlierMode::Off);
    assert!(s.noise_resolved && s.noise_limited.is_some(), "{s:?}");
    assert!(
        (s.noise_sigma / sigma - 1.0).abs() < 0.25,
        "σ = {}",
        s.noise_sigma / sigma
    );
}
