//! The degree search of open data after the reference's count search, with the next degree's
//! own count search ([`super::degree_candidates`], module doc "Own count search"): which trigger
//! fires on the reference's count choice (`CountsSeen`), the counts it searches, and the
//! search itself; the degree is then kept by [`super::degree_search`]'s rule.

use super::count_search::{choose_count, rank_fit, CountChoice, CountSearchInput, Ranked};
use super::degree_candidates::{
    at_degrees, candidate_options, open_attempt, open_candidate_with, Candidate,
};
use super::degree_search::{keep_degree_priced, Attempt, DegreeSearchOutput};
use crate::errors::Result;
use crate::optim::context::FitContext;
use crate::optim::kind::open::{best_insertion, finish};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::prepare::Prepared;
use crate::optim::search::residual_knots::residual_knots;
use crate::optim::tuning::{DegreeTuning, Tuning};
use rayon::prelude::*;

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
    pub fn of(start: &CountSearchInput<'a>, choice: &CountChoice) -> Self {
        CountsSeen {
            n: start.n,
            descent: start.descent,
            limit: start.limit,
            extrema_cost: choice.extrema_cost,
            count_gain: choice.count_gain,
            extrema: choice.extrema,
        }
    }

    /// [`CountsSeen::of`] where the next degree may search counts of its own: `None` with a
    /// fixed count or no extra control points (`opts`).
    pub fn when_counts_free(
        opts: &IntegratedOptions,
        start: &CountSearchInput<'a>,
        choice: &CountChoice,
    ) -> Option<Self> {
        (opts.control_points.is_none() && opts.max_extra_control_points > 0)
            .then(|| CountsSeen::of(start, choice))
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

/// The open degree search's input.
#[derive(Clone, Debug)]
pub(crate) struct DegreeSearchInput<'a> {
    /// The reference degree's finished fit, chosen by the count search.
    pub reference: IntegratedResult,
    /// The next degree's attempt made beside the count search
    /// ([`super::degree_candidates::first_beside`]).
    pub first: Option<Attempt>,
    /// What the count search knew (`None`: the next degree searches no counts of its own).
    pub seen: Option<CountsSeen<'a>>,
}

/// Why the next degree gets a count search of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OwnTrigger {
    /// The reference's fewest-extrema choice was costly (`DegreeTuning::own_count_search_cost`).
    ExtremaCost,
    /// The reference's extra points were still paying where its count search stopped
    /// (`DegreeTuning::steep_count_gain`); the counts are also seeded with residual-driven knots.
    CountGain,
    /// The reference's kept curve has at least `DegreeTuning::wiggly_extrema` curvature extrema: the count
    /// above the least-squares baseline, no price per added point in the degree rule (module doc,
    /// "Wiggly curves").
    Wiggly,
}

/// The degree search after the reference's count search on open data ([`DegreeSearchInput`]):
/// the reference is the finished fit at `opts.degree` of the context's prepared data.
pub(crate) fn raise_open(
    ctx: &FitContext,
    input: DegreeSearchInput<'_>,
) -> Result<DegreeSearchOutput> {
    let DegreeSearchInput {
        reference,
        first,
        seen,
    } = input;
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
        Some(OwnTrigger::Wiggly) => tuning.degree.wiggly_point_gain,
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
    let result = keep_degree_priced(
        reference,
        p + 1..=highest,
        tuning.degree.fairness_gain,
        point_gain,
        &attempt,
    )?;
    Ok(DegreeSearchOutput { result })
}

/// The wiggly trigger's counts (module doc): above the least-squares baseline `limit`, at most
/// [`DegreeTuning::wiggly_counts_above`] of them, and never more control points than the `m` data
/// points over [`DegreeTuning::wiggly_points_per_control_point`].
fn wiggly_counts(limit: usize, m: usize, t: &DegreeTuning) -> std::ops::RangeInclusive<usize> {
    let top = (limit + t.wiggly_counts_above).min(m / t.wiggly_points_per_control_point);
    limit + 1..=top
}

/// Whether the next degree's own count search also tries one count above the least-squares
/// baseline `seen.limit` (module doc, "One point above the baseline"): the reference kept the
/// baseline's count (`reference_count`) and has at least [`CountTuning::restart_min_extrema`](crate::optim::tuning::CountTuning::restart_min_extrema) curvature
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

#[cfg(test)]
mod tests {
    use super::{fairest_within, wiggly_counts, CountsSeen, OwnTrigger, Ranked};
    use crate::optim::tuning::DegreeTuning;

    const T: DegreeTuning = DegreeTuning {
        candidate_band_solves: 8,
        candidate_polish_evaluations: 500,
        own_count_search_cost: 1.5,
        steep_count_gain: 0.8,
        wiggly_extrema: 6,
        wiggly_counts_above: 1,
        wiggly_points_per_control_point: 4,
        short_search_iterations: 0,
        wiggly_point_gain: 1.0,
        fairness_gain: 1.1,
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
}
