//! Batched curve evaluation allocates nothing per point: `points_into` and `derivatives_into` (degree
//! below 8) allocate nothing at all, and `derivatives_batch_into` allocates the same few buffers for 10
//! parameters as for 10 000 (counted by a global allocator wrapper, per thread).

use crate::common::alloc_counter::allocations;
use fairfit::nurbs::knots::uniform_clamped;
use fairfit::nurbs::{NurbsCurve, Vec3};

#[test]
fn batched_evaluation_allocates_nothing_per_point() {
    let pts: Vec<Vec3> = (0..50)
        .map(|i| Vec3::new(i as f64, (i as f64).sin(), 0.1 * i as f64))
        .collect();
    let w: Vec<f64> = (0..50).map(|i| 1.0 + 0.01 * i as f64).collect();
    let c = NurbsCurve::new(3, uniform_clamped(3, 50), pts, Some(w)).unwrap();
    let small: Vec<f64> = (0..10).map(|i| i as f64 / 9.0).collect();
    let large: Vec<f64> = (0..10_000).map(|i| i as f64 / 9999.0).collect();
    let mut out_s = vec![Vec3::ZERO; small.len()];
    let mut out_l = vec![Vec3::ZERO; large.len()];
    assert_eq!(allocations(|| c.points_into(&large, &mut out_l)), 0);
    assert_eq!(allocations(|| c.points_into(&small, &mut out_s)), 0);
    let mut d = [Vec3::ZERO; 4];
    assert_eq!(allocations(|| c.derivatives_into(0.37, 3, &mut d)), 0);
    let mut ds = vec![Vec3::ZERO; 4 * small.len()];
    let mut dl = vec![Vec3::ZERO; 4 * large.len()];
    let a_small = allocations(|| c.derivatives_batch_into(&small, 3, &mut ds));
    let a_large = allocations(|| c.derivatives_batch_into(&large, 3, &mut dl));
    assert_eq!(a_small, a_large);
    assert!(a_large <= 8, "{a_large}");
    // and the results are real: the end point of a clamped curve is its last control point
    assert!((dl[4 * 9999] - c.control_points()[49]).norm() < 1e-12);
}
