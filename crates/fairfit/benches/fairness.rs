//! Fairness evaluation speed: `FairnessEvaluator::evaluate` (F and max F_j) on cubic curves with 50
//! control points, planar and spatial, as the optimiser calls it. Run with `cargo bench -p fairfit --bench fairness`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fairfit::fair::{curve_fairness, FairnessEvaluator};
use fairfit::nurbs::knots::uniform_clamped;
use fairfit::nurbs::{NurbsCurve, Vec3};

fn curve(planar: bool) -> NurbsCurve {
    let n = 50;
    let pts = (0..n)
        .map(|i| {
            let t = i as f64 * 0.25;
            let z = if planar { 0.0 } else { 0.3 * (0.7 * t).cos() };
            Vec3::new(t, t.sin() + 0.05 * ((i * 7) % 3) as f64, z)
        })
        .collect();
    NurbsCurve::bspline(3, uniform_clamped(3, n), pts).unwrap()
}

fn bench(c: &mut Criterion) {
    for planar in [true, false] {
        let cv = curve(planar);
        let name = if planar { "planar" } else { "spatial" };
        let mut ev = FairnessEvaluator::new();
        c.bench_function(&format!("evaluate_{name}_cubic_50"), |b| {
            b.iter(|| ev.evaluate(black_box(&cv)))
        });
        let mut out = Vec::new();
        c.bench_function(&format!("span_fairness_into_{name}_cubic_50"), |b| {
            b.iter(|| ev.span_fairness_into(black_box(&cv), &mut out))
        });
        c.bench_function(&format!("curve_fairness_{name}_cubic_50"), |b| {
            b.iter(|| curve_fairness(black_box(&cv)))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
