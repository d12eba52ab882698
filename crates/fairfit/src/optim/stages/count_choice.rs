//! The count choice: which of the count search's finished candidates is kept, and what that choice
//! tells the degree search (its extrema cost and count gain). Pure functions of the candidates'
//! counts, finished F and curvature extrema ([`super::count_search`] runs the searches).

use crate::optim::tuning::CountTuning;

/// How a finished candidate ranks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ranked {
    /// Whole-curve fairness `F` (infinite when the tolerance or `F*` is missed).
    pub fairness: f64,
    /// Curvature extrema.
    pub extrema: usize,
}

/// How the count search's choice went, for the next degree ([`super::degree_candidates`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CountChoice {
    /// The extrema cost ([`super::count_search::run`]).
    pub extrema_cost: f64,
    /// The **count gain**: the *least fair* finished F within the tolerance at the kept count
    /// over the fairest finished F at the smallest count, when the kept count is above the
    /// smallest and the highest finished count (the extra points were still paying where the
    /// search stopped, in every search at the kept count, not only in the luckiest of its two or
    /// three); 1 otherwise.
    pub count_gain: f64,
    /// The kept curve's curvature extrema (as [`rank_fit`] counts them).
    pub extrema: usize,
}

/// The count gain of choosing candidate `best` ([`CountChoice::count_gain`]): the least fair F
/// (within the tolerance) of the candidates at its count over the fairest F at the smallest
/// count, when it has the highest count of all candidates and more than the smallest; else 1.
///
/// The least fair, not the kept, candidate: the kept count has two or three finished searches
/// (chain, independent, restart) against one or two at the smallest, and the searches at one
/// count finish 10-40 % apart, so the best of them measures the luck of the draw as much as the
/// added point (SNL-FFA-W3-500, seed 4: 13 points 6.65e6, 14 points 4.54e6 / 5.87e6 / 4.59e6,
/// kept 4.59e6: 0.691 with the kept candidate, 0.883 with the least fair).
pub(crate) fn count_gain(counts: &[usize], ranked: &[Ranked], best: usize) -> f64 {
    let (Some(lowest), Some(highest)) =
        (counts.iter().copied().min(), counts.iter().copied().max())
    else {
        return 1.0;
    };
    if counts[best] == lowest || counts[best] != highest {
        return 1.0;
    }
    let fairness_at = |count: usize| {
        (0..counts.len())
            .filter(move |&i| counts[i] == count)
            .map(|i| ranked[i].fairness)
    };
    let at_lowest = fairness_at(lowest).fold(f64::INFINITY, f64::min);
    let least_fair_kept = fairness_at(highest)
        .filter(|f| f.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if ranked[best].fairness.is_finite()
        && least_fair_kept.is_finite()
        && at_lowest.is_finite()
        && at_lowest > 0.0
    {
        least_fair_kept / at_lowest
    } else {
        1.0
    }
}

/// The extrema cost of choosing candidate `best` ([`super::count_search::run`]): its score over the
/// lowest score of the candidates within the tolerance (1 when none is within it).
pub(crate) fn extrema_cost(
    counts: &[usize],
    ranked: &[Ranked],
    best: usize,
    t: &CountTuning,
) -> f64 {
    let Some(lowest) = counts.iter().copied().min() else {
        return 1.0;
    };
    let score = |i: usize| extra_point_score(ranked[i].fairness, counts[i], lowest, t);
    let fairest = (0..counts.len())
        .filter(|&i| ranked[i].fairness.is_finite())
        .map(score)
        .fold(f64::INFINITY, f64::min);
    let chosen = score(best);
    if chosen.is_finite() && fairest > 0.0 && fairest.is_finite() {
        chosen / fairest
    } else {
        1.0
    }
}

/// The index of the chosen candidate (module doc): `counts[i]` control points ranked
/// `ranked[i]`. Of the candidates within the tolerance (finite F), the fewest curvature extrema
/// first, then the lowest `F · extra_point_gain^(count − smallest count)`, then the fewer points;
/// with none within the tolerance, the first.
pub(crate) fn choose_count(counts: &[usize], ranked: &[Ranked], t: &CountTuning) -> usize {
    let Some(lowest) = counts.iter().copied().min() else {
        return 0;
    };
    let key = |i: usize| {
        let score = extra_point_score(ranked[i].fairness, counts[i], lowest, t);
        (ranked[i].extrema, score, counts[i])
    };
    let mut best: Option<usize> = None;
    for i in (0..counts.len()).filter(|&i| ranked[i].fairness.is_finite()) {
        let (e, s, c) = key(i);
        if best.is_none_or(|b| {
            let (be, bs, bc) = key(b);
            e < be || (e == be && (s < bs || (s == bs && c < bc)))
        }) {
            best = Some(i);
        }
    }
    best.unwrap_or(0)
}

/// `fairness` priced for its `count` control points above the smallest count `lowest`:
/// `fairness · extra_point_gain^(count − lowest)` ([`super::count_search`]).
pub(crate) fn extra_point_score(
    fairness: f64,
    count: usize,
    lowest: usize,
    t: &CountTuning,
) -> f64 {
    fairness * t.extra_point_gain.powi((count - lowest) as i32)
}

/// True when `f_next` is not at least [`CountTuning::weak_step_gain`] below `f_prev` (no gain from infinity).
pub(crate) fn weak_step(f_prev: f64, f_next: f64, t: &CountTuning) -> bool {
    !(f_prev.is_finite() && f_next < f_prev * (1.0 - t.weak_step_gain))
}
