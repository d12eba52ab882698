//! An independent deviation check: the largest distance from points to a dense polyline through a
//! curve (no projection code involved; with `n` samples the chord error of a smooth curve of unit
//! size is far below the tolerances the tests use).

use fairfit::{NurbsCurve, Vec3};

/// Largest distance from `pts` to the polyline through `n + 1` curve points equally spaced in `[0, 1]`.
pub fn polyline_deviation(curve: &NurbsCurve, pts: &[Vec3], n: usize) -> f64 {
    let us: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    let poly = curve.points(&us);
    pts.iter()
        .map(|&p| {
            poly.windows(2)
                .map(|w| {
                    let d = w[1] - w[0];
                    let t = ((p - w[0]).dot(d) / d.norm_squared()).clamp(0.0, 1.0);
                    (w[0] + d * t - p).norm()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}
