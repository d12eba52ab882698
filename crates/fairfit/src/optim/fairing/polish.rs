//! Local refinement of the control points after the knot search: the swarm and the smoothing line
//! search only reach curves of the form "least squares with smoothing λ on these knots"; this step
//! leaves that family and moves single control points while the true objective `F` decreases and
//! the tolerance holds.
//!
//! The moves are Eck & Hadenfeld's local energy fairing steps (as in [`crate::fair::fairing`]): moving
//! `P_r` alone to the minimiser of the parametric jerk `∫|C'''|² du = Σ G_ij P_i·P_j` is the step
//! `−g_r / G_rr` with `g_r = Σ_j G_rj P_j`. Candidates are ranked by the energy gain `|g_r|² / G_rr` and
//! tried with steps `1, 1/2, 1/4, …`; a move is accepted when `F` (the fast 8-node measure of
//! [`crate::optim::search::objective`]) decreases and the maximum orthogonal deviation stays within the allowance.
//! When no such move helps, one steepest-descent move of `F` itself on a single control point
//! (forward-difference gradient, steps from twice the allowance down) is tried before giving up.
//! Unlike the fit-then-fair baseline this runs on the optimiser's allocation-free power-form evaluator
//! (projections restarted from the last foot parameters), and a trial re-measures only what a move of
//! one control point can change ([`measure_move`]: `p + 1` spans and the data points whose feet lie
//! in them), so hundreds of trials cost milliseconds.
//! Everything is sequential and deterministic (ties broken by index).

use super::control_map::{ControlMap, EndCondition};
use super::extrema::ExtremaCount;
use super::tuning::{PolishTuning, MIN_ACCEPTED_GAIN};
use crate::fair::gram::Gram;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{
    measure_move, measure_move_deviations, CandidateEval, EvalWorkspace, FitData, MeasureState,
    MAX_DEGREE,
};

/// Settings of [`polish`].
#[derive(Clone, Debug, PartialEq)]
pub struct PolishOptions {
    /// Most accepted moves.
    pub max_moves: usize,
    /// Candidates (by decreasing energy gain) tried per move before giving up.
    pub max_candidates: usize,
    /// Step halvings tried per candidate after the full step.
    pub step_halvings: usize,
    /// Most curve measurements in total.
    pub max_evaluations: usize,
    /// A per-span fairness target `F*`: moves may not raise `max_j F_j` above it (or above the
    /// starting curve's, if larger).
    pub span_cap: Option<f64>,
    /// Whether a move may not add curvature extrema (counted as band fairing counts them,
    /// [`ExtremaCount`]): without it, moves that lower `F` put back the small curvature wiggles
    /// band fairing removed.
    pub keep_extrema: bool,
    /// Whether an open curve's end points stay on the data's end points or move within the
    /// tolerance ([`EndCondition`]; [`polish`] only, a mapped call takes its map's).
    pub ends: EndCondition,
}

impl PolishOptions {
    /// The options with the defaults of `tuning` (no span cap, extrema kept, ends pinned).
    pub fn tuned(tuning: &PolishTuning) -> Self {
        PolishOptions {
            max_moves: tuning.max_moves,
            max_candidates: tuning.max_candidates,
            step_halvings: tuning.step_halvings,
            max_evaluations: tuning.max_evaluations,
            span_cap: None,
            keep_extrema: true,
            ends: EndCondition::Pinned,
        }
    }
}

impl Default for PolishOptions {
    fn default() -> Self {
        PolishOptions::tuned(&PolishTuning::default())
    }
}

/// A move may not add curvature extrema (when switched on).
struct ExtremaGuard {
    counter: Option<ExtremaCount>,
    current: usize,
}

impl ExtremaGuard {
    /// Whether the curve with control points `ctrl`, the current one with the control points of
    /// movable point `v` of `map` moved, has no more extrema than the current one; the caller
    /// accepts the move when this holds, so its count becomes the current one (only the samples
    /// of the spans the move reaches are evaluated again).
    fn admits(&mut self, ctrl: &[Vec3], map: &ControlMap, v: usize) -> bool {
        let Some(counter) = self.counter.as_mut() else {
            return true;
        };
        let col = map.col(v);
        let lo = col.iter().map(|c| c.0).min().unwrap_or(0);
        let hi = col.iter().map(|c| c.0).max().unwrap_or(0);
        let k = counter.count_moved(ctrl, lo..=hi);
        if k > self.current {
            counter.revert();
            return false;
        }
        self.current = k;
        true
    }
}

