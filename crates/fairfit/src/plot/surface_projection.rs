//! Closest points on a NURBS surface, for deviation maps: a grid search per knot span, then Newton
//! iterations on `(S - q)·S_u = (S - q)·S_v = 0`, clamped to the domain.

use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};

/// The closest point found: parameters and distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceFoot {
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// Distance from the query point.
    pub distance: f64,
}

/// Start grid: up to 8 samples per span, at most about 48 per direction in all (cost per point).
fn grid(knots: &[f64], degree: usize) -> Vec<f64> {
    let bp = distinct_breakpoints(knots, degree);
    let per_span = (48 / (bp.len() - 1).max(1)).clamp(1, 8);
    let mut out = Vec::new();
    for w in bp.windows(2) {
        for k in 0..per_span {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
        }
    }
    out.extend(bp.last());
    out
}

/// Projects every point of `qs` onto `s`.
///
/// Far outside unit size (near 1e±300, where squared distances over- or underflow) the projection runs
/// on exactly rescaled copies (see [`crate::nurbs::scale`]) and the distances are scaled back.
pub fn project_points(s: &NurbsSurface, qs: &[Vec3]) -> Vec<SurfaceFoot> {
    let f = crate::nurbs::scale::normalising_factor(s.control_points_flat());
    if let Some(t) = (f != 1.0)
        .then(|| crate::nurbs::scale::scaled_surface(s, f).ok())
        .flatten()
    {
        let scaled: Vec<Vec3> = qs.iter().map(|&q| q * f).collect();
        let mut feet = project_points_as_is(&t, &scaled);
        feet.iter_mut().for_each(|x| x.distance /= f);
        return feet;
    }
    project_points_as_is(s, qs)
}

fn project_points_as_is(s: &NurbsSurface, qs: &[Vec3]) -> Vec<SurfaceFoot> {
    let us = grid(s.knots_u(), s.degree_u());
    let vs = grid(s.knots_v(), s.degree_v());
    let samples: Vec<(f64, f64, Vec3)> = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .map(|(u, v)| (u, v, s.point(u, v)))
        .collect();
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut ws = SurfaceWorkspace::new(s, 2);
    let mut d = [Vec3::ZERO; 9];
    qs.iter()
        .map(|&q| {
            let (mut u, mut v, _) = samples
                .iter()
                .copied()
                .min_by(|a, b| {
                    (a.2 - q)
                        .norm_squared()
                        .total_cmp(&(b.2 - q).norm_squared())
                })
                .unwrap_or((u0, v0, Vec3::ZERO));
            for _ in 0..20 {
                s.derivatives_with(u, v, 2, &mut ws, &mut d);
                let r = d[0] - q;
                let (su, sv) = (d[3], d[1]);
                let (suu, suv, svv) = (d[6], d[4], d[2]);
                let (g1, g2) = (r.dot(su), r.dot(sv));
                let a = su.dot(su) + r.dot(suu);
                let b = su.dot(sv) + r.dot(suv);
                let c = sv.dot(sv) + r.dot(svv);
                let det = a * c - b * b;
                if !(det.is_finite() && det.abs() > f64::MIN_POSITIVE) {
                    break;
                }
                let du = (c * g1 - b * g2) / det;
                let dv = (a * g2 - b * g1) / det;
                let (nu, nv) = ((u - du).clamp(u0, u1), (v - dv).clamp(v0, v1));
                let step = (nu - u).abs() / (u1 - u0) + (nv - v).abs() / (v1 - v0);
                (u, v) = (nu, nv);
                if step < 1e-15 {
                    break;
                }
            }
            SurfaceFoot {
                u,
                v,
                distance: (s.point(u, v) - q).norm(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rational bicubic-by-quadratic test surface with unclamped-free, non-uniform knots.
    fn test_surface() -> NurbsSurface {
        let ku = vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0, 1.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 0.6, 1.0, 1.0, 1.0, 1.0];
        let net: Vec<Vec<Vec3>> = (0..5)
            .map(|i| {
                (0..5)
                    .map(|j| {
                        let (x, y) = (i as f64, j as f64);
                        Vec3::new(x, y, 0.3 * (x - 2.0) * (y - 1.5) + 0.1 * x * x)
                    })
                    .collect()
            })
            .collect();
        let w: Vec<Vec<f64>> = (0..5)
            .map(|i| {
                (0..5)
                    .map(|j| 1.0 + 0.1 * ((i + 2 * j) % 3) as f64)
                    .collect()
            })
            .collect();
        NurbsSurface::new(3, 3, ku, kv, net, Some(w)).unwrap()
    }

    #[test]
    fn points_off_a_surface_project_back_along_the_normal() {
        let s = test_surface();
        for &(u, v) in &[(0.2, 0.3), (0.71, 0.55), (0.5, 0.9)] {
            let d = s.derivatives(u, v, 1);
            let n = d[2].cross(d[1]);
            let n = n / n.norm();
            let q = d[0] + n * 0.05;
            let f = project_points(&s, &[q])[0];
            assert!((f.u - u).abs() < 1e-9 && (f.v - v).abs() < 1e-9, "{f:?}");
            assert!((f.distance - 0.05).abs() < 1e-12);
        }
    }
}
