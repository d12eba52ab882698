//! The reduced form of dense ordered points: representatives of tolerance-sized arcs.
//!
//! The points are cut, in their order, into *bins*: runs of consecutive points that stay within a
//! bin length `h` of the bin's first point; a bin also closes where the path turns back along the
//! bin's direction by [`ReduceTuning::turn_back`]` · h` (a hairpin's two sides never share more than
//! that). Each bin is replaced by its centroid; the first and last point stay alone. Each bin
//! records its *spread*: the largest distance of its points from the line through the centroid
//! along the bin's direction. Why this form, and how the integrated method uses it, is in
//! `crate::optim::stages::reduce`.

use crate::nurbs::Vec3;

/// The reduction's thresholds (re-exported as `crate::optim::tuning::ReduceTuning`).
#[derive(Clone, Debug, PartialEq)]
pub struct ReduceTuning {
    /// Bin length in tolerances: a bin's centroid lies within `κh²/24` of the arc, below `tol/15`
    /// wherever the radius of curvature is at least 10 tolerances. Default 4.
    pub bin_tolerances: f64,
    /// How far back along its direction (a fraction of the bin length) the path may return before
    /// its bin closes (a hairpin's two sides stay apart; above any noise the tolerance can
    /// meet). Default 0.25.
    pub turn_back: f64,
    /// The reduction applies when the bins hold at least this many points each on average;
    /// sparser data are their own reduced form. Default 2.
    pub min_points_per_bin: f64,
    /// Rounds of bin cutting where an input point misses the tolerance, before the tolerance
    /// itself is tightened once. Default 3.
    pub repair_rounds: usize,
    /// The grid, in units of the bounding box's largest side, that the representatives and the
    /// reduced fit's tolerance are rounded to before the search sees them: far coarser than the
    /// few units in the last place by which a rescaled input's normalised coordinates differ
    /// (about 1e-16), so a rescaled input gives bit-identical reduced data but with probability
    /// about 1e-7 per coordinate, and far finer than any tolerance (1e-6 of a relative 1e-3).
    /// Default 2^-30.
    pub grid: f64,
}

impl Default for ReduceTuning {
    fn default() -> Self {
        ReduceTuning {
            bin_tolerances: 4.0,
            turn_back: 0.25,
            min_points_per_bin: 2.0,
            repair_rounds: 3,
            grid: 1.0 / (1u64 << 30) as f64,
        }
    }
}

/// One bin: the input points `first..=last` and their representative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bin {
    /// Index of the bin's first input point.
    pub first: usize,
    /// Index of the bin's last input point.
    pub last: usize,
    /// The representative (centroid of the bin's points).
    pub point: Vec3,
    /// Largest distance of a bin point from the line through `point` along the bin's direction.
    pub spread: f64,
}

/// The reduced form of a point sequence (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Reduced {
    /// The bins in order; the first and the last hold one point each.
    pub bins: Vec<Bin>,
}

impl Reduced {
    /// The representatives, in order.
    pub fn points(&self) -> Vec<Vec3> {
        self.bins.iter().map(|b| b.point).collect()
    }

    /// The largest spread of a bin.
    pub fn spread(&self) -> f64 {
        self.bins.iter().map(|b| b.spread).fold(0.0, f64::max)
    }
}

/// The bins of `points` (at least 3) for bin length `h` (module doc), the ends alone.
pub(crate) fn bin_points(points: &[Vec3], h: f64, tuning: &ReduceTuning) -> Reduced {
    let n = points.len();
    let mut bins = Vec::with_capacity(n.min(1024));
    bins.push(bin_of(points, 0, 0));
    bin_range(points, 1, n - 2, h, tuning, &mut bins);
    bins.push(bin_of(points, n - 1, n - 1));
    Reduced { bins }
}

/// Appends the bins of `points[a..=b]` (`a ≤ b + 1`; empty when `a > b`) for bin length `h`.
fn bin_range(
    points: &[Vec3],
    a: usize,
    b: usize,
    h: f64,
    tuning: &ReduceTuning,
    out: &mut Vec<Bin>,
) {
    if a > b {
        return;
    }
    let back = tuning.turn_back * h;
    let mut start = a;
    // the bin's direction (from its first point to the first one `back` away) and the farthest
    // progress along it so far
    let mut dir: Option<Vec3> = None;
    let mut reach = 0.0f64;
    for j in a + 1..=b {
        let r = points[j] - points[start];
        let d = r.norm();
        let t = dir.map_or(d, |u| r.dot(u));
        if d >= h || t < reach - back {
            out.push(bin_of(points, start, j - 1));
            (start, dir, reach) = (j, None, 0.0);
            continue;
        }
        if dir.is_none() && d >= back {
            dir = Some(r / d);
        }
        reach = reach.max(t);
    }
    out.push(bin_of(points, start, b));
}

/// The bin of `points[a..=b]`: centroid and spread about the line along the bin's direction (the
/// mean of its second half minus that of its first half, robust to noise).
fn bin_of(points: &[Vec3], a: usize, b: usize) -> Bin {
    let pts = &points[a..=b];
    let m = pts.len();
    let centroid = mean(pts);
    let spread = if m < 3 {
        0.0
    } else {
        let dir = mean(&pts[m / 2..]) - mean(&pts[..m / 2]);
        let len = dir.norm();
        pts.iter()
            .map(|&q| {
                let r = q - centroid;
                if len > 0.0 {
                    let t = r.dot(dir) / len;
                    (r.norm_squared() - t * t).max(0.0).sqrt()
                } else {
                    r.norm()
                }
            })
            .fold(0.0, f64::max)
    };
    Bin {
        first: a,
        last: b,
        point: centroid,
        spread,
    }
}

