//! The count search: full knot searches at the smallest feasible count `n` and at up to
//! `max_extra_control_points` more, each candidate finished in full (band fairing, polish), and
//! the count chosen on the **finished** curves' F and curvature extrema. Shared by open and
//! periodic curves (`CurveKind`).
//!
//! **Candidates.** At every count the full swarm (seeded with the given knots, the knots the
//! descent met at that count and the kind's spread knots) is followed by the smoothing line
//! search ([`tune_smoothing`]). At every count above `n` two such searches run, in effect two
//! restarts of the same search:
//!
//! - the *chain*: seeded with the previous count's best knots with one knot inserted
//!   (`CurveKind::insertion`), so it runs after it;
//! - the *independent* search: seeded with the descent's knots at that count (what
//!   `--control-points` at that count starts from), so it runs in parallel with the chain.
//!
//! Both searches at an extra count are candidates (one when they end at the same knots and
//! smoothing) while the better swarm F of the two is a clear step below the best swarm F at the
//! count below ([`CountTuning::weak_step_gain`]). Extra counts stop at `limit` (never more than
//! the least-squares baseline), at the first count where neither search meets the tolerance, and
//! are skipped with a fixed count ([`crate::optim::IntegratedOptions::control_points`]). Every
//! search's `(count, swarm F)` is recorded in [`OptimStats::fairness_by_count`].
//!
//! **Why the finished F.** The swarm minimises F of the least-squares-with-smoothing curve; band
//! fairing and the polish then lower F by very different amounts at different knots, so the
//! swarm's F ranks counts wrongly where it matters, and a short band fairing does not rank them
//! either. So every candidate is finished, in parallel (one serial band fairing per candidate).
//!
//! **Rule** (`choose_count`), on the finished curves (F as [`curve_fairness`] measures it,
//! infinite when the tolerance or `F*` is missed; its curvature extrema, counted as the
//! benchmark's measurer counts them at [`crate::fair::extrema::SAMPLES_PER_SPAN`] samples per
//! span): the fewest curvature extrema first, then the lowest `F · gain^extra` (`extra` points
//! above the smallest count, `gain` = [`CountTuning::extra_point_gain`]; ties: the fewer points),
//! so an added point must buy that factor and may not add a wiggle.
//!
//! **Restart** (seed robustness). The searches stay near their seeds, and on an open curve the
//! seeds below the first probe of the count descent depend on where that probe landed, i.e. on
//! `--seed`. When the chosen curve has at least [`CountTuning::restart_min_extrema`] curvature
//! extrema, one more full search runs at the chosen count (another random stream) and is
//! finished as a candidate of the same rule: seeded with the second descent's knots at that count
//! (`CountSearchInput::alt`, [`super::descent`]) when they differ from the first descent's, else with
//! the first descent's knots on the other stream.
//!
//! The choice is reported to the degree search as a `CountChoice` (extrema cost, count gain,
//! extrema), from which the next degree's own count search is triggered
//! ([`super::degree_candidates`]).

use super::descent::DescentOutput;
use crate::errors::{Error, Result};
use crate::fair::metrics::curve_fairness;
use crate::optim::context::FitContext;
use crate::optim::kind::CurveKind;
use crate::optim::progress::Stage;
use crate::optim::result::{IntegratedResult, OptimStats};
use crate::optim::search::objective::CandidateEval;
use crate::optim::search::problem::CountProblem;
use crate::optim::search::pso::{run_pso, PsoResult};
use crate::optim::search::smoothing::tune_smoothing;
use crate::optim::tuning::CountTuning;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

pub(crate) use super::count_choice::{
    choose_count, count_gain, extrema_cost, weak_step, CountChoice, Ranked,
};

/// The salt of the count search's full swarms (added to the count).
const MAIN_SALT: u64 = 1_000_003;

/// The salt of the restart's full swarm (added to the count): another stream of the same seed.
const COUNT_RESTART_SALT: u64 = 2_000_029;

