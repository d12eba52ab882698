//! Corners judged at the tolerance's scale, not at the point spacing.
//!
//! A point `k` is a corner when the tangent *arriving* at it and the tangent *leaving* it differ by more
//! than the corner angle, each tangent estimated over a window of arc length `s` on its side:
//! the direction from the mean of the window's first half of points to the mean of its second half.
//! - `s = max(tol, NOISE_WINDOW · σ / θ)` ([`CornerScale::new`]): a turn made within one tolerance is a
//!   corner at the tolerance's scale (a fillet that small is within `tol` of a sharp corner), and a
//!   window of `NOISE_WINDOW σ/θ` keeps the noise's wobble of the tangents a sixth of the corner angle
//!   `θ` even with a single point at each end (`≈ 4σ/s` radians), so noise alone never turns them by `θ`.
//! - Arc length is measured along every `stride`-th point: at a density where the noise is larger
//!   than the spacing, the raw polyline is many times longer than the curve.
//! - When both windows are a single chord (sparse data, or clean data sampled more coarsely than `s`),
//!   the test is exactly the chord turning angle of [`crate::fit::shape::detect_corners`]: tables of a
//!   few hundred points keep their decisions.
//! - The test fires on a run of points around a corner; the run's largest turn is kept (a later
//!   candidate inside the leaving window of an earlier one belongs to the same run).
//! - At the ends of open data a window may be shorter than `s` but not shorter than its noise part.
//!
//! Cost: one O(n) sweep (prefix sums of the coordinates for the window means); the noise estimate is
//! O(n log n) at worst.

use super::knot_placement::turning_angle;
use super::noise::{estimate_noise, NoiseEstimate};
use crate::nurbs::Vec3;

/// The noise part of the tangent window, in `σ` per radian of corner angle (module doc).
pub const NOISE_WINDOW: f64 = 24.0;

/// The scale at which corners are judged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerScale {
    /// Arc length of each tangent window.
    pub window: f64,
    /// Shortest window accepted at the ends of open data (the noise part of `window`).
    pub min_window: f64,
    /// Arc length is measured along every `stride`-th point.
    pub stride: usize,
}

impl CornerScale {
    /// Windows of one chord: the turning angle between neighbouring chords.
    pub fn chords() -> Self {
        CornerScale {
            window: 0.0,
            min_window: 0.0,
            stride: 1,
        }
    }

    /// The scale for tolerance `tol` (the points' units), measured noise `noise` and corner angle.
    pub fn new(tol: f64, noise: NoiseEstimate, angle_deg: f64) -> Self {
        let min_window = NOISE_WINDOW * noise.sigma / angle_deg.to_radians();
        let stride = if noise.sigma > 0.0 {
            (noise.block / 4).max(1)
        } else {
            1
        };
        CornerScale {
            window: tol.max(min_window),
            min_window,
            stride,
        }
    }

    /// Measures the noise of `points` and gives the scale for tolerance `tol`.
    pub fn measure(points: &[Vec3], tol: f64, angle_deg: f64) -> Self {
        Self::new(tol, estimate_noise(points), angle_deg)
    }
}

/// The corners of `points` at tolerance `tol` (the points' units): the noise measured, then
/// [`detect_corners_at`] at that scale.
pub fn corners_at_tolerance(points: &[Vec3], closed: bool, angle_deg: f64, tol: f64) -> Vec<usize> {
    if points.len() < 3 {
        return Vec::new();
    }
    if !tol.is_finite() || points.windows(2).any(|w| !w[0].distance(w[1]).is_finite()) {
        // coordinates near the floating-point limit: no arc-length window can be measured; the
        // chord rule's answer goes to the parameterisation, which refuses such data with its own
        // message
        return super::shape::detect_corners(points, closed, angle_deg);
    }
    detect_corners_at(
        points,
        closed,
        angle_deg,
        &CornerScale::measure(points, tol, angle_deg),
    )
}

