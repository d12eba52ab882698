//! The higher degrees of the staged degree search ([`super::degree_search`], module doc "Staged
//! search"): every higher degree keeps a control-point count of the reference degree's and starts
//! from its knots (open curves: the first higher degree from the count descent's knots at the
//! smallest feasible count, beside the count search, `open_next`; otherwise the reference's
//! finished fit).
//!
//! - **Open curves**: degree `d` at `n` control points has `n − d − 1` interior knots, `d − p` fewer
//!   than the reference's. Seeds: the reference's knots averaged over windows of `d − p + 1`
//!   neighbours (the same knot density, one knot per window), the reference's knots after the
//!   `d − p` least harmful removals (refitted at degree `d`, `removal_candidates`), and the
//!   averaging knots of degree `d` (the NURBS Book's rule).
//! - **Periodic curves**: a periodic curve has as many spans as distinct control points at any
//!   degree, so the reference's breakpoints are the first seed as they are; equal index steps the
//!   second.
//!
//! The knot search is short: the swarm's seeded population (no iterations), the pattern search on
//! its best, and the smoothing line search ([`tune_smoothing`]). On the 33 benchmark curves 5 or 30
//! swarm iterations kept the same degrees (geometric-mean F ratio 0.359 / 0.353 against 0.360 with
//! none) at 1.5-2 times the search's cost.
//!
//! **Own count search** (open curves; `raise_open` with `CountsSeen`). The count search keeps
//! the fewest curvature extrema first; where that rule is costly — the kept curve's score
//! (`F · 1.05^extra`) is at least [`OWN_COUNT_SEARCH_COST`] times the fairest finished candidate's —
//! the cubic cannot remove the wiggles cheaply, and a quartic (one derivative smoother) may do it
//! at more control points. Then degree `p + 1` gets a count search of its own: at every count
//! above the reference's kept count up to the least-squares baseline (the reference's limit; at
//! the reference's count and below, the staged attempt stands for it) a full knot search (the full swarm's iterations, seeded as above from the reference descent's
//! knots at that count), every feasible one finished like a staged candidate (capped band fairing
//! and polish), all counts in parallel; with the staged attempt at the smallest count, the count
//! search's rule (`choose_count`: fewest extrema, then `F · 1.05^extra`) keeps one, which then
//! competes in the degree rule ([`super::degree_search`], where every control point above the
//! reference's must buy 5 %). Not with a fixed count or `max_extra_control_points = 0` (no counts
//! to search), nor on periodic curves or pieces between corners (no trigger measured there).
//!
//! Measured (quick targets, 33 curves, seeds 0-5, main 068885d): the trigger fires on hq17 at
//! seeds 0, 2 and 5 (cost 2.01, 1.92, 2.14), where the cubic keeps 13 points with 3 extrema at
//! 0.525-0.570x splprep's F; the quartic's own count search keeps 15-16 points with 3 extrema at
//! 0.258-0.266x. It also fires on sc20714 at seed 4, where the cubic's count is the baseline's
//! (nothing to search). Every other curve and seed does the same work as before, so the 200-point
//! curves pay nothing but the cost's arithmetic.
//!
//! **Second trigger: the count gain** ([`STEEP_COUNT_GAIN`], session 13). The cubic's count search
//! tries at most one point above its smallest feasible count; where its kept curve has the highest
//! finished count and its F is at most 0.8 of the fairest F at the smallest count
//! (`super::count_search::CountChoice::count_gain`), the extra point was still paying where the
//! search stopped, and the quartic gets the same own count search (counts above the cubic's kept
//! count up to the least-squares baseline). Its counts are then also seeded with the
//! residual-driven knots of degree `p + 1` (`crate::optim::search::residual_knots`, as FITPACK's `fpcurf` places
//! them): clarky's quartic at 11-13 points finishes at 0.48-0.49x splprep's F with them and at
//! 0.52x without (seed 0). The extrema-cost trigger keeps its seeds (with the residual seeds hq17's
//! quartic lost its target at seed 2). Measured (quick targets, 33 curves, seeds 0-5, main d6ef3ef):
//! clarky 0.614 / 0.563 / 0.609 -> 0.482 / 0.482 / 0.488 at seeds 0 / 2 / 4 (quartic, 13 / 11 / 12
//! points, 1 extremum), s1223 0.390 -> 0.308 at seed 0; every other curve and seed unchanged.
//!
//! **The least fair search** (session 14). The kept count has two or three finished searches
//! (chain, independent, restart) and the smallest count one or two, and searches at one count
//! finish 10-40 % apart: the kept curve's F over the smallest count's measured the luck of the
//! best draw as much as the added point. The count gain now takes the *least fair* finished
//! search within the tolerance at the kept count (every search there must have paid). Over seeds
//! 0-5 on the 33 curves this stops 9 of the 21 own count searches, all of which lost to the cubic
//! (SNL-FFA-W3-500 at seed 4: 0.691 -> 0.883; du84132v_noise1e-4 at seeds 3 and 4, fx79w470a at
//! 0, clarky at 1, whitcomb at 2, su-26m at 4, naca4412_noise1e-4 and s1223 at 5), with every
//! curve's output unchanged at every seed; clarky keeps its trigger at seeds 0, 2 and 4 (0.78,
//! 0.72, 0.69) and s1223 at seed 0 (0.63).
//!
//! **One point above the baseline** (session 14). Where the reference kept the least-squares
//! baseline's count (its count search was stopped by that limit, not by the gain) and has at least
//! `RESTART_MIN_EXTREMA` (2) curvature extrema (a wiggle a smoother degree may remove; one extremum,
//! an airfoil's leading edge, leaves none), the own count search also tries the baseline's count
//! plus one, seeded from the reference descent's knots at the baseline with the best knot
//! insertion (`crate::optim::kind::open::best_insertion`, at the reference degree); the degree rule then
//! prices that point like any other (`F · 1.1 · 1.05^extra`). On the 33 curves at seeds 0-5 it
//! fires only on sc20714 at seeds 2-5 (baseline 12, splprep's 17 points) and fx77w343 at seed 5
//! (15, splprep 17), and wins on sc20714 at seeds 3 and 4: the cubic 0.677 / 0.869 x splprep's F
//! -> the quartic at 13 points 0.546 / 0.541 x (4 extrema, as the cubic's). The 200-point curves
//! never reach it (FFA-W3-211 keeps its baseline count with one extremum).
//!
//! **Wiggly curves** (session 15, [`WIGGLY_EXTREMA`]). Where neither trigger fires but the
//! reference's kept curve has at least 6 curvature extrema, the data wiggle more than the
//! reference's count search could smooth out, and the least-squares baseline is a poor limit:
//! the quartic searches the count one above the baseline ([`WIGGLY_COUNTS_ABOVE`]; never more
//! than a quarter of the data points, [`WIGGLY_POINTS_PER_CONTROL_POINT`]), seeded as "one point
//! above the baseline" without the residual-driven knots, finished as a staged candidate; of it
//! and the staged attempt the fairest within the reference's extrema count is kept, and the
//! degree rule prices only the degree step (`F · 1.1`, no 5 % per added point: the quartic is
//! infeasible at the reference's counts, so every point it needs would otherwise count against
//! it). Measured on the 33 benchmark curves at seeds 0-5 (docs/optim.md, session 15): it fires on
//! fx79w470a (seeds 0, 1, 2, 4, 5), sc20714_noise1e-4 (every seed) and whitcomb (seed 1, where the
//! quarter of its 73 points, 18, is below its baseline + 1 and nothing is searched); fx79w470a
//! at seed 0 0.570 -> 0.487x splprep's F (quartic, 19 points, 6 extrema), seed 2 0.967 -> 0.498x,
//! sc20714_noise1e-4 0.81-1.05 -> 0.52-0.80x. Two counts above the baseline, each searched with
//! and without the residual-driven seeds, gained two more F targets (fx79w470a at seeds 4 and 5)
//! at twice the work, which more than doubled sc20714_noise1e-4's wall time; both seedings at
//! one count gained nothing over one.

