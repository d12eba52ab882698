//! Exact iso-parametric curves of a NURBS surface: `S(u0, v)` or `S(u, v0)` as NURBS curves.
//!
//! Fixing `u = u0` gives homogeneous control points `Qw_j = Σ_i N_i(u0) Pw_ij` with the v knot vector
//! (NURBS Book §5.5 for the clamped boundary case; the same formula holds anywhere). Used for the
//! boundary edges of a STEP face and for iso-curve curvature plots.

use crate::errors::Result;
use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::{NurbsCurve, NurbsSurface};

/// Which parameter is held fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IsoDirection {
    /// `u` fixed: the curve runs along v.
    FixedU,
    /// `v` fixed: the curve runs along u.
    FixedV,
}

/// The iso-curve of `s` with the parameter `dir` fixed at `t` (clamped into the domain).
pub fn iso_curve(s: &NurbsSurface, dir: IsoDirection, t: f64) -> Result<NurbsCurve> {
    let (n_u, n_v) = s.net_size();
    let (p, knots, n) = match dir {
        IsoDirection::FixedU => (s.degree_u(), s.knots_u(), n_u),
        IsoDirection::FixedV => (s.degree_v(), s.knots_v(), n_v),
    };
    let (a, b) = (knots[p], knots[n]);
    let t = t.clamp(a, b);
    let span = find_span(n - 1, p, t, knots);
    let (mut left, mut right, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    basis_funs_into(span, t, p, knots, &mut left, &mut right, &mut nb);
    let m = match dir {
        IsoDirection::FixedU => n_v,
        IsoDirection::FixedV => n_u,
    };
    let mut cw = vec![[0.0; 4]; m];
    for (k, q) in cw.iter_mut().enumerate() {
        for (r, &basis) in nb.iter().enumerate() {
            let idx = span - p + r;
            let (i, j) = match dir {
                IsoDirection::FixedU => (idx, k),
                IsoDirection::FixedV => (k, idx),
            };
            let w = s.weight(i, j);
            let pt = s.control_point(i, j);
            for (qc, pc) in q.iter_mut().zip(pt.0) {
                *qc += basis * w * pc;
            }
            q[3] += basis * w;
        }
    }
    let (deg, kv) = match dir {
        IsoDirection::FixedU => (s.degree_v(), s.knots_v().to_vec()),
        IsoDirection::FixedV => (s.degree_u(), s.knots_u().to_vec()),
    };
    NurbsCurve::from_homogeneous(deg, kv, &cw)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::nurbs::Vec3;

    /// A rational bicubic-by-quadratic test surface with unclamped-free, non-uniform knots.
    pub(crate) fn test_surface() -> NurbsSurface {
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
    fn iso_curves_match_surface_evaluation() {
        let s = test_surface();
        for &t in &[0.0, 0.17, 0.3, 0.81, 1.0] {
            let cu = iso_curve(&s, IsoDirection::FixedU, t).unwrap();
            let cv = iso_curve(&s, IsoDirection::FixedV, t).unwrap();
            for k in 0..=20 {
                let r = k as f64 / 20.0;
                assert!((cu.point(r) - s.point(t, r)).norm() < 1e-13);
                assert!((cv.point(r) - s.point(r, t)).norm() < 1e-13);
            }
        }
    }
}