/// Indices of the corners of `points` (module doc). For `closed` data (last point not repeated) every
/// point has two sides.
///
/// ```
/// use fairfit::fit::corners::{detect_corners_at, CornerScale};
/// use fairfit::nurbs::Vec3;
/// // an L of 2001 points, corner at index 1000
/// let pts: Vec<Vec3> = (0..2001)
///     .map(|i| {
///         let t = i as f64 / 1000.0;
///         if t <= 1.0 { Vec3::new(t, 0.0, 0.0) } else { Vec3::new(1.0, t - 1.0, 0.0) }
///     })
///     .collect();
/// let s = CornerScale::measure(&pts, 1e-3, 60.0);
/// assert_eq!(detect_corners_at(&pts, false, 60.0, &s), vec![1000]);
/// ```
pub fn detect_corners_at(
    points: &[Vec3],
    closed: bool,
    angle_deg: f64,
    scale: &CornerScale,
) -> Vec<usize> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    let thr = angle_deg.to_radians();
    let w = Windows::new(points, closed, scale.stride);
    let (lo, hi) = if closed { (0, n) } else { (1, n - 1) };
    // (index, turn, end of its leaving window)
    let mut cands: Vec<(usize, f64, isize)> = Vec::new();
    let (mut j, mut jr) = (w.first_index(), lo as isize + 1);
    for k in lo..hi {
        let ki = k as isize;
        let tk = w.pos(ki);
        // left end: the last index at least `window` before k (at least one chord)
        j = j.max(w.first_index()).min(ki - 1);
        while j + 1 < ki && w.in_range(j + 1) && tk - w.pos(j + 1) >= scale.window {
            j += 1;
        }
        jr = jr.max(ki + 1);
        while w.in_range(jr) && w.pos(jr) - tk < scale.window && (closed || jr as usize != n - 1) {
            jr += 1;
        }
        if !w.in_range(jr) {
            jr = w.last_index();
        }
        let short = |len: f64| len < scale.window && len < scale.min_window;
        if !closed && (short(tk - w.pos(j)) || short(w.pos(jr) - tk)) {
            continue;
        }
        let turn = if j == ki - 1 && jr == ki + 1 {
            turning_angle(w.point(j), w.point(ki), w.point(jr))
        } else {
            let (a, b) = (w.direction(j, ki), w.direction(ki, jr));
            let (na, nb) = (a.norm(), b.norm());
            if na == 0.0 || nb == 0.0 {
                0.0
            } else {
                a.cross(b).norm().atan2(a.dot(b))
            }
        };
        if turn > thr {
            cands.push((k, turn, jr));
        }
    }
    runs_best(cands, closed, n)
}

/// The turn at the seam of open `points` read as a loop: the angle between the tangent arriving at the
/// last point and the tangent leaving the first, each estimated as in [`detect_corners_at`] over a
/// window of arc length `scale.window` on its side (at least one chord; at most the whole data). With
/// single-chord windows it is the angle between the last chord and the first. Radians in `[0, π]`;
/// `π` for fewer than three points or a zero tangent.
pub fn seam_turn(points: &[Vec3], scale: &CornerScale) -> f64 {
    let n = points.len();
    if n < 3 {
        return std::f64::consts::PI;
    }
    let w = Windows::new(points, false, scale.stride);
    let last = n as isize - 1;
    let end = w.pos(last);
    let mut j = last - 1;
    while j > 0 && end - w.pos(j) < scale.window {
        j -= 1;
    }
    let mut jr = 1;
    while jr < last && w.pos(jr) < scale.window {
        jr += 1;
    }
    let (a, b) = (w.direction(j, last), w.direction(0, jr));
    if a.norm() == 0.0 || b.norm() == 0.0 {
        return std::f64::consts::PI;
    }
    a.cross(b).norm().atan2(a.dot(b))
}

/// The largest turn of each run of candidates (module doc), in index order.
fn runs_best(cands: Vec<(usize, f64, isize)>, closed: bool, n: usize) -> Vec<usize> {
    let mut runs: Vec<Vec<(usize, f64, isize)>> = Vec::new();
    for c in cands {
        match runs.last_mut() {
            Some(r) if (c.0 as isize) < r[r.len() - 1].2 => r.push(c),
            _ => runs.push(vec![c]),
        }
    }
    if closed && runs.len() > 1 {
        let last_end = runs[runs.len() - 1].last().map_or(0, |c| c.2);
        if ((runs[0][0].0 + n) as isize) < last_end {
            let first = runs.remove(0);
            runs.last_mut()
                .expect("runs.len() > 1 before one was removed")
                .extend(first);
        }
    }
    let mut out: Vec<usize> = runs
        .iter()
        .map(|r| {
            r.iter()
                .fold(r[0], |best, &c| if c.1 > best.1 { c } else { best })
                .0
        })
        .collect();
    out.sort_unstable();
    out
}

