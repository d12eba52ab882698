//! `fairfit._fairfit`: the Python extension module of fairfit (PyO3 + rust-numpy), wrapped by the pure
//! Python package `fairfit` (`python/fairfit`), which normalises inputs and carries the docstrings.
//!
//! What holds across the module:
//! - every fit and every batch evaluation runs with the GIL released (`guarded`), in a local rayon
//!   pool of the asked number of threads (`with_pool`, the CLI's `--threads`: results do not depend
//!   on it);
//! - an error of the library becomes `fairfit.FairfitError` (a `ValueError`) whose message is the
//!   CLI's one-line message (without `error: `), and a Rust panic becomes the same exception with the
//!   CLI's `internal error (...)` line: nothing unwinds into Python;
//! - the options of `fit_curve` and `fit_chain` map to the library in one place (the `options`
//!   module), exactly as the CLI's `fairfit curve` (and `--chain`) maps its flags, so the same points
//!   and seed give byte-identical curve JSON.

use pyo3::prelude::*;

mod constrained;
mod convert;
mod curve;
mod fit_chain;
mod fit_curve;
mod options;
mod output;
mod surface;

pyo3::create_exception!(
    fairfit,
    FairfitError,
    pyo3::exceptions::PyValueError,
    "An error of fairfit: invalid input or options, or a failed read or write. The message is the \
     one-line message the `fairfit` command-line tool prints (without its `error: ` prefix)."
);

/// A fairfit error (or an internal error's message) as the Python exception.
pub(crate) fn py_err(message: impl Into<String>) -> PyErr {
    FairfitError::new_err(message.into())
}

/// The library's error as the Python exception, with the CLI's message.
pub(crate) fn lib_err(e: fairfit::Error) -> PyErr {
    py_err(e.to_string())
}

/// Runs `f` without the GIL and with panics caught: a panic becomes the CLI's `internal error` line.
pub(crate) fn guarded<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, String> + Send,
) -> PyResult<T> {
    let r = py.allow_threads(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
    match r {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(message)) => Err(py_err(message)),
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(py_err(format!(
                "internal error ({msg}); please report it with the input that caused it"
            )))
        }
    }
}

/// Runs `f` inside a rayon pool of `threads` workers (`None` or 0: `RAYON_NUM_THREADS` when set, else
/// one per core), capped at four per core like the CLI's `--threads` (more only cost memory and
/// scheduling; an environment asking for 100000 must not start them).
pub(crate) fn with_pool<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<T, String> + Send,
) -> Result<T, String> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let from_env = || {
        std::env::var("RAYON_NUM_THREADS")
            .ok()
            .and_then(|v| v.trim().parse::<usize>().ok())
            .filter(|&n| n > 0)
    };
    let threads = match threads.unwrap_or(0) {
        0 => from_env().unwrap_or(cores),
        n => n,
    }
    .min(4 * cores);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("cannot start {threads} worker threads: {e}"))?;
    pool.install(f)
}

/// The extension module.
#[pymodule]
fn _fairfit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("FairfitError", m.py().get_type::<FairfitError>())?;
    m.add_class::<curve::Curve>()?;
    m.add_class::<surface::Surface>()?;
    m.add_function(wrap_pyfunction!(fit_curve::fit_curve, m)?)?;
    m.add_function(wrap_pyfunction!(fit_chain::fit_chain, m)?)?;
    m.add_function(wrap_pyfunction!(surface::fit_surface, m)?)?;
    m.add_function(wrap_pyfunction!(surface::fit_surface_from_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(output::read, m)?)?;
    m.add_function(wrap_pyfunction!(output::read_points, m)?)?;
    m.add_function(wrap_pyfunction!(curve::curve_from_state, m)?)?;
    m.add_function(wrap_pyfunction!(surface::surface_from_state, m)?)?;
    m.add_function(wrap_pyfunction!(panic_for_tests, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

/// Panics inside `guarded`: the tests' check that a panic reaches Python as `FairfitError`.
#[pyfunction]
#[pyo3(name = "_panic_for_tests")]
fn panic_for_tests(py: Python<'_>) -> PyResult<()> {
    guarded(py, || -> Result<(), String> { panic!("a test panic") })
}
