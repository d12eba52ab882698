//! The Python package's tests (`tests/python/test_*.py`, pytest), run with `$FAIRFIT_PYTHON` (the venv
//! `.ci/run` fills from `tests/python/requirements.txt`: numpy, scipy, pytest, ray).
//!
//! The package is staged from this build, not installed: the extension module cargo just built
//! (`libfairfit_py.so` in `deps/` beside this test binary; `cargo test` does not copy it up to
//! `target/<profile>`, where an older `cargo build` may have left one) is copied as `fairfit/_fairfit.abi3.so` next
//! to the package's Python sources in a temporary folder put on `PYTHONPATH`, so the suite costs no
//! second build. The tests compare against the CLI binary of the same build (`fairfit` in the same
//! folder, built by `cargo test --workspace`). Unset `$FAIRFIT_PYTHON`: skipped with a note (except
//! under `CI=true`, where it fails).

use std::path::{Path, PathBuf};
use std::process::Command;

use fairfit_testkit::python_or_skip;

/// The folder of this test binary and the libraries built with it (`target/<profile>/deps`).
fn deps_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent()
        .expect("target/<profile>/deps/<test>")
        .to_path_buf()
}

/// Copies the package's Python sources and the built extension into `dir/fairfit`.
fn stage_package(dir: &Path, extension: &Path) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/fairfit");
    let dst = dir.join("fairfit");
    std::fs::create_dir_all(&dst).unwrap();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, dst.join(path.file_name().unwrap())).unwrap();
        }
    }
    std::fs::copy(extension, dst.join("_fairfit.abi3.so")).unwrap();
}

#[test]
fn python_package_tests_pass() {
    let Some(python) =
        python_or_skip("the Python package's tests (crates/fairfit-py/tests/python)")
    else {
        return;
    };
    let deps = deps_dir();
    let extension = deps.join("libfairfit_py.so");
    let cli = deps.parent().expect("target/<profile>").join("fairfit");
    for (what, path) in [("extension module", &extension), ("CLI binary", &cli)] {
        assert!(
            path.is_file(),
            "the {what} {} is missing: run the workspace's tests (cargo test --workspace --release)",
            path.display()
        );
    }
    let staged = tempfile::tempdir().unwrap();
    stage_package(staged.path(), &extension);
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider", "-rs"])
        .arg(manifest.join("tests/python"))
        .env("PYTHONPATH", staged.path())
        .env("FAIRFIT_BIN", &cli)
        .env("FAIRFIT_EXAMPLES", manifest.join("../../examples/data"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "the Python package's tests failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // the closing line counts what ran: a suite that ran nothing is a failure too
    let passed = stdout
        .lines()
        .rev()
        .find_map(|l| {
            l.split(" passed")
                .next()
                .filter(|_| l.contains(" passed"))
                .and_then(|s| s.trim().parse::<usize>().ok())
        })
        .unwrap_or(0);
    assert!(passed >= 10, "only {passed} Python tests passed:\n{stdout}");
}
