//! The unconstrained fit as a start for a fit under end conditions (issue 26).
//!
//! **What.** A fit under G1/G2 end conditions ([`crate::fit::end_constraints`]) searches its knots
//! with the conditions in every least-squares solve, the legs `α`, `β` of the fixed control points
//! taken from each candidate's unconstrained solve. Those legs are the least-squares curve's, not
//! a fair curve's, so at the unconstrained fit's count the constrained candidates are often less
//! fair or outside the band, and the search moves to more control points. [`from_unconstrained`]
//! gives the pipeline a second candidate: the unconstrained fit `U` (its knots and count), with
//! its end control points moved onto the conditions, legs measured on `U` itself
//! (`fixed_start`/`fixed_end`, the linearisation the search uses), then finished like any
//! candidate (band fairing, polish, re-fairing, the conditions' control points held).
//!
//! **Why it helps.** When `U` nearly meets the conditions, the move is small and the finished
//! curve keeps `U`'s count and nearly its `F`; when `U` meets them exactly (conditions taken from
//! `U`'s own ends) it is `U` to rounding. [`prefer`] keeps one of the two by the count search's
//! rule: the fewer curvature extrema, then the fairer at the rule's price per control point
//! ([`crate::optim::tuning::CountTuning::extra_point_gain`]).
//!
//! Invariants: the candidate holds the conditions exactly as the search's curves do (its fixed
//! control points are set by the same functions and never moved), and it is taken only when it
//! meets the tolerance.

use crate::fit::end_constraints::{end_gaps, fixed_end, fixed_start};
use crate::fit::max_orthogonal_deviation;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::{band_solves, tolerance_of};
use crate::optim::kind::open::{finish_measured, Finishing};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::objective::{measure_current, EvalWorkspace};
use crate::optim::search::prepare::Prepared;
use crate::optim::stages::count_choice::choose_count;
use crate::optim::stages::count_search::rank_fit;
use crate::optim::tuning::CountTuning;

/// The unconstrained fit `free` (of the same data, input coordinates) moved onto the end
/// conditions of `prep.data.ends` and finished under them (module docs); `None` when the
/// conditions do not fit its control points or the finished curve misses the tolerance.
pub(crate) fn from_unconstrained(
    prep: &Prepared,
    free: &IntegratedResult,
    opts: &IntegratedOptions,
) -> Option<IntegratedResult> {
    let curve = &free.curve;
    let p = curve.degree();
    let knots = curve.knots().to_vec();
    let (d0, d1) = curve.domain();
    if curve.is_rational() || d0 != 0.0 || d1 != 1.0 {
        return None;
    }
    let ends = &prep.data.ends;
    let n = curve.n_control_points();
    ends.check_room(p, n).ok()?;
    let mut ctrl: Vec<Vec3> = curve
        .control_points()
        .iter()
        .map(|&c| (c - prep.origin) / prep.scale)
        .collect();
    let pts = &prep.data.points;
    let (q0, qm) = (*pts.first()?, *pts.last()?);
    let (g0, g1) = (end_gaps(p, &knots, false)?, end_gaps(p, &knots, true)?);
    let (mut start, mut end) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
    let planar = prep.data.planar;
    let lo = fixed_start(&ends.start, p, g0, q0, &ctrl, planar, &mut start)?;
    let hi = fixed_end(&ends.end, p, g1, qm, &ctrl, planar, &mut end)?;
    ctrl[..lo].copy_from_slice(&start[..lo]);
    for (j, e) in end[..hi].iter().enumerate() {
        ctrl[n - 1 - j] = *e;
    }
    let mut prep = prep.clone();
    prep.data.degree = p;
    // the feet on the moved curve, by the robust projector (the curve's parameters are not the
    // data's after fairing)
    let moved = NurbsCurve::bspline(p, knots.clone(), ctrl.clone()).ok()?;
    let feet = max_orthogonal_deviation(&moved, &prep.data.points, &[]).params;
    let mut ws = EvalWorkspace::default();
    (ws.knots, ws.ctrl) = (knots, ctrl);
    let e = measure_current(&prep.data, &feet, &mut ws);
    if !e.solved {
        return None;
    }
    ws.foot_params = feet;
    let tol = tolerance_of(opts, prep.scale);
    let finishing = Finishing {
        tol,
        span_cap: opts.span_fairness,
        band_solves: band_solves(opts),
        polish_evaluations: opts.polish_evaluations,
    };
    let (curve, quality, _) = finish_measured(&prep, ws, e, p, Some(finishing)).ok()?;
    let met = quality.max_deviation <= tol * prep.scale
        && opts
            .span_fairness
            .is_none_or(|t| quality.max_span_fairness <= t);
    met.then(|| IntegratedResult {
        curve,
        quality,
        met,
        screening: Default::default(),
        ..free.clone()
    })
}

/// Whether `warm` is to be kept over `searched` (both meeting the tolerance): by the count
/// search's own rule ([`choose_count`]): the fewer curvature extrema first, then the lower `F`,
/// each control point more pricing `F` by the factor [`CountTuning::extra_point_gain`]; a tie
/// keeps `searched`.
pub(crate) fn prefer(
    warm: &IntegratedResult,
    searched: &IntegratedResult,
    t: &CountTuning,
) -> bool {
    if !warm.met {
        return false;
    }
    if !searched.met {
        return true;
    }
    let counts = [
        searched.curve.n_control_points(),
        warm.curve.n_control_points(),
    ];
    choose_count(&counts, &[rank_fit(searched), rank_fit(warm)], t) == 1
}
