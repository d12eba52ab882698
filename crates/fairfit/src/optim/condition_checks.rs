//! Checks of an open fit under end conditions ([`crate::fit::end_constraints`]): why no
//! constrained fit could be made when the conditions are the cause, which end a fit that misses the
//! tolerance fails at, and whether a fit split at corners holds the conditions at its end pieces.
//! Each gives an [`Error::InvalidSetting`] naming the end, the one-line message a front end shows.

use super::result::IntegratedResult;
use super::search::prepare::Prepared;
use crate::errors::Error;
use crate::errors::Result;
use crate::fit::end_constraints::{achieved, EndConstraints};
use crate::nurbs::Vec3;

/// Why no constrained fit could be made, when the conditions are the cause: a least-squares solve
/// with averaging knots and the fewest control points the conditions leave room for (one free)
/// refuses them ([`Error::InvalidSetting`] naming the end); `None` when it does not.
pub(crate) fn condition_error(prep: &Prepared, p: usize) -> Option<Error> {
    let (lo, hi) = prep.data.ends.fixed_points();
    let n = (lo + hi + 1).max(p + 1).min(prep.data.points.len());
    let interior = super::search::prepare::averaging_interior_knots(&prep.data.params, p, n);
    let mut knots = vec![0.0; p + 1];
    knots.extend_from_slice(&interior);
    knots.resize(knots.len() + p + 1, 1.0);
    let mut solver = crate::fit::lsq::LsqSolver::new(p);
    let mut ctrl = Vec::new();
    let d = &prep.data;
    match solver.solve_constrained(
        &d.points,
        &d.params,
        &knots,
        None,
        &Default::default(),
        &d.ends,
        d.planar,
        &mut ctrl,
    ) {
        Err(e @ Error::InvalidSetting { .. }) => Some(e),
        _ => None,
    }
}

/// The error of a constrained fit that misses the tolerance: names the constrained end nearer the
/// worst deviation (the condition leaves the tolerance band there).
pub(crate) fn unmet_condition(
    points: &[Vec3],
    r: &IntegratedResult,
    conditions: &EndConstraints,
) -> Error {
    let d = crate::fit::max_orthogonal_deviation(&r.curve, points, &[]).per_point;
    let half = d.len() / 2;
    let worst = |x: &[f64]| x.iter().copied().fold(0.0, f64::max);
    let (d0, d1) = (worst(&d[..half]), worst(&d[half..]));
    let which = match (conditions.start.is_none(), conditions.end.is_none()) {
        (false, true) => "start",
        (true, false) => "end",
        _ if d0 >= d1 => "start",
        _ => "end",
    };
    Error::InvalidSetting {
        option: which,
        reason: format!(
            "the {which} condition cannot be met within the tolerance {:.3e} (the best constrained fit deviates {:.3e}); check its direction and curvature against the data",
            r.tolerance, r.quality.max_deviation
        ),
    }
}

/// `r` when its end pieces hold the end conditions (to 1e-8 rad and relative curvature: the pieces
/// hold them to rounding). A straight end piece, which could not, is no longer made under a
/// tangent or curvature condition ([`super::corners::corners_for_conditions`]); this is the guard
/// that a piece fitted under a condition did hold it.
pub(crate) fn held_at_corner_pieces(
    r: IntegratedResult,
    conditions: &EndConstraints,
) -> Result<IntegratedResult> {
    for (at_end, c, which) in [
        (false, &conditions.start, "start"),
        (true, &conditions.end, "end"),
    ] {
        let a = achieved(&r.curve, at_end, c);
        if a.tangent_angle > 1e-8 || a.curvature_relative > 1e-8 {
            return Err(Error::InvalidSetting {
                option: which,
                reason: format!(
                    "the {which} condition cannot be held by the piece between the {which} and the nearest corner (tangent off by {:.2e} rad, curvature by {:.2e} relative)",
                    a.tangent_angle, a.curvature_relative
                ),
            });
        }
    }
    Ok(r)
}