use super::count_search::{choose_count, rank_fit, CountChoice, CountStart, Ranked};
use super::degree_search::{keep_degree, keep_degree_priced, Attempt};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::{tolerance_of, FitContext};
use crate::optim::kind::open::{best_insertion, finish, open_problem, removal_candidates};
use crate::optim::kind::periodic::{
    distinct_control_points, equal_breaks, finish_periodic, problem_at,
};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::periodic::ClosedData;
use crate::optim::search::prepare::{averaging_interior_knots, prepare, Prepared};
use crate::optim::search::problem::CountProblem;
use crate::optim::search::pso::{run_pso, PsoOptions};
use crate::optim::search::residual_knots::residual_knots;
use crate::optim::search::smoothing::tune_smoothing;
use crate::optim::tuning::{DegreeTuning, SwarmTuning, Tuning};
use rayon::prelude::*;

/// Salt of the candidates' random streams (apart from the count search's).
const DEGREE_CANDIDATE_SALT: u64 = 2_000_003;

/// A degree's knots at the reference's count, before band fairing and polish.
#[derive(Clone, Debug)]
struct Candidate {
    /// Interior knots (breakpoints of a periodic curve).
    interior: Vec<f64>,
    log_lambda: f64,
    /// Whether the knot search met the tolerance (and `F*`).
    feasible: bool,
    evaluations: usize,
    iterations: usize,
}

