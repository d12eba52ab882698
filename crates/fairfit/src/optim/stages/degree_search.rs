//! The degree search of the integrated method (`fairfit curve --degree auto`, the default of
//! `fairfit curve`; [`IntegratedOptions::max_degree`](crate::optim::IntegratedOptions::max_degree)): besides the *reference* degree
//! [`IntegratedOptions::degree`](crate::optim::IntegratedOptions::degree) (the cubic), higher degrees up to `max_degree` are tried, and one
//! result is kept by [`choose_degree_priced`]:
//!
//! 1. **admissible**: the tolerance (and `F*`) is met, and — when the reference meets it — the
//!    result has no more curvature extrema than the reference's (the extrema count is never traded
//!    for F); its control points are the reference's count or fewer, except after the next
//!    degree's own count search ([`super::degree_candidates`]);
//! 2. of the admissible degrees, the lowest `F · fairness_gain^(d − reference) · point_gain^extra`
//!    wins (`extra`: control points above the reference's; ties: the lower degree). A higher
//!    degree must buy the factor `fairness_gain`
//!    ([`crate::optim::tuning::DegreeTuning::fairness_gain`], 1.1) per degree step, so the
//!    degree does not change for F differences of a few per cent (the swarm's own noise), and
//!    every control point it adds the count search's price
//!    ([`crate::optim::tuning::CountTuning::extra_point_gain`]; none after the wiggly trigger's
//!    search above the baseline);
//! 3. when the reference misses the tolerance and another degree meets it, the fewest control
//!    points among those meeting it, then the lowest F, wins; when none meets it, the reference is
//!    returned (its miss is reported as usual).
//!
//! **Staged search**: only the reference runs the count search ([`super::count_search`]); its
//! control-point count and knots are then the start of every higher degree
//! ([`super::degree_candidates`]):
//!
//! - degree `d` keeps the reference's count; its knots come from a short knot search seeded with
//!   the reference's knots;
//! - a degree whose knot search misses the tolerance at that count is not finished; the others
//!   get band fairing and the polish with capped budgets
//!   ([`crate::optim::tuning::DegreeTuning::candidate_band_solves`],
//!   [`crate::optim::tuning::DegreeTuning::candidate_polish_evaluations`]);
//! - open curves: the first higher degree runs beside the reference's count search (rayon
//!   `join`), from the knots the count descent found at the smallest feasible count, so it fills
//!   the cores the count search leaves idle; periodic curves and pieces between corners start
//!   from the reference's finished fit;
//! - a degree higher still is tried only when the one below it won;
//! - data with corners: for a higher degree every piece is raised at its own count from its own
//!   knots and the raised pieces are joined, so one degree serves the whole curve
//!   ([`crate::optim::cornered`]).
//!
//! `F` and the curvature extrema are measured on the returned curves by
//! [`crate::fair::curve_fairness`] (the report's numbers). Every finished degree is recorded in
//! [`crate::optim::OptimStats::degrees_tried`] in degree order. Each step is thread-count
//! independent, so the result is byte-identical for any number of threads.

use crate::errors::Result;
use crate::fair::curve_fairness;
use crate::optim::kind::periodic::distinct_control_points;
use crate::optim::result::{DegreeTrial, IntegratedResult};
use crate::optim::tuning::Tuning;

/// The degree search's result: the fit of the kept degree.
#[derive(Clone, Debug)]
pub(crate) struct DegreeSearchOutput {
    /// The kept fit (the reference's when no higher degree won).
    pub result: IntegratedResult,
}

/// One higher degree's attempt in the staged search: its fit (`None` when it could not be fitted
/// within the tolerance at the reference's count) and the work spent on it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Attempt {
    /// The finished fit.
    pub fit: Option<IntegratedResult>,
    /// Candidate evaluations and swarm iterations spent on it (besides the fit's own statistics).
    pub evaluations: usize,
    pub iterations: usize,
}

