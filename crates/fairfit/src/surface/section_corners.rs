//! Corners inside the sections, held as C0 knot lines shared by all sections (the way CAD lofts split
//! sections at matching corners into compatible segments).
//!
//! - Each section's corners are found at the tolerance's scale by the curve side's detector
//!   ([`crate::fit::corners::corners_at_tolerance`], the same corner angle as `fairfit curve`); the
//!   ends of an open section and the seam (first point) of a closed one are not inner corners.
//! - When every section has the same number `c > 0` of inner corners, the `j`-th corners (in point
//!   order, after the orientation and seam alignment of [`super::orient`]) are matched. Each section is
//!   parameterised piecewise: chord length within every piece between corners, the piece mapped onto a
//!   common interval `[t_j, t_{j+1}]` whose ends are the sections' normalised chord lengths at the
//!   corners, averaged. The shared knot vector holds each `t_j` with multiplicity `p` (the knot search
//!   never moves or removes them, its other knots fall inside the pieces), so every section curve is
//!   C0 there and its corner point keeps the parameter `t_j` through the parameter correction.
//! - Otherwise (different counts, a periodic seam, parameters given by the caller, a piece of zero
//!   length) nothing is held and the reason is reported; the sections are fitted as without corners.

use super::orient::{extent, Section};
use crate::fit::corners::{corners_at_tolerance, CornerScale};
use crate::nurbs::Vec3;
use serde::Serialize;

/// What became of the sections' inner corners (the surface report's `corners`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct HeldCorners {
    /// True when the corners are held as C0 knot lines (knots of multiplicity `p` at [`Self::params`]).
    pub held: bool,
    /// Inner corners found per section, in input order.
    pub per_section: Vec<usize>,
    /// The common parameters of the held corners (empty when none is held).
    pub params: Vec<f64>,
    /// Why corners that were found are not held (`None` when they are held or none was found).
    pub reason: Option<String>,
}

/// Matched corners: per section the point indices of its inner corners (increasing), and their common
/// parameters (strictly increasing, inside `(0, 1)`).
#[derive(Clone, Debug)]
pub(crate) struct CornerPlan {
    pub(crate) indices: Vec<Vec<usize>>,
    pub(crate) params: Vec<f64>,
}

impl CornerPlan {
    /// Per section, the held `(point index, parameter)` pairs, for the parameter correction.
    pub(crate) fn held_params(&self) -> Vec<Vec<(usize, f64)>> {
        self.indices
            .iter()
            .map(|idx| {
                idx.iter()
                    .copied()
                    .zip(self.params.iter().copied())
                    .collect()
            })
            .collect()
    }
}

/// The corners of one section at the tolerance's scale, split into the seam's and the inner ones.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SectionCorners {
    /// A closed section has a corner at its seam: at its first point, at either neighbour, or
    /// within one tangent window (arc length, [`CornerScale`]) of it. Always false when open.
    pub(crate) at_seam: bool,
    /// Point indices of the inner corners (increasing): the ends of an open section and the
    /// seam's corners of a closed one excluded.
    pub(crate) inner: Vec<usize>,
}

/// The corners of `section` at tolerance `tol` ([`SectionCorners`]). On a closed section a corner
/// found within one tangent window of the seam is the seam's own corner, found a point or two off
/// (noisy or thinned sections): the detector would merge it into the seam's run.
///
/// The points are first scaled to unit extent about their first point (as the curve side detects on
/// its normalised data), so the decision does not depend on the section's size. On sparse data the
/// windows are single chords and the test is the chord turning angle; on dense noisy data it is
/// judged over tolerance-sized windows, so the noise alone never makes a corner.
pub(crate) fn section_corners(section: &Section, angle_deg: f64, tol: f64) -> SectionCorners {
    let m = section.points.len();
    let ext = extent(&section.points);
    if !(ext > 0.0 && ext.is_finite()) || m < 3 {
        return SectionCorners::default();
    }
    let origin = section.points[0];
    let pts: Vec<Vec3> = section.points.iter().map(|&p| (p - origin) / ext).collect();
    let tol = tol / ext;
    if section.closed && m > 3 {
        let distinct = &pts[..m - 1];
        let n = distinct.len();
        let found = corners_at_tolerance(distinct, true, angle_deg, tol);
        if found.is_empty() {
            return SectionCorners::default();
        }
        let window = CornerScale::measure(distinct, tol, angle_deg).window;
        let chords = cumulative_chords(&pts);
        let total = chords[m - 1];
        let near_seam =
            |k: usize| k <= 1 || k + 1 >= n || chords[k].min(total - chords[k]) <= window;
        SectionCorners {
            at_seam: found.iter().any(|&k| near_seam(k)),
            inner: found
                .into_iter()
                .filter(|&k| k > 0 && chords[k].min(total - chords[k]) > window)
                .collect(),
        }
    } else {
        SectionCorners {
            at_seam: false,
            inner: corners_at_tolerance(&pts, false, angle_deg, tol)
                .into_iter()
                .filter(|&k| k > 0 && k + 1 < m)
                .collect(),
        }
    }
}

