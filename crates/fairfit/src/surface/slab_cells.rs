//! Thinning the points of a point cloud's slab, projected onto its slicing plane, to one
//! representative per tolerance-sized cluster before the tour orders them.
//!
//! # Why
//!
//! A slab of a dense cloud holds thousands of points scattered across a band: the noise, plus the
//! slab's thickness times the surface's slope. A nearest-neighbour tour through all of them zigzags
//! across the band, leaves points behind and jumps back for them, so the "section" doubles back on
//! itself and no fair curve can follow it. Merged into clusters of a radius `r` set by the
//! tolerance, the band becomes a thread of representatives about `r` to `2r` apart along the curve:
//! the section's size follows the shape and the tolerance, not the point count, and the tour
//! follows the curve.
//!
//! # Rule
//!
//! - **Seeds**: the points are visited in their order; a point farther than `r` (in the plane) from
//!   every seed so far becomes a seed (a greedy Poisson-disk sample: seeds are more than `r` apart,
//!   and every point lies within `r` of one).
//! - **Clusters**: every point joins its nearest seed (the smaller seed index on a tie).
//! - **Radius**: `r` is asked for (a quarter of the tolerance), raised to [`NOISE_RADII`] times the
//!   noise measured across the band (below), at most [`MAX_RADIUS_GROWTH`] times: a band wider than
//!   a cluster puts representatives side by side, and a nearest-neighbour tour through them leaves
//!   some behind and jumps back for them.
//! - **Representatives**, in seed order: each cluster's centroid; a cluster of one point is that
//!   point, bit for bit, so a slab whose points are all more than `r` apart (and whose slope is not
//!   measured, below) comes back unchanged.
//! - **The slope across the slab is taken out first.** The slab's points lie on the surface at
//!   heights `h` up to the slab's half-thickness, so the band they form in the plane is widened by
//!   that height times the surface's slope (a twisted blade's trailing edge: most of a tolerance),
//!   and clusters of radius `r` would lie side by side across it. So the points are first grouped
//!   into coarse clusters of radius [`SLOPE_RADII`]` · r` (the same rule). In each, the in-plane
//!   positions are fitted by a line in `h` (least squares); the band's direction is the principal
//!   axis of the positions with that line taken out, and every point is moved back across the band
//!   (along the normal of that axis) by the fitted slope times its `h`: onto the plane's section
//!   curve. Only the component across the band is used: along it the fitted slope is noise. A coarse cluster of fewer than [`MIN_FIT`] points, or whose
//!   heights spread less than [`MIN_HEIGHT_SPREAD`] of the half-thickness (the slope would be
//!   guessed, not measured), is left as it is.
//! - **Clusters that are not bands** (a corner, or both sides of a thin part: a blunt trailing edge
//!   a few tolerances thick) have no band direction: their spread across the principal axis is
//!   more than [`LINE_RATIO`] of the spread along it. Their shift comes from the slab's motion
//!   fitted as one affine field per unit height (a twist, sweep, taper or swelling of the sections
//!   is one) to the across-band slopes of all band clusters, each fixing its component along its
//!   normal (at least [`MIN_BANDS`] of them, with normals that turn). Left unshifted, a twisted
//!   blade's trailing edge stayed smeared by the slab's thickness times its slope (0.75 of the
//!   tolerance on the 2 × 10^6-point twisted loft of `bench/hostile_scale.py`), and the tour looped
//!   through the smear.

//! # Invariants
//!
//! - Every (slope-corrected) point lies within `r` (the radius used: at most twice the one asked
//!   for) of its seed in the plane, and its representative within `2r` of it; the correction moves a point only across its band, by the measured slope
//!   times its height.
//! - Thin features: the two sides of a thin part (a blade's trailing edge) share clusters only where
//!   their bands come within `r` of each other; sides farther apart than `2r` never share one.
//! - Cost: `O(n)` expected (a uniform grid of cell `r` holds the seeds), deterministic (no hash
//!   iteration, sums in point order).

