//! The reduced form of dense ordered points: representatives of tolerance-sized arcs.
//!
//! The points are cut, in their order, into *bins*: runs of consecutive points that stay within a
//! bin length `h` of the bin's first point; a bin also closes where the path turns back along the
//! bin's direction by [`ReduceTuning::turn_back`]` · h` (a hairpin's two sides never share more than
//! that). A bin's boundaries are fractional: it ends on the segment where the path gets `h` from
//! its start, at the point exactly `h` away, and is replaced by the mean of the polyline between its
//! boundaries, so the representatives lie `h` apart whether a bin holds two points or two
//! thousand (centroids of whole points would jump by up to half a bin where the point spacing
//! is comparable to `h`, and their centripetal parameters cost control points). A bin holding
//! one point is that point. The first and last point stay alone. Each bin
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
    /// Rounds of the repair that keeps the first reduced fit's degree and count, tried where the
    /// repair by new searches ([`Self::repair_rounds`], [`Self::tighten_rounds`]) ended with more
    /// control points than the first fit (or a point outside): the shares around the bins whose
    /// points miss the tolerance are taken in and the first fit's representatives fitted again
    /// at that count. Default 3.
    pub keep_count_rounds: usize,
    /// Rounds of bin cutting where an input point misses the tolerance, before the tolerance
    /// itself is tightened ([`Self::tighten_rounds`]). Default 3.
    pub repair_rounds: usize,
    /// Rounds of tightening after the bin cutting, while an input point still misses the
    /// tolerance: each takes twice the excess off the reduced fit's tolerance. Default 3.
    pub tighten_rounds: usize,
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
            keep_count_rounds: 3,
            repair_rounds: 3,
            tighten_rounds: 3,
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

    /// Per bin, the widest spread among it and its two neighbours: what a curve passing its
    /// representative must leave room for (between two representatives it passes the points of
    /// both bins).
    pub fn neighbour_spreads(&self) -> Vec<f64> {
        let b = &self.bins;
        (0..b.len())
            .map(|k| {
                b[k.saturating_sub(1)..(k + 2).min(b.len())]
                    .iter()
                    .map(|x| x.spread)
                    .fold(0.0, f64::max)
            })
            .collect()
    }
}

/// The bins of `points` (at least 3) for bin length `h` (module doc), the ends alone.
pub(crate) fn bin_points(points: &[Vec3], h: f64, tuning: &ReduceTuning) -> Reduced {
    let n = points.len();
    let mut bins = Vec::with_capacity(n.min(1024));
    bins.push(bin_of(points, 0, 0, 0.0, 0.0));
    bin_range(points, 1, n - 2, h, tuning, &mut bins);
    bins.push(bin_of(points, n - 1, n - 1, (n - 1) as f64, (n - 1) as f64));
    Reduced { bins }
}

/// Appends the bins of `points[a..=b]` (`a ≤ b + 1`; empty when `a > b`) for bin length `h`.
///
/// A bin's boundaries are *fractional*: it closes on the segment where the path first gets `h`
/// from the bin's start, at the point of that segment exactly `h` away, and the next bin starts
/// there. Its representative is the mean of the polyline between its two boundaries (index
/// measure: every segment weighs the same, a cut one its fraction), so consecutive
/// representatives lie `h` apart however many points a bin holds. (Centroids of whole points are
/// `h` to `h + s` apart for a point spacing `s`: at two or three points a bin that jumps by half,
/// and the centripetal parameters of such representatives cost control points a smooth
/// parameterisation would not.) A bin owns the input points between its boundaries; one that
/// owns a single point is that point (where the points are `h` or more apart they are their own
/// representatives, never a point on a chord).
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
    // the bin's first owned point, its start boundary (a point and its fractional index), its
    // direction (from the start to the first point `back` away) and its farthest progress so far
    let mut start = a;
    let (mut origin, mut x0) = (points[a], a as f64);
    let mut dir: Option<Vec3> = None;
    let mut reach = 0.0f64;
    for j in a + 1..=b {
        let r = points[j] - origin;
        let d = r.norm();
        let t = dir.map_or(d, |u| r.dot(u));
        let turned = t < reach - back;
        if d >= h || turned {
            let x1 = if turned || j - 1 == start {
                (j - 1) as f64
            } else {
                (j - 1) as f64 + crossing(points[j - 1], points[j], origin, h)
            };
            out.push(bin_of(points, start, j - 1, x0, x1));
            (origin, x0) = if turned || j - 1 == start {
                (points[j], j as f64)
            } else {
                (at(points, x1), x1)
            };
            start = j;
            // measured from the new start
            let r = points[j] - origin;
            let d = r.norm();
            dir = (d >= back).then(|| r / d);
            reach = d;
            continue;
        }
        if dir.is_none() && d >= back {
            dir = Some(r / d);
        }
        reach = reach.max(t);
    }
    out.push(bin_of(points, start, b, x0, b as f64));
}