impl Candidate {
    /// The attempt of this candidate: finished by `finish` when feasible.
    fn attempt(self, finish: impl FnOnce(&Candidate) -> Result<IntegratedResult>) -> Attempt {
        Attempt {
            fit: if self.feasible {
                finish(&self).ok()
            } else {
                None
            },
            evaluations: self.evaluations,
            iterations: self.iterations,
        }
    }
}

/// What the reference degree's count search knew, for the next degree's own count search
/// (module doc, "Own count search").
#[derive(Clone, Copy, Debug)]
pub(crate) struct CountsSeen<'a> {
    /// The smallest feasible count of the reference degree.
    pub n: usize,
    /// The reference degree's feasible knots met by the count descent, by count.
    pub descent: &'a [(usize, Vec<f64>)],
    /// The largest count (the least-squares baseline's).
    pub limit: usize,
    /// The extrema cost of the reference's count choice.
    pub extrema_cost: f64,
    /// The count gain of the reference's count choice ([`super::count_search::CountChoice`]).
    pub count_gain: f64,
    /// The reference's kept curve's curvature extrema.
    pub extrema: usize,
}

impl<'a> CountsSeen<'a> {
    /// What the count search started from (`start`) and how its choice went (`choice`).
    pub fn of(start: &CountStart<'a>, choice: &CountChoice) -> Self {
        CountsSeen {
            n: start.n,
            descent: start.descent,
            limit: start.limit,
            extrema_cost: choice.extrema_cost,
            count_gain: choice.count_gain,
            extrema: choice.extrema,
        }
    }

    /// Whether the next degree gets a count search of its own, and why (module doc, "Own count
    /// search"): `None` for no own search.
    fn own_count_search(&self, t: &DegreeTuning) -> Option<OwnTrigger> {
        if self.extrema_cost >= t.own_count_search_cost {
            Some(OwnTrigger::ExtremaCost)
        } else if self.count_gain <= t.steep_count_gain {
            Some(OwnTrigger::CountGain)
        } else if self.extrema >= t.wiggly_extrema {
            Some(OwnTrigger::Wiggly)
        } else {
            None
        }
    }
}

/// Why the next degree gets a count search of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OwnTrigger {
    /// The reference's fewest-extrema choice was costly ([`OWN_COUNT_SEARCH_COST`]).
    ExtremaCost,
    /// The reference's extra points were still paying where its count search stopped
    /// ([`STEEP_COUNT_GAIN`]); the counts are also seeded with residual-driven knots.
    CountGain,
    /// The reference's kept curve has at least [`WIGGLY_EXTREMA`] curvature extrema: the count
    /// above the least-squares baseline, no price per added point in the degree rule (module doc,
    /// "Wiggly curves").
    Wiggly,
}

