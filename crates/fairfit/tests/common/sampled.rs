//! An independent deviation bound shared by test files: the largest distance from points to the
//! nearest of dense curve samples (no projection code involved; an upper bound that converges to the
//! orthogonal distance as the sampling gets denser).
#![allow(dead_code)] // each test file uses some of them

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

/// The largest distance from the points to the curve: the nearest of 200 001 curve samples equally
/// spaced over the domain, refined by a golden-section search between its neighbours (an upper
/// bound of the orthogonal distance, tighter than [`brute_force_deviation`] where a curve uses the
/// whole band).
pub fn refined_deviation(curve: &NurbsCurve, points: &[Vec3]) -> f64 {
    let n = 200_000;
    let (lo, hi) = curve.domain();
    let us: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * (i as f64 / n as f64))
        .collect();
    let samples: Vec<Vec3> = us.iter().map(|&u| curve.point(u)).collect();
    let mut worst = 0.0f64;
    for q in points {
        let (mut best, mut bi) = (f64::INFINITY, 0);
        for (i, s) in samples.iter().enumerate() {
            let d = (*s - *q).norm_squared();
            if d < best {
                (best, bi) = (d, i);
            }
        }
        let (mut a, mut b) = (us[bi.saturating_sub(1)], us[(bi + 1).min(n)]);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if (curve.point(c) - *q).norm() < (curve.point(d) - *q).norm() {
                b = d;
            } else {
                a = c;
            }
        }
        let refined = (curve.point(0.5 * (a + b)) - *q).norm();
        worst = worst.max(refined.min(best.sqrt()));
    }
    worst
}
