//! Re-measuring the curve after a move of one control point: only the spans the point
//! touches get new power-form coefficients and fairness parts, and only the data points whose feet
//! lie there are projected again.

use super::deviation::{deviation_totals, is_flat, project, project_planar_any};
use super::fairness::{fairness_totals, span_energy_length};
use super::power_form::{ensure_span_ders, span_power_coefs_cached};
use super::{CandidateEval, EvalWorkspace, FitData};

/// Re-measures the curve in `ws` after a change of the single control point `ws.ctrl[r]`, reusing
/// everything the move cannot change: only the `p + 1` spans holding `P_r` get new power-form
/// coefficients and fairness parts, and only the data points whose foot parameter (in `start`, the
/// feet on the curve before the move) lies in those spans are projected again (Newton from `start`).
/// `ws` must hold the full measurement ([`measure_current`](super::measure_current)) of the curve before the move (restore it
/// with [`EvalWorkspace::load_state`] after a rejected move). With `with_deviation = false` only the
/// fairness is updated (the deviations are reported as infinite).
pub fn measure_move(
    data: &FitData,
    r: usize,
    start: &[f64],
    with_deviation: bool,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    let give_up = if with_deviation {
        f64::INFINITY
    } else {
        f64::NAN
    };
    measure_move_within(data, r, start, give_up, ws)
}

/// [`measure_move`] with the deviations, except that the projections stop at the first data point
/// farther than `give_up` from the moved curve (its distance is then reported as the maximum, the
/// RMS as infinite, and `ws` is left part-updated: restore it): a move that must stay within
/// `give_up` is rejected either way. `give_up = NaN`: no deviations.
pub fn measure_move_within(
    data: &FitData,
    r: usize,
    start: &[f64],
    give_up: f64,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    let p = data.degree;
    if !ws.ctrl[r].is_finite() || ws.breaks.is_empty() || ws.dev2.len() != data.points.len() {
        return CandidateEval::failed();
    }
    // power-form spans j whose knot span s satisfies r <= s <= r + p
    let j0 = ws.break_knot.partition_point(|&s| s < r);
    let j1 = ws.break_knot.partition_point(|&s| s <= r + p);
    if j0 >= j1 {
        return CandidateEval::failed();
    }
    ensure_span_ders(p, ws);
    for j in j0..j1 {
        span_power_coefs_cached(p, ws.break_knot[j], j * (p + 1), ws);
        let (e, len) = span_energy_length(data, ws, j);
        ws.span_energy[j] = e;
        ws.span_length[j] = len;
    }
    let (fairness, max_span_fairness) = fairness_totals(ws);
    let e = CandidateEval {
        solved: true,
        max_deviation: f64::INFINITY,
        rms_deviation: f64::INFINITY,
        fairness,
        max_span_fairness,
    };
    if give_up.is_nan() {
        e
    } else {
        measure_move_deviations(data, r, start, give_up, e, ws)
    }
}

/// The deviations part of [`measure_move_within`] for a move whose fairness part `e` (a
/// [`measure_move_within`] with `give_up = NaN`) has just updated the power form in `ws`.
pub fn measure_move_deviations(
    data: &FitData,
    r: usize,
    start: &[f64],
    give_up: f64,
    e: CandidateEval,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    let p = data.degree;
    if !e.solved {
        return e;
    }
    let j0 = ws.break_knot.partition_point(|&s| s < r);
    let j1 = ws.break_knot.partition_point(|&s| s <= r + p);
    let a = ws.breaks[j0];
    let b = ws.breaks.get(j1).copied().unwrap_or(1.0);
    let far = with_projection!(data, ws, |proj| move_pass(
        data,
        start,
        (a, b),
        j0,
        give_up,
        ws,
        proj
    ));
    if let Some(d) = far {
        return CandidateEval {
            max_deviation: d,
            ..e
        };
    }
    let (max_deviation, rms_deviation) = deviation_totals(&ws.dev2);
    CandidateEval {
        max_deviation,
        rms_deviation,
        ..e
    }
}

/// The loop of [`measure_move_deviations`]: projects the data points whose `start` parameter
/// lies in `[a, b]` by `proj(k, u, ws, hint)` (from span `hint`); the distance of the first point
/// farther than `give_up`, if any.
#[inline(always)]
pub(super) fn move_pass(
    data: &FitData,
    start: &[f64],
    (a, b): (f64, f64),
    mut hint: usize,
    give_up: f64,
    ws: &mut EvalWorkspace,
    proj: impl Fn(usize, f64, &EvalWorkspace, &mut usize) -> (f64, f64),
) -> Option<f64> {
    for k in 1..data.points.len().saturating_sub(1) {
        let u = start[k];
        if u >= a && u <= b {
            let (mut best, best_u) = proj(k, u, ws, &mut hint);
            if !data.bands.is_none() {
                // the weighted deviation (`PointBands`)
                best *= data.bands.factor(k).powi(2);
            }
            ws.foot_params[k] = best_u;
            ws.dev2[k] = best;
            if best.sqrt() > give_up {
                return Some(best.sqrt());
            }
        }
    }
    None
}
