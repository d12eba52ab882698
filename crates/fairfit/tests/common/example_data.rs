//! The bundled example data (`examples/data`) for integration tests: a small CSV reader of its own
//! (`x,y[,z]`, `#` comments, a header line skipped), independent of the library's reader.

use fairfit::Vec3;

/// Reads `examples/data/<name>` as points (z = 0 for planar files).
pub fn read_csv(name: &str) -> Vec<Vec3> {
    let path = format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|s| s.trim().parse().ok()).collect();
            (v.len() >= 2).then(|| Vec3([v[0], v[1], v.get(2).copied().unwrap_or(0.0)]))
        })
        .collect()
}
