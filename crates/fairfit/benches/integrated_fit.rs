//! Speed of the integrated method (`fairfit curve --rel-tol 1e-3 --threads 1`, issue 4's target of
//! at most 0.2 s for a 200-point curve): the whole fit through the public API on every 200-point
//! curve of `examples/data` (copies of shared/data files, see its PROVENANCE.md), in a one-thread
//! rayon pool as the CLI's `--threads 1`.
//!
//! Three groups give a cheap phase breakdown by difference: `integrated` (the CLI's defaults),
//! `integrated_no_band` (without band fairing) and `integrated_no_band_no_polish` (knot search only).
//! Run with `cargo bench -p fairfit --bench integrated_fit` (add a group name or curve name as a
//! filter, e.g. `-- integrated/SNL`).

use criterion::{black_box, criterion_group, criterion_main, Criterion, SamplingMode};
use fairfit::optim::{fit_integrated, IntegratedOptions};
use std::time::Duration;

mod curves;

fn bench(c: &mut Criterion) {
    let curves = curves::curves_200();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let full = IntegratedOptions::default(); // relative tolerance 1e-3, the CLI's defaults
    let variants = [
        ("integrated", full.clone()),
        ("integrated_no_band", full.clone().band_fairing(false)),
        (
            "integrated_no_band_no_polish",
            full.clone().band_fairing(false).polish(false),
        ),
    ];
    for (group, opts) in variants {
        let mut g = c.benchmark_group(group);
        g.sampling_mode(SamplingMode::Flat)
            .sample_size(10)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_secs(2));
        for (short, pts) in &curves {
            g.bench_function(*short, |b| {
                b.iter(|| pool.install(|| fit_integrated(black_box(pts), &opts).expect("a fit")))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