/// The outcome of [`polish`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polished {
    /// The measurement of the polished curve (left in the workspace).
    pub eval: CandidateEval,
    /// Accepted moves.
    pub moves: usize,
    /// Curve measurements spent.
    pub evaluations: usize,
}

/// Polishes the control points in `ws.ctrl` (knots `ws.knots` fixed, end points fixed unless
/// [`PolishOptions::ends`] frees them) so that `F` decreases while the maximum orthogonal deviation
/// stays at most `allowed` (or the starting curve's, if larger). `start` holds the data's parameters on the current curve (projection seeds).
/// On return `ws` holds the polished curve, its power form and foot parameters.
pub fn polish(
    data: &FitData,
    ws: &mut EvalWorkspace,
    start: &[f64],
    allowed: f64,
    opts: &PolishOptions,
) -> Polished {
    let map = ControlMap::open_for(ws.ctrl.len(), data, opts.ends);
    polish_mapped(data, ws, start, allowed, opts, &map)
}

/// Re-measures the curve in `ws` after a move of movable point `v` of `map`: incrementally
/// ([`measure_move`]) when it moves one clamped control point, else in full.
fn measure_moved(
    data: &FitData,
    map: &ControlMap,
    v: usize,
    start: &[f64],
    with_deviation: bool,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    match map.col(v) {
        [(j, _)] => {
            let e = measure_move(data, *j, start, with_deviation, ws);
            map.with_seam(e, data, ws)
        }
        _ => map.measure(data, start, ws),
    }
}

/// [`measure_moved`] of a trial move against the current curve `cur`: the deviation (the
/// projections, most of the cost) only when `F` decreases and `max_j F_j` stays within
/// `span_cap`, and only until a point is farther than `allowed`, since a trial failing any of
/// these is rejected anyway (then the deviations are reported infinite, or the first distance
/// beyond `allowed` as the maximum). After band fairing half of the polish's trials fail on `F`
/// and most of the others on the deviation. A move of a seam point (measured in full either
/// way) is measured once.
#[allow(clippy::too_many_arguments)]
fn measure_trial(
    data: &FitData,
    map: &ControlMap,
    v: usize,
    start: &[f64],
    cur: &CandidateEval,
    span_cap: f64,
    allowed: f64,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    if map.col(v).len() != 1 {
        return measure_moved(data, map, v, start, true, ws);
    }
    let e = measure_moved(data, map, v, start, false, ws);
    if e.solved
        && e.max_span_fairness <= span_cap
        && e.fairness < cur.fairness * (1.0 - MIN_ACCEPTED_GAIN)
    {
        let j = map.col(v)[0].0;
        let e = measure_move_deviations(data, j, start, allowed, e, ws);
        map.with_seam(e, data, ws)
    } else {
        e
    }
}

/// Sets the clamped control points moved by movable point `v` to `ctrl` plus `delta` times their
/// coefficient.
fn apply_move(map: &ControlMap, v: usize, ctrl: &[Vec3], delta: Vec3, ws: &mut EvalWorkspace) {
    for &(j, c) in map.col(v) {
        ws.ctrl[j] = ctrl[j] + delta * c;
    }
}

/// Copies the clamped control points moved by movable point `v` from `src` to `dst`.
fn copy_moved(map: &ControlMap, v: usize, src: &[Vec3], dst: &mut [Vec3]) {
    for &(j, _) in map.col(v) {
        dst[j] = src[j];
    }
}

