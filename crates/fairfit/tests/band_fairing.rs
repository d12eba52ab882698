//! Band fairing in the integrated method (`IntegratedOptions::band_fairing`): on the quarter ellipse
//! and two airfoils, at the least-squares method's control-point count, the faired curve is at
//! least as fair as without the stage (F by the fairness module, independent of the stage's own
//! Gauss rule), and every data point lies within the tolerance by brute force.

use fairfit::fair::curve_fairness;
use fairfit::optim::integrated::{fit_integrated, IntegratedOptions, Tolerance};
use fairfit::{NurbsCurve, Vec3};

/// Reads an `x,y[,z]` CSV with `#` comments and a header line (test helper, not the library reader).
fn read_csv(name: &str) -> Vec<Vec3> {
    let path = format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|s| s.trim().parse().ok()).collect();
            (v.len() >= 2).then(|| Vec3([v[0], v[1], v.get(2).copied().unwrap_or(0.0)]))
        })
        .collect()
}

/// Largest distance from the points to the curve: the nearest of 200 001 uniform curve samples,
/// refined by a golden-section search between its neighbours.
fn brute_force_deviation(curve: &NurbsCurve, points: &[Vec3]) -> f64 {
    let n = 200_000;
    let us: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    let samples: Vec<Vec3> = us.iter().map(|&u| curve.point(u)).collect();
    let mut worst = 0.0f64;
    for q in points {
        let (mut best, mut bi) = (f64::INFINITY, 0);
        for (i, s) in samples.iter().enumerate() {
            let d = (*s - *q).norm_squared();
            if d < best {
                (best, bi) = (d, i);
            }
        }
        let (mut a, mut b) = (us[bi.saturating_sub(1)], us[(bi + 1).min(n)]);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if (curve.point(c) - *q).norm() < (curve.point(d) - *q).norm() {
                b = d;
            } else {
                a = c;
            }
        }
        let refined = (curve.point(0.5 * (a + b)) - *q).norm();
        worst = worst.max(refined.min(best.sqrt()));
    }
    worst
}

#[test]
fn band_fairing_lowers_fairness_within_the_tolerance() {
    use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
    for name in ["quarter_ellipse_200.csv", "naca4412.csv", "e387.csv"] {
        let pts = read_csv(name);
        let n = fit_to_tolerance(&pts, &FitOptions::default())
            .unwrap()
            .n_control_points;
        let opts = |band: bool| IntegratedOptions {
            tolerance: Tolerance::Relative(1e-3),
            seed: 42,
            control_points: Some(n),
            band_fairing: band,
            ..IntegratedOptions::default()
        };
        let off = fit_integrated(&pts, &opts(false)).unwrap();
        let on = fit_integrated(&pts, &opts(true)).unwrap();
        let (f_off, f_on) = (
            curve_fairness(&off.curve).fairness,
            curve_fairness(&on.curve).fairness,
        );
        let dev = brute_force_deviation(&on.curve, &pts);
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
