//! The release-ends stage: the last band fairing pass on the chosen open curve, with the
//! requested end condition.
//!
//! With pinned ends (the default) it is one more pass of the pinned finishing stages on the curve
//! the count and degree choice kept: those stages ran on every candidate with the budgets of the
//! search, and a pass on the winner alone still lowers `F` where the first passes stalled.
//!
//! Free end points ([`EndCondition::Free`]): the integrated method runs as with pinned ends (the
//! knot and count search, the finishing stages, the degree choice), then the chosen open curve
//! gets one more band fairing pass with its end points released: every control point moves, each
//! data end point held within the tolerance of the curve's end point
//! ([`crate::optim::fairing::control_map`]), followed by a polish with free ends and a pass holding the
//! extrema pattern ([`BandTuning::hold_persistence`]).
//!
//! The pass is kept only when it lowers `F` with no new curvature extrema (by the passes' guard,
//! then by the reports' sampled and exact counts: `more_extrema`) and every point within the
//! tolerance ([`refair`]), so the result has the pinned result's knots, count and degree and is
//! never less fair. Releasing the ends after the choice (rather than in every finishing stage, or
//! on every candidate) keeps the count and degree choice of the pinned curves. Not applicable to
//! closed curves (no end points); the pieces between corners keep theirs pinned (they are joined
//! there).

use crate::diffgeo::CurveProjector;
use crate::errors::Result;
use crate::fair::{count_extrema_exact, curve_fairness};
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::{band_solves, FitContext};
use crate::optim::fairing::EndCondition;
use crate::optim::fairing::{polish, PolishOptions};
use crate::optim::fairing::{refair, BandOptions, BandTuning};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::objective::{measure_current, CandidateEval, EvalWorkspace, FitData};
use crate::optim::search::prepare::Prepared;
use rayon::prelude::*;

/// The release-ends stage's input.
#[derive(Clone, Debug)]
pub(crate) struct ReleaseInput {
    /// The open fit the count and degree search kept.
    pub chosen: IntegratedResult,
}

/// The release-ends stage's result.
#[derive(Clone, Debug)]
pub(crate) struct ReleaseOutput {
    /// The chosen fit after the last pass, or as it was when the pass was not kept.
    pub result: IntegratedResult,
}

/// The release-ends stage of the open pipeline: [`release_result`] on the chosen result with the
/// context's data, tolerance and options.
pub(crate) fn run(ctx: &FitContext, input: ReleaseInput) -> Result<ReleaseOutput> {
    let result = release_result(ctx.prep, input.chosen, ctx.tol, ctx.opts)?;
    Ok(ReleaseOutput { result })
}

/// [`release_ends`] on the chosen open result `r` of the integrated method on `prep`'s data
/// (tolerance `tol` in its normalised units), with the budgets of `opts`; `r` unchanged without
/// finishing stages (`opts.polish` off) or when the pass is not kept.
fn release_result(
    prep: &Prepared,
    mut r: IntegratedResult,
    tol: f64,
    opts: &IntegratedOptions,
) -> Result<IntegratedResult> {
    let p = r.curve.degree();
    if !opts.polish || r.curve.is_rational() || p > crate::optim::search::objective::MAX_DEGREE {
        return Ok(r);
    }
    let mut data = prep.data.clone();
    data.degree = p;
    let inv = 1.0 / prep.scale;
    let ctrl: Vec<Vec3> = r
        .curve
        .control_points()
        .iter()
        .map(|&c| (c - prep.origin) * inv)
        .collect();
    let normalised = NurbsCurve::bspline(p, r.curve.knots().to_vec(), ctrl.clone())?;
    // the feet by a global projection (the finishing stages' feet are not kept with the result)
    let projector = CurveProjector::new(&normalised, 16);
    // (in parallel: each point's projection alone, collected in order, the same for any threads)
    let start: Vec<f64> = data
        .points
        .par_iter()
        .map(|&q| projector.project(q).u)
        .collect();
    let mut ws = EvalWorkspace::default();
    ws.knots = r.curve.knots().to_vec();
    ws.ctrl = ctrl;
    let before = measure_current(&data, &start, &mut ws);
    if !before.solved || before.max_deviation > tol {
        return Ok(r);
    }
    let ro = ReleaseOptions {
        ends: opts.ends,
        span_cap: opts.span_fairness,
        band_solves: band_solves(opts),
        polish_evaluations: opts.polish_evaluations,
    };
    let e = release_ends(&data, &mut ws, before, tol, &ro);
    if !(e.solved && e.fairness < before.fairness && e.max_deviation <= tol) {
        return Ok(r);
    }
    let ctrl: Vec<Vec3> = ws.ctrl.iter().map(|&c| prep.denormalise(c)).collect();
    let curve = NurbsCurve::bspline(p, ws.knots.clone(), ctrl)?;
    if more_extrema(&curve, &r.curve) {
        return Ok(r);
    }
    r.curve = curve;
    r.quality.max_deviation = e.max_deviation * prep.scale;
    r.quality.rms_deviation = e.rms_deviation * prep.scale;
    r.quality.fairness = e.fairness;
    r.quality.max_span_fairness = e.max_span_fairness;
    r.met = e.max_deviation <= tol && opts.span_fairness.is_none_or(|t| e.max_span_fairness <= t);
    Ok(r)
}

