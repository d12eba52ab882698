//! The wiggly trigger of the next degree's own count search
//! (`fairfit::optim::stages::own_count_search`): when the cubic's kept curve
//! has at least `Tuning::degree.wiggly_extrema` (6) curvature extrema, the quartic also searches one count above
//! the least-squares baseline (never more than a quarter of the data points), seeded from the
//! cubic's baseline knots with the best knot insertion, and the degree rule prices only the
//! degree step there. Its golden result on fx79w470a is a row of `tests/data/regression.json`
//! (`fx79w470a_quartic_one_point_above_the_baseline`).

use fairfit::optim::Tuning;

use crate::common::degree_auto;
use degree_auto::assert_same_with_one_and_two_threads;

use crate::common::example_data;
use example_data::read_csv;

#[test]
fn the_wiggly_trigger_is_six_extrema_one_count_above_at_most_a_quarter_of_the_points() {
    let t = Tuning::default().degree;
    assert_eq!(
        (
            t.wiggly_extrema,
            t.wiggly_counts_above,
            t.wiggly_points_per_control_point
        ),
        (6, 1, 4)
    );
}

#[test]
fn the_wiggly_search_is_identical_with_one_and_two_threads() {
    let a = assert_same_with_one_and_two_threads(&read_csv("fx79w470a.csv"));
    assert_eq!(a.curve.degree(), 4);
}
