//! Evaluation speed of a cubic 3D curve with 50 control points: point-only and point plus three
//! derivatives, fairfit against `curvo` in the same run (results in docs/benchmarks-evaluation.md).
//!
//! Run: `cargo bench -p fairfit --bench evaluation`.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use curvo::prelude::NurbsCurve3D;
use fairfit::nurbs::{knots::uniform_clamped, NurbsCurve, Vec3};
use nalgebra::Point4;
use std::time::Duration;

const N_CTRL: usize = 50;
const N_PARAMS: usize = 10_000;

/// A cubic 3D curve with 50 control points (a wobbly helix) and uniform clamped knots; `rational`
/// gives it weights between 0.75 and 1.25 (five levels, 1 + 0.125·((7i mod 5) − 2)).
fn curve(rational: bool) -> NurbsCurve {
    let pts: Vec<Vec3> = (0..N_CTRL)
        .map(|i| {
            let t = i as f64 * 0.4;
            Vec3::new(t.cos() * (1.0 + 0.1 * t), t.sin(), 0.05 * t * t)
        })
        .collect();
    let w = (0..N_CTRL)
        .map(|i| {
            if rational {
                1.0 + 0.5 * ((i * 7) % 5) as f64 / 4.0 - 0.25
            } else {
                1.0
            }
        })
        .collect();
    NurbsCurve::new(3, uniform_clamped(3, N_CTRL), pts, Some(w)).unwrap()
}

fn to_curvo(c: &NurbsCurve) -> NurbsCurve3D<f64> {
    let pts = c
        .homogeneous_points()
        .iter()
        .map(|q| Point4::new(q[0], q[1], q[2], q[3]))
        .collect();
    NurbsCurve3D::try_new(c.degree(), pts, c.knots().to_vec()).unwrap()
}

/// Parameters spread over the domain by a fixed low-discrepancy sequence (not sorted).
fn params() -> Vec<f64> {
    (0..N_PARAMS)
        .map(|i| (i as f64 * 0.618_033_988_749_895).fract())
        .collect()
}

fn bench(c: &mut Criterion) {
    let us = params();
    for rational in [false, true] {
        let kind = if rational { "rational" } else { "polynomial" };
        let f = curve(rational);
        let cv = to_curvo(&f);
        let mut out = vec![Vec3::ZERO; N_PARAMS];
        let mut dout = vec![Vec3::ZERO; 4 * N_PARAMS];

        let mut g = c.benchmark_group(format!("point/{kind}"));
        g.throughput(Throughput::Elements(N_PARAMS as u64));
        g.bench_function(BenchmarkId::new("fairfit", N_CTRL), |b| {
            b.iter(|| {
                f.points_into(black_box(&us), &mut out);
                black_box(&out);
            })
        });
        g.bench_function(BenchmarkId::new("curvo", N_CTRL), |b| {
            b.iter(|| {
                for &u in black_box(&us) {
                    black_box(cv.point_at(u));
                }
            })
        });
        g.finish();

        let mut g = c.benchmark_group(format!("point+3ders/{kind}"));
        g.throughput(Throughput::Elements(N_PARAMS as u64));
        g.bench_function(BenchmarkId::new("fairfit", N_CTRL), |b| {
            b.iter(|| {
                f.derivatives_batch_into(black_box(&us), 3, &mut dout);
                black_box(&dout);
            })
        });
        g.bench_function(BenchmarkId::new("curvo", N_CTRL), |b| {
            b.iter(|| {
                for &u in black_box(&us) {
                    black_box(cv.rational_derivatives(u, 3));
                }
            })
        });
        g.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20);
    targets = bench
}
criterion_main!(benches);
