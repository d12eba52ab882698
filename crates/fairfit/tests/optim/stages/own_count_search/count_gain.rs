//! The count-gain trigger of the next degree's own count search
//! (`fairfit::optim::degree_candidates`, module doc "Own count search"): when the cubic's kept
//! curve has the highest of its finished counts and its F is at most `Tuning::degree.steep_count_gain` (0.8) of
//! the fairest F at the smallest count, extra points were still paying where the cubic's count
//! search stopped, and the quartic searches every count above the cubic's up to the least-squares
//! baseline, each also seeded with the residual-driven (FITPACK-style) knots there. Its golden
//! results are rows of `tests/data/regression.json`: clarky (the trigger at work), sc20714 at seed
//! 4 (the cubic kept the baseline) and du84132v_noise1e-4 at seed 4 (a lucky search that must not
//! trigger it).

use fairfit::optim::Tuning;

use crate::common::degree_auto;
use degree_auto::assert_same_with_one_and_two_threads;

use crate::common::example_data;
use example_data::read_csv;

#[test]
fn the_count_gain_trigger_is_at_most_0_8_of_the_fairest_f() {
    assert_eq!(Tuning::default().degree.steep_count_gain, 0.8);
}

#[test]
fn the_count_gain_search_is_identical_with_one_and_two_threads() {
    let a = assert_same_with_one_and_two_threads(&read_csv("clarky.csv"));
    assert_eq!(a.curve.degree(), 4);
}