/// The fraction `f ∈ [0, 1]` of the segment `p → q` at which it is `h` from `o` (`|p − o| < h ≤
/// |q − o|`).
fn crossing(p: Vec3, q: Vec3, o: Vec3, h: f64) -> f64 {
    let (w, d) = (p - o, q - p);
    let (aa, bb, cc) = (d.norm_squared(), w.dot(d), w.norm_squared() - h * h);
    if aa <= 0.0 {
        return 1.0;
    }
    ((-bb + (bb * bb - aa * cc).max(0.0).sqrt()) / aa).clamp(0.0, 1.0)
}

/// The polyline through `points` at the fractional index `x`.
fn at(points: &[Vec3], x: f64) -> Vec3 {
    let i = (x.floor() as usize).min(points.len() - 1);
    let f = x - i as f64;
    if f <= 0.0 || i + 1 >= points.len() {
        points[i]
    } else {
        points[i] + (points[i + 1] - points[i]) * f
    }
}

/// The mean of the polyline through `points` over the fractional indices `[x0, x1]` (index
/// measure), `x0 ≤ x1`, both within `[first − 1, last + 1]` of the whole indices they span.
fn polyline_mean(points: &[Vec3], x0: f64, x1: f64) -> Vec3 {
    let (i0, i1) = (x0.ceil() as usize, x1.floor() as usize);
    let mut s = Vec3::ZERO;
    let mut w = 0.0;
    // the cut segments at both ends (trapezoids), then the whole ones
    let (p0, p1) = (at(points, x0), at(points, x1));
    if i0 > i1 {
        return (p0 + p1) * 0.5;
    }
    let head = i0 as f64 - x0;
    s += (p0 + points[i0]) * (0.5 * head);
    w += head;
    let tail = x1 - i1 as f64;
    s += (points[i1] + p1) * (0.5 * tail);
    w += tail;
    for i in i0..i1 {
        s += (points[i] + points[i + 1]) * 0.5;
        w += 1.0;
    }
    if w > 0.0 {
        s / w
    } else {
        points[i0]
    }
}

/// The bin of `points[a..=b]` between the fractional boundaries `x0 ≤ a` and `x1 ≥ b`: the
/// polyline's mean between them (the point itself when the bin owns one) and the spread of its
/// points about the line through it along the bin's direction (the mean of its second half minus
/// that of its first half, robust to noise; the chord between the boundaries for fewer than three
/// points).
fn bin_of(points: &[Vec3], a: usize, b: usize, x0: f64, x1: f64) -> Bin {
    let pts = &points[a..=b];
    let m = pts.len();
    let centroid = if m == 1 {
        pts[0]
    } else {
        polyline_mean(points, x0, x1)
    };
    let dir = if m >= 3 {
        mean(&pts[m / 2..]) - mean(&pts[..m / 2])
    } else {
        at(points, x1) - at(points, x0)
    };
    let len = dir.norm();
    let spread = pts
        .iter()
        .map(|&q| {
            let r = q - centroid;
            if len > 0.0 {
                let t = r.dot(dir) / len;
                (r.norm_squared() - t * t).max(0.0).sqrt()
            } else {
                r.norm()
            }
        })
        .fold(0.0, f64::max);
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

    #[test]
    fn representatives_lie_a_bin_length_apart_however_few_points_a_bin_holds() {
        // 85 % of a unit circle's half, the spacing growing from h/6 to h/2 along it: consecutive
        // representatives are h apart (chord) to within 1 %, where centroids of whole points were
        // h to 1.5 h apart
        let tol = 1e-3;
        let h = 4.0 * tol;
        let pts: Vec<Vec3> = (0..2000)
            .map(|i| {
                let u = i as f64 / 1999.0;
                let t = std::f64::consts::PI * (0.43 * u + 0.42 * u * u);
                Vec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let r = reduce(&pts, tol, &ReduceTuning::default()).expect("reduced");
        let inner = &r.bins[1..r.bins.len() - 2];
        let (mut lo, mut hi) = (f64::MAX, 0.0f64);
        for w in inner.windows(2) {
            let d = (w[1].point - w[0].point).norm();
            lo = lo.min(d / h);
            hi = hi.max(d / h);
        }
        assert!(lo > 0.99 && hi < 1.01, "spacing {lo} .. {hi} of h");
        // and every representative within the mean sagitta of the arc, κh²/24, plus the
        // polyline's own mean sagitta, κs²/12 for the spacing s (2 % to second order)
        let s = pts
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .fold(0.0, f64::max);
        for b in &r.bins {
            let off = (b.point.norm() - 1.0).abs();
            assert!(off <= (h * h / 24.0 + s * s / 12.0) * 1.02, "{off}");
        }
    }
}
