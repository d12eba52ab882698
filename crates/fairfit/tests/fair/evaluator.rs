//! The optimiser's fairness evaluator allocates nothing after its first call (counted by a global
//! allocator wrapper, per thread).

use crate::common::alloc_counter::allocs;
use fairfit::fair::FairnessEvaluator;
use fairfit::nurbs::knots::uniform_clamped;
use fairfit::nurbs::{NurbsCurve, Vec3};

#[test]
fn evaluate_and_span_fairness_do_not_allocate_after_warm_up() {
    let curves: Vec<NurbsCurve> = (0..4)
        .map(|k| {
            let n = 12 + k;
            let pts = (0..n)
                .map(|i| {
                    let t = i as f64 * 0.6;
                    Vec3::new(
                        t,
                        (t + k as f64).sin(),
                        if k % 2 == 0 { 0.0 } else { 0.2 * t.cos() },
                    )
                })
                .collect();
            NurbsCurve::bspline(3, uniform_clamped(3, n), pts).unwrap()
        })
        .collect();
    let mut ev = FairnessEvaluator::new();
    let mut out = Vec::new();
    // warm up on the largest curve so the buffers reach their final size
    for c in &curves {
        ev.evaluate(c);
        ev.span_fairness_into(c, &mut out);
    }
    let before = allocs();
    let mut total = 0.0;
    for _ in 0..3 {
        for c in &curves {
            total += ev.evaluate(c).0;
            total += ev.span_fairness_into(c, &mut out);
        }
    }
    assert_eq!(allocs(), before, "allocations in the hot path");
    assert!(total > 0.0);
}
