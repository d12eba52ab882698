//! The per-candidate objectives of the knot search: for one knot vector (and smoothing weight), the
//! control points by regularised least squares with interpolated end points, the maximum and RMS
//! orthogonal deviation of the data, and the fairness `F = L³ ∫ (dκ/ds)² ds` with its per-span parts
//! `F_j` (method reconstruction §2.3, §3.2).
//!
//! Everything works on reused buffers in a [`EvalWorkspace`] (one per particle), so an evaluation
//! allocates nothing once the buffers have grown. The fairness integral here is the fixed 8-node
//! Gauss–Legendre rule per knot span (nodes strictly inside spans, so C''' is never taken at a knot);
//! the final result is re-measured by the fairness module.
//!
//! The least-squares solve is the least-squares module's `LsqSolver` (one per particle, reused), with
//! the scale-free smoothing term `λ ∫|C'''|² du` (third order: it penalises curvature variation).

use crate::fit::lsq::{LsqOptions, LsqSolver, SmoothingOrder};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::Vec3;

/// Highest degree the allocation-free evaluator supports.
pub const MAX_DEGREE: usize = 7;
const P1: usize = MAX_DEGREE + 1;

pub(crate) const GL_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
pub(crate) const GL_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// The data every candidate is fitted to: points (normalised), their parameters, the degree.
#[derive(Clone, Debug)]
pub struct FitData {
    /// Data points, ordered.
    pub points: Vec<Vec3>,
    /// Their parameters in `[0, 1]`, strictly increasing, first 0 and last 1.
    pub params: Vec<f64>,
    /// Curve degree (3 for the fairness metric).
    pub degree: usize,
    /// Whether all points lie in the xy plane (use the signed planar curvature).
    pub planar: bool,
    /// Parameter-correction passes per candidate (refit at the foot points of the last fit).
    pub corrections: usize,
}

/// Runs `$body` with `$proj` bound to the projection of one data point onto the curve in `$ws`,
/// chosen once per pass, not per point: [`project_planar_any`] with a constant degree 3, 4 or 5
/// (a run-time degree above) when [`is_flat`], else [`project`]. Each arm compiles `$body` with its
/// own closure (monomorphised loops); every arm gives the same feet and distances as [`project`].
/// The one place the choice is made, so the passes that project ([`deviations_bounded`],
/// [`measure_move_deviations`]) cannot pick different projections.
macro_rules! with_projection {
    ($data:expr, $ws:expr, |$proj:ident| $body:expr) => {{
        let data: &FitData = $data;
        match (is_flat(data, $ws), data.degree) {
            (true, 3) => {
                let $proj = |k, u, ws: &EvalWorkspace, hint: &mut usize| {
                    project_planar_any(data, 3, k, u, ws, hint)
                };
                $body
            }
            (true, 4) => {
                let $proj = |k, u, ws: &EvalWorkspace, hint: &mut usize| {
                    project_planar_any(data, 4, k, u, ws, hint)
                };
                $body
            }
            (true, 5) => {
                let $proj = |k, u, ws: &EvalWorkspace, hint: &mut usize| {
                    project_planar_any(data, 5, k, u, ws, hint)
                };
                $body
            }
            (true, p) => {
                let $proj = |k, u, ws: &EvalWorkspace, hint: &mut usize| {
                    project_planar_any(data, p, k, u, ws, hint)
                };
                $body
            }
            (false, _) => {
                let $proj =
                    |k, u, ws: &EvalWorkspace, hint: &mut usize| project(data, k, u, ws, hint);
                $body
            }
        }
    }};
}

/// The measured quality of one candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CandidateEval {
    /// Whether the least-squares system could be solved.
    pub solved: bool,
    /// Maximum orthogonal deviation of the data points.
    pub max_deviation: f64,
    /// RMS orthogonal deviation.
    pub rms_deviation: f64,
    /// Whole-curve fairness `F`.
    pub fairness: f64,
    /// `max_j F_j`.
    pub max_span_fairness: f64,
}

impl CandidateEval {
    /// The evaluation of a candidate whose system could not be solved.
    pub fn failed() -> Self {
        CandidateEval {
            solved: false,
            max_deviation: f64::INFINITY,
            rms_deviation: f64::INFINITY,
            fairness: f64::INFINITY,
            max_span_fairness: f64::INFINITY,
        }
    }
}

/// Reused buffers for [`evaluate_candidate`].
#[derive(Clone, Debug, Default)]
pub struct EvalWorkspace {
    /// The full clamped knot vector of the last candidate.
    pub knots: Vec<f64>,
    /// The control points of the last candidate.
    pub ctrl: Vec<Vec3>,
    /// Per-span fairness `F_j` of the last candidate.
    pub span_fairness: Vec<f64>,
    /// Projected parameters of the data on the last candidate.
    pub foot_params: Vec<f64>,
    solver: Option<LsqSolver>,
    /// Parameters of the data in the last least-squares solve.
    fit_params: Vec<f64>,
    /// Span start parameters of the piecewise power form.
    breaks: Vec<f64>,
    /// `(p + 1)` Taylor coefficients `C^(k)(u_s) / k!` per span.
    coef: Vec<Vec3>,
    /// Knot index `s` (`knots[s] <= u < knots[s + 1]`) of every power-form span.
    break_knot: Vec<usize>,
    span_energy: Vec<f64>,
    span_length: Vec<f64>,
    /// Squared orthogonal distance of every data point (0 at the interpolated ends).
    dev2: Vec<f64>,
    kept: KeptFit,
    span_ders: SpanDers,
}

