//! The default `refine` knot rule also tries the curvature-adaptive rule below its count and keeps the
//! fewer control points (naca4412 at rel-tol 1e-3: refine alone 17, adaptive 14), without breaking
//! reversal mirroring.

use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions, KnotRule};
use fairfit::nurbs::Vec3;

fn read(name: &str) -> Vec<Vec3> {
    let p = format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    fairfit::io::read_points(p).unwrap().points
}

#[test]
fn default_keeps_the_fewer_control_points_of_refine_and_adaptive() {
    for name in ["naca4412.csv", "e387.csv", "fx77w343.csv"] {
        let q = read(name);
        let count = |opts: FitOptions| fit_to_tolerance(&q, &opts).unwrap().n_control_points;
        let refine_only = count(FitOptions {
            try_adaptive: false,
            ..Default::default()
        });
        let adaptive = count(FitOptions {
            knot_rule: KnotRule::Adaptive,
            ..Default::default()
        });
        let r = fit_to_tolerance(&q, &FitOptions::default()).unwrap();
        assert_eq!(r.n_control_points, refine_only.min(adaptive), "{name}");
        assert!(r.deviation.max <= r.tolerance, "{name}");
        if name == "naca4412.csv" {
            assert_eq!((refine_only, adaptive), (17, 14));
        }
        // reversed data give the mirrored curve
        let rev: Vec<Vec3> = q.iter().rev().copied().collect();
        let b = fit_to_tolerance(&rev, &FitOptions::default()).unwrap();
        let (pa, pb) = (r.curve.control_points(), b.curve.control_points());
        assert_eq!(pa.len(), pb.len(), "{name}");
        for (x, y) in pa.iter().zip(pb.iter().rev()) {
            assert!((*x - *y).norm() < 1e-9, "{name}: {x:?} vs {y:?}");
        }
    }
}
