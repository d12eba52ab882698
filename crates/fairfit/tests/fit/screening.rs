//! `fit::screening`: the noise warning when the tolerance is below the noise, and only then.

use crate::common::scan_data::{extent, noisy_spiral};
use fairfit::fit::screening::{screen, OutlierMode, NOISE_TOLERANCE_SIGMAS};

#[test]
fn noise_warning_only_when_the_tolerance_is_below_the_noise() {
    let n = 20_000;
    let tol = 1e-3 * extent(&noisy_spiral(n, 0.0, 1));
    for (rel, warned) in [(1.0 / 3.0, true), (0.1, false), (0.01, false)] {
        let (s, kept) = screen(&noisy_spiral(n, rel * tol, 4), tol, OutlierMode::Auto);
        assert_eq!(s.noise_limited.is_some(), warned, "σ = tol · {rel}");
        assert!(kept.is_none() && s.outliers.is_empty(), "σ = tol · {rel}");
        if let Some(t) = s.noise_limited {
            assert_eq!(t, NOISE_TOLERANCE_SIGMAS * s.noise_sigma);
            let line = s.noise_warning(tol).unwrap();
            assert!(!line.contains('\n') && line.contains("below the noise"));
        }
    }
}