/// The degree search after the reference's count search on open data: `reference` is the
/// finished fit at `opts.degree` of the prepared data `prep`; `first` the next degree's attempt
/// made beside the count search; `seen` what the count search knew.
pub(crate) fn raise_open(
    ctx: &FitContext,
    reference: IntegratedResult,
    first: Option<Attempt>,
    seen: Option<CountsSeen<'_>>,
) -> Result<IntegratedResult> {
    let (prep, tol, opts, tuning) = (ctx.prep, ctx.tol, ctx.opts, ctx.tuning);
    let t = &tuning.degree;
    let p = opts.degree;
    let highest = opts.max_degree.unwrap_or(p).max(p);
    let preps = at_degrees(prep, p, highest);
    let k = reference.curve.knots().to_vec();
    let interior = &k[p + 1..k.len() - p - 1];
    let first = std::sync::Mutex::new(first);
    let reference_count = reference.curve.n_control_points();
    // one count above the baseline (module doc), decided before `reference` moves on
    let above = seen.is_some_and(|s| {
        s.own_count_search(t).is_some()
            && one_above_baseline(reference_count, s, prep.data.points.len(), tuning)
    });
    let m = prep.data.points.len();
    // the wiggly trigger's counts pay only the degree's price (module doc, "Wiggly curves")
    let point_gain = match seen.and_then(|s| s.own_count_search(t)) {
        Some(OwnTrigger::Wiggly) => 1.0,
        _ => tuning.count.extra_point_gain,
    };
    let attempt = |d: usize| {
        let a = match (d == p + 1)
            .then(|| {
                first
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .take()
            })
            .flatten()
        {
            Some(a) => a,
            None => open_attempt(&preps[d - p], p, interior, tol, opts, d, tuning),
        };
        match seen {
            Some(s) if d == p + 1 => match s.own_count_search(t) {
                Some(trigger) => {
                    let counts = if trigger == OwnTrigger::Wiggly {
                        wiggly_counts(s.limit, m, t)
                    } else {
                        let top = s.limit + usize::from(above);
                        (reference_count + 1).max(s.n)..=top
                    };
                    if counts.is_empty() {
                        // the reference kept the top count: nothing above it to search
                        return a;
                    }
                    let q = &preps[d - p];
                    own_count_search(q, p, s, counts, trigger, tol, opts, d, a, tuning)
                }
                None => a,
            },
            _ => a,
        }
    };
    keep_degree_priced(reference, p + 1..=highest, opts, point_gain, &attempt)
}

/// The wiggly trigger's counts (module doc, "Wiggly curves"): above the least-squares baseline
/// `limit`, at most [`WIGGLY_COUNTS_ABOVE`] of them, and never more control points than the `m`
/// data points over [`WIGGLY_POINTS_PER_CONTROL_POINT`].
fn wiggly_counts(limit: usize, m: usize, t: &DegreeTuning) -> std::ops::RangeInclusive<usize> {
    let top = (limit + t.wiggly_counts_above).min(m / t.wiggly_points_per_control_point);
    limit + 1..=top
}

/// Whether the next degree's own count search also tries one count above the least-squares
/// baseline `seen.limit` (module doc, "One point above the baseline"): the reference kept the
/// baseline's count (`reference_count`) and has at least [`RESTART_MIN_EXTREMA`] curvature
/// extrema, and `m` data points leave a data parameter inside every span there.
fn one_above_baseline(reference_count: usize, seen: CountsSeen<'_>, m: usize, t: &Tuning) -> bool {
    reference_count == seen.limit
        && seen.limit + 2 <= m
        && seen.extrema >= t.count.restart_min_extrema
}

/// The reference degree's (`p`) knots at count `c` for the own count search: the descent's knots
/// there, or one count above the descent's largest count (the baseline), its knots with the best
/// insertion ([`crate::optim::kind::open::best_insertion`] at degree `p`, no smoothing).
fn reference_knots(
    q: &Prepared,
    p: usize,
    seen: CountsSeen<'_>,
    counts: &std::ops::RangeInclusive<usize>,
    tol: f64,
) -> Vec<(usize, Vec<f64>)> {
    let at = |c: usize| seen.descent.iter().find(|(k, _)| *k == c).map(|(_, k)| k);
    // above the baseline: one best insertion per count, from the descent's knots at the baseline
    let mut above: Vec<Vec<f64>> = Vec::new();
    if let Some(k) = at(seen.limit).filter(|_| *counts.end() > seen.limit) {
        let mut data = q.data.clone();
        data.degree = p;
        let mut knots = k.clone();
        for _ in seen.limit..*counts.end() {
            knots = best_insertion(&data, &knots, f64::NEG_INFINITY, tol);
            above.push(knots.clone());
        }
    }
    counts
        .clone()
        .filter_map(|c| {
            let k = match c.checked_sub(seen.limit + 1) {
                Some(j) => above.get(j)?.clone(),
                None => at(c)?.clone(),
            };
            Some((c, k))
        })
        .collect()
}