use super::linalg::{cholesky, cholesky_solve, Dense};
use crate::nurbs::Vec3;
use std::collections::HashMap;

/// The most grid cells across the points' extent for which the thinning runs (`extent / r`);
/// beyond it the radius is negligible against the data (below `1e-9` of it) and the points are
/// returned as they are, so the grid's integer cell keys never saturate.
const MAX_CELLS_ACROSS: f64 = 1e9;

/// The radius of the clusters whose slope across the slab is measured, in cluster radii: wide
/// enough to hold the whole band across a steep slope, small enough to follow the curve.
pub(crate) const SLOPE_RADII: f64 = 16.0;

/// The clusters' radius is raised to this many noise standard deviations across the band (the
/// median over the coarse clusters), so that the band is about one cluster wide and the
/// representatives lie in single file, which the tour follows without leaving points behind.
const NOISE_RADII: f64 = 5.0;

/// The most the noise may raise the clusters' radius, as a factor of the radius asked for.
const MAX_RADIUS_GROWTH: f64 = 2.0;

/// The fewest points of a coarse cluster whose slope across the slab is fitted.
const MIN_FIT: usize = 8;

/// A coarse cluster is a band when the standard deviation of its points across their principal
/// axis is at most this fraction of the one along it (a band of noise `σ` and length `L` has
/// `σ / (L / √12)`, a few hundredths; a corner or a thin part's two sides about a half).
const LINE_RATIO: f64 = 0.25;

/// The fewest band clusters whose slopes fix the slab's affine motion (six unknowns).
const MIN_BANDS: usize = 12;

/// The smallest standard deviation of a coarse cluster's heights, as a fraction of the slab's
/// half-thickness, for which its slope across the slab is fitted.
const MIN_HEIGHT_SPREAD: f64 = 0.1;

/// The greedy Poisson-disk clusters of radius `r` of the in-plane points `q` (module doc): the
/// number of clusters and each point's cluster (numbered in seed order); `None` when `r` is not a
/// positive number or negligible against the points' extent.
fn clusters(q: &[[f64; 2]], r: f64) -> Option<(usize, Vec<usize>)> {
    if !(r.is_finite() && r > 0.0) {
        return None;
    }
    let (lo, hi) = q.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), x| {
            (
                [lo[0].min(x[0]), lo[1].min(x[1])],
                [hi[0].max(x[0]), hi[1].max(x[1])],
            )
        },
    );
    let across = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if !(across.is_finite() && across / r <= MAX_CELLS_ACROSS) {
        return None;
    }
    let cell = |x: [f64; 2]| {
        (
            ((x[0] - lo[0]) / r).floor() as i64,
            ((x[1] - lo[1]) / r).floor() as i64,
        )
    };
    let d2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let r2 = r * r;
    // seeds by grid cell (indices into `seeds`)
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut seeds: Vec<usize> = Vec::new();
    let near = |grid: &HashMap<(i64, i64), Vec<usize>>, seeds: &[usize], i: usize| {
        let (cx, cy) = cell(q[i]);
        let mut best: Option<(f64, usize)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &s in grid.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let d = d2(q[seeds[s]], q[i]);
                    if d <= r2 && best.is_none_or(|(bd, bs)| d < bd || (d == bd && s < bs)) {
                        best = Some((d, s));
                    }
                }
            }
        }
        best.map(|(_, s)| s)
    };
    for (i, &x) in q.iter().enumerate() {
        if near(&grid, &seeds, i).is_none() {
            grid.entry(cell(x)).or_default().push(seeds.len());
            seeds.push(i);
        }
    }
    // every point is within r of some seed (it is one, or it was covered when visited)
    let of = (0..q.len())
        .map(|i| near(&grid, &seeds, i).unwrap_or(0))
        .collect();
    Some((seeds.len(), of))
}

