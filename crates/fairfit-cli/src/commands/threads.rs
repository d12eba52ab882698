//! Worker-thread counts: what `--threads` and `RAYON_NUM_THREADS` ask for, clamped to something sane.
//!
//! More workers than four per available core only cost memory and scheduling (results never depend
//! on the count), and a count from the environment such as `RAYON_NUM_THREADS=100000` would otherwise
//! spend minutes starting threads. So every pool, the global one included, is built explicitly with
//! a count of at most [`max_threads`].

/// The largest useful pool: four workers per core the system reports (at least four).
pub fn max_threads() -> usize {
    4 * std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The workers for a `--threads` value: `requested` capped at [`max_threads`]; 0 means
/// `RAYON_NUM_THREADS` when it is set to a positive count (capped the same way), else one per core.
pub fn pool_threads(requested: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let wanted = match requested {
        0 => std::env::var("RAYON_NUM_THREADS")
            .ok()
            .and_then(|v| v.trim().parse::<usize>().ok())
            .filter(|&n| n > 0)
            .unwrap_or(cores),
        n => n,
    };
    wanted.min(max_threads())
}

/// Builds rayon's global pool with [`pool_threads`]`(0)` workers, so that no code path starts the
/// unclamped count rayon would read from the environment.
pub fn build_global_pool() -> Result<(), String> {
    let threads = pool_threads(0);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .map_err(|e| format!("cannot start {threads} worker threads: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_capped_at_four_per_core() {
        let cap = max_threads();
        assert!(cap >= 4);
        assert_eq!(pool_threads(1_000_000), cap);
        assert_eq!(pool_threads(2), 2.min(cap));
        assert!((1..=cap).contains(&pool_threads(0)));
    }
}