/// The own count search of degree `d` (data `q`; module doc): a full knot search at every count
/// of `counts` (in parallel), seeded from the reference degree's descent knots at that count,
/// every feasible one finished like a staged candidate; of these and `at_n` (the staged attempt)
/// the count search's rule ([`choose_count`]) keeps one.
#[allow(clippy::too_many_arguments)]
fn own_count_search(
    q: &Prepared,
    p: usize,
    seen: CountsSeen<'_>,
    counts: std::ops::RangeInclusive<usize>,
    trigger: OwnTrigger,
    tol: f64,
    opts: &IntegratedOptions,
    d: usize,
    at_n: Attempt,
    tuning: &Tuning,
) -> Attempt {
    let o = candidate_options(opts, d, &tuning.degree);
    // the count-gain trigger also seeds every count with the residual-driven knots of degree d
    // there (module doc)
    let jobs: Vec<(Vec<f64>, Vec<Vec<f64>>)> = reference_knots(q, p, seen, &counts, tol)
        .into_iter()
        .map(|(c, knots)| match trigger {
            OwnTrigger::CountGain => (knots, residual_knots(&q.data, c).into_iter().collect()),
            OwnTrigger::ExtremaCost | OwnTrigger::Wiggly => (knots, Vec::new()),
        })
        .collect();
    let searched: Vec<(Option<Candidate>, Option<IntegratedResult>)> = jobs
        .into_par_iter()
        .map(|(knots, extra)| {
            let iterations = opts.max_iterations;
            let cand = open_candidate_with(q, p, &knots, &extra, tol, opts, d, iterations, tuning);
            let fit = cand.as_ref().filter(|c| c.feasible).and_then(|c| {
                finish(
                    q,
                    &c.interior,
                    c.log_lambda,
                    tol,
                    &o,
                    o.polish.then_some(tol),
                )
                .ok()
            });
            (cand, fit)
        })
        .collect();
    let mut evaluations = at_n.evaluations;
    let mut iterations = at_n.iterations;
    let mut fits: Vec<IntegratedResult> = at_n.fit.into_iter().collect();
    for (cand, fit) in searched {
        if let Some(c) = cand {
            evaluations += c.evaluations;
            iterations += c.iterations;
        }
        fits.extend(fit);
    }
    if fits.is_empty() {
        return Attempt {
            fit: None,
            evaluations,
            iterations,
        };
    }
    let counts: Vec<usize> = fits.iter().map(|r| r.curve.n_control_points()).collect();
    let ranked: Vec<Ranked> = fits.iter().map(rank_fit).collect();
    let best = match trigger {
        // the fairest within the reference's extrema (what the degree rule admits)
        OwnTrigger::Wiggly => fairest_within(&counts, &ranked, seen.extrema)
            .unwrap_or_else(|| choose_count(&counts, &ranked, &tuning.count)),
        _ => choose_count(&counts, &ranked, &tuning.count),
    };
    // the work of the fits not kept
    for (i, r) in fits.iter().enumerate() {
        if i != best {
            evaluations += r.stats.evaluations;
            iterations += r.stats.iterations;
        }
    }
    Attempt {
        fit: Some(fits.swap_remove(best)),
        evaluations,
        iterations,
    }
}

/// The index of the fairest candidate within the tolerance with at most `extrema` curvature
/// extrema (ties: the fewer points, then the first); `None` when there is none.
fn fairest_within(counts: &[usize], ranked: &[Ranked], extrema: usize) -> Option<usize> {
    (0..counts.len())
        .filter(|&i| ranked[i].fairness.is_finite() && ranked[i].extrema <= extrema)
        .min_by(|&a, &b| {
            ranked[a]
                .fairness
                .total_cmp(&ranked[b].fairness)
                .then(counts[a].cmp(&counts[b]))
        })
}

