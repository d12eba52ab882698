//! Spikes: isolated points far from the curve their neighbours describe.
//!
//! Each point is compared with the curve of the points on each side of it:
//! - the points (outliers already found excluded) are grouped into bins of `r` consecutive points,
//!   `r = block / 8` from the noise measure (`r = 1` on clean or sparse data), so that a bin's mean
//!   carries `1/√r` of the noise and [`SIDE_BINS`] bins span about one noise block;
//! - on each side, a quadratic through the means of the [`SIDE_BINS`] nearest bins that hold no part of
//!   the point's own bin is extrapolated to the point; its *side distance* is how far it lies from that
//!   quadratic, and its distance is the smaller of its two side distances.
//!
//! A point is a spike when that distance exceeds all of `SPIKE_TOLS · tol`, `SPIKE_SIGMAS · σ` and
//! `SPIKE_SPACINGS ·` half the gap between its two sides. Taking the smaller side keeps every feature
//! made of points: a corner lies on the extrapolation of the side it ends, a trailing edge point on
//! both surfaces' extrapolations, a point of a short straight piece on the side holding the rest of
//! the piece. The spacing term keeps sparse data (where a point's neighbours can be further apart
//! than any tolerance) from calling geometry a spike. A run of more than [`MAX_RUN`] consecutive
//! candidates is a feature, not spikes.
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
            let s = c.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &i| a + points[i]);
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
        let dl = side_distance(left, p);
        let dr = side_distance(right, p);
        let d = dl.min(dr);
        if !(d.is_finite() && d > thr) {
            return None;
        }
        let gap = match (left.last(), right.first()) {
            (Some(&a), Some(&b)) => 0.5 * (b - a).norm(),
            // at an end: the spacing of the side's two nearest bins
            (Some(_), None) => 0.5 * (left[left.len() - 1] - left[left.len() - 2]).norm(),
            (None, Some(_)) => 0.5 * (right[1] - right[0]).norm(),
            (None, None) => return None,
        };
        (d > SPIKE_SPACINGS * gap).then_some(Outlier { index: i, distance: d })
    }
}

/// Distance of `p` from the quadratic (a line for two means) through the means `q` (infinite for
/// fewer than two).
fn side_distance(q: &[Vec3], p: Vec3) -> f64 {
    if q.len() < 2 {
        return f64::INFINITY;
    }
    let d = q[q.len() - 1] - q[0];
    let len = d.norm();
    if !(len > 0.0) {
        return f64::INFINITY;
    }
    let u = d / len;
    let x = |v: Vec3| (v - q[0]).dot(u) / len;
    let deg = if q.len() >= 3 { 2 } else { 1 };
    // normal equations of the vector-valued polynomial a + b x (+ c x²)
    let mut g = [[0.0; 3]; 3];
    let mut rhs = [Vec3::new(0.0, 0.0, 0.0); 3];
    for &v in q {
        let xv = x(v);
        let phi = [1.0, xv, xv * xv];
        for a in 0..=deg {
            for b in 0..=deg {
                g[a][b] += phi[a] * phi[b];
            }
            rhs[a] += v * phi[a];
        }
    }
    let Some(coef) = solve(&mut g, &mut rhs, deg + 1) else {
        return f64::INFINITY;
    };
    let xp = x(p);
    let phi = [1.0, xp, xp * xp];
    let at = (0..=deg).fold(Vec3::new(0.0, 0.0, 0.0), |a, k| a + coef[k] * phi[k]);
    (p - at).norm()
}

/// Gaussian elimination with partial pivoting on the leading `k × k` block.
fn solve(g: &mut [[f64; 3]; 3], rhs: &mut [Vec3; 3], k: usize) -> Option<[Vec3; 3]> {
    for col in 0..k {
        let piv = (col..k).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        if g[piv][col].abs() < 1e-12 {
            return None;
        }
        g.swap(col, piv);
        rhs.swap(col, piv);
        for r in col + 1..k {
            let f = g[r][col] / g[col][col];
            for c in col..k {
                g[r][c] -= f * g[col][c];
            }
            let sub = rhs[col] * f;
            rhs[r] -= sub;
        }
    }
    let mut out = [Vec3::new(0.0, 0.0, 0.0); 3];
    for r in (0..k).rev() {
        let mut s = rhs[r];
        for c in r + 1..k {
            s -= out[c] * g[r][c];
        }
        out[r] = s / g[r][r];
    }
    Some(out)
}
