//! Fit-then-fair baseline: classic post-processing fairing of a fitted curve held to a tolerance
//! (issue 4 item 6), by Eck & Hadenfeld's local energy fairing ("Local energy fairing of B-spline
//! curves", 1995).
//!
//! The parametric energy `E_k = ∫ |C^(k)|² du = Σ_ij G_ij P_i·P_j` ([`super::gram`], `k = 3` for cubics
//! and above, the "jerk") is quadratic in each control point, so moving `P_r` alone to the minimiser
//! `P_r* = P_r − g_r / G_rr` (with `g_r = Σ_j G_rj P_j`) lowers it by `|g_r|² / G_rr`. Each iteration
//! ranks the movable control points by that gain and tries them in order, with steps `t = 1, 1/2, 1/4,
//! ...` along `P_r* − P_r`; a move is accepted when
//!
//! 1. the scale-free MVC fairness `F = L³ ∫ (dκ/ds)² ds` of the whole curve decreases, and
//! 2. every data point stays within its allowance of the curve: `tol`, or its initial distance when the
//!    input curve already missed it (so the fairing never makes any point worse than the fit left it).
//!    Distances are orthogonal, by [`crate::diffgeo::CurveProjector`] started from each point's last
//!    foot parameter; a local search can only overestimate a distance, so the check is conservative.
//!
//! The iteration stops when no candidate is accepted or after `max_iterations` moves. End control points
//! stay fixed by default (a clamped curve keeps its end points). For rational curves the step is computed
//! on the Euclidean control points with the weights held fixed, which is only a model of the true energy;
//! every move is still judged on the true curve. Everything is deterministic (ties broken by index).

use super::evaluator::FairnessEvaluator;
use super::gram::Gram;
use crate::diffgeo::CurveProjector;
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, Vec3};

/// Options of [`fair_curve`].
#[derive(Clone, Debug, PartialEq)]
pub struct FairingOptions {
    /// Maximum number of accepted control-point moves.
    pub max_iterations: usize,
    /// Keep the first and last control points fixed.
    pub fix_ends: bool,
    /// Derivative order of the parametric energy (default `min(3, degree)`).
    pub energy_order: Option<usize>,
    /// Step halvings tried per candidate after the full step.
    pub step_halvings: usize,
    /// Candidates (by decreasing energy gain) tried per iteration before giving up.
    pub max_candidates: usize,
    /// Curve samples per knot span for the closest-point search.
    pub projection_samples: usize,
    /// Control points of an open curve that never move, counted from the start and from the end
    /// (`(3, 2)`: `P_0 … P_2` and `P_{n−1}, P_n`); they hold end conditions (a tangent fixes two,
    /// a curvature three: `fit::end_constraints`). Default `(0, 0)`: only `fix_ends`.
    pub held: (usize, usize),
}

impl Default for FairingOptions {
    fn default() -> Self {
        FairingOptions {
            max_iterations: 300,
            fix_ends: true,
            energy_order: None,
            step_halvings: 6,
            max_candidates: 8,
            projection_samples: 16,
            held: (0, 0),
        }
    }
}

/// Result of [`fair_curve`].
#[derive(Clone, Debug, PartialEq)]
pub struct FairingResult {
    /// The faired curve (same degree, knots and weights as the input).
    pub curve: NurbsCurve,
    /// Number of accepted control-point moves.
    pub iterations: usize,
    /// `F` of the input curve.
    pub fairness_before: f64,
    /// `F` of the faired curve (never above `fairness_before`).
    pub fairness_after: f64,
    /// Largest orthogonal distance of a data point to the input curve.
    pub max_deviation_before: f64,
    /// Largest orthogonal distance of a data point to the faired curve.
    pub max_deviation_after: f64,
}

