//! The open curve kind: a clamped B-spline whose ends sit on the data's first and last points.
//!
//! Its knot search places the `n − p − 1` interior knots in `(0, 1)` (softmax gaps, at least
//! [`MIN_KNOT_GAP`] apart); the baseline is the least-squares method's own knots mapped onto these
//! parameters when they meet the tolerance, else the averaging knots with the fewest control
//! points that do; finishing is band fairing, the polish and the pass that re-fairs holding the
//! extrema pattern ([`finish_curve`]).

use super::{Baseline, CurveKind};
use crate::errors::{Error, Result};
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::band_solves;
use crate::optim::fairing::{band_fair, later_passes, refair, BandOptions};
use crate::optim::fairing::{polish, PolishOptions, Polished};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::{FitQuality, IntegratedResult, OptimStats};
use crate::optim::search::encoding::KnotEncoding;
use crate::optim::search::knot_edits::{self, insertion_spans, lsq_method_fit, map_knots};
use crate::optim::search::objective::{
    evaluate_candidate, set_knots, CandidateEval, EvalWorkspace, FitData,
};
use crate::optim::search::prepare::{averaging_interior_knots, Prepared};
use crate::optim::search::problem::KnotProblem;
use crate::optim::tuning::{SwarmTuning, Tuning};
use rayon::prelude::*;

/// Smallest knot gap as a fraction of the parameter domain.
pub(crate) const MIN_KNOT_GAP: f64 = 1e-4;

/// The open knot search for `n` control points.
pub(crate) fn open_problem<'a>(
    data: &'a FitData,
    n: usize,
    tol: f64,
    opts: &IntegratedOptions,
    swarm: &SwarmTuning,
) -> KnotProblem<'a> {
    KnotProblem {
        data,
        encoding: KnotEncoding::new(n - opts.degree - 1, MIN_KNOT_GAP, swarm.search_smoothing),
        tolerance: tol,
        span_target: opts.span_fairness,
        fairness_cutoff: 1.0,
    }
}

/// The open curve on one prepared data set and tolerance.
pub(crate) struct OpenKind<'a> {
    /// The prepared data.
    pub prep: &'a Prepared,
    /// The tolerance (normalised units).
    pub tol: f64,
    /// The fit's options.
    pub opts: &'a IntegratedOptions,
    /// The method's measured thresholds.
    pub tuning: &'a Tuning,
}

impl<'a> CurveKind for OpenKind<'a> {
    type Problem = KnotProblem<'a>;

    fn baseline(&self, stats: &mut OptimStats) -> Baseline {
        let (data, tol, p) = (&self.prep.data, self.tol, self.opts.degree);
        let m1 = data.points.len();
        let mut ws = EvalWorkspace::default();
        let mut baseline = m1;
        for n in p + 1..=m1 {
            let knots = averaging_interior_knots(&data.params, p, n);
            set_knots(p, &knots, &mut ws);
            let e = evaluate_candidate(data, f64::NEG_INFINITY, &mut ws);
            stats.evaluations += 1;
            if e.solved && e.max_deviation <= tol {
                baseline = n;
                break;
            }
        }
        // the least-squares method's own knots (adaptive placement), mapped onto these
        // parameters: a much better start than averaging knots, and a tighter baseline count
        let mut lsq_start: Option<Vec<f64>> = None;
        if let Some(knots) = lsq_method_knots(data, tol) {
            set_knots(p, &knots, &mut ws);
            let e = evaluate_candidate(data, f64::NEG_INFINITY, &mut ws);
            stats.evaluations += 1;
            let n = knots.len() + p + 1;
            if e.solved && e.max_deviation <= tol && n <= baseline {
                baseline = n;
                lsq_start = Some(knots);
            }
        }
        Baseline {
            count: baseline,
            knots: lsq_start,
        }
    }

    fn start(&self, baseline: &Baseline, fixed: Option<usize>) -> (usize, Vec<f64>) {
        let (data, p) = (&self.prep.data, self.opts.degree);
        // a fixed count descends from the baseline to it (feasible seeds), or starts above it
        let best_n = fixed.map_or(baseline.count, |n| n.max(baseline.count));
        let knots = match &baseline.knots {
            Some(k) if baseline.count == best_n => k.clone(),
            Some(k) if baseline.count < best_n => {
                // a fixed count above the least-squares one: add knots where they help most
                let mut k = k.clone();
                while k.len() + p + 1 < best_n {
                    k = best_insertion(data, &k, f64::NEG_INFINITY, self.tol);
                }
                k
            }
            _ => averaging_interior_knots(&data.params, p, best_n),
        };
        (best_n, knots)
    }