/// With a degree search, the attempt of the next degree at the count of the descent's `interior`
/// knots, made beside the count search ([`open_next`]); `None` without a degree search.
pub(crate) fn first_beside(ctx: &FitContext, interior: &[f64]) -> Option<Attempt> {
    ctx.opts
        .searches_degree()
        .then(|| open_next(ctx.prep, interior, ctx.tol, ctx.opts, ctx.tuning))
}

/// The attempt of degree `opts.degree + 1` at the count of the reference degree's `interior` knots
/// (run beside the count search, from the descent's knots).
fn open_next(
    prep: &Prepared,
    interior: &[f64],
    tol: f64,
    opts: &IntegratedOptions,
    tuning: &Tuning,
) -> Attempt {
    let (p, d) = (opts.degree, opts.degree + 1);
    let mut q = prep.clone();
    q.data.degree = d;
    open_attempt(&q, p, interior, tol, opts, d, tuning)
}

/// Degree `d` (data `q`) at the count of the degree-`p` `interior` knots, finished when feasible.
fn open_attempt(
    q: &Prepared,
    p: usize,
    interior: &[f64],
    tol: f64,
    opts: &IntegratedOptions,
    d: usize,
    tuning: &Tuning,
) -> Attempt {
    match open_candidate(q, p, interior, tol, opts, d, 0, tuning) {
        Some(c) => c.attempt(|c| {
            let o = candidate_options(opts, d, &tuning.degree);
            finish(
                q,
                &c.interior,
                c.log_lambda,
                tol,
                &o,
                o.polish.then_some(tol),
            )
        }),
        None => Attempt::default(),
    }
}

/// Degree `d` of an open curve at the count of the reference's `interior` knots (degree `p`), by
/// the short knot search from the seeds of the module doc (`iterations` swarm iterations: 0, or
/// the full search's in the own count search); `None` when the degree cannot have that count here.
fn open_candidate(
    q: &Prepared,
    p: usize,
    interior: &[f64],
    tol: f64,
    opts: &IntegratedOptions,
    d: usize,
    iterations: usize,
    tuning: &Tuning,
) -> Option<Candidate> {
    open_candidate_with(q, p, interior, &[], tol, opts, d, iterations, tuning)
}

/// [`open_candidate`] with `extra` seeds (interior knots of degree `d` at that count).
#[allow(clippy::too_many_arguments)]
fn open_candidate_with(
    q: &Prepared,
    p: usize,
    interior: &[f64],
    extra: &[Vec<f64>],
    tol: f64,
    opts: &IntegratedOptions,
    d: usize,
    iterations: usize,
    tuning: &Tuning,
) -> Option<Candidate> {
    let n = interior.len() + p + 1;
    // at least d + 1 control points, and a data parameter inside every span
    if n < d + 1 || q.data.points.len() < n + 1 {
        return None;
    }
    let o = opts.at_degree(d);
    let mut seeds = vec![averaged_knots(interior, d - p)];
    let mut k = interior.to_vec();
    while k.len() + d + 1 > n {
        match removal_candidates(&q.data, &k).into_iter().next() {
            Some((_, r)) => k = r,
            None => break,
        }
    }
    if k.len() + d + 1 == n {
        seeds.push(k);
    }
    seeds.push(averaging_interior_knots(&q.data.params, d, n));
    seeds.extend(extra.iter().cloned());
    short_search(
        &open_problem(&q.data, n, tol, &o),
        d,
        &seeds,
        &o,
        iterations,
        &tuning.swarm,
    )
}

/// Degree `d` of an open piece between corners ([`crate::optim::cornered`]): `points` are the piece's,
/// `reference` its fit at `opts.degree`, `opts` the piece's options.
pub(crate) fn raise_open_piece(
    points: &[Vec3],
    reference: &NurbsCurve,
    opts: &IntegratedOptions,
    d: usize,
    tuning: &Tuning,
) -> Attempt {
    let p = reference.degree();
    let k = reference.knots();
    let Ok(q) = prepare(points, d) else {
        return Attempt::default();
    };
    if k.len() < 2 * (p + 1) {
        return Attempt::default();
    }
    let interior = &k[p + 1..k.len() - p - 1];
    open_attempt(
        &q,
        p,
        interior,
        tolerance_of(opts, q.scale),
        opts,
        d,
        tuning,
    )
}