/// Fairs `curve` while every point of `points` stays within `tol` (absolute) of it.
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3, knots::uniform_clamped};
/// use fairfit::fair::{fair_curve, FairingOptions};
/// // a wobbly cubic and the points it was "fitted" to (the smooth parabola y = x²/10)
/// let pts: Vec<Vec3> = (0..10)
///     .map(|i| { let x = i as f64; Vec3::new(x, x * x / 10.0 + 0.02 * (-1f64).powi(i), 0.0) })
///     .collect();
/// let c = NurbsCurve::bspline(3, uniform_clamped(3, 10), pts).unwrap();
/// let data: Vec<Vec3> = (0..=90).map(|i| { let x = i as f64 / 10.0; Vec3::new(x, x * x / 10.0, 0.0) }).collect();
/// let r = fair_curve(&c, &data, 0.05, &FairingOptions::default()).unwrap();
/// assert!(r.fairness_after < r.fairness_before);
/// assert!(r.max_deviation_after <= 0.05f64.max(r.max_deviation_before));
/// ```
pub fn fair_curve(
    curve: &NurbsCurve,
    points: &[Vec3],
    tol: f64,
    opts: &FairingOptions,
) -> Result<FairingResult> {
    check_inputs(points, tol)?;
    if let Some(r) = fair_rescaled(curve, points, tol, opts) {
        return r;
    }
    let moves = Moves::new(curve, opts);
    let samples = opts.projection_samples.max(2);
    let mut ev = FairnessEvaluator::new();
    let fairness_before = ev.evaluate(curve).0;
    let mut state = State::new(curve, points, samples, fairness_before);
    let max_deviation_before = state.dist.iter().fold(0.0f64, |m, &d| m.max(d));
    let allowance: Vec<f64> = state.dist.iter().map(|&d| d.max(tol)).collect();
    let mut iterations = 0;
    let mut candidates: Vec<(f64, usize, Vec3)> = Vec::with_capacity(moves.movable.len());
    while iterations < opts.max_iterations {
        moves.rank(&state.ctrl, &mut candidates);
        let accepted = candidates
            .iter()
            .take(opts.max_candidates.max(1))
            .any(|&(_, r, delta)| {
                moves.try_move(
                    r, delta, &mut state, points, &allowance, samples, opts, &mut ev,
                )
            });
        if !accepted {
            break;
        }
        iterations += 1;
    }
    let max_deviation_after = state.dist.iter().fold(0.0f64, |m, &d| m.max(d));
    Ok(FairingResult {
        curve: state.current,
        iterations,
        fairness_before,
        fairness_after: state.f_cur,
        max_deviation_before,
        max_deviation_after,
    })
}

/// A positive finite tolerance and finite data points, at least one.
fn check_inputs(points: &[Vec3], tol: f64) -> Result<()> {
    if !(tol.is_finite() && tol > 0.0) {
        return Err(Error::InvalidOption(format!(
            "fairing tolerance must be a positive finite number, got {tol}"
        )));
    }
    if points.is_empty() {
        return Err(Error::InvalidData(
            "fairing needs at least one data point".into(),
        ));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::InvalidData(format!("data point {i} is not finite")));
    }
    Ok(())
}

/// Far outside unit size F overflows or underflows and no move is ever judged: the fairing of an
/// exactly rescaled copy (see `nurbs::scale`), scaled back; `None` when the curve is of unit size
/// or the copy cannot be made or scaled back (then the curve is faired as it is).
fn fair_rescaled(
    curve: &NurbsCurve,
    points: &[Vec3],
    tol: f64,
    opts: &FairingOptions,
) -> Option<Result<FairingResult>> {
    let f = crate::nurbs::scale::normalising_factor(curve.control_points());
    let scaled_points: Vec<Vec3> = points.iter().map(|&q| q * f).collect();
    let c = (f != 1.0 && scaled_points.iter().all(|q| q.is_finite()))
        .then(|| crate::nurbs::scale::scaled_curve(curve, f).ok())
        .flatten()?;
    let r = match fair_curve(&c, &scaled_points, tol * f, opts) {
        Ok(r) => r,
        Err(e) => return Some(Err(e)),
    };
    let back = crate::nurbs::scale::scaled_curve(&r.curve, 1.0 / f).ok()?;
    Some(Ok(FairingResult {
        curve: back,
        max_deviation_before: r.max_deviation_before / f,
        max_deviation_after: r.max_deviation_after / f,
        ..r
    }))
}

/// The current curve of the fairing, its control points and `F`, and every data point's foot
/// parameter and distance (with scratch copies for a trial move).
struct State {
    ctrl: Vec<Vec3>,
    current: NurbsCurve,
    f_cur: f64,
    params: Vec<f64>,
    dist: Vec<f64>,
    trial_params: Vec<f64>,
    trial_dist: Vec<f64>,
}

impl State {
    /// The input curve with `F = fairness` and the data points' feet on it.
    fn new(curve: &NurbsCurve, points: &[Vec3], samples: usize, fairness: f64) -> Self {
        let (mut params, mut dist) = (
            Vec::with_capacity(points.len()),
            Vec::with_capacity(points.len()),
        );
        let proj = CurveProjector::new(curve, samples);
        for &q in points {
            let pr = proj.project(q);
            params.push(pr.u);
            dist.push(pr.distance);
        }
        State {
            ctrl: curve.control_points().to_vec(),
            current: curve.clone(),
            f_cur: fairness,
            trial_params: params.clone(),
            trial_dist: dist.clone(),
            params,
            dist,
        }
    }
}

/// The control-point moves of the fairing: the energy's Gram matrix, the knots and weights every
/// trial curve keeps, and which control points move (with their periodic copies).
struct Moves {
    p: usize,
    n: usize,
    knots: Vec<f64>,
    weights: Vec<f64>,
    gram: Gram,
    /// The number of distinct control points of a periodic curve.
    wrap: Option<usize>,
    movable: Vec<usize>,
}

