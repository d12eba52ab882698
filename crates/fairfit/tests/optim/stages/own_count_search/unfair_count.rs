//! The next degree's own count search in the degree search of the integrated method
//! (`fairfit::optim::stages::degree_candidates`, module doc "Own count search"): when the cubic's count
//! choice kept a curve at least `OWN_COUNT_SEARCH_COST` times less fair than its fairest candidate
//! (the fewest-extrema rule at work), the quartic searches every count up to the least-squares
//! baseline. On hq17 (shared airfoil, seed 0) the cubic keeps 13 points with 3 curvature extrema
//! at about twice the F of a 5-extrema candidate; the quartic's own count search finds 15 points
//! with 3 extrema at less than half the cubic's F.

use fairfit::fair::curve_fairness;
use fairfit::optim::distinct_control_points;
use fairfit::optim::{fit_integrated, IntegratedOptions};

use crate::common::degree_auto;
use degree_auto::{assert_same_with_one_and_two_threads, auto};

use crate::common::example_data;
use example_data::read_csv;

use crate::common::sampled;
use sampled::brute_force_deviation;

#[test]
fn hq17_gets_a_quartic_at_more_points_that_halves_the_cubics_fairness() {
    let pts = read_csv("hq17.csv");
    let cubic = fit_integrated(&pts, &IntegratedOptions::default()).unwrap();
    let r = fit_integrated(&pts, &auto()).unwrap();
    assert!(r.met && cubic.met);
    let (c3, c) = (curve_fairness(&cubic.curve), curve_fairness(&r.curve));
    let (n3, n) = (
        distinct_control_points(&cubic.curve),
        distinct_control_points(&r.curve),
    );
    // measured on main 068885d: the cubic 13 points, 3 extrema, F 9.03e6 (0.568 x splprep's);
    // this quartic 15 points, 3 extrema, F 4.28e6 (0.262 x)
    assert_eq!(r.curve.degree(), 4);
    assert!(n > n3, "{n} points, the cubic's {n3}");
    assert!(
        n <= r.baseline_control_points,
        "{n} > baseline {}",
        r.baseline_control_points
    );
    assert!(c.curvature_extrema <= c3.curvature_extrema);
    assert!(
        c.fairness < 0.6 * c3.fairness,
        "F {} vs the cubic's {}",
        c.fairness,
        c3.fairness
    );
    // the rule's price for a degree step and every added point is paid
    let extra = (n - n3) as i32;
    assert!(c.fairness * 1.1 * 1.05f64.powi(extra) < c3.fairness);
    // the tolerance holds at every point by dense sampling (1e-3 of the bounding box)
    let dev = brute_force_deviation(&r.curve, &pts);
    assert!(
        dev <= r.tolerance * (1.0 + 1e-6),
        "deviation {dev} > {}",
        r.tolerance
    );
    // the cubic trial is the separate cubic fit
    let tried = &r.stats.degrees_tried;
    assert_eq!(tried[0].degree, 3);
    assert_eq!(tried[0].control_points, n3);
    assert_eq!(tried[0].fairness, c3.fairness);
}

#[test]
fn the_own_count_search_is_identical_with_one_and_two_threads() {
    let a = assert_same_with_one_and_two_threads(&read_csv("hq17.csv"));
    assert_eq!(a.curve.degree(), 4);
}

#[test]
fn a_fixed_count_keeps_the_quartic_at_the_cubics_count() {
    // with --control-points the next degree has no counts of its own
    let pts = read_csv("hq17.csv");
    let opts = auto().control_points(13);
    let r = fit_integrated(&pts, &opts).unwrap();
    assert_eq!(distinct_control_points(&r.curve), 13);
    for t in &r.stats.degrees_tried {
        assert_eq!(t.control_points, 13, "degree {}", t.degree);
    }
}