/// Where [`run`] starts: the count descent's result.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CountSearchInput<'a> {
    /// The smallest feasible count (or the fixed one).
    pub n: usize,
    /// Its interior knots.
    pub knots: &'a [f64],
    /// The feasible knots met on the way down, by count.
    pub descent: &'a [(usize, Vec<f64>)],
    /// The largest count an extra control point may reach.
    pub limit: usize,
    /// A second descent's feasible knots by count, on other random streams (empty: none): the
    /// seeds of the restart at the chosen count.
    pub alt: &'a [(usize, Vec<f64>)],
}

impl<'a> CountSearchInput<'a> {
    /// The count search after the descent `down`, extra counts up to `limit`; the restart seeded
    /// from the second descent when `down` ran one.
    pub fn after(down: &'a DescentOutput, limit: usize) -> Self {
        CountSearchInput {
            n: down.n,
            knots: &down.knots,
            descent: &down.met,
            limit,
            alt: &down.alt,
        }
    }
}

/// The count search's result: the chosen finished fit and how it was chosen.
#[derive(Clone, Debug)]
pub(crate) struct CountSearchOutput {
    /// The finished fit at the chosen count.
    pub result: IntegratedResult,
    /// The choice, for the degree search's triggers.
    pub choice: CountChoice,
}

/// One full search at one count: its knots, smoothing, swarm F (infinite when infeasible).
#[derive(Clone, Debug)]
struct Draw {
    count: usize,
    /// Interior knots (`None` when the best position decodes to no valid knot vector).
    interior: Option<Vec<f64>>,
    log_lambda: f64,
    fairness: f64,
    stats: OptimStats,
}

/// [`run`], with the **extrema cost** of the choice: the chosen candidate's score
/// `F · extra_point_gain^extra` over the lowest score of all finished candidates within the
/// tolerance (1 when the fairest candidate was kept; above 1 when the fewest-extrema rule kept a
/// less fair curve), and the count gain ([`CountChoice`]). The degree search reads both
/// ([`super::degree_candidates`]).
pub(crate) fn run<K: CurveKind>(
    ctx: &FitContext,
    family: &K,
    start: CountSearchInput<'_>,
) -> Result<CountSearchOutput> {
    let opts = ctx.opts;
    let CountSearchInput {
        n,
        knots,
        descent,
        limit,
        alt,
    } = start;
    let max_extra = if opts.control_points.is_some() {
        0
    } else {
        opts.max_extra_control_points
    };
    let top = (n + max_extra).min(limit).max(n);
    let search = |count: usize, seeds: &[Vec<f64>]| {
        full_search(ctx, family, count, seeds, descent, MAIN_SALT)
    };
    let (chain, independent) = rayon::join(
        || {
            let mut chain = vec![search(n, &[knots.to_vec()])];
            for count in n + 1..=top {
                let prev = &chain[chain.len() - 1];
                let (true, Some(k)) = (prev.fairness.is_finite(), &prev.interior) else {
                    break;
                };
                let seed = family.insertion(k, prev.log_lambda);
                chain.push(search(count, &[seed]));
            }
            chain
        },
        || {
            (n + 1..=top)
                .into_par_iter()
                .filter_map(|count| {
                    let (_, k) = descent.iter().find(|(c, _)| *c == count)?;
                    Some(search(count, std::slice::from_ref(k)))
                })
                .collect::<Vec<Draw>>()
        },
    );
    let mut stats = ctx.stats();
    for d in chain.iter().chain(&independent) {
        stats.evaluations += d.stats.evaluations;
        stats.iterations += d.stats.iterations;
        stats.counts_tried.extend(&d.stats.counts_tried);
        stats.fairness_by_count.extend(&d.stats.fairness_by_count);
    }
    let t = &ctx.tuning.count;
    let candidates = candidate_draws(&chain, &independent, n, top, t);
    let mut finished = finish_draws(ctx, family, &candidates);
    let mut counts: Vec<usize> = candidates.iter().map(|d| d.count).collect();
    let mut ranked: Vec<Ranked> = finished.iter().map(rank).collect();
    let mut best = choose_count(&counts, &ranked, t);
    if ranked[best].extrema >= t.restart_min_extrema {
        // the restart at the chosen count (module doc): from the second descent's knots there, else
        // from the first descent's on another stream
        let count = counts[best];
        let d = match restart_seed(count, descent, alt) {
            Some(k) => full_search(ctx, family, count, &[k.to_vec()], &[], COUNT_RESTART_SALT),
            None => full_search(ctx, family, count, &[], descent, COUNT_RESTART_SALT),
        };
        stats.evaluations += d.stats.evaluations;
        stats.iterations += d.stats.iterations;
        stats.counts_tried.extend(&d.stats.counts_tried);
        stats.fairness_by_count.extend(&d.stats.fairness_by_count);
        if d.fairness.is_finite() {
            let r = finish_draws(ctx, family, &[&d]).remove(0);
            counts.push(d.count);
            ranked.push(rank(&r));
            finished.push(r);
            best = choose_count(&counts, &ranked, t);
        }
    }
    let choice = CountChoice {
        extrema_cost: extrema_cost(&counts, &ranked, best, t),
        count_gain: count_gain(&counts, &ranked, best),
        extrema: ranked[best].extrema,
    };
    let chosen = finished.into_iter().nth(best).unwrap_or_else(|| {
        Err(Error::Fit(
            "no valid knot vector for the data (too few points?)".into(),
        ))
    })?;
    Ok(CountSearchOutput {
        result: chosen,
        choice,
    })
}