/// Basis derivatives `0..=p` at the start of every knot span, for the power form
/// ([`span_power_coefs_cached`]): a parameter correction or a control-point move changes the
/// control points on fixed knots, so they are computed once per knot vector.
#[derive(Clone, Debug, Default)]
struct SpanDers {
    knots: Vec<f64>,
    degree: usize,
    /// `(p + 1)²` values per knot span index `s` (every one written when the cache is rebuilt).
    ders: Vec<f64>,
}

/// A fit kept during a parameter correction ([`evaluate_candidate_within`]).
#[derive(Clone, Debug, Default)]
struct KeptFit {
    params: Vec<f64>,
    ctrl: Vec<Vec3>,
    breaks: Vec<f64>,
    coef: Vec<Vec3>,
    break_knot: Vec<usize>,
    foot_params: Vec<f64>,
    dev2: Vec<f64>,
}

/// The parts of a measured curve that [`measure_move`] updates, saved so that a rejected move can
/// be undone by [`EvalWorkspace::load_state`].
#[derive(Clone, Debug, Default)]
pub struct MeasureState {
    coef: Vec<Vec3>,
    span_energy: Vec<f64>,
    span_length: Vec<f64>,
    span_fairness: Vec<f64>,
    dev2: Vec<f64>,
    foot_params: Vec<f64>,
}

impl EvalWorkspace {
    /// Keeps the current fit (solved at `params`, measured) for [`EvalWorkspace::restore_fit`].
    fn keep_fit(&mut self, params: &[f64]) {
        let k = &mut self.kept;
        copy_into(&mut k.params, params);
        copy_into(&mut k.ctrl, &self.ctrl);
        copy_into(&mut k.breaks, &self.breaks);
        copy_into(&mut k.coef, &self.coef);
        copy_into(&mut k.break_knot, &self.break_knot);
        copy_into(&mut k.foot_params, &self.foot_params);
        copy_into(&mut k.dev2, &self.dev2);
    }

    /// Restores the fit kept by [`EvalWorkspace::keep_fit`] (`params` gets its parameters).
    fn restore_fit(&mut self, params: &mut Vec<f64>) {
        let k = &self.kept;
        copy_into(params, &k.params);
        copy_into(&mut self.ctrl, &k.ctrl);
        copy_into(&mut self.breaks, &k.breaks);
        copy_into(&mut self.coef, &k.coef);
        copy_into(&mut self.break_knot, &k.break_knot);
        copy_into(&mut self.foot_params, &k.foot_params);
        copy_into(&mut self.dev2, &k.dev2);
    }

    /// Copies the measured state of the current curve into `st`.
    pub fn save_state(&self, st: &mut MeasureState) {
        copy_into(&mut st.coef, &self.coef);
        copy_into(&mut st.span_energy, &self.span_energy);
        copy_into(&mut st.span_length, &self.span_length);
        copy_into(&mut st.span_fairness, &self.span_fairness);
        copy_into(&mut st.dev2, &self.dev2);
        copy_into(&mut st.foot_params, &self.foot_params);
    }

    /// Restores a state saved by [`EvalWorkspace::save_state`] (the control points are the
    /// caller's to restore).
    pub fn load_state(&mut self, st: &MeasureState) {
        copy_into(&mut self.coef, &st.coef);
        copy_into(&mut self.span_energy, &st.span_energy);
        copy_into(&mut self.span_length, &st.span_length);
        copy_into(&mut self.span_fairness, &st.span_fairness);
        copy_into(&mut self.dev2, &st.dev2);
        copy_into(&mut self.foot_params, &st.foot_params);
    }
}

fn copy_into<T: Copy>(dst: &mut Vec<T>, src: &[T]) {
    dst.clear();
    dst.extend_from_slice(src);
}

#[cfg(test)]
/// `[C, C', .., C^(nd)]` of the B-spline (`ctrl`, `knots`, degree `p`) at `u`.
#[inline]
fn bspline_ders(knots: &[f64], ctrl: &[Vec3], p: usize, u: f64, nd: usize, out: &mut [Vec3; 4]) {
    let n = ctrl.len() - 1;
    let span = crate::nurbs::knots::find_span(n, p, u, knots);
    let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
    let (mut ndu, mut a) = ([0.0; P1 * P1], [0.0; 2 * P1]);
    let mut ders = [0.0; 4 * P1];
    ders_basis_funs_into(
        span, u, p, nd, knots, &mut left, &mut right, &mut ndu, &mut a, &mut ders,
    );
    for (k, o) in out.iter_mut().enumerate().take(nd + 1) {
        let mut s = Vec3::default();
        for j in 0..=p {
            s += ctrl[span - p + j] * ders[k * (p + 1) + j];
        }
        *o = s;
    }
}

/// Fits control points for the full knot vector in `ws.knots` and measures the candidate.
///
/// `log_lambda` is `log10` of the smoothing weight (`-inf` for none).
pub fn evaluate_candidate(
    data: &FitData,
    log_lambda: f64,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    evaluate_candidate_within(data, log_lambda, f64::INFINITY, ws)
}

/// [`evaluate_candidate`], skipping the fairness integral (reported as infinite) when the maximum
/// deviation exceeds `fairness_cutoff`: a swarm ranks such candidates by their violation alone.
pub fn evaluate_candidate_within(
    data: &FitData,
    log_lambda: f64,
    fairness_cutoff: f64,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    evaluate_candidate_bounded(data, log_lambda, fairness_cutoff, None, ws)
}