/// Whether `curve` has more curvature extrema than `before`, sampled as the reports count them
/// ([`curve_fairness`]) or exactly ([`count_extrema_exact`]). The passes' own guard
/// ([`crate::optim::band_fairing::ExtremaCount`], 96 samples per knot span) can miss a flat ripple in a
/// long span: naca4412 at seed 1 got two extrema 0.005 apart in a span of 0.4 (`κ` 0.31422 and
/// 0.31421), seen by both of these counts.
/// The two curves are measured in parallel (each alone, so the same for any thread count).
fn more_extrema(curve: &NurbsCurve, before: &NurbsCurve) -> bool {
    let (a, b) = rayon::join(|| curve_fairness(curve), || curve_fairness(before));
    a.curvature_extrema > b.curvature_extrema || {
        let (x, y) = rayon::join(
            || count_extrema_exact(curve, a.length).curvature_extrema,
            || count_extrema_exact(before, b.length).curvature_extrema,
        );
        x > y
    }
}

/// Budgets and targets of [`release_ends`] (those of the pinned stages).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReleaseOptions {
    /// The end condition of the pass: [`EndCondition::Free`] releases the end points,
    /// [`EndCondition::Pinned`] keeps them (a last pass of the pinned stages on the chosen curve).
    pub ends: EndCondition,
    /// The per-span fairness target `F*`.
    pub span_cap: Option<f64>,
    /// Most subproblems of the band fairing pass (0: no band fairing, the polish alone).
    pub band_solves: usize,
    /// Most curve measurements of the polish.
    pub polish_evaluations: usize,
}

/// Releases the end points of the finished open curve in `ws` (measured as `before`, ends pinned):
/// a band fairing pass with free ends (kept only when it lowers `F` without new curvature extrema
/// and within `tol`), then, when it was kept (or without band fairing), a polish with free ends and
/// a pass holding the extrema pattern. Returns the measurement of the curve left in `ws` (with the
/// end points' distances from the curve's ends).
pub fn release_ends(
    data: &FitData,
    ws: &mut EvalWorkspace,
    before: CandidateEval,
    tol: f64,
    opts: &ReleaseOptions,
) -> CandidateEval {
    let bo = BandOptions {
        span_cap: opts.span_cap,
        max_solves: opts.band_solves,
        ends: opts.ends,
        ..BandOptions::default()
    };
    let mut e = before;
    let kept = if opts.band_solves > 0 {
        refair(data, ws, &e, tol, &bo)
    } else {
        None
    };
    if let Some(k) = kept {
        e = k;
    }
    if kept.is_some() || opts.band_solves == 0 {
        let start = ws.foot_params.clone();
        let po = PolishOptions {
            span_cap: opts.span_cap,
            max_evaluations: opts.polish_evaluations,
            ends: opts.ends,
            ..PolishOptions::default()
        };
        e = polish(data, ws, &start, tol, &po).eval;
    }
    if kept.is_some() {
        let hold = BandOptions {
            extrema_persistence: BandTuning::new().hold_persistence,
            max_solves: opts.band_solves.min(BandTuning::new().refair_solves),
            ..bo
        };
        e = refair(data, ws, &e, tol, &hold).unwrap_or(e);
    }
    e
}
