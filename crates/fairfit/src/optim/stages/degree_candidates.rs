//! The higher degrees of the staged degree search ([`super::degree_search`]): every higher degree
//! keeps a control-point count of the reference degree's and starts from its knots (open curves:
//! the first higher degree from the count descent's knots at the smallest feasible count, beside
//! the count search, `first_beside`; otherwise the reference's finished fit).
//!
//! - **Open curves**: degree `d` at `n` control points has `n − d − 1` interior knots, `d − p`
//!   fewer than the reference's. Seeds: the reference's knots averaged over windows of `d − p + 1`
//!   neighbours (the same knot density, one knot per window), the reference's knots after the
//!   `d − p` least harmful removals (refitted at degree `d`), and the averaging knots of degree
//!   `d` (the NURBS Book's rule).
//! - **Periodic curves**: a periodic curve has as many spans as distinct control points at any
//!   degree, so the reference's breakpoints are the first seed as they are; equal index steps the
//!   second.
//!
//! The knot search is short: the swarm's seeded population (no iterations), the pattern search on
//! its best, and the smoothing line search ([`tune_smoothing`]). A higher degree's candidate is
//! finished with capped budgets ([`DegreeTuning::candidate_band_solves`],
//! [`DegreeTuning::candidate_polish_evaluations`]).
//!
//! **Own count search** (open curves, `raise_open` with `CountsSeen`). The next degree `p + 1`
//! gets a count search of its own when one of three triggers fires on the reference's count
//! choice (`CountsSeen::own_count_search`, in this order):
//!
//! 1. *extrema cost*: the count search's fewest-extrema rule kept a curve at least
//!    [`DegreeTuning::own_count_search_cost`] times less fair (scored per added point) than the
//!    fairest finished candidate: the cubic cannot remove the wiggles cheaply, a quartic may at
//!    more control points;
//! 2. *count gain*: the reference kept its highest finished count, and even the least fair
//!    finished search there is at most [`DegreeTuning::steep_count_gain`] of the fairest F at the
//!    smallest count: the extra points were still paying where the count search stopped; these
//!    counts are also seeded with residual-driven knots of degree `p + 1`;
//! 3. *wiggly*: the reference's kept curve has at least [`DegreeTuning::wiggly_extrema`]
//!    curvature extrema: the data wiggle more than the reference's count search could smooth
//!    out, and the least-squares baseline is a poor limit.
//!
//! The first two search every count above the reference's kept count up to the least-squares
//! baseline (one above it where the reference kept the baseline's count and has at least
//! [`CountTuning::restart_min_extrema`](crate::optim::tuning::CountTuning::restart_min_extrema)
//! extrema, seeded by the best knot insertion); the wiggly trigger searches
//! [`DegreeTuning::wiggly_counts_above`] counts above the baseline, never more control points than
//! the data points over [`DegreeTuning::wiggly_points_per_control_point`], and keeps the fairest
//! within the reference's extrema count, priced in the degree rule for the degree step only (the
//! quartic is infeasible at the reference's counts). Every searched count is a full knot search
//! from the reference descent's knots, finished like a staged candidate, all counts in parallel;
//! with the staged attempt at the smallest count, the count search's rule keeps one. Not with a
//! fixed count or `max_extra_control_points = 0`, nor on periodic curves or pieces between
//! corners.

use super::degree_search::{keep_degree, Attempt, DegreeSearchOutput};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::{tolerance_of, FitContext};
use crate::optim::kind::open::{finish, open_problem, removal_candidates};
use crate::optim::kind::periodic::{
    distinct_control_points, equal_breaks, finish_periodic, problem_at,
};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::periodic::ClosedData;
use crate::optim::search::prepare::{averaging_interior_knots, prepare, Prepared};
use crate::optim::search::problem::CountProblem;
use crate::optim::search::pso::{run_pso, PsoOptions};
use crate::optim::search::smoothing::tune_smoothing;
use crate::optim::tuning::{DegreeTuning, SwarmTuning, Tuning};

/// Salt of the candidates' random streams (apart from the count search's).
const DEGREE_CANDIDATE_SALT: u64 = 2_000_003;

/// A degree's knots at the reference's count, before band fairing and polish.
#[derive(Clone, Debug)]
pub(crate) struct Candidate {
    /// Interior knots (breakpoints of a periodic curve).
    pub interior: Vec<f64>,
    pub log_lambda: f64,
    /// Whether the knot search met the tolerance (and `F*`).
    pub feasible: bool,
    pub evaluations: usize,
    pub iterations: usize,
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

/// With a degree search, the attempt of the next degree at the count of the descent's `interior`
/// knots, made beside the count search (`open_next`); `None` without a degree search.
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
pub(crate) fn open_attempt(
    q: &Prepared,
    p: usize,
    interior: &[f64],
    tol: f64,
    opts: &IntegratedOptions,
    d: usize,
    tuning: &Tuning,
) -> Attempt {
    let iterations = tuning.degree.short_search_iterations;
    match open_candidate(q, p, interior, tol, opts, d, iterations, tuning) {
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
#[allow(clippy::too_many_arguments)]
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
pub(crate) fn open_candidate_with(
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
        &open_problem(&q.data, n, tol, &o, &tuning.swarm),
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

/// The periodic degree search's input.
#[derive(Clone, Debug)]
pub(crate) struct PeriodicDegreeInput {
    /// The reference degree's finished fit, chosen by the count search.
    pub reference: IntegratedResult,
}

/// The degree search of a periodic closed curve from its finished reference fit.
pub(crate) fn raise_periodic(
    ctx: &FitContext,
    input: PeriodicDegreeInput,
) -> Result<DegreeSearchOutput> {
    let (prep, tol, opts, tuning) = (ctx.prep, ctx.tol, ctx.opts, ctx.tuning);
    let reference = input.reference;
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
        let iterations = tuning.degree.short_search_iterations;
        match short_search(
            &problem_at(cd, n, tol, &o, &tuning.swarm),
            d,
            &seeds,
            &o,
            iterations,
            &tuning.swarm,
        ) {
            Some(c) => c.attempt(|c| {
                let o = candidate_options(opts, d, &tuning.degree);
                finish_periodic(&preps[d - p], cd, &c.interior, c.log_lambda, tol, &o)
            }),
            None => Attempt::default(),
        }
    };
    let result = keep_degree(reference, p + 1..=highest, tuning, &attempt)?;
    Ok(DegreeSearchOutput { result })
}

/// The prepared data at every degree from `p` to `highest` (only the degree differs).
pub(crate) fn at_degrees(prep: &Prepared, p: usize, highest: usize) -> Vec<Prepared> {
    (p..=highest)
        .map(|d| {
            let mut q = prep.clone();
            q.data.degree = d;
            q
        })
        .collect()
}

/// The options a degree is finished with: the reference's own, a higher degree's band fairing
/// capped at [`DegreeTuning::candidate_band_solves`] subproblems and its polish at
/// [`DegreeTuning::candidate_polish_evaluations`] measurements.
pub(crate) fn candidate_options(
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
pub(crate) fn averaged_knots(knots: &[f64], extra: usize) -> Vec<f64> {
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
    use super::averaged_knots;

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
