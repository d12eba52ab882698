//! Band fairing in the integrated method (`IntegratedOptions::band_fairing`): on the quarter ellipse
//! and two airfoils, at the least-squares method's control-point count, the faired curve is at
//! least as fair as without the stage (F by the fairness module, independent of the stage's own
//! Gauss rule), and every data point lies within the tolerance by brute force.

use fairfit::fair::curve_fairness;
use fairfit::optim::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::NurbsCurve;

use crate::common::example_data;
use example_data::read_csv;

use crate::common::sampled;
use sampled::refined_deviation;

#[test]
fn band_fairing_lowers_fairness_within_the_tolerance() {
    use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
    for name in ["quarter_ellipse_200.csv", "naca4412.csv", "e387.csv"] {
        let pts = read_csv(name);
        let n = fit_to_tolerance(&pts, &FitOptions::default())
            .unwrap()
            .n_control_points;
        let opts = |band: bool| {
            IntegratedOptions::new(Tolerance::Relative(1e-3))
                .seed(42)
                .control_points(n)
                .band_fairing(band)
        };
        let off = fit_integrated(&pts, &opts(false)).unwrap();
        let on = fit_integrated(&pts, &opts(true)).unwrap();
        let (f_off, f_on) = (
            curve_fairness(&off.curve).fairness,
            curve_fairness(&on.curve).fairness,
        );
        let dev = refined_deviation(&on.curve, &pts);
        eprintln!(
            "{name}: n={n} F without band fairing {f_off:.4e}, with {f_on:.4e} ({:.3}), dev/tol {:.5}",
            f_on / f_off,
            dev / on.tolerance
        );
        assert_eq!(on.curve.n_control_points(), n, "{name}");
        assert!(f_on <= f_off, "{name}: {f_on} > {f_off}");
        assert!(on.met, "{name}");
        assert!(dev <= on.tolerance * (1.0 + 1e-9), "{name}: {dev}");
    }
}

/// Curvature extrema of a planar curve: sign changes of `dκ/ds L²` on 400 samples strictly inside
/// every knot span, with the benchmark measurer's hysteresis floor (`1e-6` of the largest
/// magnitude plus `1e-9`); `κ` and `dκ/ds` from the curve's own derivatives (independent of the
/// optimiser's node rules).
fn dense_extrema(curve: &NurbsCurve) -> usize {
    let knots = curve.knots();
    let mut sig = Vec::new();
    let mut length = 0.0;
    for w in knots.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        let k = 400;
        for i in 0..k {
            let u = a + (b - a) * (i as f64 + 0.5) / k as f64;
            let d = curve.derivatives(u, 3);
            let v = d[1].norm();
            let cross = d[1][0] * d[2][1] - d[1][1] * d[2][0];
            let dcross = d[1][0] * d[3][1] - d[1][1] * d[3][0];
            let dk_du = dcross / v.powi(3) - 3.0 * cross * d[1].dot(d[2]) / v.powi(5);
            sig.push(dk_du / v);
            length += v * (b - a) / k as f64;
        }
    }
    let sig: Vec<f64> = sig.iter().map(|s| s * length * length).collect();
    let floor = 1e-6 * sig.iter().fold(0.0f64, |a, v| a.max(v.abs())) + 1e-9;
    let (mut state, mut changes) = (0, 0);
    for v in sig {
        let s = if v >= floor {
            1
        } else if v <= -floor {
            -1
        } else {
            continue;
        };
        if state != 0 && s != state {
            changes += 1;
        }
        state = s;
    }
    changes
}