/// Arc positions and window means over (cyclically extended, for closed data) indices.
struct Windows<'a> {
    points: &'a [Vec3],
    closed: bool,
    /// Arc position of each point (along every `stride`-th point).
    t: Vec<f64>,
    /// Total length including the closing chord (closed data).
    length: f64,
    /// Prefix sums of `p - p_0`.
    sums: Vec<Vec3>,
}

impl<'a> Windows<'a> {
    fn new(points: &'a [Vec3], closed: bool, stride: usize) -> Self {
        let n = points.len();
        let stride = stride.clamp(1, (n - 1).max(1));
        let mut nodes: Vec<usize> = (0..n).step_by(stride).collect();
        if *nodes
            .last()
            .expect("n >= 3 (detect_corners_at): index 0 is a node")
            != n - 1
        {
            nodes.push(n - 1);
        }
        let mut t = vec![0.0; n];
        let mut acc = 0.0;
        for w in nodes.windows(2) {
            let (a, b) = (w[0], w[1]);
            let d = (points[b] - points[a]).norm();
            for (i, ti) in t.iter_mut().enumerate().take(b + 1).skip(a + 1) {
                *ti = acc + d * (i - a) as f64 / (b - a) as f64;
            }
            acc += d;
        }
        let length = acc
            + if closed {
                (points[0] - points[n - 1]).norm()
            } else {
                0.0
            };
        let mut sums = Vec::with_capacity(n + 1);
        let mut s = Vec3::new(0.0, 0.0, 0.0);
        sums.push(s);
        for &p in points {
            s += p - points[0];
            sums.push(s);
        }
        Windows {
            points,
            closed,
            t,
            length,
            sums,
        }
    }

    fn n(&self) -> isize {
        self.points.len() as isize
    }

    fn in_range(&self, i: isize) -> bool {
        if self.closed {
            i > -self.n() && i < 2 * self.n()
        } else {
            i >= 0 && i < self.n()
        }
    }

    fn first_index(&self) -> isize {
        if self.closed {
            1 - self.n()
        } else {
            0
        }
    }

    fn last_index(&self) -> isize {
        if self.closed {
            2 * self.n() - 1
        } else {
            self.n() - 1
        }
    }

    fn pos(&self, i: isize) -> f64 {
        let n = self.n();
        self.t[i.rem_euclid(n) as usize] + i.div_euclid(n) as f64 * self.length
    }

    fn point(&self, i: isize) -> Vec3 {
        self.points[i.rem_euclid(self.n()) as usize]
    }

    /// `Σ_{a <= i < b} (p_i - p_0)` over the cyclic extension.
    fn sum(&self, a: isize, b: isize) -> Vec3 {
        self.prefix(b) - self.prefix(a)
    }

    fn prefix(&self, i: isize) -> Vec3 {
        let n = self.n();
        self.sums[i.rem_euclid(n) as usize] + self.sums[n as usize] * i.div_euclid(n) as f64
    }

    /// Mean of the second half of points `a..=b` minus the mean of the first half.
    fn direction(&self, a: isize, b: isize) -> Vec3 {
        let m = b - a + 1;
        let h = a + m / 2;
        let first = self.sum(a, h) / (h - a) as f64;
        let second = self.sum(h, b + 1) / (b + 1 - h) as f64;
        second - first
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::shape::detect_corners;

    #[test]
    fn sparse_data_keep_the_chord_rule() {
        let sq: Vec<Vec3> = [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        for closed in [false, true] {
            let s = CornerScale::measure(&sq, 1e-3, 60.0);
            assert_eq!(
                detect_corners_at(&sq, closed, 60.0, &s),
                detect_corners(&sq, closed, 60.0)
            );
        }
    }
}