/// [`evaluate_candidate_within`] that may give up: with `give_up = Some((tol, v))` the last
/// projection pass stops as soon as the result's maximum deviation `d` is certain to have
/// `d / tol − 1 > v` (a constraint violation above `v`), and the returned evaluation then holds a
/// lower bound of `d` with that property (RMS and fairness infinite). A swarm passes the violation
/// of the particle's best so far: such a candidate cannot replace it, so the search takes exactly
/// the same path as with full evaluations.
pub fn evaluate_candidate_bounded(
    data: &FitData,
    log_lambda: f64,
    fairness_cutoff: f64,
    give_up: Option<(f64, f64)>,
    ws: &mut EvalWorkspace,
) -> CandidateEval {
    let mut params = std::mem::take(&mut ws.fit_params);
    params.clear();
    params.extend_from_slice(&data.params);
    if !solve_control_points(data, &params, log_lambda, ws) {
        ws.fit_params = params;
        return CandidateEval::failed();
    }
    build_power_form(data.degree, ws);
    let gave_up = |d: f64| CandidateEval {
        solved: true,
        max_deviation: d,
        rms_deviation: f64::INFINITY,
        fairness: f64::INFINITY,
        max_span_fairness: f64::INFINITY,
    };
    let last = |pass: usize| {
        if pass == data.corrections {
            give_up
        } else {
            None
        }
    };
    let (mut max_dev, mut rms) = match deviations_bounded(data, &params, f64::INFINITY, last(0), ws)
    {
        Ok(d) => d,
        Err(d) => {
            ws.fit_params = params;
            return gave_up(d);
        }
    };
    for pass in 1..=data.corrections {
        // parameter correction: refit at the foot points of the last fit, keeping that fit to
        // restore it (by copy, not by solving again) when the correction does not help
        ws.keep_fit(&params);
        std::mem::swap(&mut params, &mut ws.foot_params);
        if solve_control_points(data, &params, log_lambda, ws) {
            build_power_form(data.degree, ws);
            match deviations_bounded(data, &params, max_dev, last(pass), ws) {
                Ok((d2, r2)) => {
                    if d2 <= max_dev {
                        (max_dev, rms) = (d2, r2);
                        continue;
                    }
                }
                Err(d) => {
                    ws.fit_params = params;
                    return gave_up(d);
                }
            }
        }
        // no better: restore the previous fit and stop
        ws.restore_fit(&mut params);
        break;
    }
    ws.fit_params = params;
    let (f, fmax) = if max_dev <= fairness_cutoff {
        fairness(data, ws)
    } else {
        (f64::INFINITY, f64::INFINITY)
    };
    CandidateEval {
        solved: true,
        max_deviation: max_dev,
        rms_deviation: rms,
        fairness: f,
        max_span_fairness: fmax,
    }
}

/// Measures the curve already held in `ws` (`ws.knots`, `ws.ctrl`) without fitting: orthogonal
/// deviations by projection started at `start` (one parameter per data point; the foot parameters go
/// to `ws.foot_params`) and the fairness. Used to judge control-point moves.
pub fn measure_current(data: &FitData, start: &[f64], ws: &mut EvalWorkspace) -> CandidateEval {
    if ws.ctrl.len() + data.degree + 1 != ws.knots.len() || ws.ctrl.iter().any(|c| !c.is_finite()) {
        return CandidateEval::failed();
    }
    build_power_form(data.degree, ws);
    let (max_deviation, rms_deviation) = deviations(data, start, ws);
    let (fairness, max_span_fairness) = fairness(data, ws);
    CandidateEval {
        solved: true,
        max_deviation,
        rms_deviation,
        fairness,
        max_span_fairness,
    }
}

/// Re-measures the curve in `ws` after a change of the single control point `ws.ctrl[r]`, reusing
/// everything the move cannot change: only the `p + 1` spans holding `P_r` get new power-form
/// coefficients and fairness parts, and only the data points whose foot parameter (in `start`, the
/// feet on the curve before the move) lies in those spans are projected again (Newton from `start`).
/// `ws` must hold the full measurement ([`measure_current`]) of the curve before the move (restore it
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
fn move_pass(
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
            let (best, best_u) = proj(k, u, ws, &mut hint);
            ws.foot_params[k] = best_u;
            ws.dev2[k] = best;
            if best.sqrt() > give_up {
                return Some(best.sqrt());
            }
        }
    }
    None
}

/// Sets `ws.knots` to the clamped knot vector on `[0, 1]` with the given interior knots.
pub fn set_knots(degree: usize, interior: &[f64], ws: &mut EvalWorkspace) {
    ws.knots.clear();
    ws.knots.extend(std::iter::repeat_n(0.0, degree + 1));
    ws.knots.extend_from_slice(interior);
    ws.knots.extend(std::iter::repeat_n(1.0, degree + 1));
}

/// Least squares with `P_0 = Q_0`, `P_n = Q_m` and the smoothing `λ ∫|C'''|² du` (the least-squares
/// module's [`LsqSolver`]); false if the normal equations are singular.
fn solve_control_points(
    data: &FitData,
    params: &[f64],
    log_lambda: f64,
    ws: &mut EvalWorkspace,
) -> bool {
    let p = data.degree;
    if p > MAX_DEGREE || ws.knots.len() < 2 * (p + 1) {
        return false;
    }
    let solver = ws.solver.get_or_insert_with(|| LsqSolver::new(p));
    if solver.degree() != p {
        *solver = LsqSolver::new(p);
    }
    let opts = LsqOptions {
        smoothing: if log_lambda > super::encoding::LOG_LAMBDA_OFF {
            10f64.powf(log_lambda)
        } else {
            0.0
        },
        smoothing_order: SmoothingOrder::Third,
        end_tangents: None,
        closed: false,
    };
    solver
        .solve(&data.points, params, &ws.knots, None, &opts, &mut ws.ctrl)
        .is_ok()
        && ws.ctrl.iter().all(|c| c.is_finite())
}