/// [`raise_open`] for a periodic closed curve.
pub(crate) fn raise_periodic(
    prep: &Prepared,
    reference: IntegratedResult,
    tol: f64,
    opts: &IntegratedOptions,
    tuning: &Tuning,
) -> Result<IntegratedResult> {
    let p = opts.degree;
    let highest = opts.max_degree.unwrap_or(p).max(p);
    let preps = at_degrees(prep, p, highest);
    // the breakpoints between the seam at 0 and 1
    let n = distinct_control_points(&reference.curve);
    let interior = reference.curve.knots()[p + 1..p + n].to_vec();
    // the higher degrees' closed data (None: too few points for the degree)
    let datas: Vec<Option<ClosedData>> = preps
        .iter()
        .skip(1)
        .map(|q| ClosedData::new(q).ok())
        .collect();
    let attempt = |d: usize| {
        let Some(cd) = datas[d - p - 1].as_ref() else {
            return Attempt::default();
        };
        if n < d + 1 || n + 1 > cd.points.len() {
            return Attempt::default();
        }
        let o = opts.at_degree(d);
        let seeds = vec![interior.clone(), equal_breaks(&cd.params, n)];
        match short_search(&problem_at(cd, n, tol, &o), d, &seeds, &o, 0, &tuning.swarm) {
            Some(c) => c.attempt(|c| {
                let o = candidate_options(opts, d, &tuning.degree);
                finish_periodic(&preps[d - p], cd, &c.interior, c.log_lambda, tol, &o)
            }),
            None => Attempt::default(),
        }
    };
    keep_degree(reference, p + 1..=highest, opts, tuning, &attempt)
}

/// The prepared data at every degree from `p` to `highest` (only the degree differs).
fn at_degrees(prep: &Prepared, p: usize, highest: usize) -> Vec<Prepared> {
    (p..=highest)
        .map(|d| {
            let mut q = prep.clone();
            q.data.degree = d;
            q
        })
        .collect()
}

/// The options a degree is finished with: the reference's own, a higher degree's band fairing
/// capped at [`CANDIDATE_BAND_SOLVES`] subproblems and its polish at
/// [`CANDIDATE_POLISH_EVALUATIONS`] measurements.
fn candidate_options(
    opts: &IntegratedOptions,
    degree: usize,
    t: &DegreeTuning,
) -> IntegratedOptions {
    let mut o = opts.at_degree(degree);
    if degree > opts.degree {
        o.band_solves = o.band_solves.min(t.candidate_band_solves);
        o.polish_evaluations = o.polish_evaluations.min(t.candidate_polish_evaluations);
    }
    o
}

/// The short knot search of degree `degree` from the knot vectors `seeds` (module doc); `None` when
/// no seed fits the problem or the best position decodes to no valid knot vector.
fn short_search<P: CountProblem>(
    pr: &P,
    degree: usize,
    seeds: &[Vec<f64>],
    opts: &IntegratedOptions,
    iterations: usize,
    swarm: &SwarmTuning,
) -> Option<Candidate> {
    let dim = pr.dim();
    let positions: Vec<Vec<f64>> = seeds
        .iter()
        .map(|k| pr.position(k))
        .filter(|x| x.len() == dim)
        .collect();
    if positions.is_empty() {
        return None;
    }
    let po = PsoOptions {
        max_iterations: iterations,
        ..swarm.options(
            opts,
            iterations,
            false,
            DEGREE_CANDIDATE_SALT + degree as u64,
        )
    };
    let mut r = run_pso(pr, &positions, &po, &|_| {});
    let mut evaluations = r.evaluations;
    if let Some(coord) = pr.smoothing_coord() {
        let t = tune_smoothing(pr, coord, (&r.position, &r.output, r.fitness));
        evaluations += t.evaluations;
        (r.position, r.output, r.fitness) = (t.position, t.output, t.fitness);
    }
    Some(Candidate {
        interior: pr.decode(&r.position)?,
        log_lambda: pr.log_lambda(&r.position),
        feasible: r.fitness.feasible(),
        evaluations,
        iterations: r.iterations,
    })
}