    fn problem(&self, n: usize) -> KnotProblem<'a> {
        open_problem(&self.prep.data, n, self.tol, self.opts, &self.tuning.swarm)
    }

    fn spread_knots(&self, n: usize) -> Vec<f64> {
        averaging_interior_knots(&self.prep.data.params, self.opts.degree, n)
    }

    fn insertion(&self, knots: &[f64], log_lambda: f64) -> Vec<f64> {
        best_insertion(&self.prep.data, knots, log_lambda, self.tol)
    }

    fn removal_candidates(&self, knots: &[f64]) -> Vec<(f64, Vec<f64>)> {
        removal_candidates(&self.prep.data, knots)
    }

    fn finish(&self, interior: &[f64], log_lambda: f64) -> Result<IntegratedResult> {
        let polish_within = self.opts.polish.then_some(self.tol);
        finish(
            self.prep,
            interior,
            log_lambda,
            self.tol,
            self.opts,
            polish_within,
        )
    }
}

/// The interior knots of the least-squares method (`fit::tolerance`, centripetal as here, corners
/// off, open curve) on the
/// normalised points, mapped from its parameterisation onto `data.params` piecewise linearly (corner
/// or coincident knots are spread by the encoding's repair). `None` when that fit fails.
fn lsq_method_knots(data: &FitData, tol: f64) -> Option<Vec<f64>> {
    let p = data.degree;
    let fit = lsq_method_fit(&data.points, p, tol, ClosedMode::Open)?;
    if fit.closed || fit.params.len() != data.params.len() || fit.curve.degree() != p {
        return None;
    }
    let knots = fit.curve.knots();
    let interior = knots.get(p + 1..knots.len().checked_sub(p + 1)?)?;
    let mut out = map_knots(interior, &fit.params, &data.params);
    let enc = KnotEncoding::new(out.len(), 0.0, false);
    enc.repair(&mut out, &data.params).then_some(out)
}

/// Every way to remove one interior knot, refitted by least squares (no smoothing), sorted by the
/// resulting maximum deviation (ties by knot index): `(deviation, knots)`. Evaluated in parallel,
/// collected in order.
pub(crate) fn removal_candidates(data: &FitData, knots: &[f64]) -> Vec<(f64, Vec<f64>)> {
    knot_edits::removal_candidates(knots, &data.params, |ws: &mut EvalWorkspace, k| {
        set_knots(data.degree, k, ws);
        evaluate_candidate(data, f64::NEG_INFINITY, ws)
    })
}

/// The interior knots with one more knot at the middle of one span: of all spans holding at least
/// two interior data parameters, the one whose refit (smoothing `log_lambda`) has the best
/// feasibility-first fitness (violation of `tol`, then `F + max_j F_j`; ties by span index).
/// Evaluated in parallel, chosen in span order.
pub(crate) fn best_insertion(data: &FitData, knots: &[f64], log_lambda: f64, tol: f64) -> Vec<f64> {
    let inner = &data.params[1..data.params.len().saturating_sub(1)];
    let (edges, spans) = insertion_spans(knots, inner);
    let scored: Vec<(f64, f64, Vec<f64>)> = spans
        .par_iter()
        .map_init(EvalWorkspace::default, |ws, &j| {
            let mut k = knots.to_vec();
            k.insert(j, 0.5 * (edges[j] + edges[j + 1]));
            set_knots(data.degree, &k, ws);
            let e = evaluate_candidate(data, log_lambda, ws);
            if !e.solved {
                return (f64::INFINITY, f64::INFINITY, k);
            }
            let violation = (e.max_deviation / tol - 1.0).max(0.0);
            let objective = e.fairness + e.max_span_fairness;
            (
                violation,
                if objective.is_nan() {
                    f64::INFINITY
                } else {
                    objective
                },
                k,
            )
        })
        .collect();
    let mut best: Option<(f64, f64, Vec<f64>)> = None;
    for c in scored {
        if best
            .as_ref()
            .is_none_or(|b| c.0 < b.0 || (c.0 == b.0 && c.1 < b.1))
        {
            best = Some(c);
        }
    }
    match best {
        Some((_, _, k)) => k,
        None => {
            // no span holds two parameters: fall back to the widest span
            let mut widest = 0;
            for j in 1..edges.len() - 1 {
                if edges[j + 1] - edges[j] > edges[widest + 1] - edges[widest] {
                    widest = j;
                }
            }
            let mut out = knots.to_vec();
            out.insert(widest, 0.5 * (edges[widest] + edges[widest + 1]));
            out
        }
    }
}

