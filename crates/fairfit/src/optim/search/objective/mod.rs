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

use crate::fit::end_constraints::EndConstraints;
use crate::fit::lsq::{LsqOptions, LsqSolver, SmoothingOrder};
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
    /// End conditions of an open curve, in these (normalised) coordinates: every least-squares
    /// solve honours them ([`LsqSolver::solve_constrained`]) and the final fairing keeps their
    /// control points fixed.
    pub ends: EndConstraints,
    /// Per-point weights and points to interpolate (empty: none; [`PointBands`]).
    pub bands: PointBands,
}

/// Per-point weights and points to interpolate of the data a search sees (issue 26): every
/// least-squares solve is weighted (`Σ w_k² |C(ū_k) − Q_k|²`) and meets `C(ū_k) = Q_k` at the
/// points to interpolate ([`LsqSolver::set_point_terms`]); every measured deviation is the
/// weighted one, `band_k · d_k`, so a candidate within the tolerance `tol` has each point within
/// `tol / band_k` (the band fairing's cones likewise). Empty: every factor 1, and every
/// computation is the unweighted one bit for bit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointBands {
    /// The least-squares weight of every point (empty: all 1).
    pub weights: Vec<f64>,
    /// Indices of the points to interpolate.
    pub interpolate: Vec<usize>,
    /// The deviation factor of every point (empty: all 1): its weight, and for a point to
    /// interpolate a large factor (its band a small fraction of the tolerance).
    pub band: Vec<f64>,
}

impl PointBands {
    /// The bands of weights `weights` (empty: all 1) and points to interpolate `interpolate`
    /// (held to `tol / interpolation_band`) for `m` points; none when both are empty.
    pub fn new(m: usize, weights: &[f64], interpolate: &[usize], interpolation_band: f64) -> Self {
        if weights.is_empty() && interpolate.is_empty() {
            return PointBands::default();
        }
        let mut band: Vec<f64> = if weights.is_empty() {
            vec![1.0; m]
        } else {
            weights.to_vec()
        };
        for &k in interpolate {
            if k < m {
                band[k] = band[k].max(interpolation_band);
            }
        }
        PointBands {
            weights: weights.to_vec(),
            interpolate: interpolate.to_vec(),
            band,
        }
    }

    /// Deviation factors alone (no weight, no point to interpolate): point `k` held within
    /// `tol / factors[k]`; none unless there is one factor for each of the `m` points (the
    /// reduction's shares of the tolerance, `IntegratedOptions::tolerance_factors`).
    pub fn of_factors(factors: &[f64], m: usize) -> Self {
        if factors.is_empty() || factors.len() != m {
            return PointBands::default();
        }
        PointBands {
            weights: Vec::new(),
            interpolate: Vec::new(),
            band: factors.to_vec(),
        }
    }

    /// Whether nothing is asked.
    pub fn is_none(&self) -> bool {
        self.band.is_empty()
    }

    /// The deviation factor of point `k` (1 without bands).
    #[inline]
    pub fn factor(&self, k: usize) -> f64 {
        if self.band.is_empty() {
            1.0
        } else {
            self.band[k]
        }
    }
}

/// Runs `$body` with `$proj` bound to the projection of one data point onto the curve in `$ws`,
/// chosen once per pass, not per point: [`project_planar_any`] with a constant degree 3, 4 or 5
/// (a run-time degree above) when [`is_flat`], else [`project`]. Each arm compiles `$body` with its
/// own closure (monomorphised loops); every arm gives the same feet and distances as [`project`].
/// The one place the choice is made, so the passes that project ([`deviations_bounded`],
/// [`measure_move_deviations`]) cannot pick different projections. The expansion names
/// `FitData`, `EvalWorkspace`, `is_flat`, `project` and `project_planar_any`: a module that invokes
/// it imports them.
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

mod deviation;
mod fairness;
mod moves;
mod power_form;

use deviation::{deviations, deviations_bounded};
use fairness::fairness;
pub(crate) use fairness::speed_and_dkappa_du;
pub use moves::{measure_move, measure_move_deviations};
use power_form::build_power_form;

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
    crate::nurbs::basis::ders_basis_funs_into(
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
pub(crate) fn evaluate_candidate_bounded(
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

/// Sets `ws.knots` to the clamped knot vector on `[0, 1]` with the given interior knots.
pub(crate) fn set_knots(degree: usize, interior: &[f64], ws: &mut EvalWorkspace) {
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
    solver.set_point_terms(&data.bands.weights, &data.bands.interpolate);
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
        .solve_constrained(
            &data.points,
            params,
            &ws.knots,
            None,
            &opts,
            &data.ends,
            data.planar,
            &mut ws.ctrl,
        )
        .is_ok()
        && ws.ctrl.iter().all(|c| c.is_finite())
}

#[cfg(test)]
mod tests;
