//! The periodic curve kind: a closed curve `C^(p−1)` everywhere, the seam included.
//!
//! The seam is fixed at the first data point and the knot search places the other `n_u − 1`
//! breakpoints on the circle ([`crate::optim::search::periodic`]); the control points come from
//! periodic least squares, `F` is measured over the whole loop and every point's orthogonal
//! deviation counts. The baseline is the least-squares method's periodic knots mapped onto these
//! parameters when they meet the tolerance with fewer spans, else the fewest equal index steps
//! that do. Finishing is the periodic band fairing and polish
//! ([`crate::optim::periodic_fairing`]). The curve is written like the least-squares method's
//! closed curves: an unclamped periodic knot vector with `n_u + p` control points of which the
//! last `p` repeat the first ([`distinct_control_points`]).

use super::{Baseline, CurveKind};
use crate::errors::{Error, Result};
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::band_solves;
use crate::optim::fairing::fair_periodic;
use crate::optim::options::IntegratedOptions;
use crate::optim::result::{FitQuality, IntegratedResult, OptimStats};
use crate::optim::search::knot_edits::{self, insertion_spans, lsq_method_fit, map_knots};
use crate::optim::search::objective::CandidateEval;
use crate::optim::search::periodic::{evaluate_closed, ClosedData, ClosedProblem, ClosedWorkspace};
use crate::optim::search::prepare::Prepared;
use crate::optim::search::pso::SwarmProblem;
use crate::optim::tuning::{SwarmTuning, Tuning};
use rayon::prelude::*;

/// Smallest breakpoint gap as a fraction of the loop's parameter length.
const MIN_BREAK_GAP: f64 = 1e-4;

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

/// The periodic knot search for `n` distinct control points.
pub(crate) fn problem_at<'a>(
    data: &'a ClosedData,
    n: usize,
    tol: f64,
    opts: &IntegratedOptions,
    swarm: &SwarmTuning,
) -> ClosedProblem<'a> {
    ClosedProblem::new(
        data,
        n,
        MIN_BREAK_GAP,
        swarm.search_smoothing,
        tol,
        opts.span_fairness,
    )
}

/// The periodic curve on one closed data set and tolerance.
pub(crate) struct PeriodicKind<'a> {
    /// The prepared distinct points.
    pub prep: &'a Prepared,
    /// Their closed data.
    pub data: &'a ClosedData,
    /// The tolerance (normalised units).
    pub tol: f64,
    /// The fit's options.
    pub opts: &'a IntegratedOptions,
    /// The method's measured thresholds.
    pub tuning: &'a Tuning,
}

impl<'a> CurveKind for PeriodicKind<'a> {
    type Problem = ClosedProblem<'a>;

    fn baseline(&self, stats: &mut OptimStats) -> Baseline {
        let (data, tol, p) = (self.data, self.tol, self.opts.degree);
        // every span needs a data parameter inside (Schoenberg–Whitney): at most m − 1 spans
        let max_n = data.points.len() - 1;
        let mut ws = ClosedWorkspace::default();
        let mut eval = |knots: &[f64], stats: &mut OptimStats| {
            stats.evaluations += 1;
            evaluate_closed(data, knots, f64::NEG_INFINITY, &mut ws)
        };
        let meets = |e: &CandidateEval| e.solved && e.max_deviation <= tol;
        // equal index steps with the fewest spans meeting the tolerance (growth, bisection)
        let (mut count, mut knots) = baseline(data, p + 1, max_n, tol, stats);
        if let Some(k) = lsq_periodic_knots(data, tol) {
            if k.len() + 1 < count && meets(&eval(&k, stats)) {
                count = k.len() + 1;
                knots = k;
            }
        }
        Baseline {
            count,
            knots: Some(knots),
        }
    }

    fn start(&self, baseline: &Baseline, fixed: Option<usize>) -> (usize, Vec<f64>) {
        let mut best_n = baseline.count;
        let mut best_knots = match &baseline.knots {
            Some(k) => k.clone(),
            None => equal_breaks(&self.data.params, best_n),
        };
        if let Some(n) = fixed {
            while best_n < n {
                best_knots = best_insertion(self.data, &best_knots, self.tol);
                best_n += 1;
            }
        }
        (best_n, best_knots)
    }

    fn problem(&self, n: usize) -> ClosedProblem<'a> {
        problem_at(self.data, n, self.tol, self.opts, &self.tuning.swarm)
    }

    fn spread_knots(&self, n: usize) -> Vec<f64> {
        equal_breaks(&self.data.params, n)
    }

    fn insertion(&self, knots: &[f64], _log_lambda: f64) -> Vec<f64> {
        best_insertion(self.data, knots, self.tol)
    }

    fn removal_candidates(&self, knots: &[f64]) -> Vec<(f64, Vec<f64>)> {
        removal_candidates(self.data, knots)
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
        screening: Default::default(),
        closure: Default::default(),
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
pub(crate) fn equal_breaks(params: &[f64], n: usize) -> Vec<f64> {
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
    let enc = crate::optim::search::encoding::KnotEncoding::new(out.len(), 0.0, false);
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
    let scored: Vec<(crate::optim::search::pso::Fitness, Vec<f64>)> = spans
        .par_iter()
        .map_init(ClosedWorkspace::default, |ws, &j| {
            let mut k = knots.to_vec();
            k.insert(j, 0.5 * (edges[j] + edges[j + 1]));
            let e = evaluate_closed(data, &k, f64::NEG_INFINITY, ws);
            (problem.fitness(&e), k)
        })
        .collect();
    let mut best: Option<(crate::optim::search::pso::Fitness, Vec<f64>)> = None;
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
