//! The seam of closed sections: whether it is smooth, so the sections are fitted and skinned
//! periodically in u (an unclamped periodic knot vector whose last `p` control points repeat the first:
//! the surface is `C^(p−1)` across `u = 0 ≡ 1`), or a deliberate C0 edge; and how continuous a surface
//! is across it.
//!
//! A seam is smooth when every section is closed and none has a corner at or next to its (aligned)
//! start: a turn above the corner angle (default 60°) judged at the tolerance's scale by the curve
//! side's detector ([`crate::fit::corners::corners_at_tolerance`], through
//! [`super::section_corners`]): at its first point, at either neighbour, or within one tangent
//! window of it. On sparse sections that is the chord turning angle at the point and its two
//! neighbours; on dense noisy ones (cloud slices, scans) the noise alone never makes the seam a
//! corner, so a smooth scanned ring is not given a crease. Open sections or a corner at any
//! section's seam (a sharp trailing edge) keep the clamped fit whose ends meet there (C0).

use super::orient::Section;
use super::section_corners::section_corners;
use crate::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};
use serde::Serialize;

/// True when `section` is closed and has no corner at its seam at tolerance `tol` (module doc).
pub(crate) fn smooth_at_seam(section: &Section, corner_angle_deg: f64, tol: f64) -> bool {
    section.closed
        && section.points.len() >= 5
        && !section_corners(section, corner_angle_deg, tol).at_seam
}

/// True when all `sections` are smooth at their seams at tolerance `tol` (see the module documentation).
pub fn periodic_seam(sections: &[Section], corner_angle_deg: f64, tol: f64) -> bool {
    !sections.is_empty()
        && sections
            .iter()
            .all(|s| smooth_at_seam(s, corner_angle_deg, tol))
}

/// Discontinuity of a surface across its u seam, over iso-curves `v = const`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SeamContinuity {
    /// Largest angle (radians) between the u tangents `S_u` at the two ends of the u domain.
    pub max_tangent_angle: f64,
    /// Largest relative jump `|κ_0 − κ_1| / max(κ_0, κ_1)` of the curvature of the u iso-curves.
    pub max_curvature_jump: f64,
}

/// The seam discontinuity of `surface` between `u = u_0` and `u = u_1` (the ends of its u domain) at
/// `samples + 1` equally spaced v (ends included). Meaningful when the surface is closed in u.
pub fn seam_continuity(surface: &NurbsSurface, samples: usize) -> SeamContinuity {
    let (v0, v1) = surface.domain_v();
    let n = samples.max(1);
    let vs: Vec<f64> = (0..=n)
        .map(|k| v0 + (v1 - v0) * k as f64 / n as f64)
        .collect();
    seam_continuity_at(surface, &vs)
}

/// The seam discontinuity of `surface` (see [`seam_continuity`]) on the iso-curves at `vs` only, e.g.
/// at the closed sections of a surface lofted through closed and open sections.
pub fn seam_continuity_at(surface: &NurbsSurface, vs: &[f64]) -> SeamContinuity {
    let (u0, u1) = surface.domain_u();
    let mut ws = SurfaceWorkspace::new(surface, 2);
    let (mut a, mut b) = ([Vec3::ZERO; 9], [Vec3::ZERO; 9]);
    let mut out = SeamContinuity::default();
    let kappa = |d: &[Vec3; 9]| {
        let (d1, d2) = (d[3], d[6]);
        let l = d1.norm();
        if l > 0.0 {
            d1.cross(d2).norm() / (l * l * l)
        } else {
            0.0
        }
    };
    for &v in vs {
        surface.derivatives_with(u0, v, 2, &mut ws, &mut a);
        surface.derivatives_with(u1, v, 2, &mut ws, &mut b);
        let (ta, tb) = (a[3], b[3]);
        let (la, lb) = (ta.norm(), tb.norm());
        if la > 0.0 && lb > 0.0 {
            let angle = ta.cross(tb).norm().atan2(ta.dot(tb));
            out.max_tangent_angle = out.max_tangent_angle.max(angle);
        }
        let (ka, kb) = (kappa(&a), kappa(&b));
        if ka.max(kb) > 0.0 {
            out.max_curvature_jump = out.max_curvature_jump.max((ka - kb).abs() / ka.max(kb));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loop_points(f: impl Fn(f64) -> Vec3, n: usize) -> Section {
        Section::closed_loop(
            (0..n)
                .map(|i| f(std::f64::consts::TAU * i as f64 / n as f64))
                .collect(),
        )
    }

    #[test]
    fn circles_are_smooth_a_teardrop_is_not() {
        let circle = loop_points(|t| Vec3::new(t.cos(), t.sin(), 0.0), 40);
        assert!(smooth_at_seam(&circle, 60.0, 1e-3));
        // a teardrop with its tip (a 90° turn) at the start
        let drop = loop_points(
            |t| {
                let r = (0.5 * t).sin().abs() + 1e-3;
                Vec3::new(-r * t.cos() + 1.0, r * t.sin(), 0.0)
            },
            40,
        );
        assert!(!smooth_at_seam(&drop, 60.0, 1e-3));
        let mut open = circle.clone();
        open.points.pop();
        open.closed = false;
        assert!(!smooth_at_seam(&open, 60.0, 1e-3));
        assert!(!periodic_seam(&[circle.clone(), open], 60.0, 1e-3));
        assert!(periodic_seam(&[circle.clone(), circle], 60.0, 1e-3));
    }

    /// Deterministic noise in `[-1, 1]` (a hash of `i`).
    fn jitter(i: usize) -> f64 {
        let x = (i as f64 * 12.9898).sin() * 43_758.545_312_3;
        2.0 * (x - x.floor()) - 1.0
    }

    #[test]
    fn a_dense_noisy_ring_is_smooth_at_its_seam_at_the_tolerance_scale() {
        // 20,000 points of a unit circle, noise of tol/10 along the radius: neighbouring chords
        // turn by far more than 60° (the chord rule finds corners at the seam), the tolerance's
        // windows do not
        let tol = 1e-3;
        let ring = loop_points(|t| Vec3::new(t.cos(), t.sin(), 0.0), 20_000);
        let noisy = Section::closed_loop(
            ring.points[..ring.points.len() - 1]
                .iter()
                .enumerate()
                .map(|(i, &p)| p * (1.0 + 0.17 * tol * jitter(i)))
                .collect(),
        );
        let distinct = &noisy.points[..noisy.points.len() - 1];
        let chord = crate::fit::shape::detect_corners(distinct, true, 60.0);
        assert!(chord.len() > 100, "{}", chord.len());
        assert!(smooth_at_seam(&noisy, 60.0, tol));
        // the same noise on a teardrop keeps its tip a corner
        let drop = loop_points(
            |t| {
                let r = (0.5 * t).sin().abs() + 1e-3;
                Vec3::new(-r * t.cos() + 1.0, r * t.sin(), 0.0)
            },
            20_000,
        );
        let noisy_drop = Section::closed_loop(
            drop.points[..drop.points.len() - 1]
                .iter()
                .enumerate()
                .map(|(i, &p)| p + Vec3::new(0.0, 0.17 * tol * jitter(i), 0.0))
                .collect(),
        );
        assert!(!smooth_at_seam(&noisy_drop, 60.0, tol));
    }
}