/// [`polish`] moving the movable points of `map` (for a periodic curve every distinct control
/// point, the seam kept `C^(p−1)`; the Eck–Hadenfeld step then minimises the jerk energy over that
/// point), with the data points and measure of `map`.
pub fn polish_mapped(
    data: &FitData,
    ws: &mut EvalWorkspace,
    start: &[f64],
    allowed: f64,
    opts: &PolishOptions,
    map: &ControlMap,
) -> Polished {
    let p = data.degree;
    let n = ws.ctrl.len();
    let mut params = start.to_vec();
    let mut cur = map.measure(data, &params, ws);
    let mut out = Polished {
        eval: cur,
        moves: 0,
        evaluations: 1,
    };
    if !cur.solved || !cur.fairness.is_finite() || n < 3 {
        return out;
    }
    params.copy_from_slice(&ws.foot_params);
    let mut saved = MeasureState::default();
    ws.save_state(&mut saved);
    let allowed = allowed.max(cur.max_deviation);
    let span_cap = opts
        .span_cap
        .map_or(f64::INFINITY, |c| c.max(cur.max_span_fairness));
    let gram = Gram::new(p, &ws.knots, n, p.min(3));
    let mut counter = (opts.keep_extrema && (3..=MAX_DEGREE).contains(&p))
        .then(|| ExtremaCount::new(&ws.knots, p, n, data.planar));
    let current = counter.as_mut().map_or(0, |c| c.count(&ws.ctrl));
    let mut guard = ExtremaGuard { counter, current };
    let mut ctrl: Vec<Vec3> = ws.ctrl.clone();
    let mut candidates: Vec<(f64, usize, Vec3)> = Vec::with_capacity(n);
    'moves: while out.moves < opts.max_moves {
        candidates.clear();
        for v in 0..map.vars() {
            // the jerk energy over z_v: G_vv = Σ c_r c_s G_rs, g_v = Σ c_r (G P)_r
            let col = map.col(v);
            let mut grr = 0.0;
            let mut g = Vec3::ZERO;
            for &(r, c) in col {
                for &(s, d) in col {
                    grr += (c * d) * gram.get(r, s);
                }
                let mut gr = Vec3::ZERO;
                for j in r.saturating_sub(p)..=(r + p).min(n - 1) {
                    gr += ctrl[j] * gram.get(r, j);
                }
                g += gr * c;
            }
            if grr.is_nan() || grr <= 0.0 {
                continue;
            }
            let gain = g.norm_squared() / grr;
            if gain > 0.0 && gain.is_finite() {
                candidates.push((gain, v, g * (-1.0 / grr)));
            }
        }
        candidates.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        for &(_, r, delta) in candidates.iter().take(opts.max_candidates.max(1)) {
            let mut t = 1.0;
            for _ in 0..=opts.step_halvings {
                if out.evaluations >= opts.max_evaluations {
                    break 'moves;
                }
                apply_move(map, r, &ctrl, delta * t, ws);
                t *= 0.5;
                let e = measure_trial(data, map, r, &params, &cur, span_cap, allowed, ws);
                out.evaluations += 1;
                if e.solved
                    && e.max_deviation <= allowed
                    && e.max_span_fairness <= span_cap
                    && e.fairness < cur.fairness * (1.0 - MIN_ACCEPTED_GAIN)
                    && guard.admits(&ws.ctrl, map, r)
                {
                    copy_moved(map, r, &ws.ctrl, &mut ctrl);
                    cur = e;
                    params.copy_from_slice(&ws.foot_params);
                    ws.save_state(&mut saved);
                    out.moves += 1;
                    continue 'moves;
                }
                ws.load_state(&saved);
            }
            copy_moved(map, r, &ctrl, &mut ws.ctrl);
        }
        // no jerk-minimising move helps: steepest descent of F on single control points
        if !gradient_move(
            data,
            ws,
            &mut saved,
            &mut ctrl,
            &mut params,
            &mut cur,
            allowed,
            span_cap,
            opts,
            &mut guard,
            &mut out,
            map,
        ) {
            break;
        }
        out.moves += 1;
    }
    ws.ctrl.copy_from_slice(&ctrl);
    out.eval = map.measure(data, &params, ws);
    out.evaluations += 1;
    out
}