/// Converts the B-spline in `ws` to its piecewise power form (Taylor coefficients at each span start),
/// so points and derivatives cost one Horner scheme instead of a basis-function recursion.
fn build_power_form(p: usize, ws: &mut EvalWorkspace) {
    let n = ws.ctrl.len() - 1;
    ws.breaks.clear();
    ws.coef.clear();
    ws.break_knot.clear();
    ensure_span_ders(p, ws);
    for s in p..=n {
        let u0 = ws.knots[s];
        if ws.knots[s + 1] <= u0 {
            continue;
        }
        ws.breaks.push(u0);
        ws.break_knot.push(s);
        ws.coef.extend(std::iter::repeat_n(Vec3::default(), p + 1));
        span_power_coefs_cached(p, s, ws.coef.len() - (p + 1), ws);
    }
}

/// Rebuilds `ws.span_ders` (the basis derivatives at every span start) when the knots or the
/// degree changed since it was built; [`span_power_coefs_cached`] reads it.
fn ensure_span_ders(p: usize, ws: &mut EvalWorkspace) {
    let q = (p + 1) * (p + 1);
    if ws.span_ders.degree != p || ws.span_ders.knots != ws.knots {
        let cache = &mut ws.span_ders;
        cache.knots.clone_from(&ws.knots);
        cache.degree = p;
        cache.ders.resize(ws.knots.len() * q, 0.0);
        let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
        let (mut ndu, mut a) = ([0.0; P1 * P1], [0.0; 2 * P1]);
        for k in p..ws.knots.len().saturating_sub(p + 1) {
            let ders = &mut cache.ders[k * q..(k + 1) * q];
            ders_basis_funs_into(
                k,
                ws.knots[k],
                p,
                p,
                &ws.knots,
                &mut left,
                &mut right,
                &mut ndu,
                &mut a,
                ders,
            );
        }
    }
}

/// Writes the `p + 1` Taylor coefficients of knot span `s` at `ws.coef[at..]`, with the basis
/// derivatives at the span starts from `ws.span_ders` (made current by [`ensure_span_ders`] once
/// before a run of spans): a candidate's parameter correction, band fairing's and the polish's
/// measurements reuse them on the same knots.
fn span_power_coefs_cached(p: usize, s: usize, at: usize, ws: &mut EvalWorkspace) {
    let q = (p + 1) * (p + 1);
    let ders = &ws.span_ders.ders[s * q..(s + 1) * q];
    taylor_coefs(p, &ws.ctrl[s - p..=s], ders, &mut ws.coef[at..=at + p]);
}

/// The `p + 1` Taylor coefficients `C^(k)(u_0) / k!` of a span from its `p + 1` control points and
/// the basis derivatives `ders[k (p + 1) + j] = N_j^(k)(u_0)` at the span's start.
#[inline]
fn taylor_coefs(p: usize, ctrl: &[Vec3], ders: &[f64], coef: &mut [Vec3]) {
    if p == 3 {
        // the usual cubic: the same loops with a constant degree, unrolled by the compiler
        taylor_coefs_any(3, ctrl, ders, coef);
    } else {
        taylor_coefs_any(p, ctrl, ders, coef);
    }
}

/// [`taylor_coefs`] for any degree (always inlined so a constant `p` unrolls the loops).
#[inline(always)]
fn taylor_coefs_any(p: usize, ctrl: &[Vec3], ders: &[f64], coef: &mut [Vec3]) {
    let mut fact = 1.0;
    for k in 0..=p {
        if k > 0 {
            fact *= k as f64;
        }
        let mut c = Vec3::default();
        for j in 0..=p {
            c += ctrl[j] * ders[k * (p + 1) + j];
        }
        coef[k] = c / fact;
    }
}

/// The point and derivatives 1..=3 at `u` from the power form, in span `j` (index into `breaks`).
#[inline]
fn power_eval(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    if p == 3 {
        // the usual cubic: `power_eval_any` inlined with a constant degree, unrolled by the compiler
        power_eval_any(coef, 3, j, t, out);
    } else {
        power_eval_any(coef, p, j, t, out);
    }
}

/// [`power_eval`] for any degree (always inlined so a constant `p` unrolls the Horner loop).
#[inline(always)]
fn power_eval_any(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    // Horner for the value and the first three derivatives
    let (mut v0, mut v1, mut v2, mut v3) =
        (c[p], Vec3::default(), Vec3::default(), Vec3::default());
    for k in (0..p).rev() {
        v3 = v3 * t + v2;
        v2 = v2 * t + v1;
        v1 = v1 * t + v0;
        v0 = v0 * t + c[k];
    }
    out[0] = v0;
    out[1] = v1;
    out[2] = v2 * 2.0;
    out[3] = v3 * 6.0;
}

/// The point and derivatives 1..=2 at `u` from the power form, in span `j` (`out[3]` untouched):
/// what a projection needs, bit-identical to [`power_eval`]'s first three entries.
#[inline]
fn power_eval2(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    if p == 3 {
        power_eval2_any(coef, 3, j, t, out);
    } else {
        power_eval2_any(coef, p, j, t, out);
    }
}