/// Finishes the draws in parallel (an error for a draw without knots), reporting
/// [`Stage::BandFairing`] as each is done.
fn finish_draws<K: CurveKind>(
    ctx: &FitContext,
    family: &K,
    draws: &[&Draw],
) -> Vec<Result<IntegratedResult>> {
    let done = AtomicUsize::new(0);
    (ctx.progress)(Stage::BandFairing, 0, draws.len());
    draws
        .par_iter()
        .map(|d| {
            let r = match &d.interior {
                Some(k) => family.finish(k, d.log_lambda),
                None => Err(Error::Fit(
                    "no valid knot vector for the data (too few points?)".into(),
                )),
            };
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            (ctx.progress)(Stage::BandFairing, n, draws.len());
            r
        })
        .collect()
}

/// How a finished curve ranks: F infinite when the tolerance or `F*` is missed.
fn rank(r: &Result<IntegratedResult>) -> Ranked {
    match r {
        Ok(r) => rank_fit(r),
        Err(_) => Ranked {
            fairness: f64::INFINITY,
            extrema: usize::MAX,
        },
    }
}

/// How a finished fit ranks: its F ([`curve_fairness`]), infinite when the tolerance or `F*` is
/// missed, and its curvature extrema.
pub(crate) fn rank_fit(r: &IntegratedResult) -> Ranked {
    let m = curve_fairness(&r.curve);
    Ranked {
        fairness: if r.met { m.fairness } else { f64::INFINITY },
        extrema: m.curvature_extrema,
    }
}

/// The restart's seed at `count` (module doc): the second descent's knots there when they differ
/// from the first descent's (the same knots, met by greedy removals only, restart nothing new).
fn restart_seed<'a>(
    count: usize,
    descent: &[(usize, Vec<f64>)],
    alt: &'a [(usize, Vec<f64>)],
) -> Option<&'a [f64]> {
    let (_, k) = alt.iter().find(|(c, _)| *c == count)?;
    let same = descent.iter().any(|(c, d)| *c == count && d == k);
    (!same).then_some(k.as_slice())
}

