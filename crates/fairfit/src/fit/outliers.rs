//! Spikes: isolated points far from the curve their neighbours describe.
//!
//! Each point is compared with the curve of the points on each side of it:
//! - the points (outliers already found excluded) are grouped into bins of `r` consecutive points,
//!   `r = block / 8` from the noise measure (`r = 1` on clean or sparse data), so that a bin's mean
//!   carries `1/√r` of the noise and [`SIDE_BINS`] bins span about one noise block;
//! - on each side, the least-squares line through the means of the [`SIDE_BINS`] nearest bins that
//!   hold no part of the point's own bin is extrapolated to the point, over the stretch where the
//!   point belongs in the sequence (just behind that side's nearest mean to just beyond the other
//!   side's); the point's distance is the smaller of its distances from the two side stretches, so a
//!   spike displaced along the curve, out of its order, is as far off as one displaced across it.
//!
//! A point is a spike when that distance exceeds all of `SPIKE_TOLS · tol`, `SPIKE_SIGMAS · σ` and
//! `SPIKE_SPACINGS ·` half the gap between its two sides. Taking the smallest keeps every feature
//! made of points: a corner lies on the extrapolation of the side it ends, a trailing edge point on
//! both surfaces' extrapolations, a point of a short straight piece on the side holding the rest of
//! the piece. The spacing term keeps sparse data (where a point's neighbours can be further apart
//! than any tolerance) from calling geometry a spike. A run of more than [`MAX_RUN`] consecutive
//! candidates is a feature, not spikes, and the first and last points (one side only) are never spikes.
//!
//! Candidates are found in one pass, then tested again with all candidates excluded from the bins: a
//! spike near another can spoil the first pass's extrapolation, never the second's.
//!
//! Cost: O(n log n) (a binary search per point over the bins).

use super::noise::NoiseEstimate;
use crate::nurbs::Vec3;

/// Bins per side fitted by the quadratic.
pub const SIDE_BINS: usize = 4;
/// A spike lies at least this many tolerances from both sides' curves.
pub const SPIKE_TOLS: f64 = 4.0;
/// ... and this many noise `σ`.
pub const SPIKE_SIGMAS: f64 = 8.0;
/// ... and this many half-gaps between its neighbours.
pub const SPIKE_SPACINGS: f64 = 2.0;
/// Longest run of consecutive points taken as spikes.
pub const MAX_RUN: usize = 3;

/// One excluded point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Outlier {
    /// Its index in the input sequence.
    pub index: usize,
    /// Its distance from the curve of its neighbours (the smaller side distance), in the points' units.
    pub distance: f64,
}

/// The spikes of `points` at tolerance `tol` (the points' units) and noise `noise`, in index order.
///
/// ```
/// use fairfit::fit::noise::estimate_noise;
/// use fairfit::fit::outliers::find_outliers;
/// use fairfit::nurbs::Vec3;
/// let mut pts: Vec<Vec3> = (0..400)
///     .map(|i| {
///         let a = i as f64 / 399.0 * 3.0;
///         Vec3::new(a.cos(), a.sin(), 0.0)
///     })
///     .collect();
/// pts[123] = pts[123] * 1.05; // 50 tolerances off
/// let found = find_outliers(&pts, 1e-3, estimate_noise(&pts));
/// assert_eq!(found.iter().map(|o| o.index).collect::<Vec<_>>(), vec![123]);
/// ```
pub fn find_outliers(points: &[Vec3], tol: f64, noise: NoiseEstimate) -> Vec<Outlier> {
    let n = points.len();
    if n < 2 * SIDE_BINS + 1 {
        return Vec::new();
    }
    let r = (noise.block / 8).max(1);
    let thr = (SPIKE_TOLS * tol).max(SPIKE_SIGMAS * noise.sigma);
    let all: Vec<usize> = (0..n).collect();
    let bins = Bins::new(points, &all, r);
    let first: Vec<Outlier> = all
        .iter()
        .filter_map(|&i| bins.spike(points, i, thr))
        .collect();
    if first.is_empty() {
        return first;
    }
    let mut excluded = vec![false; n];
    first.iter().for_each(|o| excluded[o.index] = true);
    let kept: Vec<usize> = all.into_iter().filter(|&i| !excluded[i]).collect();
    let bins = Bins::new(points, &kept, r);
    let second: Vec<Outlier> = first
        .iter()
        .filter_map(|o| bins.spike(points, o.index, thr))
        .collect();
    drop_long_runs(second)
}

