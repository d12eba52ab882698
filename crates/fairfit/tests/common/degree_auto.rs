//! The integrated method as `fairfit curve` runs it by default, shared by the degree-search test
//! crates: `--rel-tol 1e-3` with the degree search up to 5 (`--degree auto`), and a fit on a pool
//! of a given thread count.
//!
//! Included by path (`#[path = "common/degree_auto.rs"] mod degree_auto;`), like `sampled.rs`.
#![allow(dead_code)] // not every test crate runs fits on its own pool

use fairfit::optim::integrated::{fit_integrated, IntegratedOptions, IntegratedResult, Tolerance};
use fairfit::Vec3;

/// The CLI's default integrated options: relative tolerance 1e-3, degrees 3 to 5.
pub fn auto() -> IntegratedOptions {
    IntegratedOptions {
        tolerance: Tolerance::Relative(1e-3),
        max_degree: Some(5),
        ..IntegratedOptions::default()
    }
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