/// [`power_eval2`] for any degree (always inlined so a constant `p` unrolls the Horner loop).
#[inline(always)]
fn power_eval2_any(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    let (mut v0, mut v1, mut v2) = (c[p], Vec3::default(), Vec3::default());
    for k in (0..p).rev() {
        v2 = v2 * t + v1;
        v1 = v1 * t + v0;
        v0 = v0 * t + c[k];
    }
    out[0] = v0;
    out[1] = v1;
    out[2] = v2 * 2.0;
}

/// The span index in `breaks` holding `u` (last span for `u` at the end).
#[cfg(test)]
fn power_span(breaks: &[f64], u: f64) -> usize {
    match breaks.binary_search_by(|b| b.total_cmp(&u)) {
        Ok(i) => i,
        Err(i) => i.saturating_sub(1),
    }
}

/// [`power_span`] by walking from the span `hint` (same result; cheap for ordered queries).
#[inline]
fn power_span_from(breaks: &[f64], u: f64, hint: usize) -> usize {
    // plain comparisons: `breaks[j]` for `j > 0` is positive, so they order as `total_cmp` does
    // for every `u` but NaN (whose evaluation is NaN in any span and never kept)
    let mut j = hint.min(breaks.len().saturating_sub(1));
    while j + 1 < breaks.len() && breaks[j + 1] <= u {
        j += 1;
    }
    while j > 0 && breaks[j] > u {
        j -= 1;
    }
    j
}

/// Max and RMS orthogonal deviation: Newton projection started at each point's own parameter
/// (fills `ws.foot_params` and `ws.dev2`).
fn deviations(data: &FitData, start: &[f64], ws: &mut EvalWorkspace) -> (f64, f64) {
    deviations_bounded(data, start, f64::INFINITY, None, ws)
        .unwrap_or((f64::INFINITY, f64::INFINITY))
}

/// [`deviations`], giving up (`Err(bound)`) once `min(floor, max so far)` is certain to exceed the
/// violation `v` of `give_up = Some((tol, v))`: `bound / tol − 1 > v` (`floor` is the maximum
/// deviation the caller keeps if this pass is worse).
fn deviations_bounded(
    data: &FitData,
    start: &[f64],
    floor: f64,
    give_up: Option<(f64, f64)>,
    ws: &mut EvalWorkspace,
) -> Result<(f64, f64), f64> {
    let m = data.points.len();
    ws.foot_params.clear();
    ws.foot_params.extend_from_slice(start);
    ws.dev2.clear();
    ws.dev2.resize(m, 0.0);
    with_projection!(data, ws, |proj| deviation_pass(
        data, start, floor, give_up, ws, proj
    ))
}

/// The loop of [`deviations_bounded`] with the projection `proj(k, u, ws, hint)` of point `k` from
/// `u` (`hint`: the span of the last evaluation).
#[inline(always)]
fn deviation_pass(
    data: &FitData,
    start: &[f64],
    floor: f64,
    give_up: Option<(f64, f64)>,
    ws: &mut EvalWorkspace,
    proj: impl Fn(usize, f64, &EvalWorkspace, &mut usize) -> (f64, f64),
) -> Result<(f64, f64), f64> {
    let m = data.points.len();
    let mut hint = 0;
    let mut worst2 = 0.0f64;
    for k in 1..m.saturating_sub(1) {
        let (best, best_u) = proj(k, start[k], ws, &mut hint);
        ws.foot_params[k] = best_u;
        ws.dev2[k] = best;
        if best > worst2 {
            worst2 = best;
            if let Some((tol, v)) = give_up {
                let bound = floor.min(worst2.sqrt());
                if bound / tol - 1.0 > v {
                    return Err(bound);
                }
            }
        }
    }
    Ok(deviation_totals(&ws.dev2))
}

/// `(max, rms)` of the distances whose squares are `dev2` (ends included as zeros).
fn deviation_totals(dev2: &[f64]) -> (f64, f64) {
    let m = dev2.len();
    let (mut max_d, mut sum2) = (0.0f64, 0.0);
    for &d in dev2.iter().take(m.saturating_sub(1)).skip(1) {
        max_d = max_d.max(d);
        sum2 += d;
    }
    (max_d.sqrt(), (sum2 / m as f64).sqrt())
}

/// Squared orthogonal distance and foot parameter of data point `k` by at most three Newton steps
/// from `u`; `hint` is the span of the last evaluation (updated).
#[inline]
fn project(
    data: &FitData,
    k: usize,
    mut u: f64,
    ws: &EvalWorkspace,
    hint: &mut usize,
) -> (f64, f64) {
    let p = data.degree;
    let (breaks, coef) = (&ws.breaks, &ws.coef);
    let mut eval = |u: f64, d: &mut [Vec3; 4]| {
        let j = power_span_from(breaks, u, *hint);
        *hint = j;
        power_eval2(coef, p, j, u - breaks[j], d);
    };
    let mut d = [Vec3::default(); 4];
    let qk = data.points[k];
    eval(u, &mut d);
    // any curve point bounds the orthogonal distance from above; Newton steps tighten it
    let mut best = (d[0] - qk).norm_squared();
    let mut best_u = u;
    for _ in 0..3 {
        let diff = d[0] - qk;
        let f = d[1].dot(diff);
        let fp = d[2].dot(diff) + d[1].norm_squared();
        if fp.is_nan() || fp <= 0.0 {
            break;
        }
        let step = (-f / fp).clamp(-0.05, 0.05);
        u = (u + step).clamp(0.0, 1.0);
        eval(u, &mut d);
        let dist2 = (d[0] - qk).norm_squared();
        if dist2 < best {
            best = dist2;
            best_u = u;
        }
        // Newton converges quadratically: after a step this small the foot is exact to ~1e-12
        if step.abs() < 1e-6 {
            break;
        }
    }
    (best, best_u)
}