/// Removes runs of more than [`MAX_RUN`] consecutive indices.
fn drop_long_runs(found: Vec<Outlier>) -> Vec<Outlier> {
    let mut out = Vec::with_capacity(found.len());
    let mut i = 0;
    while i < found.len() {
        let mut j = i + 1;
        while j < found.len() && found[j].index == found[j - 1].index + 1 {
            j += 1;
        }
        if j - i <= MAX_RUN {
            out.extend_from_slice(&found[i..j]);
        }
        i = j;
    }
    out
}

/// Bins of `r` consecutive kept points: their index ranges and means.
struct Bins {
    /// First and last input index of each bin.
    span: Vec<(usize, usize)>,
    mean: Vec<Vec3>,
}

impl Bins {
    fn new(points: &[Vec3], kept: &[usize], r: usize) -> Self {
        let mut span = Vec::with_capacity(kept.len() / r + 1);
        let mut mean = Vec::with_capacity(kept.len() / r + 1);
        for c in kept.chunks(r) {
            let s = c
                .iter()
                .fold(Vec3::new(0.0, 0.0, 0.0), |a, &i| a + points[i]);
            span.push((c[0], c[c.len() - 1]));
            mean.push(s / c.len() as f64);
        }
        Bins { span, mean }
    }

    /// `Some` when point `i` is a spike at threshold `thr` (module doc).
    fn spike(&self, points: &[Vec3], i: usize, thr: f64) -> Option<Outlier> {
        // bins wholly before i: 0..before; wholly after i: after..
        let before = self.span.partition_point(|&(_, b)| b < i);
        let after = self.span.partition_point(|&(a, _)| a <= i);
        let left = &self.mean[before.saturating_sub(SIDE_BINS)..before];
        let right = &self.mean[after..(after + SIDE_BINS).min(self.mean.len())];
        let p = points[i];
        let (Some(&l), Some(&r)) = (left.last(), right.first()) else {
            return None;
        };
        let mut far_to_near = [Vec3::new(0.0, 0.0, 0.0); SIDE_BINS];
        let nr = right.len();
        for (k, &v) in right.iter().rev().enumerate() {
            far_to_near[k] = v;
        }
        let d = side_distance(left, p, r).min(side_distance(&far_to_near[..nr], p, l));
        if !(d.is_finite() && d > thr) {
            return None;
        }
        // an end point has one side only: a turn there cannot be told from a spike, so it stays
        let gap = 0.5 * (r - l).norm();
        (d > SPIKE_SPACINGS * gap).then_some(Outlier {
            index: i,
            distance: d,
        })
    }
}

/// Distance of `p` from the least-squares line through the means `q` (ordered from far to near
/// `p`), on the stretch where `p` belongs: from half a bin spacing behind the nearest mean to the
/// larger of two bin spacings and the distance to `reach` (the other side's nearest mean) ahead of
/// it. A line, not a curve: its error grows slowly along it; the stretch makes a spike displaced
/// along the curve (out of its order) as far off as one displaced across it. Infinite for fewer than
/// two means.
fn side_distance(q: &[Vec3], p: Vec3, reach: Vec3) -> f64 {
    if q.len() < 2 {
        return f64::INFINITY;
    }
    let c = q.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &v| a + v) / q.len() as f64;
    let near = q[q.len() - 1];
    let d = near - q[0];
    let len = d.norm();
    if len.is_nan() || len <= 0.0 {
        return f64::INFINITY;
    }
    let u = d / len;
    let (mut sxx, mut sxv) = (0.0, Vec3::new(0.0, 0.0, 0.0));
    for &v in q {
        let x = (v - c).dot(u);
        sxx += x * x;
        sxv += (v - c) * x;
    }
    if sxx.is_nan() || sxx <= 0.0 {
        return f64::INFINITY;
    }
    let slope = sxv / sxx;
    let spacing = (near - q[q.len() - 2]).norm();
    let t_near = (near - c).dot(u);
    let (lo, hi) = (
        t_near - 0.5 * spacing,
        t_near + (2.0 * spacing).max((reach - near).norm()),
    );
    let t = (p - c).dot(u).clamp(lo, hi);
    (p - (c + slope * t)).norm()
}