/// Cumulative chord lengths of `points` (first 0).
pub(crate) fn cumulative_chords(points: &[Vec3]) -> Vec<f64> {
    let mut s = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    s.push(0.0);
    for w in points.windows(2) {
        acc += w[0].distance(w[1]);
        s.push(acc);
    }
    s
}

/// What allows or forbids holding corners besides the corners themselves.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CornerFreedom {
    /// The shared knot vector is clamped (a periodic one holds no corner).
    pub(crate) clamped: bool,
    /// The caller fixed the point parameters.
    pub(crate) params_given: bool,
    /// The caller switched holding off.
    pub(crate) switched_off: bool,
}

/// The inner corners of every section and, when they can be held, the plan to hold them (module doc).
pub(crate) fn plan_corners(
    sections: &[Section],
    angle_deg: f64,
    tol: f64,
    freedom: CornerFreedom,
) -> (HeldCorners, Option<CornerPlan>) {
    let indices: Vec<Vec<usize>> = sections
        .iter()
        .map(|s| section_corners(s, angle_deg, tol).inner)
        .collect();
    let per_section: Vec<usize> = indices.iter().map(Vec::len).collect();
    let not_held = |reason: Option<String>| {
        let report = HeldCorners {
            held: false,
            per_section: per_section.clone(),
            params: Vec::new(),
            reason,
        };
        (report, None)
    };
    if per_section.iter().all(|&c| c == 0) {
        return not_held(None);
    }
    if per_section.iter().any(|&c| c != per_section[0]) {
        return not_held(Some(format!(
            "the sections have different numbers of inner corners ({per_section:?}): they are \
             smoothed over"
        )));
    }
    if freedom.switched_off {
        return not_held(Some("holding corners is switched off".into()));
    }
    if !freedom.clamped {
        return not_held(Some(
            "the sections are fitted periodically (smooth seams): inner corners are smoothed over"
                .into(),
        ));
    }
    if freedom.params_given {
        return not_held(Some(
            "the section parameters were given: inner corners are smoothed over".into(),
        ));
    }
    let c = per_section[0];
    let mut sums = vec![0.0; c];
    for (s, idx) in sections.iter().zip(&indices) {
        let chords = cumulative_chords(&s.points);
        let total = chords.last().copied().unwrap_or(0.0);
        let mut prev = 0.0;
        for (sum, &k) in sums.iter_mut().zip(idx) {
            let t = chords[k] / total;
            if !(t > prev && t < 1.0) {
                return not_held(Some(
                    "a piece between corners has zero length: inner corners are smoothed over"
                        .into(),
                ));
            }
            prev = t;
            *sum += t;
        }
    }
    let params: Vec<f64> = sums.iter().map(|s| s / sections.len() as f64).collect();
    let report = HeldCorners {
        held: true,
        per_section,
        params: params.clone(),
        reason: None,
    };
    (report, Some(CornerPlan { indices, params }))
}

/// Piecewise chord-length parameters of `points` whose corners at `corners` (increasing point indices)
/// take the parameters `at` (module doc). The pieces have positive length ([`plan_corners`] checked).
pub(crate) fn piecewise_params(points: &[Vec3], corners: &[usize], at: &[f64]) -> Vec<f64> {
    let m = points.len();
    let chords = cumulative_chords(points);
    let mut ends: Vec<(usize, f64)> = vec![(0, 0.0)];
    ends.extend(corners.iter().copied().zip(at.iter().copied()));
    ends.push((m - 1, 1.0));
    let mut t = vec![0.0; m];
    for w in ends.windows(2) {
        let ((a, ta), (b, tb)) = (w[0], w[1]);
        let len = chords[b] - chords[a];
        for i in a..=b {
            t[i] = ta + (tb - ta) * (chords[i] - chords[a]) / len;
        }
        // exact values at the piece ends: the corner's parameter is its knot
        t[a] = ta;
        t[b] = tb;
    }
    t
}

/// Keeps corrected parameters inside their pieces: each held point `(k, t)` gets `t` back, every
/// point between two held ones stays between their parameters (a point never crosses a corner).
pub(crate) fn hold_params(params: &mut [f64], held: &[(usize, f64)]) {
    if held.is_empty() {
        return;
    }
    let m = params.len();
    let mut ends: Vec<(usize, f64)> = vec![(0, params[0])];
    ends.extend_from_slice(held);
    ends.push((m - 1, params[m - 1]));
    for w in ends.windows(2) {
        let ((a, ta), (b, tb)) = (w[0], w[1]);
        for u in &mut params[a..=b] {
            *u = u.clamp(ta, tb);
        }
    }
    for &(k, t) in held {
        params[k] = t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_keep_their_points() {
        let pts: Vec<Vec3> = (0..7).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
        let t = piecewise_params(&pts, &[2, 4], &[0.5, 0.6]);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[2], 0.5);
        assert_eq!(t[4], 0.6);
        assert_eq!(t[6], 1.0);
        assert!((t[1] - 0.25).abs() < 1e-15 && (t[5] - 0.8).abs() < 1e-15);
        let mut u = vec![0.0, 0.7, 0.4, 0.3, 0.65, 0.5, 1.0];
        hold_params(&mut u, &[(2, 0.5), (4, 0.6)]);
        assert_eq!(u, vec![0.0, 0.5, 0.5, 0.5, 0.6, 0.6, 1.0]);
    }
}
