//! The integrated fitting-and-fairing method (method reconstruction §3.2, §7): the knot vector is
//! searched by particle swarm optimisation so that the curve stays within the tolerance of the data
//! while its fairness `F` (and the worst span's `F_j`) is as small as possible, with the fewest
//! control points that allow it.
//!
//! 1. The data are normalised (scale-free) and parameterised centripetally.
//! 2. Baseline: the least-squares method's own knots (`fit::tolerance`, same parameters) when they
//!    meet the tolerance here, else the averaging knots with the fewest control points that do.
//! 3. Count search: for one control point fewer at a time, the best single knot removal, else a short
//!    swarm probe (seeded with the removals and the averaging knots) looks for any knot vector meeting
//!    the tolerance (and `F*`); the first count where none is found ends the search.
//! 4. At the smallest feasible count, the full swarm minimises `F + max_j F_j` subject to the
//!    tolerance (ε-constraint, feasibility-first), then a pattern search refines the best particle
//!    and a line search on the smoothing weight λ smooths it as far as the tolerance allows.
//! 5. Up to `max_extra_control_points` more control points are tried (never more than the baseline).
//! 6. Every candidate's control points are faired inside the tolerance band
//!    ([`super::band_fairing`], with `band_fairing`) and polished by single-point moves
//!    ([`super::polish`], with `polish`); the count is chosen on these finished curves
//!    ([`super::count_search`]: an added point must lower F by 5 % and add no curvature extrema).
//!
//! With [`IntegratedOptions::control_points`] the count is fixed instead (the descent
//! stops there, or knots are inserted where they help most above the baseline; step 5 is skipped), which is how the benchmark compares
//! methods at equal control points.

use super::band_fairing::{band_fair, later_passes, refair, BandOptions};
pub use super::control_map::EndCondition;
use super::count_search::{search_counts_costed, CountFamily, CountStart};
use super::degree_candidates::CountsSeen;
use super::descent::second_descent;
use super::encoding::KnotEncoding;
use super::knot_edits::{self, descend, insertion_spans, lsq_method_fit, map_knots, Descent};
use super::objective::{evaluate_candidate, set_knots, CandidateEval, EvalWorkspace, FitData};
use super::options::validate;
pub use super::options::{Budget, IntegratedOptions, NonExhaustive};
use super::polish::{polish, PolishOptions, Polished};
use super::prepare::{averaging_interior_knots, prepare, Prepared};
use super::problem::KnotProblem;
use crate::errors::{Error, Result};
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
pub use crate::tolerance::Tolerance;
use rayon::prelude::*;
use std::time::Instant;

/// What the optimiser did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OptimStats {
    /// Candidate evaluations (least-squares solves) in total.
    pub evaluations: usize,
    /// Swarm iterations in total.
    pub iterations: usize,
    /// Control-point counts tried, in order.
    pub counts_tried: Vec<usize>,
    /// `(count, F)` of every full knot search (F infinite when the tolerance was not met).
    pub fairness_by_count: Vec<(usize, f64)>,
    /// Accepted control-point moves of the final polish ([`super::polish`]).
    pub polish_moves: usize,
    /// Every degree's fit, in degree order, when the degree was searched
    /// ([`IntegratedOptions::max_degree`]; empty otherwise). Evaluations, iterations and seconds
    /// then count all degrees; the other fields are the chosen degree's.
    pub degrees_tried: Vec<super::degree_search::DegreeTrial>,
    /// Wall time in seconds.
    pub seconds: f64,
    /// Whether the chosen curve's end points were free in its last fairing pass
    /// ([`EndCondition::Free`] on an open curve without corners; [`super::free_ends`]).
    pub free_ends: bool,
}

impl OptimStats {
    /// Adds the evaluations and iterations of the chosen result's `finished` statistics and takes
    /// its polish moves and degree trials; the wall time is measured from `start`.
    pub(crate) fn absorb(&mut self, finished: &mut OptimStats, start: Instant) {
        self.evaluations += finished.evaluations;
        self.iterations += finished.iterations;
        self.polish_moves = finished.polish_moves;
        self.degrees_tried = std::mem::take(&mut finished.degrees_tried);
        self.seconds = start.elapsed().as_secs_f64();
    }
}

/// The measured quality of a fitted curve (in the input's units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitQuality {
    /// Maximum orthogonal deviation.
    pub max_deviation: f64,
    /// RMS orthogonal deviation.
    pub rms_deviation: f64,
    /// Whole-curve fairness F.
    pub fairness: f64,
    /// max_j F_j.
    pub max_span_fairness: f64,
}

