//! The integrated method as `fairfit curve` runs it by default, shared by the degree-search test
//! files: `--rel-tol 1e-3` with the degree search up to 5 (`--degree auto`), and a fit on a pool
//! of a given thread count.
#![allow(dead_code)] // not every test file runs fits on its own pool

use fairfit::optim::{fit_integrated, IntegratedOptions, IntegratedResult, Tolerance};
use fairfit::Vec3;

/// The CLI's default integrated options: relative tolerance 1e-3, degrees 3 to 5.
pub fn auto() -> IntegratedOptions {
    IntegratedOptions::new(Tolerance::Relative(1e-3)).degree_search(5)
}

/// `fit_integrated` on a rayon pool of `threads` threads.
pub fn fit_with_threads(
    pts: &[Vec3],
    opts: &IntegratedOptions,
    threads: usize,
) -> IntegratedResult {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| fit_integrated(pts, opts).unwrap())
}

/// The default fit of `pts` ([`auto`]) with one and with two threads: asserts byte-identical JSON,
/// the same evaluation count and the same degrees tried, and returns the one-thread result.
pub fn assert_same_with_one_and_two_threads(pts: &[Vec3]) -> IntegratedResult {
    let (a, b) = (
        fit_with_threads(pts, &auto(), 1),
        fit_with_threads(pts, &auto(), 2),
    );
    assert_eq!(
        fairfit::io::json::curve_to_json(&a.curve),
        fairfit::io::json::curve_to_json(&b.curve)
    );
    assert_eq!(a.stats.evaluations, b.stats.evaluations);
    assert_eq!(a.stats.degrees_tried, b.stats.degrees_tried);
    a
}
