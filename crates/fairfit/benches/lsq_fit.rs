//! Speed of the least-squares baseline (`fairfit curve --method lsq --rel-tol 1e-3`, issue 3): the
//! whole tolerance-driven fit through the public API, one benchmark per 200-point curve of
//! `examples/data` (copies of shared/data files, see its PROVENANCE.md), single-threaded.
//! Run with `cargo bench -p fairfit --bench lsq_fit`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fairfit::fit::{fit_to_tolerance, FitOptions};
use std::time::Duration;

mod curves;

fn bench(c: &mut Criterion) {
    let opts = FitOptions::default(); // relative tolerance 1e-3, the CLI's lsq defaults
    let mut g = c.benchmark_group("lsq_fit_rel_tol_1e-3");
    g.sample_size(30)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for (short, pts) in curves::curves_200() {
        g.bench_function(short, |b| {
            b.iter(|| fit_to_tolerance(black_box(&pts), &opts).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
