//! Helpers shared by the test suites of the workspace's crates, so that each suite stays one binary
//! whose modules mirror its crate's `src` without including another crate's files by path.
//!
//! - [`python_or_skip`]: the Python interpreter with the peers (`$FAIRFIT_PYTHON`) that tests running
//!   the repository's scripts (OpenCASCADE, scipy, the independent measurer, pytest) call.
//! - [`json_triple`] / [`json_triples`]: the `[x, y, z]` points those scripts print as JSON.
//!
//! It depends on nothing of fairfit's, so every crate can take it as a dev-dependency without a
//! cycle; the callers wrap the triples in their own point type.

/// `$FAIRFIT_PYTHON`, or `None` (with a note on stdout) when it is unset outside CI, so that a plain
/// `cargo test` on a machine without the Python peers still passes.
///
/// Under `CI=true` an unset variable panics: CI must run what needs Python. Set but empty also
/// panics. `what` names the tests that need it, for the note and the panic message.
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
///
/// # Panics
/// When `p` is not an array of three numbers (a broken script output fails the test).
pub fn json_triple(p: &serde_json::Value) -> [f64; 3] {
    let coordinate = |i: usize| {
        p[i].as_f64()
            .unwrap_or_else(|| panic!("expected [x, y, z] numbers, got {p}"))
    };
    [coordinate(0), coordinate(1), coordinate(2)]
}

/// The points of a JSON array of `[x, y, z]` arrays.
///
/// # Panics
/// When `v` is not an array of such points.
pub fn json_triples(v: &serde_json::Value) -> Vec<[f64; 3]> {
    v.as_array()
        .unwrap_or_else(|| panic!("expected an array of points, got {v}"))
        .iter()
        .map(json_triple)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triples_read_back_what_a_script_prints() {
        let v: serde_json::Value =
            serde_json::from_str("[[1, -2.5, 3e-3], [0, 0, 1e300]]").unwrap();
        assert_eq!(json_triples(&v), vec![[1.0, -2.5, 3e-3], [0.0, 0.0, 1e300]]);
    }

    #[test]
    #[should_panic(expected = "expected [x, y, z] numbers")]
    fn a_short_point_fails_the_test() {
        json_triple(&serde_json::json!([1.0, 2.0]));
    }
}