/// The staged search's choice: the reference's fit, then the higher degrees `higher` one at a
/// time (`attempt`), a degree higher still only when the one below it won; one fit kept by
/// [`choose_degree_priced`] (module doc, "Staged search").
pub(crate) fn keep_degree(
    reference: IntegratedResult,
    higher: std::ops::RangeInclusive<usize>,
    tuning: &Tuning,
    attempt: &(dyn Fn(usize) -> Attempt + Sync),
) -> Result<IntegratedResult> {
    let point_gain = tuning.count.extra_point_gain;
    keep_degree_priced(
        reference,
        higher,
        tuning.degree.fairness_gain,
        point_gain,
        attempt,
    )
}

/// [`keep_degree`] with `point_gain` per control point above the reference's in place of
/// the count search's price per point ([`choose_degree_priced`]).
pub(crate) fn keep_degree_priced(
    reference: IntegratedResult,
    higher: std::ops::RangeInclusive<usize>,
    fairness_gain: f64,
    point_gain: f64,
    attempt: &(dyn Fn(usize) -> Attempt + Sync),
) -> Result<IntegratedResult> {
    let mut trials = vec![trial_of(&reference)];
    let mut results = vec![reference];
    let (mut evaluations, mut iterations) = (0, 0);
    for d in higher {
        let a = attempt(d);
        evaluations += a.evaluations;
        iterations += a.iterations;
        let Some(r) = a.fit else { break };
        trials.push(trial_of(&r));
        results.push(r);
        // a degree higher still only when this one won
        if choose_degree_priced(&trials, fairness_gain, point_gain) + 1 != trials.len() {
            break;
        }
    }
    let pick = choose_degree_priced(&trials, fairness_gain, point_gain);
    evaluations += results.iter().map(|r| r.stats.evaluations).sum::<usize>();
    iterations += results.iter().map(|r| r.stats.iterations).sum::<usize>();
    let mut chosen = results.swap_remove(pick);
    chosen.stats.evaluations = evaluations;
    chosen.stats.iterations = iterations;
    chosen.stats.degrees_tried = trials;
    Ok(chosen)
}

/// The measured summary of one fit.
fn trial_of(r: &IntegratedResult) -> DegreeTrial {
    let f = curve_fairness(&r.curve);
    DegreeTrial {
        degree: r.curve.degree(),
        control_points: distinct_control_points(&r.curve),
        fairness: f.fairness,
        curvature_extrema: f.curvature_extrema,
        tolerance_met: r.met,
    }
}