/// The result of [`fit_integrated`].
#[derive(Clone, Debug)]
pub struct IntegratedResult {
    /// The fitted curve.
    pub curve: NurbsCurve,
    /// Its quality.
    pub quality: FitQuality,
    /// The tolerance in the input's units.
    pub tolerance: f64,
    /// Whether the tolerance (and `F*`) was met.
    pub met: bool,
    /// `log10 λ` of the smoothing weight used (`-inf` for none).
    pub log_lambda: f64,
    /// Control points of the least-squares baseline (averaging knots) meeting the tolerance.
    pub baseline_control_points: usize,
    /// Optimiser statistics.
    pub stats: OptimStats,
}

/// Smallest knot gap as a fraction of the parameter domain.
const MIN_GAP: f64 = 1e-4;

/// Fits a fair cubic B-spline to ordered `points` by the integrated method.
///
/// ```
/// use fairfit::prelude::*;
/// let pts: Vec<Vec3> = (0..60)
///     .map(|i| {
///         let t = i as f64 / 59.0 * 1.5;
///         Vec3([2.0 * t.cos(), t.sin(), 0.0])
///     })
///     .collect();
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_integrated(&pts, &opts).unwrap();
/// assert!(r.met && r.quality.max_deviation <= r.tolerance);
/// assert!(r.curve.n_control_points() <= r.baseline_control_points);
/// ```
pub fn fit_integrated(points: &[Vec3], opts: &IntegratedOptions) -> Result<IntegratedResult> {
    fit_integrated_with_progress(points, opts, &|_, _| {})
}

/// [`fit_integrated`] with a progress callback `(stage, iteration)` called from the calling thread
/// between swarm iterations (stage = control-point count being searched); with a degree search
/// ([`IntegratedOptions::max_degree`]) every degree's fit reports from its own worker thread.
pub fn fit_integrated_with_progress(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<IntegratedResult> {
    let start = Instant::now();
    validate(opts)?;
    if let Some(r) = super::closed::fit_if_closed(points, opts, progress, start)? {
        return Ok(r);
    }
    let prep = prepare(points, opts.degree)?;
    if let Some(angle) = opts.corner_angle_deg {
        let corners = crate::fit::shape::detect_corners(&prep.data.points, false, angle);
        let ranges = super::corners::pieces(prep.data.points.len(), &corners);
        if ranges.len() > 1 {
            return super::corner_fit::fit_with_corners(&prep, &ranges, opts, progress, start);
        }
    }
    let tol = tolerance_of(opts, prep.scale);
    let p = opts.degree;
    let data = &prep.data;
    let m1 = data.points.len();
    if let Some(n) = opts.control_points {
        // every knot span needs a data parameter strictly inside (Schoenberg–Whitney)
        if n + 1 > m1 {
            return Err(Error::InvalidOption(format!(
                "{n} control points are too many for {m1} points (at most {})",
                m1 - 1
            )));
        }
    }
    let mut stats = OptimStats::default();

    // 2. least-squares baseline count
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

    // the least-squares method's own knots (adaptive placement), mapped onto these parameters: a
    // much better start than averaging knots, and a tighter baseline count
    let mut lsq_start: Option<(usize, Vec<f64>)> = None;
    if let Some(knots) = lsq_method_knots(data, tol) {
        set_knots(p, &knots, &mut ws);
        let e = evaluate_candidate(data, f64::NEG_INFINITY, &mut ws);
        stats.evaluations += 1;
        let n = knots.len() + p + 1;
        if e.solved && e.max_deviation <= tol && n <= baseline {
            baseline = n;
            lsq_start = Some((n, knots));
        }
    }

    // 3. count search downwards from the baseline: greedy knot removal, then a swarm probe
    // a fixed count descends from the baseline to it (feasible seeds), or starts above it
    let fixed = opts.control_points;
    let best_n = fixed.map_or(baseline, |n| n.max(baseline));
    let lowest = fixed.unwrap_or(p + 1).max(p + 1).max(4);
    let best_knots = match lsq_start {
        Some((n, k)) if n == best_n => k,
        Some((n, mut k)) if n < best_n => {
            // a fixed count above the least-squares one: add knots where they help most
            while k.len() + p + 1 < best_n {
                k = best_insertion(data, &k, f64::NEG_INFINITY, tol);
            }
            k
        }
        _ => averaging_interior_knots(&data.params, p, best_n),
    };
    // feasible knots met on the way down, by count: seeds for the searches with extra points
    let family = OpenFamily {
        prep: &prep,
        tol,
        opts,
    };
    let mut down = Descent::new(best_n, best_knots);
    let removals = |k: &[f64]| removal_candidates(data, k);
    descend(
        &family, &mut down, lowest, tol, removals, false, opts, progress, &mut stats,
    );
    // a second descent on other random streams seeds the count search's restart
    let alt = second_descent(
        &family, &down, lowest, tol, removals, opts, progress, &mut stats,
    );
    let Descent {
        n: mut best_n,
        knots: mut best_knots,
        met: descent,
        ..
    } = down;
    if let Some(n) = fixed {
        // the tolerance cannot be met at the fixed count: remove the knots that hurt least anyway
        while best_n > n {
            match removal_candidates(data, &best_knots).into_iter().next() {
                Some((_, k)) => best_knots = k,
                None => best_knots = averaging_interior_knots(&data.params, p, n),
            }
            best_n -= 1;
        }
    }

    // 4. full search at the smallest feasible count, then at one more control point at a time
    //    while that buys a factor `fairness_gain` in F (never more than the baseline)
    let start_at = CountStart {
        n: best_n,
        knots: &best_knots,
        descent: &descent,
        limit: m1.min(baseline),
        alt: &alt,
    };
    // with a degree search, the next degree (from the descent's knots) runs beside the count search
    let (result, first) = rayon::join(
        || search_counts_costed(&family, start_at, opts, progress, &mut stats),
        || {
            opts.searches_degree()
                .then(|| super::degree_candidates::open_next(&prep, &best_knots, tol, opts))
        },
    );
    let (result, choice) = result?;
    let mut result = if opts.searches_degree() {
        // a fixed count, or no extra points, leaves the next degree no counts of its own
        let seen = (fixed.is_none() && opts.max_extra_control_points > 0).then_some(CountsSeen {
            n: best_n,
            descent: &descent,
            limit: start_at.limit,
            extrema_cost: choice.extrema_cost,
            count_gain: choice.count_gain,
            extrema: choice.extrema,
        });
        super::degree_candidates::raise_open(&prep, result, tol, opts, first, seen)?
    } else {
        result
    };
    // one more band fairing pass on the chosen curve, with the requested end condition
    result = super::free_ends::release_result(&prep, result, tol, opts)?;
    stats.free_ends = opts.ends == EndCondition::Free;
    stats.absorb(&mut result.stats, start);
    Ok(IntegratedResult {
        baseline_control_points: baseline,
        stats,
        ..result
    })
}

/// The open knot search for `n` control points.
pub(crate) fn open_problem<'a>(
    data: &'a FitData,
    n: usize,
    tol: f64,
    opts: &IntegratedOptions,
) -> KnotProblem<'a> {
    KnotProblem {
        data,
        encoding: KnotEncoding::new(n - opts.degree - 1, MIN_GAP, opts.search_smoothing),
        tolerance: tol,
        span_target: opts.span_fairness,
        fairness_cutoff: 1.0,
    }
}

