//! The benchmark data shared by the fitting benchmarks: every 200-point curve of the shared data,
//! copied into `examples/data` (see its PROVENANCE.md). Each fitting benchmark declares it as its
//! module `curves` (`mod curves;`).

use fairfit::Vec3;

/// The 200-point curves, relative to `examples/data`.
const CURVES: [&str; 8] = [
    "quarter_ellipse_200.csv",
    "quarter_ellipse_200_noise1e-4.csv",
    "du06-w-200-selig.csv",
    "iea15mw_airfoils/FFA-W3-211.csv",
    "iea15mw_airfoils/FFA-W3-241.csv",
    "iea15mw_airfoils/FFA-W3-301.csv",
    "iea15mw_airfoils/FFA-W3-360.csv",
    "iea15mw_airfoils/SNL-FFA-W3-500.csv",
];

/// Each 200-point curve as (short name without folder and `.csv`, its points).
pub fn curves_200() -> Vec<(&'static str, Vec<Vec3>)> {
    let dir = format!("{}/../../examples/data", env!("CARGO_MANIFEST_DIR"));
    CURVES
        .iter()
        .map(|&name| {
            let pts = fairfit::io::read_points(format!("{dir}/{name}"))
                .expect("readable example data")
                .points;
            assert_eq!(pts.len(), 200, "{name}");
            let short = name.rsplit('/').next().unwrap_or(name);
            (short.trim_end_matches(".csv"), pts)
        })
        .collect()
}
