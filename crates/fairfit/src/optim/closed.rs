//! Closed curves in the integrated method.
//!
//! Data are closed when the last point repeats the first (the least-squares method's test,
//! [`crate::fit::shape::looks_closed`]) or when the caller says so ([`ClosedMode::Closed`]); the
//! repeated point is dropped. Then, as in the least-squares method:
//!
//! - with corners (turning angle above the threshold, every point — the first included — judged
//!   with its two neighbours on the loop), the loop is cut at its first corner and fitted as an open
//!   curve from that corner back to it, the other corners kept as C0 knots ([`super::corners`]): the
//!   result is a clamped curve whose two ends meet at the corner;
//! - without corners, the curve is **periodic**: the seam is fixed at the first point, the swarm
//!   searches the other `n_u − 1` breakpoints on the circle ([`super::periodic`]), the control points
//!   come from periodic least squares (`C^(p−1)` at the seam), `F` is measured over the whole loop
//!   and every point's orthogonal deviation counts. The output is written like the least-squares
//!   method's closed curves: an unclamped periodic knot vector with `n_u + p` control points of which
//!   the last `p` repeat the first.
//!
//! The search is the open method's ([`super::integrated`]) on periodic candidates: a baseline count
//! (the least-squares method's periodic knots mapped onto these parameters, else equal index steps),
//! the count descent by greedy knot removal and swarm probes, the full swarm and the smoothing line
//! search at the smallest feasible count, and up to `max_extra_control_points` more, the count chosen
//! on the finished curves ([`super::count_search`]). `--control-points N` fixes `n_u = N` distinct
//! control points. The
//! control-point polish of open curves is not applied (its moves would have to keep the seam
//! periodic).

use super::count_search::{search_counts, CountFamily, CountStart};
use super::integrated::{
    band_solves, fit_integrated_with_progress, tolerance_of, FitQuality, IntegratedOptions,
    IntegratedResult, OptimStats,
};
use super::knot_edits::{self, descend, insertion_spans, lsq_method_fit, map_knots, Descent};
use super::objective::CandidateEval;
use super::periodic::{evaluate_closed, ClosedData, ClosedProblem, ClosedWorkspace};
use super::periodic_fairing::fair_periodic;
use super::prepare::{prepare, Prepared};
use super::pso::SwarmProblem;
use crate::errors::{Error, Result};
use crate::fit::shape::{detect_corners, looks_closed};
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use rayon::prelude::*;
use std::time::Instant;

/// Smallest breakpoint gap as a fraction of the loop's parameter length.
const MIN_GAP: f64 = 1e-4;

/// Whether `points` are fitted as a closed curve under `mode`.
pub fn is_closed(points: &[Vec3], mode: ClosedMode) -> bool {
    match mode {
        ClosedMode::Open => false,
        ClosedMode::Closed => true,
        ClosedMode::Auto => looks_closed(points),
    }
}

/// The number of distinct control points of a curve: for a periodic curve (unclamped knots, the
/// last `p` control points repeating the first) `n − p`, else `n`.
pub fn distinct_control_points(curve: &NurbsCurve) -> usize {
    let (p, n) = (curve.degree(), curve.n_control_points());
    let k = curve.knots();
    let c = curve.control_points();
    let clamped = k[..=p].iter().all(|&u| u == k[0]);
    if !clamped && n > 2 * p && (0..p).all(|i| c[i] == c[n - p + i]) {
        n - p
    } else {
        n
    }
}