/// The draws finished as candidates (module doc): the search at `n`, then at every count up to
/// `top` all of its searches (chain first; a search with the knots and smoothing of one before it
/// is left out) while the best of their swarm F is a clear step down from the count below.
fn candidate_draws<'d>(
    chain: &'d [Draw],
    independent: &'d [Draw],
    n: usize,
    top: usize,
    t: &CountTuning,
) -> Vec<&'d Draw> {
    let mut candidates = vec![&chain[0]];
    let mut prev_fairness = chain[0].fairness;
    for count in n + 1..=top {
        let mut at: Vec<&Draw> = Vec::new();
        for d in chain.iter().chain(independent) {
            let same = |e: &&Draw| e.interior == d.interior && e.log_lambda == d.log_lambda;
            if d.count == count && d.interior.is_some() && !at.iter().any(same) {
                at.push(d);
            }
        }
        let best = at.iter().map(|d| d.fairness).fold(f64::INFINITY, f64::min);
        if at.is_empty() || weak_step(prev_fairness, best, t) {
            break;
        }
        candidates.extend(at);
        prev_fairness = best;
    }
    candidates
}

/// The F of a full search's result, infinite when it is infeasible.
fn swarm_fairness(r: &PsoResult<CandidateEval>) -> f64 {
    if r.fitness.feasible() {
        r.output.fairness
    } else {
        f64::INFINITY
    }
}

/// The full swarm at count `n` from the `seeds` knots (plus the descent's knots at `n` and the
/// spread knots) and the smoothing line search; records `(n, F)`.
fn full_search<K: CurveKind>(
    ctx: &FitContext,
    family: &K,
    n: usize,
    seeds: &[Vec<f64>],
    descent: &[(usize, Vec<f64>)],
    salt: u64,
) -> Draw {
    let (opts, progress) = (ctx.opts, ctx.progress);
    let mut stats = OptimStats::default();
    stats.counts_tried.push(n);
    let pr = family.problem(n);
    let mut x0: Vec<Vec<f64>> = seeds.iter().map(|k| pr.position(k)).collect();
    if let Some((_, k)) = descent.iter().find(|(c, k)| *c == n && !seeds.contains(k)) {
        x0.push(pr.position(k));
    }
    x0.push(pr.position(&family.spread_knots(n)));
    let po = ctx
        .tuning
        .swarm
        .options(opts, opts.max_iterations, false, n as u64 + salt);
    let stage = Stage::CountSearch { control_points: n };
    let mut r = run_pso(&pr, &x0, &po, &|it| {
        progress(stage, it, opts.max_iterations)
    });
    stats.evaluations += r.evaluations;
    stats.iterations += r.iterations;
    if let Some(coord) = pr.smoothing_coord() {
        // the swarm explores the smoothing weight poorly: a line search on it at the best knots
        let t = tune_smoothing(&pr, coord, (&r.position, &r.output, r.fitness));
        stats.evaluations += t.evaluations;
        (r.position, r.output, r.fitness) = (t.position, t.output, t.fitness);
    }
    let fairness = swarm_fairness(&r);
    stats.fairness_by_count.push((n, fairness));
    Draw {
        count: n,
        interior: pr.decode(&r.position),
        log_lambda: pr.log_lambda(&r.position),
        fairness,
        stats,
    }
}

#[cfg(test)]
mod tests {
    use super::{candidate_draws, choose_count, count_gain, restart_seed, weak_step, Draw, Ranked};
    use crate::optim::result::OptimStats;
    use crate::optim::tuning::{CountTuning, Tuning};

    const T: CountTuning = CountTuning {
        extra_point_gain: 1.05,
        weak_step_gain: 0.02,
        restart_min_extrema: 2,
    };

    fn draw(count: usize, knot: f64, fairness: f64) -> Draw {
        Draw {
            count,
            interior: Some(vec![knot]),
            log_lambda: -3.0,
            fairness,
            stats: OptimStats::default(),
        }
    }

