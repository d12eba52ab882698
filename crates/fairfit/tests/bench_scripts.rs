//! The benchmark's own Python tests (`bench/test_*.py`), run with `$FAIRFIT_PYTHON` so that CI checks the
//! independent measurer (against analytic curves and quadrature) and the target bookkeeping that writes
//! `docs/benchmarks.md`. They need numpy and scipy only, not fairfit's binary. Unset: skipped with a note
//! (except under `CI=true`, where it fails).

use crate::common::python;

use std::path::Path;

fn run_bench_test(script: &str) {
    let Some(python) = python::python_or_skip(&format!("bench/{script}")) else {
        return;
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../bench")
        .join(script);
    let out = std::process::Command::new(&python)
        .arg(&path)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "bench/{script} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Each script prints "ok <test>" per test it ran: a script that ran nothing is a failure too.
    let passed = stdout.lines().filter(|l| l.starts_with("ok test_")).count();
    assert!(
        passed >= 3,
        "bench/{script} ran only {passed} tests:\n{stdout}"
    );
}

#[test]
fn measurer_tests_pass() {
    run_bench_test("test_measure.py");
}

#[test]
fn benchmark_bookkeeping_tests_pass() {
    run_bench_test("test_compare.py");
}

#[test]
fn band_optimum_study_tests_pass() {
    run_bench_test("test_band_optimum.py");
}

#[test]
fn band_lower_bound_tests_pass() {
    run_bench_test("test_band_lower_bound.py");
}

#[test]
fn dense_benchmark_bookkeeping_tests_pass() {
    run_bench_test("test_dense.py");
}

#[test]
fn constraints_benchmark_bookkeeping_tests_pass() {
    run_bench_test("test_constraints.py");
}