/// The integrated fit of closed data, or `None` when the data are open under `opts.closed` (the
/// caller then fits an open curve).
pub fn fit_if_closed(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    start: Instant,
) -> Result<Option<IntegratedResult>> {
    if !is_closed(points, opts.closed) {
        return Ok(None);
    }
    let mut pts = points.to_vec();
    if looks_closed(&pts) {
        pts.pop();
    }
    let prep = prepare(&pts, opts.degree)?;
    let open = IntegratedOptions {
        closed: ClosedMode::Open,
        // the open curve from a corner back to it closes there
        ends: super::integrated::EndCondition::Pinned,
        ..opts.clone()
    };
    if let Some(angle) = opts.corner_angle_deg {
        let found = detect_corners(&prep.data.points, true, angle);
        if let Some(&c0) = found.first() {
            // cut the loop at its first corner: an open curve from the corner back to it
            let mut seq: Vec<Vec3> = pts[c0..].iter().chain(&pts[..c0]).copied().collect();
            seq.push(pts[c0]);
            return fit_integrated_with_progress(&seq, &open, progress).map(Some);
        }
    }
    fit_periodic(&prep, opts, progress, start).map(Some)
}

/// The periodic integrated fit of the prepared distinct points of a closed curve without corners.
fn fit_periodic(
    prep: &Prepared,
    opts: &IntegratedOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    start: Instant,
) -> Result<IntegratedResult> {
    let data = ClosedData::new(prep)?;
    let p = opts.degree;
    let m = data.points.len();
    // every span needs a data parameter inside (Schoenberg–Whitney): at most m − 1 spans
    let max_n = m - 1;
    if let Some(n) = opts.control_points {
        if n < p + 1 || n > max_n {
            return Err(Error::InvalidOption(format!(
                "{n} control points do not fit a closed curve of degree {p} through {m} points \
                 (give between {} and {max_n})",
                p + 1
            )));
        }
    }
    let tol = tolerance_of(opts, prep.scale);
    let mut stats = OptimStats::default();
    let mut ws = ClosedWorkspace::default();
    let mut eval = |knots: &[f64], stats: &mut OptimStats| {
        stats.evaluations += 1;
        evaluate_closed(&data, knots, f64::NEG_INFINITY, &mut ws)
    };
    let meets = |e: &CandidateEval| e.solved && e.max_deviation <= tol;

    // baseline: equal index steps with the fewest spans meeting the tolerance (growth, bisection)
    let (mut baseline, mut best_knots) = baseline(&data, p + 1, max_n, tol, &mut stats);
    if let Some(k) = lsq_periodic_knots(&data, tol) {
        if k.len() + 1 < baseline && meets(&eval(&k, &mut stats)) {
            baseline = k.len() + 1;
            best_knots = k;
        }
    }
    let fixed = opts.control_points;
    let mut best_n = baseline;
    if let Some(n) = fixed {
        while best_n < n {
            best_knots = best_insertion(&data, &best_knots, tol);
            best_n += 1;
        }
    }
    // count descent: greedy removal, then a swarm probe
    let family = ClosedFamily {
        prep,
        data: &data,
        tol,
        opts,
    };
    let lowest = fixed.unwrap_or(p + 1).max(p + 1);
    let mut down = Descent::new(best_n, best_knots);
    let removals = |k: &[f64]| removal_candidates(&data, k);
    let force = fixed.is_some();
    descend(
        &family, &mut down, lowest, tol, removals, force, opts, progress, &mut stats,
    );
    let Descent {
        n: best_n,
        knots: best_knots,
        met: descent,
        ..
    } = down;

    // full search at the smallest feasible count, then with extra points while they pay
    let start_at = CountStart {
        n: best_n,
        knots: &best_knots,
        descent: &descent,
        limit: max_n.min(baseline),
        alt: &[],
    };
    let result = search_counts(&family, start_at, opts, progress, &mut stats)?;
    let mut result = if opts.searches_degree() {
        super::degree_candidates::raise_periodic(prep, result, tol, opts)?
    } else {
        result
    };
    stats.absorb(&mut result.stats, start);
    result.baseline_control_points = baseline;
    result.stats = stats;
    Ok(result)
}

/// The periodic knot search for `n` distinct control points.
pub(crate) fn problem_at<'a>(
    data: &'a ClosedData,
    n: usize,
    tol: f64,
    opts: &IntegratedOptions,
) -> ClosedProblem<'a> {
    ClosedProblem::new(
        data,
        n,
        MIN_GAP,
        opts.search_smoothing,
        tol,
        opts.span_fairness,
    )
}

