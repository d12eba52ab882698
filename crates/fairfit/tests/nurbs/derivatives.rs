//! Curve derivatives up to order 3 and surface partials up to order 2 against fourth-order central
//! finite differences, on random rational curves and surfaces (parameters kept away from knots).

use crate::common;
use common::*;
use fairfit::nurbs::Vec3;
use rand::Rng;

/// A step of 1e-3 times the width of the knot span holding `u`, if `u` lies at least 0.1 span widths
/// from its ends (so the stencil `u ± 2h` stays inside one polynomial piece).
fn local_step(knots: &[f64], u: f64) -> Option<f64> {
    let i = knots.partition_point(|&k| k <= u);
    if i == 0 || i >= knots.len() {
        return None;
    }
    let (lo, hi) = (knots[i - 1], knots[i]);
    let w = hi - lo;
    (u - lo > 0.1 * w && hi - u > 0.1 * w).then_some(1e-3 * w)
}

/// Fourth-order central difference of `f` at `x`.
fn fd4(f: impl Fn(f64) -> Vec3, x: f64, h: f64) -> Vec3 {
    ((f(x + h) - f(x - h)) * 8.0 - (f(x + 2.0 * h) - f(x - 2.0 * h))) / (12.0 * h)
}

#[test]
fn curve_derivatives_match_finite_differences() {
    let mut r = rng(11);
    let mut checked = 0;
    for case in 0..80 {
        let p = 1 + case % 6;
        let c = random_curve(&mut r, p, p + 2 + case % 6, case % 2 == 0, 1);
        let (a, b) = c.domain();
        for _ in 0..10 {
            let u = r.random_range(a..b);
            let Some(h) = local_step(c.knots(), u) else {
                continue;
            };
            let d = c.derivatives(u, 3);
            for k in 0..3 {
                let fd = fd4(|x| c.derivatives(x, 3)[k], u, h);
                let size = d[k + 1].norm() + d[k].norm() / (1e3 * h);
                let err = (fd - d[k + 1]).norm();
                assert!(
                    err < 1e-6 * size.max(1e-3),
                    "case {case} p={p} k={k} u={u}: {err} vs {size}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 300, "only {checked} parameters checked");
}

#[test]
fn surface_partials_match_finite_differences() {
    let mut r = rng(12);
    let mut checked = 0;
    for case in 0..40 {
        let (p, q) = (1 + case % 4, 1 + (case / 4) % 4);
        let s = random_surface(&mut r, p, q, p + 2 + case % 3, q + 3, case % 2 == 0);
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        for _ in 0..8 {
            let u = r.random_range(u0..u1);
            let v = r.random_range(v0..v1);
            let (Some(hu), Some(hv)) = (local_step(s.knots_u(), u), local_step(s.knots_v(), v))
            else {
                continue;
            };
            let d = s.derivatives(u, v, 2);
            let at = |x: f64, y: f64, i: usize| s.derivatives(x, y, 2)[i];
            // (computed index, finite difference of which entry, along u?)
            let checks = [
                (3, 0, true),
                (1, 0, false),
                (6, 3, true),
                (4, 1, true),
                (2, 1, false),
                (4, 3, false),
            ];
            for (idx, from, along_u) in checks {
                let fd = if along_u {
                    fd4(|x| at(x, v, from), u, hu)
                } else {
                    fd4(|y| at(u, y, from), v, hv)
                };
                let size = d[idx].norm() + d[from].norm() / (1e3 * hu.min(hv));
                let err = (fd - d[idx]).norm();
                assert!(
                    err < 1e-6 * size.max(1e-3),
                    "case {case} idx {idx}: {err} vs {size}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 150, "only {checked} parameters checked");
}

#[test]
fn batch_single_and_high_degree_paths_agree() {
    // degree 3 elevated to 10 (heap buffers) must have the same derivatives as the original
    let mut r = rng(13);
    for case in 0..10 {
        let c = random_curve(&mut r, 3, 8, true, 1);
        let e = c.elevate_degree(7).unwrap();
        let (a, b) = c.domain();
        let us: Vec<f64> = (0..200).map(|_| r.random_range(a..b)).collect();
        let mut batch = vec![Vec3::ZERO; 4 * us.len()];
        c.derivatives_batch_into(&us, 3, &mut batch);
        let mut batch_e = vec![Vec3::ZERO; 4 * us.len()];
        e.derivatives_batch_into(&us, 3, &mut batch_e);
        for (i, &u) in us.iter().enumerate() {
            let single = c.derivatives(u, 3);
            let single_e = e.derivatives(u, 3);
            for k in 0..=3 {
                assert_eq!(
                    single[k],
                    batch[4 * i + k],
                    "case {case}: batch and single differ"
                );
                assert_eq!(single_e[k], batch_e[4 * i + k]);
                if local_step(c.knots(), u).is_some() {
                    let size = single[k].norm().max(1.0);
                    assert!(
                        (single[k] - single_e[k]).norm() < 1e-9 * size,
                        "case {case} k={k} u={u}"
                    );
                }
            }
        }
    }
}