/// The index of the trial the module's rule keeps; `trials[0]` is the reference (lowest degree),
/// and `point_gain` prices each control point above the reference's: the count search's
/// [`CountTuning::extra_point_gain`](crate::optim::tuning::CountTuning::extra_point_gain) as a
/// rule, 1 after the wiggly trigger's search above the least-squares baseline
/// ([`super::degree_candidates`], "Wiggly curves"), where only the degree's price is paid.
pub fn choose_degree_priced(trials: &[DegreeTrial], fairness_gain: f64, point_gain: f64) -> usize {
    let Some(reference) = trials.first() else {
        return 0;
    };
    let lower = |a: (usize, f64, usize), b: (usize, f64, usize)| {
        a.0.cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
            .is_lt()
    };
    let mut best: Option<(usize, (usize, f64, usize))> = None;
    for (i, t) in trials.iter().enumerate() {
        if !t.tolerance_met {
            continue;
        }
        let key = if reference.tolerance_met {
            if t.curvature_extrema > reference.curvature_extrema {
                continue;
            }
            let steps = t.degree.saturating_sub(reference.degree) as i32;
            let extra = t.control_points.saturating_sub(reference.control_points) as i32;
            let score = t.fairness * fairness_gain.powi(steps) * point_gain.powi(extra);
            (0, score, t.degree)
        } else {
            (t.control_points, t.fairness, t.degree)
        };
        if best.is_none_or(|(_, b)| lower(key, b)) {
            best = Some((i, key));
        }
    }
    best.map_or(0, |(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The index of the trial the module's rule keeps; `trials[0]` is the reference (lowest degree);
    /// every control point above the reference's is priced at the default
    /// [`CountTuning::extra_point_gain`].
    fn choose_degree(trials: &[DegreeTrial], fairness_gain: f64) -> usize {
        choose_degree_priced(
            trials,
            fairness_gain,
            crate::optim::tuning::CountTuning::default().extra_point_gain,
        )
    }

    fn t(degree: usize, n: usize, f: f64, ex: usize, met: bool) -> DegreeTrial {
        DegreeTrial {
            degree,
            control_points: n,
            fairness: f,
            curvature_extrema: ex,
            tolerance_met: met,
        }
    }

    #[test]
    fn lowest_scored_fairness_among_admissible_degrees() {
        // degree 4 wins by more than the gain; degree 5 is fairer still but has more extrema
        let trials = [
            t(3, 7, 100.0, 3, true),
            t(4, 7, 50.0, 3, true),
            t(5, 7, 1.0, 4, true),
        ];
        assert_eq!(choose_degree(&trials, 1.1), 1);
    }

    #[test]
    fn every_added_point_must_buy_five_per_cent() {
        // hq17 (seed 0): the cubic at 13 points F 9.03e6, the quartic's own count search 15
        // points F 4.28e6: 4.28e6 · 1.1 · 1.05² = 5.19e6 wins
        let hq17 = [t(3, 13, 9.03e6, 3, true), t(4, 15, 4.28e6, 3, true)];
        assert_eq!(choose_degree(&hq17, 1.1), 1);
        // 80 · 1.1 · 1.05² = 97.0 < 100 wins; 85 · 1.1 · 1.05² = 103.1 does not
        let wins = [t(3, 13, 100.0, 3, true), t(4, 15, 80.0, 3, true)];
        assert_eq!(choose_degree(&wins, 1.1), 1);
        let loses = [t(3, 13, 100.0, 3, true), t(4, 15, 85.0, 3, true)];
        assert_eq!(choose_degree(&loses, 1.1), 0);
        // fewer points than the reference earn nothing
        let fewer = [t(3, 13, 100.0, 3, true), t(4, 11, 95.0, 3, true)];
        assert_eq!(choose_degree(&fewer, 1.1), 0);
    }

    #[test]
    fn the_wiggly_price_is_the_degrees_alone() {
        // fx79w470a (seed 0): the cubic at 16 points F 3.589e5, the quartic one above the
        // baseline, 19 points, F 3.068e5: 3.068e5 · 1.1 = 3.375e5 wins without a point price,
        // 3.068e5 · 1.1 · 1.05³ = 3.907e5 loses with it
        let fx79 = [t(3, 16, 3.589e5, 6, true), t(4, 19, 3.068e5, 6, true)];
        assert_eq!(choose_degree_priced(&fx79, 1.1, 1.0), 1);
        assert_eq!(choose_degree(&fx79, 1.1), 0);
        assert_eq!(choose_degree_priced(&fx79, 1.1, 1.05), 0);
        // the degree's price stays: 3.3e5 · 1.1 > 3.589e5
        let close = [t(3, 16, 3.589e5, 6, true), t(4, 19, 3.3e5, 6, true)];
        assert_eq!(choose_degree_priced(&close, 1.1, 1.0), 0);
    }

    #[test]
    fn a_few_per_cent_do_not_change_the_degree() {
        let trials = [t(3, 7, 100.0, 3, true), t(4, 7, 95.0, 3, true)];
        assert_eq!(choose_degree(&trials, 1.1), 0);
        assert_eq!(choose_degree(&trials, 1.0), 1);
    }

    #[test]
    fn more_extrema_or_a_miss_are_never_chosen() {
        let trials = [
            t(3, 7, 100.0, 3, true),
            t(4, 7, 1.0, 4, true),
            t(5, 6, 1.0, 2, false),
        ];
        assert_eq!(choose_degree(&trials, 1.1), 0);
    }

    #[test]
    fn a_missed_reference_gives_way_to_the_fewest_points_meeting_the_tolerance() {
        let trials = [
            t(3, 7, 1.0, 0, false),
            t(4, 9, 5.0, 3, true),
            t(5, 8, 50.0, 5, true),
        ];
        assert_eq!(choose_degree(&trials, 1.1), 2);
        let none = [t(3, 7, 1.0, 0, false), t(4, 9, 5.0, 3, false)];
        assert_eq!(choose_degree(&none, 1.1), 0);
    }
}
