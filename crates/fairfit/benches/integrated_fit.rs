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
use fairfit::optim::integrated::{fit_integrated, IntegratedOptions};
use std::time::Duration;

/// The 200-point curves of the shared data, copied into examples/data.
const CURVES: [&str; 8] = [
    "quarter_ellipse_200.csv",
    "quarter_ellipse_200_noise1e-4.csv",
    "du06-w-200-selig.csv",
    "iea15mw_airfoils/FFA-W3-211.csv",
    "iea15mw_airfoils/FFA-W3-241.csv",
    "iea15mw_airfoils/FFA-W3-301.csv",
    "iea15mw_airfoils/FFA-W3-360.csv",
    "iea15mw_airfoils/SNL-FFA-W3-500.csv",
];

fn bench(c: &mut Criterion) {
    let dir = format!("{}/../../examples/data", env!("CARGO_MANIFEST_DIR"));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let full = IntegratedOptions::default(); // relative tolerance 1e-3, the CLI's defaults
    let variants = [
        ("integrated", full.clone()),
        (
            "integrated_no_band",
            IntegratedOptions {
                band_fairing: false,
                ..full.clone()
            },
        ),
        (
            "integrated_no_band_no_polish",
            IntegratedOptions {
                band_fairing: false,
                polish: false,
                ..full.clone()
            },
        ),
    ];
    for (group, opts) in variants {
        let mut g = c.benchmark_group(group);
        g.sampling_mode(SamplingMode::Flat)
            .sample_size(10)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_secs(2));
        for name in CURVES {
            let pts = fairfit::io::read_points(format!("{dir}/{name}"))
                .expect("readable example data")
                .points;
            assert_eq!(pts.len(), 200, "{name}");
            let short = name.rsplit('/').next().unwrap_or(name);
            let short = short.trim_end_matches(".csv");
            g.bench_function(short, |b| {
                b.iter(|| pool.install(|| fit_integrated(black_box(&pts), &opts).expect("a fit")))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