/// Whether the curve in `ws` lies in the xy plane with the data (every power-form coefficient has
/// `z = 0`), so that [`project_planar_any`] gives what [`project`] gives.
fn is_flat(data: &FitData, ws: &EvalWorkspace) -> bool {
    data.planar && ws.coef.iter().all(|c| c[2] == 0.0)
}

/// Value, first and second derivative (x, y) at `u` of the planar power form by Horner, as
/// [`power_eval2`]; `hint` is the span of the last evaluation (updated).
#[inline(always)]
fn planar_eval2(
    breaks: &[f64],
    coef: &[Vec3],
    p: usize,
    u: f64,
    hint: &mut usize,
) -> [[f64; 2]; 3] {
    let j = power_span_from(breaks, u, *hint);
    *hint = j;
    let t = u - breaks[j];
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    let mut v = [[c[p][0], c[p][1]], [0.0; 2], [0.0; 2]];
    for ck in c[..p].iter().rev() {
        for a in 0..2 {
            v[2][a] = v[2][a] * t + v[1][a];
            v[1][a] = v[1][a] * t + v[0][a];
            v[0][a] = v[0][a] * t + ck[a];
        }
    }
    v[2] = [v[2][0] * 2.0, v[2][1] * 2.0];
    v
}

/// [`project`] for a curve and data in the xy plane: the same Newton steps on two coordinates (the
/// z terms it leaves out are exact zeros, so the feet and distances are the same), for degree `p`
/// (always inlined, so a constant `p` unrolls the Horner loops; the arithmetic is the same for a
/// constant and a run-time `p`).
#[inline(always)]
fn project_planar_any(
    data: &FitData,
    p: usize,
    k: usize,
    mut u: f64,
    ws: &EvalWorkspace,
    hint: &mut usize,
) -> (f64, f64) {
    let (breaks, coef) = (&ws.breaks[..], &ws.coef[..]);
    let q = data.points[k];
    let (qx, qy) = (q[0], q[1]);
    let mut d = planar_eval2(breaks, coef, p, u, hint);
    let dist2 = |d: &[[f64; 2]; 3]| {
        let (x, y) = (d[0][0] - qx, d[0][1] - qy);
        x * x + y * y
    };
    let mut best = dist2(&d);
    let mut best_u = u;
    for _ in 0..3 {
        let (x, y) = (d[0][0] - qx, d[0][1] - qy);
        let f = d[1][0] * x + d[1][1] * y;
        let fp = (d[2][0] * x + d[2][1] * y) + (d[1][0] * d[1][0] + d[1][1] * d[1][1]);
        if fp.is_nan() || fp <= 0.0 {
            break;
        }
        let step = (-f / fp).clamp(-0.05, 0.05);
        u = (u + step).clamp(0.0, 1.0);
        d = planar_eval2(breaks, coef, p, u, hint);
        let d2 = dist2(&d);
        if d2 < best {
            best = d2;
            best_u = u;
        }
        if step.abs() < 1e-6 {
            break;
        }
    }
    (best, best_u)
}

/// `(F, max_j F_j)` by 8-point Gauss–Legendre per span; fills `ws.span_fairness`.
fn fairness(data: &FitData, ws: &mut EvalWorkspace) -> (f64, f64) {
    ws.span_energy.clear();
    ws.span_length.clear();
    for j in 0..ws.breaks.len() {
        let (e, len) = span_energy_length(data, ws, j);
        ws.span_energy.push(e);
        ws.span_length.push(len);
    }
    fairness_totals(ws)
}

/// `(∫ (dκ/du)² / |C'| du, ∫ |C'| du)` over power-form span `j`.
fn span_energy_length(data: &FitData, ws: &EvalWorkspace, j: usize) -> (f64, f64) {
    let a = ws.breaks[j];
    let b = ws.breaks.get(j + 1).copied().unwrap_or(1.0);
    let (mid, half) = (0.5 * (a + b) - a, 0.5 * (b - a));
    let (mut e, mut length) = (0.0, 0.0);
    let mut d = [Vec3::default(); 4];
    for i in 0..8 {
        let t = if i < 4 { -GL_X[i] } else { GL_X[i - 4] };
        let w = GL_W[i % 4] * half;
        power_eval(&ws.coef, data.degree, j, mid + half * t, &mut d);
        let (speed, dk) = speed_and_dkappa_du(&d, data.planar);
        length += w * speed;
        if speed > 0.0 {
            e += w * dk * dk / speed;
        }
    }
    (e, length)
}

/// `(F, max_j F_j)` from `ws.span_energy` and `ws.span_length`; fills `ws.span_fairness`.
fn fairness_totals(ws: &mut EvalWorkspace) -> (f64, f64) {
    let length: f64 = ws.span_length.iter().sum();
    let l3 = length * length * length;
    ws.span_fairness.clear();
    let (mut total, mut fmax) = (0.0, 0.0f64);
    for &e in &ws.span_energy {
        let fj = l3 * e;
        ws.span_fairness.push(fj);
        total += fj;
        fmax = fmax.max(fj);
    }
    if !total.is_finite() {
        return (f64::INFINITY, f64::INFINITY);
    }
    (total, fmax)
}

