//! An independent deviation bound shared by test crates: the largest distance from points to the
//! nearest of dense curve samples (no projection code involved; an upper bound that converges to the
//! orthogonal distance as the sampling gets denser).
//!
//! Included by path (`#[path = "common/sampled.rs"] mod sampled;`), like `polyline.rs`.
#![allow(dead_code)] // each test crate uses one of the two

use fairfit::{NurbsCurve, Vec3};

/// The largest distance from a point of `points` to the nearest of 40 001 curve points equally
/// spaced over the domain.
pub fn brute_force_deviation(curve: &NurbsCurve, points: &[Vec3]) -> f64 {
    brute_force_deviation_n(curve, points, 40_000)
}

/// [`brute_force_deviation`] with `n + 1` samples: the nearest sample overestimates a distance `d` by
/// about `(h/2)² / (2d)` for a sample spacing `h`.
pub fn brute_force_deviation_n(curve: &NurbsCurve, points: &[Vec3], n: usize) -> f64 {
    let (a, b) = curve.domain();
    let samples: Vec<Vec3> = (0..=n)
        .map(|i| curve.point(a + (b - a) * i as f64 / n as f64))
        .collect();
    points
        .iter()
        .map(|q| {
            samples
                .iter()
                .map(|s| (*s - *q).norm())
                .fold(f64::MAX, f64::min)
        })
        .fold(0.0, f64::max)
}