/// The periodic knot searches of one closed data set, for [`search_counts`].
struct ClosedFamily<'a> {
    prep: &'a Prepared,
    data: &'a ClosedData,
    tol: f64,
    opts: &'a IntegratedOptions,
}

impl<'a> CountFamily for ClosedFamily<'a> {
    type Problem = ClosedProblem<'a>;

    fn problem(&self, n: usize) -> ClosedProblem<'a> {
        problem_at(self.data, n, self.tol, self.opts)
    }

    fn spread_knots(&self, n: usize) -> Vec<f64> {
        equal_breaks(&self.data.params, n)
    }

    fn insertion(&self, knots: &[f64], _log_lambda: f64) -> Vec<f64> {
        best_insertion(self.data, knots, self.tol)
    }

    fn finish(&self, interior: &[f64], log_lambda: f64) -> Result<IntegratedResult> {
        finish_periodic(
            self.prep, self.data, interior, log_lambda, self.tol, self.opts,
        )
    }
}

/// The periodic curve (input coordinates) for normalised breakpoints and smoothing, measured.
pub(crate) fn finish_periodic(
    prep: &Prepared,
    data: &ClosedData,
    interior: &[f64],
    log_lambda: f64,
    tol: f64,
    opts: &IntegratedOptions,
) -> Result<IntegratedResult> {
    let mut ws = ClosedWorkspace::default();
    let mut e = evaluate_closed(data, interior, log_lambda, &mut ws);
    if !e.solved {
        return Err(Error::Fit(
            "the periodic least-squares system is singular for these knots".into(),
        ));
    }
    let mut stats = OptimStats::default();
    if opts.polish {
        let f = fair_periodic(
            data,
            &mut ws,
            tol,
            opts.span_fairness,
            band_solves(opts),
            opts.polish_evaluations,
        )?;
        e = f.eval;
        stats.evaluations = f.evaluations;
        stats.polish_moves = f.moves;
    }
    let ctrl: Vec<Vec3> = ws.ctrl.iter().map(|&c| prep.denormalise(c)).collect();
    let curve = NurbsCurve::bspline(opts.degree, ws.knots.clone(), ctrl)?;
    let quality = FitQuality {
        max_deviation: e.max_deviation * prep.scale,
        rms_deviation: e.rms_deviation * prep.scale,
        fairness: e.fairness,
        max_span_fairness: e.max_span_fairness,
    };
    let met = e.max_deviation <= tol && opts.span_fairness.is_none_or(|t| e.max_span_fairness <= t);
    Ok(IntegratedResult {
        curve,
        quality,
        tolerance: tol * prep.scale,
        met,
        log_lambda,
        baseline_control_points: interior.len() + 1,
        stats,
    })
}

/// `n` spans at equal steps of the data index (interior breakpoints, seam at 0).
pub fn equal_breaks(params: &[f64], n: usize) -> Vec<f64> {
    let m = params.len();
    if m == 0 {
        // no data: equal steps of the parameter itself
        return (1..n).map(|j| j as f64 / n as f64).collect();
    }
    (1..n)
        .map(|j| {
            let t = (j * m) as f64 / n as f64;
            let i = t.floor() as usize;
            let a = t - i as f64;
            let next = if i + 1 < m { params[i + 1] } else { 1.0 };
            (1.0 - a) * params[i] + a * next
        })
        .collect()
}

