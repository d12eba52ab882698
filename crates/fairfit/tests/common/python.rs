//! The Python used by tests that run scripts of the repository (`$FAIRFIT_PYTHON`).

/// `$FAIRFIT_PYTHON`, or `None` (with a note) when it is unset outside CI, so that a plain `cargo test`
/// on a machine without the Python peers still passes. Under `CI=true` an unset variable fails the test:
/// CI must run what needs Python. Set but empty also fails.
pub fn python_or_skip(what: &str) -> Option<String> {
    match std::env::var("FAIRFIT_PYTHON") {
        Ok(p) => {
            assert!(!p.trim().is_empty(), "FAIRFIT_PYTHON is set but empty");
            Some(p)
        }
        Err(_) => {
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!("FAIRFIT_PYTHON is not set under CI=true: {what} must run in CI");
            }
            println!("note: FAIRFIT_PYTHON unset, skipping {what}");
            None
        }
    }
}