impl Moves {
    fn new(curve: &NurbsCurve, opts: &FairingOptions) -> Self {
        let p = curve.degree();
        let n = curve.n_control_points();
        let knots = curve.knots().to_vec();
        let weights = curve.weights().to_vec();
        let order = opts.energy_order.unwrap_or(3).clamp(1, p);
        let gram = Gram::new(p, &knots, n, order);
        // a periodic curve (the last p control points repeat the first): every distinct point
        // moves, together with its copy, so the seam stays C^(p−1)
        let wrap = periodic_copies(curve);
        let n_distinct = wrap.unwrap_or(n);
        let movable: Vec<usize> = (0..n_distinct)
            .filter(|&r| wrap.is_some() || !(opts.fix_ends && (r == 0 || r + 1 == n)))
            .filter(|&r| wrap.is_some() || (r >= opts.held.0 && r + opts.held.1 < n))
            .collect();
        Moves {
            p,
            n,
            knots,
            weights,
            gram,
            wrap,
            movable,
        }
    }

    /// The control points that move with `r`: itself, and its copy on a periodic curve.
    fn copies(&self, r: usize) -> ([usize; 2], usize) {
        match self.wrap {
            Some(nu) if r < self.p => ([r, r + nu], 2),
            _ => ([r, r], 1),
        }
    }

    /// Every movable point's energy gain `|g_r|² / G_rr` and step `−g_r / G_rr`, best first (ties
    /// by index).
    fn rank(&self, ctrl: &[Vec3], candidates: &mut Vec<(f64, usize, Vec3)>) {
        let (p, n, gram) = (self.p, self.n, &self.gram);
        candidates.clear();
        for &r in &self.movable {
            // the energy over the moved point: Σ G_ab over its copies a, b, gradient Σ_a (G P)_a
            let (idx, k) = self.copies(r);
            let idx = &idx[..k];
            let mut grr = 0.0;
            let mut g = Vec3::ZERO;
            for &a in idx {
                for &b in idx {
                    grr += gram.get(a, b);
                }
                let lo = a.saturating_sub(p);
                let hi = (a + p).min(n - 1);
                let mut ga = Vec3::ZERO;
                for (j, cj) in ctrl.iter().enumerate().take(hi + 1).skip(lo) {
                    ga += *cj * gram.get(a, j);
                }
                g += ga;
            }
            if grr <= 0.0 {
                continue;
            }
            let gain = g.norm_squared() / grr;
            if gain > 0.0 && gain.is_finite() {
                candidates.push((gain, r, g * (-1.0 / grr)));
            }
        }
        candidates.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    }

    /// Moves `r` by `delta` with steps `1, ½, ¼, …` and keeps the first trial that lowers `F` with
    /// every data point within its allowance; whether one was kept.
    #[allow(clippy::too_many_arguments)]
    fn try_move(
        &self,
        r: usize,
        delta: Vec3,
        state: &mut State,
        points: &[Vec3],
        allowance: &[f64],
        samples: usize,
        opts: &FairingOptions,
        ev: &mut FairnessEvaluator,
    ) -> bool {
        let mut t = 1.0;
        for _ in 0..=opts.step_halvings {
            let mut trial_ctrl = state.ctrl.clone();
            let (idx, k) = self.copies(r);
            for &a in &idx[..k] {
                trial_ctrl[a] += delta * t;
            }
            t *= 0.5;
            let Ok(trial) = NurbsCurve::new(
                self.p,
                self.knots.clone(),
                trial_ctrl.clone(),
                Some(self.weights.clone()),
            ) else {
                continue;
            };
            let f_trial = ev.evaluate(&trial).0;
            if f_trial.is_nan() || f_trial >= state.f_cur * (1.0 - 1e-12) {
                continue;
            }
            let proj = CurveProjector::new(&trial, samples);
            let mut ok = true;
            for (i, &q) in points.iter().enumerate() {
                let pr = proj.project_near(q, state.params[i]);
                if pr.distance > allowance[i] {
                    ok = false;
                    break;
                }
                state.trial_params[i] = pr.u;
                state.trial_dist[i] = pr.distance;
            }
            if ok {
                state.ctrl = trial_ctrl;
                state.current = trial;
                state.f_cur = f_trial;
                state.params.copy_from_slice(&state.trial_params);
                state.dist.copy_from_slice(&state.trial_dist);
                return true;
            }
        }
        false
    }
}

/// For a periodic curve (unclamped knots, the last `p` control points and weights repeating the
/// first, as the least-squares method writes closed curves), the number of distinct control points.
fn periodic_copies(curve: &NurbsCurve) -> Option<usize> {
    let (p, n) = (curve.degree(), curve.n_control_points());
    let k = curve.knots();
    let c = curve.control_points();
    let w = curve.weights();
    let clamped = k[..=p].iter().all(|&u| u == k[0]);
    (!clamped && n > 2 * p && (0..p).all(|i| c[i] == c[n - p + i] && w[i] == w[n - p + i]))
        .then_some(n - p)
}