    #[test]
    fn every_search_at_a_clear_step_is_a_candidate() {
        let counts = |c: &[&Draw]| c.iter().map(|d| (d.count, d.fairness)).collect::<Vec<_>>();
        // naca633418's swarm F (ratios to splprep's): 1.387 at 12, chain 1.060 and independent
        // 1.122 at 13: both searches at 13 are finished (they finish at 0.513 and 0.480)
        let chain = [draw(12, 0.5, 1.387), draw(13, 0.4, 1.060)];
        let independent = [draw(13, 0.6, 1.122)];
        let c = candidate_draws(&chain, &independent, 12, 13, &T);
        assert_eq!(counts(&c), vec![(12, 1.387), (13, 1.060), (13, 1.122)]);
        // the step is measured from the best search below: 13 steps from 1.0 to 0.97, 14 must
        // be 2 % below 0.97 (0.96 is not; 0.94 is)
        let chain = [draw(12, 0.5, 1.0), draw(13, 0.4, 0.97), draw(14, 0.3, 0.96)];
        let independent = [draw(13, 0.6, 0.99), draw(14, 0.7, 0.94)];
        let c = candidate_draws(&chain, &independent, 12, 14, &T);
        assert_eq!(
            counts(&c),
            vec![(12, 1.0), (13, 0.97), (13, 0.99), (14, 0.96), (14, 0.94)]
        );
        let c = candidate_draws(&chain, &independent[..1], 12, 14, &T);
        assert_eq!(counts(&c), vec![(12, 1.0), (13, 0.97), (13, 0.99)]);
        // a weak step ends the candidates (hq17: 0.442 at 13, 0.441 and 0.434 at 14)
        let chain = [draw(13, 0.5, 0.442), draw(14, 0.4, 0.441)];
        let independent = [draw(14, 0.6, 0.434)];
        assert_eq!(
            counts(&candidate_draws(&chain, &independent, 13, 14, &T)).len(),
            1
        );
        // the same knots and smoothing are finished once; a search without knots is left out
        let chain = [draw(10, 0.5, 1.0), draw(11, 0.4, 0.8)];
        let mut none = draw(11, 0.6, 0.7);
        none.interior = None;
        let independent = [draw(11, 0.4, 0.8), none];
        let c = candidate_draws(&chain, &independent, 10, 11, &T);
        assert_eq!(counts(&c), vec![(10, 1.0), (11, 0.8)]);
    }

    #[test]
    fn the_tests_use_the_default_tuning() {
        assert_eq!(CountTuning::default(), T);
    }

    #[test]
    fn weak_step_needs_two_percent_drop() {
        // SNL-FFA-W3-500's swarm F ratio at n + 1 (0.992) and hq17's (0.981) are weak, du06's
        // (0.968) is not
        assert!(weak_step(1.0, 0.992, &T));
        assert!(weak_step(1.0, 0.981, &T));
        assert!(!weak_step(1.0, 0.968, &T));
        assert!(!weak_step(1.0, 0.979, &T));
        // a worse or infeasible n + 1, or an infeasible n, is no gain
        assert!(weak_step(1.0, 1.005, &T));
        assert!(weak_step(1.0, f64::INFINITY, &T));
        assert!(weak_step(f64::INFINITY, 1.0, &T));
    }

    fn r(fairness: f64, extrema: usize) -> Ranked {
        Ranked { fairness, extrema }
    }

    #[test]
    fn fewest_extrema_first_then_five_percent_per_extra_point() {
        // du06-w-200-selig's finished F (ratios to splprep's): 12 -> 13 points gains 5.6 %
        assert_eq!(choose_count(&[12, 13], &[r(0.503, 1), r(0.475, 1)], &T), 1);
        // 4 % is not enough for one point, 9 % not for two
        assert_eq!(choose_count(&[10, 11], &[r(1.0, 1), r(0.96, 1)], &T), 0);
        assert_eq!(choose_count(&[10, 12], &[r(1.0, 1), r(0.91, 1)], &T), 0);
        assert_eq!(
            choose_count(&[10, 11, 12], &[r(1.0, 1), r(0.97, 1), r(0.90, 1)], &T),
            2
        );
        // a fairer curve with more curvature extrema loses (FFA-W3-211: 13 points 0.249, 2
        // extrema against 12 points 0.369, 1)
        assert_eq!(choose_count(&[12, 13], &[r(0.369, 1), r(0.249, 2)], &T), 0);
        // and fewer extrema win even at a higher F (naca633418: 12 points 0.496 with 3 extrema
        // at the dense count, 13 points 0.509 with 1)
        assert_eq!(choose_count(&[12, 13], &[r(0.496, 3), r(0.509, 1)], &T), 1);
        // outside the tolerance (infinite F) never wins, whatever its extrema
        assert_eq!(
            choose_count(&[9, 10], &[r(f64::INFINITY, 0), r(5.0, 2)], &T),
            1
        );
        assert_eq!(
            choose_count(&[9, 10], &[r(1.0, 1), r(f64::INFINITY, 0)], &T),
            0
        );
        assert_eq!(
            choose_count(&[9, 10], &[r(f64::INFINITY, 0), r(f64::INFINITY, 0)], &T),
            0
        );
    }