/// The open knot searches of one data set, for [`search_counts`].
struct OpenFamily<'a> {
    prep: &'a Prepared,
    tol: f64,
    opts: &'a IntegratedOptions,
}

impl<'a> CountFamily for OpenFamily<'a> {
    type Problem = KnotProblem<'a>;

    fn problem(&self, n: usize) -> KnotProblem<'a> {
        open_problem(&self.prep.data, n, self.tol, self.opts)
    }

    fn spread_knots(&self, n: usize) -> Vec<f64> {
        averaging_interior_knots(&self.prep.data.params, self.opts.degree, n)
    }

    fn insertion(&self, knots: &[f64], log_lambda: f64) -> Vec<f64> {
        best_insertion(&self.prep.data, knots, log_lambda, self.tol)
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

/// The least-squares fit with averaging knots and `n_ctrl` control points (the baseline the
/// integrated method starts from), measured like the integrated result.
pub fn fit_lsq_baseline(
    points: &[Vec3],
    n_ctrl: usize,
    opts: &IntegratedOptions,
) -> Result<IntegratedResult> {
    validate(opts)?;
    let prep = prepare(points, opts.degree)?;
    if n_ctrl < opts.degree + 1 || n_ctrl > prep.data.points.len() {
        return Err(Error::InvalidOption(format!(
            "{n_ctrl} control points: need between {} and {}",
            opts.degree + 1,
            prep.data.points.len()
        )));
    }
    let tol = tolerance_of(opts, prep.scale);
    let knots = averaging_interior_knots(&prep.data.params, opts.degree, n_ctrl);
    let r = finish(&prep, &knots, f64::NEG_INFINITY, tol, opts, None)?;
    Ok(IntegratedResult {
        baseline_control_points: n_ctrl,
        ..r
    })
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

/// The band fairing's subproblem budget under `opts` (0: no band fairing).
pub(crate) fn band_solves(opts: &IntegratedOptions) -> usize {
    if opts.band_fairing {
        opts.band_solves
    } else {
        0
    }
}

/// The tolerance in normalised units.
pub(crate) fn tolerance_of(opts: &IntegratedOptions, scale: f64) -> f64 {
    match opts.tolerance {
        Tolerance::Relative(r) => r,
        Tolerance::Absolute(t) => t / scale,
    }
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
    let mut e: CandidateEval = evaluate_candidate(&prep.data, log_lambda, &mut ws);
    if !e.solved {
        return Err(Error::Fit(
            "the least-squares system is singular for these knots".into(),
        ));
    }
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
