//! The band-fairing passes after the first pass and the polish.
//!
//! The first pass often stops by small gains with `μ` grown and guard rows piled up. A second pass
//! from the polished curve ([`refair`]: fresh `μ`, guard and sign targets) gets past that point;
//! when it is kept, a third one holds the present curvature-extrema pattern (persistence
//! [`BandTuning::hold_persistence`]): the persistence-simplified targets can ask for extrema the
//! band does not let go, and their unmet penalty then stops a pass early. After a first pass that
//! stalled (no step of its last subproblem accepted) no later pass runs.
//!
//! Invariant: a later pass is kept only when it lowers `F`, adds no curvature extrema and keeps
//! every point within the tolerance; otherwise the workspace is restored.

use super::super::control_map::ControlMap;
use super::super::extrema::ExtremaCount;
use super::super::tuning::BandTuning;
use super::band_fair_counted;
use super::options::{BandFaired, BandOptions};
use crate::optim::search::objective::{CandidateEval, EvalWorkspace, FitData};

/// The passes after the first band fairing pass (options `bo`, outcome `first`) and a polish, with
/// the default [`BandTuning`]: see [`later_passes_tuned`].
pub fn later_passes(bo: &BandOptions, first: &BandFaired) -> Option<(BandOptions, BandOptions)> {
    later_passes_tuned(bo, first, &BandTuning::default())
}

/// The options of the second pass ([`refair`]; at most [`BandTuning::refair_solves`]
/// subproblems) and of the pass holding the extrema pattern ([`BandTuning::hold_persistence`],
/// the same budget); `None` when no second pass runs (after a stalled first pass, or with no
/// budget).
pub fn later_passes_tuned(
    bo: &BandOptions,
    first: &BandFaired,
    tuning: &BandTuning,
) -> Option<(BandOptions, BandOptions)> {
    if first.stalled {
        return None;
    }
    let solves = bo.max_solves.min(tuning.refair_solves);
    if solves == 0 {
        return None;
    }
    let second = BandOptions {
        max_solves: solves,
        ..bo.clone()
    };
    let hold = BandOptions {
        extrema_persistence: tuning.hold_persistence,
        ..second.clone()
    };
    Some((second, hold))
}

/// A second band-fairing pass from a finished (band-faired and polished) curve in `ws`: a fresh
/// start (Levenberg–Marquardt `μ`, extrema guard and sign targets taken from the polished curve)
/// gets past where the first pass stopped by small gains; the first pass's multiplier and guard
/// rows had made its last steps tiny. The pass is kept only when it lowers `F`, adds no
/// curvature extrema ([`ExtremaCount`]) and keeps every point within `tol`; else `ws` is left as
/// it was. Returns the kept curve's measurement.
pub fn refair(
    data: &FitData,
    ws: &mut EvalWorkspace,
    before: &CandidateEval,
    tol: f64,
    opts: &BandOptions,
) -> Option<CandidateEval> {
    let mut counter = ExtremaCount::new(&ws.knots, data.degree, ws.ctrl.len(), data.planar);
    let extrema = counter.count(&ws.ctrl);
    let saved = ws.clone();
    let start = ws.foot_params.clone();
    let map = ControlMap::open_for(ws.ctrl.len(), data, opts.ends);
    let r = band_fair_counted(data, ws, &start, tol, opts, &map, Some(&mut counter));
    if r.steps > 0
        && r.eval.solved
        && r.eval.fairness < before.fairness
        && r.eval.max_deviation <= tol
        && counter.count(&ws.ctrl) <= extrema
    {
        Some(r.eval)
    } else {
        *ws = saved;
        None
    }
}
