//! The Python used by tests that run scripts of the repository (`$FAIRFIT_PYTHON`, see
//! [`fairfit_testkit::python_or_skip`]), and the points those scripts print as JSON, as [`Vec3`].

use fairfit::Vec3;
pub use fairfit_testkit::python_or_skip;

/// A point written by a script as the JSON array `[x, y, z]`.
#[allow(dead_code)] // not every test file reads points
pub fn json_point(p: &serde_json::Value) -> Vec3 {
    Vec3(fairfit_testkit::json_triple(p))
}

/// The points of a JSON array of `[x, y, z]` arrays.
#[allow(dead_code)] // not every test file reads points
pub fn json_points(v: &serde_json::Value) -> Vec<Vec3> {
    fairfit_testkit::json_triples(v)
        .into_iter()
        .map(Vec3)
        .collect()
}