#[test]
fn band_fairing_removes_small_curvature_extrema_and_stays_fair() {
    // Default integrated method against the least-squares method on three shared airfoils,
    // counted by a dense sampling of dκ/ds. Measured (2026-11-26): du06-w-200 lsq 5 extrema,
    // F 3.0e6 -> integrated 1 extremum (the leading edge's peak), F 3.2e5; FFA-W3-241 lsq 9,
    // F 2.5e5 -> 1, F 1.3e5; NACA 4412 lsq 6, F 5.1e6 -> 1, F 8.6e5 (scipy splprep: 3, 2 and 1
    // extrema, F 6.4e5, 3.0e5 and 3.1e6, with more control points). Before the sign targets
    // the integrated method had 3, 5 and 3.
    use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
    for (name, most) in [
        ("du06-w-200-selig.csv", 1),
        ("iea15mw_airfoils/FFA-W3-241.csv", 1),
        ("naca4412.csv", 1),
    ] {
        let pts = read_csv(name);
        let lsq = fit_to_tolerance(&pts, &FitOptions::default()).unwrap();
        // the CLI's defaults (seed 0), as the benchmark runs it
        let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
        let on = fit_integrated(&pts, &opts).unwrap();
        let (e_lsq, e_on) = (dense_extrema(&lsq.curve), dense_extrema(&on.curve));
        let (f_lsq, f_on) = (
            curve_fairness(&lsq.curve).fairness,
            curve_fairness(&on.curve).fairness,
        );
        let dev = refined_deviation(&on.curve, &pts);
        eprintln!(
            "{name}: lsq {} ctrl pts, {e_lsq} extrema, F {f_lsq:.3e}; integrated {} ctrl pts, \
             {e_on} extrema, F {f_on:.3e}, dev/tol {:.5}",
            lsq.curve.n_control_points(),
            on.curve.n_control_points(),
            dev / on.tolerance
        );
        assert!(e_on <= most, "{name}: {e_on} extrema");
        assert!(e_lsq >= e_on + 3, "{name}: lsq {e_lsq}");
        assert!(f_on <= 0.6 * f_lsq, "{name}: {f_on} vs {f_lsq}");
        assert!(on.curve.n_control_points() <= lsq.curve.n_control_points());
        assert!(dev <= on.tolerance * (1.0 + 1e-9), "{name}: {dev}");
    }
}

#[test]
fn band_fairing_lowers_the_clark_y_leading_edge_peak_without_new_extrema() {
    // Clark Y at the CLI's defaults: band fairing's full steps at the leading edge used to add a
    // curvature extremum, were halved and the stage stopped at F = 2.53e6 (0.908 x scipy
    // splprep's 2.789e6 in docs/benchmarks.md, 13 control points against fairfit's 11). With the
    // flipped dκ/ds samples held on their side (band_fairing::SignGuard) the stage goes on:
    // measured F 2.13e6 (0.762 x splprep's), still one curvature extremum (splprep: 4); with the
    // second pass after the polish (band_fairing::refair) 1.79e6 (0.643 x), with the third pass
    // holding the extrema pattern 1.73e6 (0.621 x). The independent study
    // (docs/f-target-study.md) reaches 0.498 x at splprep's 13 points.
    let pts = read_csv("clarky.csv");
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    let on = fit_integrated(&pts, &opts).unwrap();
    let f = curve_fairness(&on.curve).fairness;
    let extrema = dense_extrema(&on.curve);
    let dev = refined_deviation(&on.curve, &pts);
    let splprep_f = 2.789e6;
    eprintln!(
        "clarky: {} ctrl pts, F {f:.4e} ({:.3} x splprep), {extrema} extrema, dev/tol {:.5}",
        on.curve.n_control_points(),
        f / splprep_f,
        dev / on.tolerance
    );
    assert!(on.curve.n_control_points() <= 13);
    assert!(f <= 0.635 * splprep_f, "{f}");
    assert!(extrema <= 1, "{extrema}");
    assert!(on.met);
    assert!(dev <= on.tolerance * (1.0 + 1e-9), "{dev}");
}

#[test]
fn a_second_band_fairing_pass_lowers_the_naca633418_curve_below_its_first_pass() {
    // NACA 63(3)-418 at the CLI's defaults: the first band-fairing pass stops by small gains
    // (its Levenberg–Marquardt multiplier and extrema-guard rows had made the steps tiny), so
    // fairfit ended at F 0.483 x scipy splprep's 9.955e5 (docs/benchmarks.md, 14 control points
    // against fairfit's 13). A fresh pass after the polish (band_fairing::refair) goes on:
    // measured F 0.441 x splprep's, still one curvature extremum (splprep: 1), 13 control points.
    let pts = read_csv("naca633418.csv");
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    let on = fit_integrated(&pts, &opts).unwrap();
    let f = curve_fairness(&on.curve).fairness;
    let extrema = dense_extrema(&on.curve);
    let dev = refined_deviation(&on.curve, &pts);
    let splprep_f = 9.955e5;
    eprintln!(
        "naca633418: {} ctrl pts, F {f:.4e} ({:.3} x splprep), {extrema} extrema, dev/tol {:.5}",
        on.curve.n_control_points(),
        f / splprep_f,
        dev / on.tolerance
    );
    assert!(on.curve.n_control_points() <= 13);
    assert!(f <= 0.45 * splprep_f, "{f}");
    assert!(extrema <= 1, "{extrema}");
    assert!(on.met);
    assert!(dev <= on.tolerance * (1.0 + 1e-9), "{dev}");
}