/// Speed `|C'|` and `dκ/du` (signed planar curvature when `planar`), guarded near zero.
#[inline]
pub(crate) fn speed_and_dkappa_du(d: &[Vec3; 4], planar: bool) -> (f64, f64) {
    let (r, a, b) = (d[1], d[2], d[3]);
    let v2 = r.norm_squared();
    let v = v2.sqrt();
    if v.is_nan() || v <= 0.0 {
        return (0.0, 0.0);
    }
    let v3 = v2 * v;
    let v5 = v3 * v2;
    let ra = r.dot(a);
    if planar {
        let cz = r[0] * a[1] - r[1] * a[0];
        let bz = r[0] * b[1] - r[1] * b[0];
        return (v, bz / v3 - 3.0 * cz * ra / v5);
    }
    let c = r.cross(a);
    let cn = c.norm();
    let rb = r.cross(b);
    let dc = if cn > 1e-12 * v * a.norm() && cn > 0.0 {
        c.dot(rb) / cn
    } else {
        rb.norm()
    };
    (v, dc / v3 - 3.0 * cn * ra / v5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle_data(n: usize, radius: f64) -> FitData {
        let points: Vec<Vec3> = (0..n)
            .map(|i| {
                let t = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
                Vec3([radius * t.cos(), radius * t.sin(), 0.0])
            })
            .collect();
        let params = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
        FitData {
            points,
            params,
            degree: 3,
            planar: true,
            corrections: 0,
        }
    }

    #[test]
    fn reproduces_a_cubic_exactly_with_zero_deviation() {
        // data sampled from a known cubic B-spline with the same knots: LSQ must reproduce it
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0];
        let ctrl = vec![
            Vec3([0.0, 0.0, 0.0]),
            Vec3([1.0, 2.0, 0.0]),
            Vec3([2.0, -1.0, 0.0]),
            Vec3([3.0, 3.0, 0.0]),
            Vec3([4.0, 0.5, 0.0]),
            Vec3([5.0, 1.0, 0.0]),
        ];
        let params: Vec<f64> = (0..41).map(|i| i as f64 / 40.0).collect();
        let mut d = [Vec3::default(); 4];
        let points = params
            .iter()
            .map(|&u| {
                bspline_ders(&knots, &ctrl, 3, u, 0, &mut d);
                d[0]
            })
            .collect();
        let data = FitData {
            points,
            params,
            degree: 3,
            planar: true,
            corrections: 0,
        };
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[0.3, 0.7], &mut ws);
        let ev = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
        assert!(ev.solved);
        assert!(ev.max_deviation < 1e-12, "{}", ev.max_deviation);
        for (a, b) in ws.ctrl.iter().zip(&ctrl) {
            assert!((*a - *b).norm() < 1e-10);
        }
    }

    #[test]
    fn quarter_circle_deviation_and_fairness_are_small_and_scale_free() {
        // a cubic with 6 control points approximates a quarter circle within ~1e-4 of the radius;
        // the circle has F = 0, so F of the fit is small (0.15), and identical for radius 1 and 1000
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[1.0 / 3.0, 2.0 / 3.0], &mut ws);
        let e1 = evaluate_candidate(&circle_data(60, 1.0), f64::NEG_INFINITY, &mut ws);
        let e2 = evaluate_candidate(&circle_data(60, 1000.0), f64::NEG_INFINITY, &mut ws);
        assert!(
            e1.max_deviation < 3e-4 && e1.max_deviation > 1e-7,
            "{}",
            e1.max_deviation
        );
        assert!(e1.fairness < 0.5, "{}", e1.fairness);
        assert!((e2.max_deviation / 1000.0 - e1.max_deviation).abs() < 1e-12);
        assert!((e2.fairness - e1.fairness).abs() < 1e-9 * e1.fairness.max(1e-12));
        // per-span parts add up to F
        let s: f64 = ws.span_fairness.iter().sum();
        assert!((s - e2.fairness).abs() <= 1e-12 * e2.fairness);
    }

    #[test]
    fn every_projection_arm_gives_the_feet_of_the_spatial_projection() {
        // planar B-splines of degree 3 to 6 (each arm of `with_projection!`: constant degrees 3, 4,
        // 5 and a run-time degree), fitted exactly from points on them; points offset by a known
        // distance δ along the normal at known parameters must project back to that foot at
        // distance δ, bit for bit as the spatial `project` does, from a start 0.01 off
        let delta = 1e-3;
        for p in 3..=6 {
            let interior = [0.25, 0.5, 0.75];
            let mut knots = vec![0.0; p + 1];
            knots.extend_from_slice(&interior);
            knots.extend(std::iter::repeat_n(1.0, p + 1));
            let n = knots.len() - p - 1;
            let ctrl: Vec<Vec3> = (0..n)
                .map(|i| {
                    let x = i as f64 / (n - 1) as f64;
                    Vec3([x, 0.2 * (5.0 * x).sin(), 0.0])
                })
                .collect();
            let params: Vec<f64> = (0..61).map(|i| i as f64 / 60.0).collect();
            let mut d = [Vec3::default(); 4];
            let on = |u: f64, d: &mut [Vec3; 4]| bspline_ders(&knots, &ctrl, p, u, 1, d);
            let points = params
                .iter()
                .map(|&u| {
                    on(u, &mut d);
                    d[0]
                })
                .collect();
            let data = FitData {
                points,
                params: params.clone(),
                degree: p,
                planar: true,
                corrections: 0,
            };
            let mut ws = EvalWorkspace::default();
            set_knots(p, &interior, &mut ws);
            let ev = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
            assert!(ev.solved && ev.max_deviation < 1e-12, "{p}: {ev:?}");
            assert!(is_flat(&data, &ws));
            // the offset points, alternating sides of the curve
            let offset: Vec<Vec3> = params
                .iter()
                .enumerate()
                .map(|(k, &u)| {
                    on(u, &mut d);
                    let t = d[1] / d[1].norm();
                    let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                    d[0] + Vec3([-t.y(), t.x(), 0.0]) * (side * delta)
                })
                .collect();
            let query = FitData {
                points: offset,
                ..data
            };
            let start: Vec<f64> = params.iter().map(|&u| (u + 0.01).clamp(0.0, 1.0)).collect();
            let feet = with_projection!(&query, &ws, |proj| {
                let mut hint = 0;
                (1..params.len() - 1)
                    .map(|k| proj(k, start[k], &ws, &mut hint))
                    .collect::<Vec<_>>()
            });
            let mut hint = 0;
            for (k, &(d2, u)) in (1..params.len() - 1).zip(&feet) {
                let spatial = project(&query, k, start[k], &ws, &mut hint);
                assert_eq!(
                    (d2.to_bits(), u.to_bits()),
                    (spatial.0.to_bits(), spatial.1.to_bits())
                );
                assert!((d2.sqrt() - delta).abs() < 1e-9, "{p} {k}: {}", d2.sqrt());
                assert!((u - params[k]).abs() < 1e-6, "{p} {k}: {u}");
            }
        }
    }

    #[test]
    fn hinted_span_search_agrees_with_binary_search() {
        let breaks = [0.0, 0.1, 0.25, 0.5, 0.9];
        for hint in 0..7 {
            for i in 0..=100 {
                let u = i as f64 / 100.0;
                assert_eq!(
                    power_span_from(&breaks, u, hint),
                    power_span(&breaks, u),
                    "{u} {hint}"
                );
            }
        }
    }

    #[test]
    fn a_move_measured_in_part_equals_the_full_measurement() {
        // wavy data, 9 control points; moving P_4 and re-measuring only its spans must give the
        // deviations and F of a full re-measurement from the same feet
        let m = 80;
        let points: Vec<Vec3> = (0..m)
            .map(|i| {
                let x = i as f64 / (m - 1) as f64;
                Vec3([x, 0.3 * (3.0 * x).sin(), 0.0])
            })
            .collect();
        let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
        let data = FitData {
            points,
            params,
            degree: 3,
            planar: true,
            corrections: 1,
        };
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[0.2, 0.35, 0.5, 0.65, 0.8], &mut ws);
        assert!(evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws).solved);
        let feet = ws.foot_params.clone();
        let before = measure_current(&data, &feet, &mut ws);
        let feet = ws.foot_params.clone();
        let mut saved = MeasureState::default();
        ws.save_state(&mut saved);
        ws.ctrl[4] += Vec3([0.0, 0.01, 0.0]);
        let part = measure_move(&data, 4, &feet, true, &mut ws);
        let full = measure_current(&data, &feet, &mut ws);
        assert!(part.fairness != before.fairness);
        assert!((part.fairness - full.fairness).abs() <= 1e-12 * full.fairness);
        assert!((part.max_span_fairness - full.max_span_fairness).abs() <= 1e-12 * full.fairness);
        assert!((part.max_deviation - full.max_deviation).abs() <= 1e-12);
        assert!((part.rms_deviation - full.rms_deviation).abs() <= 1e-12);
        assert!(part.max_deviation > before.max_deviation + 1e-3);
        // undoing restores the earlier measurement exactly
        ws.ctrl[4] -= Vec3([0.0, 0.01, 0.0]);
        ws.load_state(&saved);
        let again = measure_move(&data, 4, &feet, true, &mut ws);
        assert!((again.fairness - before.fairness).abs() <= 1e-12 * before.fairness);
        assert!((again.max_deviation - before.max_deviation).abs() <= 1e-12);
    }

    #[test]
    fn fairness_matches_closed_form_for_a_parabola() {
        // C(u) = (u, u²): κ = 2/(1+4u²)^{3/2}; exactly representable as a cubic B-spline (Bézier)
        // F = L³ ∫ (dκ/ds)² ds computed by dense trapezoid quadrature as independent truth
        let ctrl = vec![
            Vec3([0.0, 0.0, 0.0]),
            Vec3([1.0 / 3.0, 0.0, 0.0]),
            Vec3([2.0 / 3.0, 1.0 / 3.0, 0.0]),
            Vec3([1.0, 1.0, 0.0]),
        ];
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[], &mut ws);
        ws.ctrl = ctrl;
        let data = FitData {
            points: vec![],
            params: vec![],
            degree: 3,
            planar: true,
            corrections: 0,
        };
        build_power_form(3, &mut ws);
        let (f, _) = fairness(&data, &mut ws);
        let n = 200_000;
        let (mut len, mut e) = (0.0, 0.0);
        for i in 0..n {
            let u = (i as f64 + 0.5) / n as f64;
            let s = (1.0 + 4.0 * u * u).sqrt();
            let dk_du = -24.0 * u / s.powi(5);
            len += s / n as f64;
            e += dk_du * dk_du / s / n as f64;
        }
        let truth = len * len * len * e;
        // one span over the whole curve: 8-point Gauss–Legendre is good to ~1e-4 here
        assert!((f - truth).abs() < 2e-4 * truth, "{f} vs {truth}");
        // the 3D formula agrees on a planar curve
        let data3 = FitData {
            planar: false,
            ..data
        };
        let (f3, _) = fairness(&data3, &mut ws);
        assert!((f3 - f).abs() < 1e-9 * truth);
    }
}
