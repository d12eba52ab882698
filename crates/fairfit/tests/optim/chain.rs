//! Chains of `fairfit::optim::chain`: two arcs of one circle joined G1 and G2 (the join's tangent
//! and curvature against the circle's, in closed form), and the NACA 4412 airfoil split at its
//! leading edge and fitted as a G2 chain (its F against the single-curve fit of the whole airfoil),
//! and three pieces of a helix (the curvature vector `R/(R² + c²)` towards the axis at both joins).

use crate::common::example_data::read_csv;
use fairfit::fit::max_orthogonal_deviation;
use fairfit::optim::chain::{fit_chain, JoinContinuity};
use fairfit::prelude::*;

const R: f64 = 2.0;

/// `n` points on the circle of radius `R` from angle `a0` to `a1`.
fn arc(a0: f64, a1: f64, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let a = a0 + (a1 - a0) * i as f64 / (n - 1) as f64;
            Vec3::new(R * a.cos(), R * a.sin(), 0.0)
        })
        .collect()
}

/// The largest deviation of every piece from its own points, against the tolerance.
fn assert_within(pieces: &[Vec<Vec3>], r: &fairfit::optim::chain::ChainResult) {
    for (pts, fit) in pieces.iter().zip(&r.pieces) {
        let d = max_orthogonal_deviation(&fit.curve, pts, &[]).max;
        assert!(d <= r.tolerance * (1.0 + 1e-9), "{d} > {}", r.tolerance);
    }
}

#[test]
fn two_arcs_of_a_circle_join_with_its_tangent_and_curvature() {
    let join = 1.0_f64;
    let pieces = vec![arc(0.0, join, 40), arc(join, 2.3, 50)];
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-4));
    // the circle's tangent and curvature at the join
    let tangent = Vec3::new(-join.sin(), join.cos(), 0.0);
    for continuity in [JoinContinuity::G1, JoinContinuity::G2] {
        let r = fit_chain(&pieces, continuity, &opts).unwrap();
        eprintln!(
            "{continuity:?}: from the single curve {:?}, joins {:?}",
            r.from_single, r.joins
        );
        assert!(r.met);
        assert_within(&pieces, &r);
        let j = r.joins[0];
        assert!(j.position_gap < 1e-12, "{continuity:?}: {}", j.position_gap);
        assert!(
            j.tangent_angle <= 1e-9,
            "{continuity:?}: {}",
            j.tangent_angle
        );
        // the join lies on the circle, at the shared point, within the tolerance
        assert!((j.point.norm() - R).abs() <= r.tolerance);
        assert!((j.point - pieces[0][39]).norm() <= r.tolerance);
        // each piece's tangent there is the circle's within the tolerance's effect
        let d = r.pieces[0]
            .curve
            .derivatives(r.pieces[0].curve.domain().1, 1);
        let angle = d[1].cross(tangent).norm().atan2(d[1].dot(tangent));
        assert!(angle < 1e-3, "{continuity:?}: {angle}");
        if continuity == JoinContinuity::G2 {
            assert!(j.curvature_relative <= 1e-9, "{}", j.curvature_relative);
            assert!((j.curvature * R - 1.0).abs() < 0.02, "{}", j.curvature * R);
        }
    }
}

/// NACA 4412 split at its leading edge (least x; both pieces hold it): upper surface from the
/// trailing edge to the leading edge, lower surface back.
fn naca_halves() -> (Vec<Vec3>, Vec<Vec<Vec3>>) {
    let all = read_csv("naca4412.csv");
    let le = (0..all.len())
        .min_by(|&a, &b| all[a][0].total_cmp(&all[b][0]))
        .unwrap();
    (all.clone(), vec![all[..=le].to_vec(), all[le..].to_vec()])
}

#[test]
fn an_airfoil_as_a_g2_chain_is_nearly_as_fair_as_one_curve() {
    let (all, pieces) = naca_halves();
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).degree_search(5);
    let r = fit_chain(&pieces, JoinContinuity::G2, &opts).unwrap();
    // the chain's single curve is the whole airfoil's fit (every point once, the same options)
    let single = &r.single;
    assert!(single.met);
    let d = max_orthogonal_deviation(&single.curve, &all, &[]).max;
    assert!(d <= single.tolerance * (1.0 + 1e-9));
    assert!(r.met);
    assert_within(&pieces, &r);
    let j = r.joins[0];
    assert!(
        j.tangent_angle <= 1e-9 && j.curvature_relative <= 1e-9,
        "{j:?}"
    );
    let ratio = r.fairness / r.single_fairness;
    assert!((r.single_fairness / single.quality.fairness - 1.0).abs() < 1e-2);
    eprintln!(
        "airfoil G2 chain: F {:.4} vs single {:.4} (ratio {ratio:.4}), pieces {:?} from the single curve {:?}, join κ {:.3}",
        r.fairness,
        r.single_fairness,
        r.pieces
            .iter()
            .map(|p| (p.curve.degree(), p.curve.n_control_points(), p.quality.fairness))
            .collect::<Vec<_>>(),
        r.from_single,
        j.curvature
    );
    assert!(ratio <= 1.10, "{ratio}");
}

#[test]
fn three_pieces_of_a_helix_join_g2_with_its_curvature_vector() {
    // x = R cos t, y = R sin t, z = c t: curvature R / (R² + c²), towards the axis
    let c = 0.3;
    let helix = |t0: f64, t1: f64, n: usize| -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let t = t0 + (t1 - t0) * i as f64 / (n - 1) as f64;
                Vec3::new(R * t.cos(), R * t.sin(), c * t)
            })
            .collect()
    };
    let pieces = vec![
        helix(0.0, 1.0, 30),
        helix(1.0, 2.0, 30),
        helix(2.0, 3.5, 40),
    ];
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-4));
    let r = fit_chain(&pieces, JoinContinuity::G2, &opts).unwrap();
    assert!(r.met && r.joins.len() == 2);
    assert_within(&pieces, &r);
    let kappa = R / (R * R + c * c);
    for (k, j) in r.joins.iter().enumerate() {
        assert!(
            j.position_gap < 1e-12 && j.tangent_angle <= 1e-9,
            "{k}: {j:?}"
        );
        assert!(j.curvature_relative <= 1e-9, "{k}: {j:?}");
        assert!(
            (j.curvature / kappa - 1.0).abs() < 0.02,
            "{k}: {}",
            j.curvature
        );
        // the curvature vector points at the axis: horizontal, opposite the join's radius
        let d = r.pieces[k]
            .curve
            .derivatives(r.pieces[k].curve.domain().1, 2);
        let kv = d[1].cross(d[2]).cross(d[1]) / d[1].norm().powi(4);
        let radial = Vec3::new(j.point[0], j.point[1], 0.0);
        assert!(
            kv.dot(radial) / (kv.norm() * radial.norm()) < -0.999,
            "{k}: {kv:?}"
        );
    }
    // the chain's F is the joined chain's: L³ times the pieces' energies summed
    let (length, fairness) =
        fairfit::optim::chain::chain_fairness(r.pieces.iter().map(|p| &p.curve));
    assert_eq!((length, fairness), (r.length, r.fairness));
}