/// How [`finish_curve`] finishes the control points of a knot vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Finishing {
    /// The tolerance (normalised units).
    pub tol: f64,
    /// The per-span fairness target `F*`.
    pub span_cap: Option<f64>,
    /// Most band-fairing subproblems (0: no band fairing).
    pub band_solves: usize,
    /// Most polish measurements.
    pub polish_evaluations: usize,
}

/// The curve (input coordinates) and its quality for normalised interior knots and smoothing.
///
/// With `polish_within = Some(f)` the control points are then refined by [`polish`] within
/// `f.tol` (and the per-span target `f.span_cap`), after [`band_fair`] when `f.band_solves > 0`.
pub(crate) fn finish_curve(
    prep: &Prepared,
    interior: &[f64],
    log_lambda: f64,
    degree: usize,
    polish_within: Option<Finishing>,
) -> Result<(NurbsCurve, FitQuality, Option<Polished>)> {
    let mut ws = EvalWorkspace::default();
    set_knots(degree, interior, &mut ws);
    let e: CandidateEval = evaluate_candidate(&prep.data, log_lambda, &mut ws);
    if !e.solved {
        return Err(Error::Fit(
            "the least-squares system is singular for these knots".into(),
        ));
    }
    finish_measured(prep, ws, e, degree, polish_within)
}

/// The finishing of [`finish_curve`] from the measured curve in `ws` (`e` its measure, the
/// feet in `ws.foot_params`): band fairing, the polish and the re-fairing, then the curve in
/// input coordinates.
pub(crate) fn finish_measured(
    prep: &Prepared,
    mut ws: EvalWorkspace,
    mut e: CandidateEval,
    degree: usize,
    polish_within: Option<Finishing>,
) -> Result<(NurbsCurve, FitQuality, Option<Polished>)> {
    let mut polished = None;
    if let Some(Finishing {
        tol,
        span_cap,
        band_solves: band,
        polish_evaluations,
    }) = polish_within
    {
        let mut refair_from = None;
        if band > 0 {
            let start = ws.foot_params.clone();
            let bo = BandOptions {
                span_cap,
                max_solves: band,
                ..BandOptions::default()
            };
            refair_from = later_passes(&bo, &band_fair(&prep.data, &mut ws, &start, tol, &bo));
        }
        let start = ws.foot_params.clone();
        let po = PolishOptions {
            span_cap,
            max_evaluations: polish_evaluations,
            ..PolishOptions::default()
        };
        let pol = polish(&prep.data, &mut ws, &start, tol, &po);
        e = pol.eval;
        if let Some((bo, hold)) = refair_from {
            if let Some(kept) = refair(&prep.data, &mut ws, &e, tol, &bo) {
                // then once more holding the present extrema pattern (targets the band does not
                // allow stop the pass early)
                e = refair(&prep.data, &mut ws, &kept, tol, &hold).unwrap_or(kept);
            }
        }
        polished = Some(pol);
    }
    let ctrl: Vec<Vec3> = ws.ctrl.iter().map(|&c| prep.denormalise(c)).collect();
    let curve = NurbsCurve::bspline(degree, ws.knots.clone(), ctrl)?;
    Ok((
        curve,
        FitQuality {
            max_deviation: e.max_deviation * prep.scale,
            rms_deviation: e.rms_deviation * prep.scale,
            fairness: e.fairness,
            max_span_fairness: e.max_span_fairness,
        },
        polished,
    ))
}

/// Builds the curve in input coordinates from normalised interior knots and measures it.
pub(crate) fn finish(
    prep: &Prepared,
    interior: &[f64],
    log_lambda: f64,
    tol: f64,
    opts: &IntegratedOptions,
    polish_within: Option<f64>,
) -> Result<IntegratedResult> {
    let (curve, quality, polished) = finish_curve(
        prep,
        interior,
        log_lambda,
        opts.degree,
        polish_within.map(|tol| Finishing {
            tol,
            span_cap: opts.span_fairness,
            band_solves: band_solves(opts),
            polish_evaluations: opts.polish_evaluations,
        }),
    )?;
    let met = quality.max_deviation <= tol * prep.scale
        && opts
            .span_fairness
            .is_none_or(|t| quality.max_span_fairness <= t);
    Ok(IntegratedResult {
        screening: Default::default(),
        closure: Default::default(),
        curve,
        quality,
        tolerance: tol * prep.scale,
        met,
        log_lambda,
        baseline_control_points: 0,
        stats: OptimStats {
            evaluations: polished.map_or(0, |p| p.evaluations),
            polish_moves: polished.map_or(0, |p| p.moves),
            ..OptimStats::default()
        },
    })
}
