//! The Python used by tests that run scripts of the repository (`$FAIRFIT_PYTHON`), and the points
//! those scripts print as JSON. One file for both crates: the command-line tool's tests include it
//! (`crates/fairfit-cli/tests/common/mod.rs`).

use fairfit::Vec3;

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

/// A point written by a script as the JSON array `[x, y, z]`.
#[allow(dead_code)] // not every test file reads points
pub fn json_point(p: &serde_json::Value) -> Vec3 {
    Vec3::new(
        p[0].as_f64().unwrap(),
        p[1].as_f64().unwrap(),
        p[2].as_f64().unwrap(),
    )
}

/// The points of a JSON array of `[x, y, z]` arrays.
#[allow(dead_code)] // not every test file reads points
pub fn json_points(v: &serde_json::Value) -> Vec<Vec3> {
    v.as_array().unwrap().iter().map(json_point).collect()
}