    #[test]
    fn the_count_gain_is_the_least_fair_top_counts_drop_from_the_smallest() {
        // clarky, seed 0 (finished F over splprep's): 9 points 0.827, 10 points 0.621 (kept) and
        // 0.645: the kept curve has the highest count; its least fair search there 0.645 / 0.827
        let g = count_gain(&[9, 10, 10], &[r(0.827, 1), r(0.621, 1), r(0.645, 1)], 1);
        assert!((g - 0.645 / 0.827).abs() < 1e-15, "{g}");
        // SNL-FFA-W3-500, seed 4 (finished F): one search at 13, three at 14 (chain, independent,
        // restart; the chain's has 4 extrema): 0.883, not the kept one's 0.691
        let snl = [
            r(6.645_474e6, 3),
            r(4.544_894e6, 4),
            r(5.866_423e6, 3),
            r(4.593_783e6, 3),
        ];
        let g = count_gain(&[13, 14, 14, 14], &snl, 3);
        assert!((g - 5.866_423 / 6.645_474).abs() < 1e-12, "{g}");
        assert!(g > Tuning::default().degree.steep_count_gain);
        // the fairest candidate at the smallest count is the reference (du84132v_noise1e-4-like:
        // two finishes at 12)
        let g = count_gain(&[12, 13, 12], &[r(0.5, 3), r(0.4, 3), r(0.45, 3)], 1);
        assert!((g - 0.4 / 0.45).abs() < 1e-15, "{g}");
        // a search at the kept count outside the tolerance is not the least fair one
        let g = count_gain(
            &[9, 10, 10],
            &[r(0.8, 1), r(0.6, 1), r(f64::INFINITY, 0)],
            1,
        );
        assert!((g - 0.75).abs() < 1e-15, "{g}");
        // the smallest count kept, a kept count below the highest, or one count only: 1
        assert_eq!(count_gain(&[9, 10], &[r(0.8, 1), r(0.9, 1)], 0), 1.0);
        assert_eq!(
            count_gain(&[9, 10, 11], &[r(0.8, 1), r(0.6, 1), r(0.7, 2)], 1),
            1.0
        );
        assert_eq!(count_gain(&[11, 11], &[r(0.8, 1), r(0.6, 1)], 1), 1.0);
        // nothing within the tolerance at the smallest count: no gain to measure
        assert_eq!(
            count_gain(&[9, 10], &[r(f64::INFINITY, 0), r(0.6, 1)], 1),
            1.0
        );
    }

    #[test]
    fn the_restart_starts_from_the_second_descents_own_knots() {
        let descent = vec![(14, vec![0.1, 0.5]), (13, vec![0.2])];
        // the second descent met other knots at 13 (after a probe): they seed the restart there
        let alt = vec![(14, vec![0.1, 0.5]), (13, vec![0.3]), (12, vec![])];
        assert_eq!(restart_seed(13, &descent, &alt), Some(&[0.3][..]));
        // the same knots (greedy removals only) or no knots at the count: no seed of its own
        assert_eq!(restart_seed(14, &descent, &alt), None);
        assert_eq!(restart_seed(15, &descent, &alt), None);
        assert_eq!(restart_seed(13, &descent, &[]), None);
        // a count the first descent did not reach
        assert_eq!(restart_seed(12, &descent, &alt), Some(&[][..]));
    }
}
