//! Sample files: parameters and fairfit's own points on a curve or surface, as JSON, written beside a
//! CAD file so another program (a CAD kernel, `tests/python/occ_roundtrip.py`) can check what it reads.
//!
//! Format: `{"kind": "curve"|"surface", "params": [[u] | [u, v], ...], "points": [[x, y, z], ...]}`.

use super::numbers::{unsigned_zero, unsigned_zeros};
use crate::nurbs::{NurbsCurve, NurbsSurface};
use serde_json::json;

fn lerp(a: f64, b: f64, k: usize, n: usize) -> f64 {
    if k == n {
        b
    } else {
        a + (b - a) * k as f64 / n as f64
    }
}

/// `n + 1` evenly spaced parameters over the domain (ends included) and the curve points there.
pub fn curve_samples_json(c: &NurbsCurve, n: usize) -> String {
    let n = n.max(1);
    let (a, b) = c.domain();
    let params: Vec<[f64; 1]> = (0..=n).map(|k| [unsigned_zero(lerp(a, b, k, n))]).collect();
    let points: Vec<[f64; 3]> = params
        .iter()
        .map(|u| unsigned_zeros(c.point(u[0]).0))
        .collect();
    json!({"kind": "curve", "params": params, "points": points}).to_string()
}

/// An `(n_u + 1) x (n_v + 1)` parameter grid over the domain (ends included) and the surface points.
pub fn surface_samples_json(s: &NurbsSurface, n_u: usize, n_v: usize) -> String {
    let (n_u, n_v) = (n_u.max(1), n_v.max(1));
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let params: Vec<[f64; 2]> = (0..=n_u)
        .flat_map(|i| {
            (0..=n_v).map(move |j| unsigned_zeros([lerp(u0, u1, i, n_u), lerp(v0, v1, j, n_v)]))
        })
        .collect();
    let points: Vec<[f64; 3]> = params
        .iter()
        .map(|p| unsigned_zeros(s.point(p[0], p[1]).0))
        .collect();
    json!({"kind": "surface", "params": params, "points": points}).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::Vec3;

    #[test]
    fn samples_cover_the_domain_ends_exactly() {
        let c = NurbsCurve::bspline(
            1,
            vec![0.0, 0.0, 0.3, 1.0, 1.0],
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 2.0, 0.0),
                Vec3::new(3.0, 0.0, 0.0),
            ],
        )
        .unwrap();
        let v: serde_json::Value = serde_json::from_str(&curve_samples_json(&c, 7)).unwrap();
        assert_eq!(v["params"].as_array().unwrap().len(), 8);
        assert_eq!(v["params"][7][0], 1.0);
        assert_eq!(v["points"][7], serde_json::json!([3.0, 0.0, 0.0]));
    }
}