/// The fewest equal-index spans in `lo..=hi` meeting `tol` (doubling, then bisection), with their
/// breakpoints; `hi` when none does.
fn baseline(
    data: &ClosedData,
    lo: usize,
    hi: usize,
    tol: f64,
    stats: &mut OptimStats,
) -> (usize, Vec<f64>) {
    let mut ws = ClosedWorkspace::default();
    let mut ok = |n: usize, stats: &mut OptimStats| {
        stats.evaluations += 1;
        let k = equal_breaks(&data.params, n);
        let e = evaluate_closed(data, &k, f64::NEG_INFINITY, &mut ws);
        (e.solved && e.max_deviation <= tol).then_some(k)
    };
    let (mut fail, mut n) = (lo - 1, lo);
    let mut good = loop {
        if let Some(k) = ok(n, stats) {
            break (n, k);
        }
        if n >= hi {
            return (hi, equal_breaks(&data.params, hi));
        }
        fail = n;
        n = (2 * n).min(hi);
    };
    while good.0 - fail > 1 {
        let mid = fail + (good.0 - fail) / 2;
        match ok(mid, stats) {
            Some(k) => good = (mid, k),
            None => fail = mid,
        }
    }
    good
}

/// The least-squares method's periodic breakpoints for these data (`fit::tolerance`, closed,
/// centripetal, corners off), mapped onto `data.params` through the data index; `None` when that
/// fit fails or gives no valid breakpoints here.
fn lsq_periodic_knots(data: &ClosedData, tol: f64) -> Option<Vec<f64>> {
    let p = data.degree();
    let fit = lsq_method_fit(&data.points, p, tol, ClosedMode::Closed)?;
    if !fit.closed || fit.params.len() != data.params.len() {
        return None;
    }
    let k = fit.curve.knots();
    let nu = fit.n_control_points;
    let interior = k.get(p + 1..p + nu)?;
    // the fit's own parameters, unwrapped to increase from 0 (a foot just across the seam)
    let fp: Vec<f64> = fit
        .params
        .iter()
        .enumerate()
        .map(|(i, &u)| {
            if i > 0 && u < 0.5 * fit.params[1] {
                u + 1.0
            } else {
                u
            }
        })
        .chain(std::iter::once(1.0))
        .collect();
    let up = &data.measure.params;
    let mut out = map_knots(interior, &fp, up);
    let enc = super::encoding::KnotEncoding::new(out.len(), 0.0, false);
    (out.windows(2).all(|w| w[0] < w[1]) && enc.repair(&mut out, up)).then_some(out)
}

/// Every removal of one breakpoint, refitted without smoothing, sorted by the maximum deviation
/// (ties by index); evaluated in parallel, collected in order.
fn removal_candidates(data: &ClosedData, knots: &[f64]) -> Vec<(f64, Vec<f64>)> {
    if knots.len() < data.degree() + 1 {
        return Vec::new();
    }
    knot_edits::removal_candidates(
        knots,
        &data.measure.params,
        |ws: &mut ClosedWorkspace, k| evaluate_closed(data, k, f64::NEG_INFINITY, ws),
    )
}

/// The breakpoints with one more at the middle of the span (holding at least two data parameters)
/// whose refit is best by the feasibility-first fitness; the widest span when none holds two.
fn best_insertion(data: &ClosedData, knots: &[f64], tol: f64) -> Vec<f64> {
    let (edges, spans) = insertion_spans(knots, &data.params);
    let problem = ClosedProblem::new(data, knots.len() + 2, 0.0, false, tol, None);
    let scored: Vec<(super::pso::Fitness, Vec<f64>)> = spans
        .par_iter()
        .map_init(ClosedWorkspace::default, |ws, &j| {
            let mut k = knots.to_vec();
            k.insert(j, 0.5 * (edges[j] + edges[j + 1]));
            let e = evaluate_closed(data, &k, f64::NEG_INFINITY, ws);
            (problem.fitness(&e), k)
        })
        .collect();
    let mut best: Option<(super::pso::Fitness, Vec<f64>)> = None;
    for c in scored {
        if best.as_ref().is_none_or(|b| c.0.better_than(&b.0)) {
            best = Some(c);
        }
    }
    if let Some((_, k)) = best {
        return k;
    }
    let widest = (0..edges.len() - 1)
        .max_by(|&a, &b| (edges[a + 1] - edges[a]).total_cmp(&(edges[b + 1] - edges[b])))
        .unwrap_or(0);
    let mut out = knots.to_vec();
    out.insert(widest, 0.5 * (edges[widest] + edges[widest + 1]));
    out
}