/// Per coarse cluster, the in-plane shift per unit height that takes its points back onto the
/// plane's section curve (module doc), or zero where the slope is not measured; and, per cluster
/// whose slope is measured, the standard deviation of its points across the band once moved (the
/// noise).
fn slopes(
    q: &[[f64; 2]],
    heights: &[f64],
    half: f64,
    count: usize,
    of: &[usize],
) -> (Vec<[f64; 2]>, Vec<f64>) {
    let (m, v) = moments(q, heights, count, of);
    let mut noise = Vec::new();
    let mut fits: Vec<Option<Across>> = Vec::with_capacity(count);
    for (c, s) in m.iter().zip(&v) {
        let w = c.0 as f64;
        if c.0 < MIN_FIT || (s[3] / w).sqrt() < MIN_HEIGHT_SPREAD * half {
            fits.push(None);
            continue;
        }
        // the band's direction: the principal axis of the positions once their fitted line in
        // height is taken out (before, a cluster as wide across a steep band as along it has
        // no reliable axis); its normal is `nu`
        let (xx, xy, yy) = (
            s[0] - s[4] * s[4] / s[3],
            s[1] - s[4] * s[5] / s[3],
            s[2] - s[5] * s[5] / s[3],
        );
        let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
        let nu = [-angle.sin(), angle.cos()];
        let b = (s[4] * nu[0] + s[5] * nu[1]) / s[3];
        let root = (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
        let (along, across) = (0.5 * (xx + yy) + root, 0.5 * (xx + yy) - root);
        noise.push((across.max(0.0) / w).sqrt());
        fits.push(Some(Across {
            mean: c.1,
            normal: nu,
            slope: b,
            weight: w,
            line: across.max(0.0) <= LINE_RATIO * LINE_RATIO * along,
        }));
    }
    let field = SlabMotion::fit(&fits);
    let shifts = fits
        .iter()
        .map(|f| match f {
            None => [0.0, 0.0],
            Some(f) if f.line => [f.slope * f.normal[0], f.slope * f.normal[1]],
            Some(f) => field.as_ref().map_or([0.0, 0.0], |a| a.at(f.mean)),
        })
        .collect();
    (shifts, noise)
}

/// Per cluster: the point count, the mean position and the mean height; and the second moments
/// about the means (xx, xy, yy, hh, hx, hy).
#[allow(clippy::type_complexity)]
fn moments(
    q: &[[f64; 2]],
    heights: &[f64],
    count: usize,
    of: &[usize],
) -> (Vec<(usize, [f64; 2], f64)>, Vec<[f64; 6]>) {
    let mut m = vec![(0usize, [0.0f64; 2], 0.0f64); count];
    for ((x, &h), &k) in q.iter().zip(heights).zip(of) {
        m[k].0 += 1;
        m[k].1[0] += x[0];
        m[k].1[1] += x[1];
        m[k].2 += h;
    }
    for c in &mut m {
        let w = c.0.max(1) as f64;
        c.1 = [c.1[0] / w, c.1[1] / w];
        c.2 /= w;
    }
    let mut v = vec![[0.0f64; 6]; count];
    for ((x, &h), &k) in q.iter().zip(heights).zip(of) {
        let (dx, dy, dh) = (x[0] - m[k].1[0], x[1] - m[k].1[1], h - m[k].2);
        let s = &mut v[k];
        s[0] += dx * dx;
        s[1] += dx * dy;
        s[2] += dy * dy;
        s[3] += dh * dh;
        s[4] += dh * dx;
        s[5] += dh * dy;
    }
    (m, v)
}

/// A coarse cluster's measured motion across its band: the component `slope` of its shift per unit
/// height along its band's `normal`.
struct Across {
    mean: [f64; 2],
    normal: [f64; 2],
    slope: f64,
    weight: f64,
    /// The cluster is a band (across it the spread is at most [`LINE_RATIO`] of the spread along
    /// it): its slope across is measured. Otherwise (a corner, both sides of a thin part) it has
    /// no band direction, and its shift comes from [`SlabMotion`].
    line: bool,
}

/// The slab's motion with height as one affine field `shift(p) = A p + t` per unit height (a
/// twist, a sweep, a taper or a swelling of the sections are such motions), fitted by least
/// squares to the across-band slopes of the band clusters, each of which fixes its component
/// along its band's normal. It gives the full shift of the clusters that are not bands: their
/// own fit measures no direction, and leaving them unshifted leaves a twisted blade's thin
/// trailing edge smeared by the slab's thickness times its slope.
struct SlabMotion {
    a: [[f64; 2]; 2],
    t: [f64; 2],
    centre: [f64; 2],
    scale: f64,
}

impl SlabMotion {
    /// The field of the band clusters among `fits`, or `None` when they do not fix it (fewer
    /// than [`MIN_BANDS`], or normals that leave it singular).
    fn fit(fits: &[Option<Across>]) -> Option<Self> {
        let bands: Vec<&Across> = fits.iter().flatten().filter(|f| f.line).collect();
        if bands.len() < MIN_BANDS || bands.len() == fits.iter().flatten().count() {
            return None;
        }
        let wsum: f64 = bands.iter().map(|f| f.weight).sum();
        let centre = [0, 1].map(|i| bands.iter().map(|f| f.weight * f.mean[i]).sum::<f64>() / wsum);
        let scale = bands
            .iter()
            .map(|f| (f.mean[0] - centre[0]).hypot(f.mean[1] - centre[1]))
            .fold(0.0, f64::max);
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let mut n = Dense::zeros(6);
        let mut rhs = [[0.0f64; 1]; 6];
        for f in &bands {
            let (x, y) = (
                (f.mean[0] - centre[0]) / scale,
                (f.mean[1] - centre[1]) / scale,
            );
            let [u, v] = f.normal;
            let row = [u * x, u * y, v * x, v * y, u, v];
            for i in 0..6 {
                rhs[i][0] += f.weight * row[i] * f.slope;
                for j in 0..6 {
                    *n.at(i, j) += f.weight * row[i] * row[j];
                }
            }
        }
        // the normals must turn: a section that is one straight band fixes no motion along it
        let trace: f64 = (0..6).map(|i| n.get(i, i)).sum();
        for i in 0..6 {
            if n.get(i, i) <= 1e-9 * trace {
                return None;
            }
        }
        cholesky(&mut n).ok()?;
        cholesky_solve(&n, &mut rhs);
        let x = rhs.map(|r| r[0]);
        x.iter().all(|v| v.is_finite()).then_some(SlabMotion {
            a: [[x[0], x[1]], [x[2], x[3]]],
            t: [x[4], x[5]],
            centre,
            scale,
        })
    }

    /// The shift per unit height at `p`.
    fn at(&self, p: [f64; 2]) -> [f64; 2] {
        let (x, y) = (
            (p[0] - self.centre[0]) / self.scale,
            (p[1] - self.centre[1]) / self.scale,
        );
        [
            self.a[0][0] * x + self.a[0][1] * y + self.t[0],
            self.a[1][0] * x + self.a[1][1] * y + self.t[1],
        ]
    }
}

/// The points (projected onto a plane spanned by the orthonormal `e1`, `e2`, from `heights` above it,
/// within `half` of it) thinned to one representative per cluster of radius `r` (module doc); the
/// points themselves when no two are within `r` and no slope is measured, when `r` is not a positive
/// number, or when `r` is negligible against their extent.
pub(crate) fn thin(
    points: &[Vec3],
    heights: &[f64],
    half: f64,
    r: f64,
    (e1, e2): (Vec3, Vec3),
) -> Vec<Vec3> {
    let n = points.len();
    if n < 2 || heights.len() != n {
        return points.to_vec();
    }
    let mut q: Vec<[f64; 2]> = points.iter().map(|p| [p.dot(e1), p.dot(e2)]).collect();
    let mut moved = points.to_vec();
    let mut r = r;
    if let Some((count, of)) = clusters(&q, SLOPE_RADII * r) {
        let (b, mut noise) = slopes(&q, heights, half, count, &of);
        if !noise.is_empty() {
            noise.sort_by(f64::total_cmp);
            r = r.max((NOISE_RADII * noise[noise.len() / 2]).min(MAX_RADIUS_GROWTH * r));
        }
        for (((x, p), &h), &k) in q.iter_mut().zip(&mut moved).zip(heights).zip(&of) {
            let [bx, by] = b[k];
            if bx != 0.0 || by != 0.0 {
                *x = [x[0] - bx * h, x[1] - by * h];
                *p -= (e1 * bx + e2 * by) * h;
            }
        }
    }
    let Some((count, of)) = clusters(&q, r) else {
        return moved;
    };
    if count == n {
        return moved;
    }
    let mut sums = vec![(Vec3::ZERO, 0usize, 0usize); count];
    for (i, (&p, &k)) in moved.iter().zip(&of).enumerate() {
        let s = &mut sums[k];
        if s.1 == 0 {
            s.2 = i;
        }
        s.0 += p;
        s.1 += 1;
    }
    sums.iter()
        .map(
            |&(sum, c, first)| {
                if c == 1 {
                    moved[first]
                } else {
                    sum / c as f64
                }
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_apart_points_come_back_unchanged_and_close_ones_merge() {
        let e = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        let pts: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new(i as f64 * 0.3, 0.1, 2.0))
            .collect();
        assert_eq!(thin(&pts, &[0.0; 10], 0.1, 0.25, e), pts);
        // pairs 0.01 apart merge into their midpoints
        let pairs: Vec<Vec3> = pts
            .iter()
            .flat_map(|&p| [p, p + Vec3::new(0.01, 0.0, 0.0)])
            .collect();
        let t = thin(&pairs, &[0.0; 20], 0.1, 0.1, e);
        assert_eq!(t.len(), 10);
        for (a, b) in t.iter().zip(&pts) {
            assert!(a.distance(*b + Vec3::new(0.005, 0.0, 0.0)) < 1e-15);
        }
        // a negligible radius leaves the points as they are
        assert_eq!(thin(&pairs, &[0.0; 20], 0.1, 1e-12, e), pairs);
    }

    #[test]
    fn a_band_widened_by_the_slope_collapses_onto_the_section() {
        // the line y = 0 on the plane, seen in a slab of half-thickness 0.01 on a surface of slope
        // 20 across it (y = 20 h): the band is 0.4 wide, clusters of r = 0.05 would lie across
        // it; the slope is measured over 8 r and every representative lands on y = 0
        let e = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        let mut pts = Vec::new();
        let mut hs = Vec::new();
        for i in 0..20_000 {
            let x = (i as f64 * 0.618_033_988_749_895).fract();
            let h = 0.01 * (2.0 * (i as f64 * 0.754_877_666_246_693).fract() - 1.0);
            pts.push(Vec3::new(x, 20.0 * h, 0.0));
            hs.push(h);
        }
        let t = thin(&pts, &hs, 0.01, 0.05, e);
        assert!(t.len() < pts.len() / 10, "{}", t.len());
        let worst = t.iter().map(|p| p.y().abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "{worst}");
        // without the heights' spread (all on the plane) the representatives are centroids
        let flat: Vec<Vec3> = pts.iter().map(|p| Vec3::new(p.x(), 0.0, 0.0)).collect();
        let c = thin(&flat, &vec![0.0; flat.len()], 0.01, 0.05, e);
        assert!(c.iter().all(|p| p.y() == 0.0));
        assert!(c.len() < flat.len() / 10);
    }
}
