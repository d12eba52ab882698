//! The wiggly trigger of the next degree's own count search
//! (`fairfit::optim::degree_candidates`, module doc "Wiggly curves"): when the cubic's kept curve
//! has at least `WIGGLY_EXTREMA` (6) curvature extrema, the quartic also searches one count above
//! the least-squares baseline (never more than a quarter of the data points), seeded from the
//! cubic's baseline knots with the best knot insertion, and the degree rule prices only the
//! degree step there. On fx79w470a (shared airfoil, 94 points, seed 0) the cubic keeps 16 points
//! with 6 extrema at 0.570 x splprep's F (main c00701b's result); the quartic at the baseline's 18
//! + 1 = 19 points finishes at 0.487 x with 6 extrema, within splprep's 24 points and 12 extrema.

use fairfit::fair::curve_fairness;
use fairfit::optim::closed::distinct_control_points;
use fairfit::optim::degree_candidates::{
    WIGGLY_COUNTS_ABOVE, WIGGLY_EXTREMA, WIGGLY_POINTS_PER_CONTROL_POINT,
};
use fairfit::optim::integrated::fit_integrated;

use crate::common::degree_auto;
use degree_auto::{assert_same_with_one_and_two_threads, auto};

use crate::common::example_data;
use example_data::read_csv;

use crate::common::sampled;
use sampled::brute_force_deviation;

/// scipy splprep's curve on fx79w470a at `--rel-tol 1e-3` (tools' splprep cache,
/// bench/compare.py): F, control points, curvature extrema.
const SPLPREP: (f64, usize, usize) = (629_434.034_630_292_4, 24, 12);

/// The cubic main c00701b keeps on fx79w470a at seed 0 (CLI report): 16 points, 6 extrema, F.
const MAIN_CUBIC_F: f64 = 358_884.522_540_296_4;

#[test]
fn fx79w470a_gets_a_quartic_one_point_above_the_baseline_below_half_of_splpreps_fairness() {
    assert_eq!(
        (
            WIGGLY_EXTREMA,
            WIGGLY_COUNTS_ABOVE,
            WIGGLY_POINTS_PER_CONTROL_POINT
        ),
        (6, 1, 4)
    );
    let pts = read_csv("fx79w470a.csv");
    assert_eq!(pts.len(), 94);
    let r = fit_integrated(&pts, &auto()).unwrap();
    assert!(r.met);
    // the cubic is main's, unchanged: 16 points, 6 extrema (the trigger), F 3.589e5
    let tried = &r.stats.degrees_tried;
    assert_eq!(tried.len(), 2, "{tried:?}");
    assert_eq!((tried[0].degree, tried[0].control_points), (3, 16));
    assert_eq!(tried[0].curvature_extrema, 6);
    assert!(
        (tried[0].fairness / MAIN_CUBIC_F - 1.0).abs() < 1e-9,
        "{}",
        tried[0].fairness
    );
    // the quartic: one point above the least-squares baseline (18), within a quarter of the 94
    // points and splprep's 24
    let n = distinct_control_points(&r.curve);
    assert_eq!(r.curve.degree(), 4);
    assert_eq!(r.baseline_control_points, 18);
    assert_eq!(n, r.baseline_control_points + 1);
    assert!(n <= pts.len() / 4 && n <= SPLPREP.1, "{n} points");
    // F below the old result by more than the degree's 10 %, and below half of splprep's
    // (measured 3.068e5: 0.487 x splprep's, 0.855 x the cubic's)
    let m = curve_fairness(&r.curve);
    assert!(m.fairness * 1.1 < MAIN_CUBIC_F, "F {}", m.fairness);
    assert!(
        m.fairness <= 0.49 * SPLPREP.0,
        "F {} = {:.3} x splprep's",
        m.fairness,
        m.fairness / SPLPREP.0
    );
    // no more curvature extrema than the cubic (nor splprep)
    assert!(m.curvature_extrema <= 6, "{} extrema", m.curvature_extrema);
    assert!(m.curvature_extrema <= SPLPREP.2);
    // the tolerance holds at every point by dense sampling (1e-3 of the bounding box)
    let dev = brute_force_deviation(&r.curve, &pts);
    assert!(
        dev <= r.tolerance * (1.0 + 1e-6),
        "deviation {dev} > {}",
        r.tolerance
    );
}

#[test]
fn the_wiggly_search_is_identical_with_one_and_two_threads() {
    let a = assert_same_with_one_and_two_threads(&read_csv("fx79w470a.csv"));
    assert_eq!(a.curve.degree(), 4);
}