/// `knots` averaged over windows of `extra + 1` neighbours: `extra` fewer knots with the same
/// density (the interior knots of a degree `extra` higher at the same count).
pub fn averaged_knots(knots: &[f64], extra: usize) -> Vec<f64> {
    if knots.len() <= extra {
        return Vec::new();
    }
    knots
        .windows(extra + 1)
        .map(|w| w.iter().sum::<f64>() / w.len() as f64)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{averaged_knots, fairest_within, wiggly_counts, CountsSeen, OwnTrigger, Ranked};
    use crate::optim::tuning::DegreeTuning;

    const T: DegreeTuning = DegreeTuning {
        candidate_band_solves: 8,
        candidate_polish_evaluations: 500,
        own_count_search_cost: 1.5,
        steep_count_gain: 0.8,
        wiggly_extrema: 6,
        wiggly_counts_above: 1,
        wiggly_points_per_control_point: 4,
    };

    #[test]
    fn the_tests_use_the_default_tuning() {
        assert_eq!(DegreeTuning::default(), T);
    }

    fn seen(extrema: usize, extrema_cost: f64, count_gain: f64) -> CountsSeen<'static> {
        CountsSeen {
            n: 15,
            descent: &[],
            limit: 18,
            extrema_cost,
            count_gain,
            extrema,
        }
    }

    #[test]
    fn the_wiggly_trigger_fires_at_six_extrema_after_the_other_two() {
        // fx79w470a at seed 0: 6 extrema, count gain 1.080, extrema cost 1
        assert_eq!(
            seen(6, 1.0, 1.080).own_count_search(&T),
            Some(OwnTrigger::Wiggly)
        );
        // hq17 at seeds 1, 3, 4: 5 extrema, nothing
        assert_eq!(
            seen(T.wiggly_extrema - 1, 1.0, 1.0).own_count_search(&T),
            None
        );
        // the older triggers keep their searches
        assert_eq!(
            seen(9, 2.0, 1.0).own_count_search(&T),
            Some(OwnTrigger::ExtremaCost)
        );
        assert_eq!(
            seen(9, 1.0, 0.7).own_count_search(&T),
            Some(OwnTrigger::CountGain)
        );
    }

    #[test]
    fn wiggly_counts_are_one_above_the_baseline_within_a_quarter_of_the_points() {
        // fx79w470a: baseline 18, 94 points
        assert_eq!(wiggly_counts(18, 94, &T), 19..=19);
        // sc20714_noise1e-4: baseline 11, 205 points
        assert_eq!(wiggly_counts(11, 205, &T), 12..=12);
        // whitcomb (seed 1, 7 extrema): baseline 20 above splprep's 19, 73 points: none
        assert!(wiggly_counts(20, 73, &T).is_empty());
    }

    #[test]
    fn the_fairest_within_the_extrema_bound_is_kept() {
        let r = |fairness: f64, extrema: usize| Ranked { fairness, extrema };
        let ranked = [r(3.5e5, 4), r(3.1e5, 6), r(3.0e5, 7), r(f64::INFINITY, 1)];
        assert_eq!(fairest_within(&[15, 19, 19, 19], &ranked, 6), Some(1));
        assert_eq!(fairest_within(&[15, 19, 19, 19], &ranked, 7), Some(2));
        assert_eq!(fairest_within(&[15, 19, 19, 19], &ranked, 3), None);
        // ties: the fewer points
        let tie = [r(3.0e5, 4), r(3.0e5, 4)];
        assert_eq!(fairest_within(&[20, 19], &tie, 6), Some(1));
    }

    #[test]
    fn averaged_knots_keep_the_density_with_fewer_knots() {
        let k = [0.1, 0.2, 0.4, 0.8];
        assert_eq!(averaged_knots(&k, 0), k);
        let one = averaged_knots(&k, 1);
        assert_eq!(one.len(), 3);
        for (a, b) in one.iter().zip([0.15, 0.3, 0.6]) {
            assert!((a - b).abs() < 1e-15);
        }
        let two = averaged_knots(&k, 2);
        assert_eq!(two.len(), 2);
        assert!((two[0] - 0.7 / 3.0).abs() < 1e-15 && (two[1] - 1.4 / 3.0).abs() < 1e-15);
        assert!(averaged_knots(&k, 4).is_empty());
    }
}
