//! The count descent of an open curve ([`super::integrated`], step 3) and its second start.
//!
//! From the baseline count, one control point fewer at a time: the best single knot removal when it
//! keeps the tolerance, else a short swarm probe (seeded with the three best removals and the
//! averaging knots) that stops at the first feasible position; the first count where the probe finds
//! none ends the descent. The feasible knots met on the way down seed the count search's full
//! searches ([`super::count_search`]).
//!
//! The greedy removals are deterministic; the probes are not, and where a probe lands decides the
//! knots of every count below it. The count search's swarms stay close to their seeds (3 % spread,
//! one random particle in 16), so on whitcomb at `--seed 2` its searches and a restart from the same
//! seeds on another random stream all finish with 9 curvature extrema (splprep: 8). A **second
//! descent** ([`second_descent`]) starts where the first one ran its first probe and probes on
//! another random stream ([`RESTART_SALT`]); its knots are the seeds of the count search's restart
//! (the first descent's count and knots are kept, so the count search starts as before).

use super::count_search::{pso_options, CountProblem};
use super::integrated::{open_problem, removal_candidates, IntegratedOptions};
use super::objective::FitData;
use super::prepare::averaging_interior_knots;
use super::pso::run_pso;

/// The salt added to the probes' salts on the second descent (an independent stream of the seed).
pub(crate) const RESTART_SALT: u64 = 3_000_017;

/// Where a descent ended, and what it met on the way.
#[derive(Clone, Debug, Default)]
pub(crate) struct Descent {
    /// The smallest feasible count reached.
    pub n: usize,
    /// Its interior knots.
    pub knots: Vec<f64>,
    /// The feasible knots met on the way down, by count (the start first).
    pub by_count: Vec<(usize, Vec<f64>)>,
    /// The count and knots the first probe started from (`None`: greedy removals only).
    pub probe_start: Option<(usize, Vec<f64>)>,
    /// Counts tried, in order.
    pub counts_tried: Vec<usize>,
    /// Candidate evaluations.
    pub evaluations: usize,
    /// Swarm iterations.
    pub iterations: usize,
}

/// The descent from `start` (count, interior knots) down to `lowest`, the probes' random streams
/// salted by `salt` on top of the count (0 for the first descent).
pub(crate) fn descend(
    data: &FitData,
    tol: f64,
    opts: &IntegratedOptions,
    start: (usize, Vec<f64>),
    lowest: usize,
    salt: u64,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Descent {
    let p = opts.degree;
    let (mut best_n, mut best_knots) = start;
    let mut d = Descent {
        by_count: vec![(best_n, best_knots.clone())],
        ..Descent::default()
    };
    while best_n > lowest {
        let cand = best_n - 1;
        d.counts_tried.push(cand);
        let removals = removal_candidates(data, &best_knots);
        d.evaluations += best_knots.len();
        if let Some((dev, knots)) = removals.first() {
            if *dev <= tol {
                best_knots = knots.clone();
                best_n = cand;
                d.by_count.push((cand, best_knots.clone()));
                continue;
            }
        }
        if d.probe_start.is_none() {
            d.probe_start = Some((best_n, best_knots.clone()));
        }
        let pr = open_problem(data, cand, tol, opts);
        let mut seeds: Vec<Vec<f64>> = removals
            .iter()
            .take(3)
            .map(|(_, k)| pr.position(k))
            .collect();
        seeds.push(pr.position(&averaging_interior_knots(&data.params, p, cand)));
        let r = run_pso(
            &pr,
            &seeds,
            &pso_options(opts, opts.probe_iterations, true, cand as u64 + salt),
            &|it| progress(cand, it),
        );
        d.evaluations += r.evaluations;
        d.iterations += r.iterations;
        if !r.fitness.feasible() {
            break;
        }
        let mut kw = Default::default();
        if !pr.decode_into(&r.position, &mut kw) {
            break;
        }
        best_knots = kw.interior;
        best_n = cand;
        d.by_count.push((cand, best_knots.clone()));
    }
    d.n = best_n;
    d.knots = best_knots;
    d
}

/// The second descent of `first` (module doc): from its first probe's start down to `lowest` on
/// the [`RESTART_SALT`] streams; `None` when `first` made no probe (nothing random to redo).
pub(crate) fn second_descent(
    first: &Descent,
    data: &FitData,
    tol: f64,
    opts: &IntegratedOptions,
    lowest: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Option<Descent> {
    let start = first.probe_start.clone()?;
    Some(descend(
        data,
        tol,
        opts,
        start,
        lowest,
        RESTART_SALT,
        progress,
    ))
}