/// One steepest-descent move of `F` on a single control point: the forward-difference gradient of
/// `F` with respect to every movable control point, then, in order of decreasing gradient norm, steps
/// of `2 allowed, allowed, allowed / 2, …` against it; the first one lowering `F` within the
/// allowance is kept. False when none is found (or the evaluation budget is spent).
#[allow(clippy::too_many_arguments)]
fn gradient_move(
    data: &FitData,
    ws: &mut EvalWorkspace,
    saved: &mut MeasureState,
    ctrl: &mut [Vec3],
    params: &mut [f64],
    cur: &mut CandidateEval,
    allowed: f64,
    span_cap: f64,
    opts: &PolishOptions,
    guard: &mut ExtremaGuard,
    out: &mut Polished,
    map: &ControlMap,
) -> bool {
    const H: f64 = 1e-7;
    let n = ctrl.len();
    let dims = if data.planar { 2 } else { 3 };
    let mut grads: Vec<(f64, usize, Vec3)> = Vec::with_capacity(n);
    for r in 0..map.vars() {
        let mut g = Vec3::ZERO;
        for d in 0..dims {
            if out.evaluations >= opts.max_evaluations {
                return false;
            }
            copy_moved(map, r, ctrl, &mut ws.ctrl);
            for &(j, c) in map.col(r) {
                ws.ctrl[j][d] += c * H;
            }
            let e = measure_moved(data, map, r, params, false, ws).fairness;
            ws.load_state(saved);
            out.evaluations += 1;
            g[d] = (e - cur.fairness) / H;
        }
        copy_moved(map, r, ctrl, &mut ws.ctrl);
        let norm = g.norm();
        if norm > 0.0 && norm.is_finite() {
            grads.push((norm, r, g * (-1.0 / norm)));
        }
    }
    grads.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, r, dir) in grads.iter().take(opts.max_candidates.max(1)) {
        let mut t = 2.0 * allowed;
        for _ in 0..=opts.step_halvings {
            if out.evaluations >= opts.max_evaluations {
                copy_moved(map, r, ctrl, &mut ws.ctrl);
                return false;
            }
            apply_move(map, r, ctrl, dir * t, ws);
            t *= 0.5;
            let e = measure_trial(data, map, r, params, cur, span_cap, allowed, ws);
            out.evaluations += 1;
            if e.solved
                && e.max_deviation <= allowed
                && e.max_span_fairness <= span_cap
                && e.fairness < cur.fairness * (1.0 - MIN_ACCEPTED_GAIN)
                && guard.admits(&ws.ctrl, map, r)
            {
                copy_moved(map, r, &ws.ctrl, ctrl);
                *cur = e;
                params.copy_from_slice(&ws.foot_params);
                ws.save_state(saved);
                return true;
            }
            ws.load_state(saved);
        }
        copy_moved(map, r, ctrl, &mut ws.ctrl);
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;
    use crate::optim::search::objective::{evaluate_candidate, set_knots};

    #[test]
    fn polish_lowers_fairness_within_the_tolerance() {
        // a wavy arc y = 0.3 sin(3x) sampled at 80 points, fitted with 9 control points; the
        // polish must lower F while every point stays within tol of the curve, checked by brute
        // force on 200 001 curve samples (independent of the Newton projection used inside)
        let m = 80;
        let points: Vec<Vec3> = (0..m)
            .map(|i| {
                let x = i as f64 / (m - 1) as f64;
                Vec3([x, 0.3 * (3.0 * x).sin() + 0.002 * (i % 3) as f64, 0.0])
            })
            .collect();
        let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
        let data = FitData {
            points: points.clone(),
            params,
            degree: 3,
            planar: true,
            corrections: 1,
            ends: Default::default(),
            bands: Default::default(),
        };
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[0.2, 0.35, 0.5, 0.65, 0.8], &mut ws);
        let before = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
        let tol = 3e-3;
        assert!(before.solved && before.max_deviation < tol);
        let start = ws.foot_params.clone();
        let r = polish(&data, &mut ws, &start, tol, &PolishOptions::default());
        assert!(r.moves > 0);
        assert!(
            r.eval.fairness < 0.95 * before.fairness,
            "{} vs {}",
            r.eval.fairness,
            before.fairness
        );
        let curve = NurbsCurve::bspline(3, ws.knots.clone(), ws.ctrl.clone()).unwrap();
        let samples: Vec<Vec3> = (0..=200_000)
            .map(|i| curve.point(i as f64 / 200_000.0))
            .collect();
        let worst = points
            .iter()
            .map(|q| {
                samples
                    .iter()
                    .map(|s| (*s - *q).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0f64, f64::max);
        assert!(worst <= tol * (1.0 + 1e-6), "{worst} > {tol}");
        assert!((worst - r.eval.max_deviation).abs() < 1e-3 * tol + 1e-9);
    }
}