fn mean(pts: &[Vec3]) -> Vec3 {
    let mut s = Vec3::ZERO;
    for &p in pts {
        s += p;
    }
    s / pts.len() as f64
}

/// The reduced form of `points` for the tolerance `tol` (input units), or `None` when it would not
/// at least halve the points (module doc: the data are then their own reduced form).
pub fn reduce(points: &[Vec3], tol: f64, tuning: &ReduceTuning) -> Option<Reduced> {
    if points.len() < 3 || tol.is_nan() || tol <= 0.0 {
        return None;
    }
    let r = bin_points(points, tuning.bin_tolerances * tol, tuning);
    (r.bins.len() as f64 * tuning.min_points_per_bin <= points.len() as f64).then_some(r)
}

/// Cuts every bin of `r` flagged in `cut` into bins of half its length (input `points`); returns
/// whether any bin changed.
pub fn refine(
    points: &[Vec3],
    r: &mut Reduced,
    cut: &[bool],
    h: f64,
    tuning: &ReduceTuning,
) -> bool {
    let mut bins = Vec::with_capacity(r.bins.len() + cut.len());
    let mut changed = false;
    for (b, &c) in r.bins.iter().zip(cut) {
        if c && b.last > b.first {
            let before = bins.len();
            let len = (points[b.last] - points[b.first]).norm().max(h * 0.5);
            bin_range(points, b.first, b.last, 0.5 * len, tuning, &mut bins);
            changed |= bins.len() > before + 1;
        } else {
            bins.push(*b);
        }
    }
    r.bins = bins;
    changed
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(n: usize, burst: bool) -> Vec<Vec3> {
        // a unit circle's half, sampled evenly or with a 100:1 burst on its middle third
        let mut us = Vec::new();
        if burst {
            for i in 0..n {
                let u = i as f64 / (n - 1) as f64;
                if (1.0 / 3.0..2.0 / 3.0).contains(&u) {
                    for k in 0..100 {
                        us.push(u + k as f64 / (100.0 * (n - 1) as f64));
                    }
                } else {
                    us.push(u);
                }
            }
        } else {
            us = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
        }
        us.iter()
            .map(|&u| {
                let t = std::f64::consts::PI * u;
                Vec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn bins_hold_arcs_of_the_bin_length_and_centroids_stay_on_the_arc() {
        let pts = arc(100_000, false);
        let t = ReduceTuning::default();
        let tol = 1e-3;
        let r = reduce(&pts, tol, &t).expect("dense data are reduced");
        // π / (4 tol) ≈ 785 bins of length 4 tol, plus the two ends
        let n = r.bins.len();
        assert!((780..=800).contains(&n), "{n} bins");
        // every bin point within h of the bin's first point; the bins cover the points in order
        let mut next = 0;
        for b in &r.bins {
            assert_eq!(b.first, next);
            next = b.last + 1;
            // the centroid lies within κh²/24 of the unit circle (to second order: 2 %)
            let off = (b.point.norm() - 1.0).abs();
            assert!(off <= 16.0 * tol * tol / 24.0 * 1.02, "{off}");
        }
        assert_eq!(next, pts.len());
    }

    #[test]
    fn a_burst_gives_the_bins_of_even_sampling() {
        let t = ReduceTuning::default();
        let even = reduce(&arc(20_000, false), 1e-3, &t).unwrap();
        let burst = reduce(&arc(20_000, true), 1e-3, &t).unwrap();
        let (a, b) = (even.bins.len() as i64, burst.bins.len() as i64);
        // the boundaries shift, the density does not show: within 1 %
        assert!((a - b).abs() * 100 <= a, "{a} vs {b} bins");
    }

    #[test]
    fn sparse_data_are_their_own_reduced_form() {
        // 200 points on a half circle: spacing 16 tol at tol = 1e-3
        assert!(reduce(&arc(200, false), 1e-3, &ReduceTuning::default()).is_none());
    }

    #[test]
    fn a_hairpin_never_shares_a_bin() {
        // out along x and back 2·tol above: the bin closes at the tip
        let tol = 1e-3;
        let mut pts: Vec<Vec3> = (0..=1000)
            .map(|i| Vec3::new(i as f64 * 1e-5, 0.0, 0.0))
            .collect();
        pts.extend(
            (0..=1000)
                .rev()
                .map(|i| Vec3::new(i as f64 * 1e-5, 2.0 * tol, 0.0)),
        );
        let r = reduce(&pts, tol, &ReduceTuning::default()).unwrap();
        for b in &r.bins {
            let ys = pts[b.first..=b.last].iter().map(|p| p[1]);
            let upper = ys.clone().filter(|&y| y > tol).count();
            let lower = ys.filter(|&y| y < tol).count();
            // a bin may hold the tip and the return until it has come back by h/4 (100 points),
            // never a long stretch of both sides
            assert!(
                upper.min(lower) <= 102,
                "bin {b:?}: {upper} above, {lower} below"
            );
        }
    }
}
