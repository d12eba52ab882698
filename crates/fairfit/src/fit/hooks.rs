//! End hooks of open least-squares fits: with few control points (smoothing makes that likely) a fit
//! can fold a near-cusp at an open end inside the tolerance. Two kinds are caught, both measured
//! against the data's end direction (the chord to the first point two tolerances away, above the
//! noise):
//!
//! - the end derivative points against the data (speed ~1 % of the mean, F ~ 1e15 and up);
//! - a mild hook: the end direction is turned more than [`HOOK_ANGLE_DEG`] from the data's while the
//!   end speed is below [`HOOK_SPEED_RATIO`] of the data's speed there (e387 with smoothing 1e-7:
//!   26° and 0.26, F_j of the end span 3e6 times the median span's). Clean fits of the 33 benchmark
//!   curves stay within 11° and, when turned at all, above 0.86 of the data's speed.

use crate::nurbs::{NurbsCurve, Vec3};

/// Turning (degrees) of the end direction from the data's beyond which a slow end is a hook.
pub const HOOK_ANGLE_DEG: f64 = 15.0;
/// End speed, relative to the data's `|chord| / Δū` at that end, below which a turned end is a hook.
pub const HOOK_SPEED_RATIO: f64 = 0.5;

/// The index of the first point (from the start, or from the end when `from_end`) at least twice the
/// tolerance away from the end point, so that the chord to it gives the data's end direction above
/// the noise (the far end when no point is that far).
pub(crate) fn end_chord_index(pts: &[Vec3], from_end: bool, tol: f64) -> usize {
    let m = pts.len() - 1;
    let far_enough = |k: usize, end: usize| (pts[k] - pts[end]).norm() >= 2.0 * tol;
    if from_end {
        (0..m).rev().find(|&k| far_enough(k, m)).unwrap_or(0)
    } else {
        (1..=m).find(|&k| far_enough(k, 0)).unwrap_or(m)
    }
}

/// Whether an end derivative `d` is a hook against the data's chord `c` covering `du` of parameter.
fn is_hook(d: Vec3, c: Vec3, du: f64) -> bool {
    let dot = d.dot(c);
    if dot < 0.0 {
        return true;
    }
    let (dn, cn) = (d.norm(), c.norm());
    if dn == 0.0 || cn == 0.0 || du <= 0.0 {
        return false;
    }
    let turned = dot < dn * cn * HOOK_ANGLE_DEG.to_radians().cos();
    turned && dn < HOOK_SPEED_RATIO * cn / du
}

/// Whether the curve leaves its start / enters its end with a hook (see the module docs); `params`
/// are the points' parameters on the curve.
pub(crate) fn end_hooks(
    curve: &NurbsCurve,
    pts: &[Vec3],
    params: &[f64],
    tol: f64,
) -> (bool, bool) {
    let (a, b) = curve.domain();
    let m = pts.len() - 1;
    let mut d = [Vec3::ZERO; 2];
    curve.derivatives_into(a, 1, &mut d);
    let k = end_chord_index(pts, false, tol);
    let start = is_hook(d[1], pts[k] - pts[0], params[k] - params[0]);
    curve.derivatives_into(b, 1, &mut d);
    let k = end_chord_index(pts, true, tol);
    let end = is_hook(d[1], pts[m] - pts[k], params[m] - params[k]);
    (start, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reversed_slow_and_turned_ends_are_hooks_others_not() {
        let c = Vec3::new(1.0, 0.0, 0.0);
        // data speed |c| / du = 10
        assert!(is_hook(Vec3::new(-5.0, 0.1, 0.0), c, 0.1));
        // 30° turned at 0.3 of the data's speed: a hook
        let t = 30f64.to_radians();
        assert!(is_hook(Vec3::new(t.cos(), t.sin(), 0.0) * 3.0, c, 0.1));
        // the same turn at 0.9 of the speed, or 10° at 0.3: not
        assert!(!is_hook(Vec3::new(t.cos(), t.sin(), 0.0) * 9.0, c, 0.1));
        let t = 10f64.to_radians();
        assert!(!is_hook(Vec3::new(t.cos(), t.sin(), 0.0) * 3.0, c, 0.1));
    }
}
