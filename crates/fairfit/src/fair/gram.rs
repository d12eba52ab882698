//! The Gram matrix `G_ij = ∫ N_i^(k)(u) N_j^(k)(u) du` of the B-spline basis derivatives of order `k`, so
//! that the parametric energy of a non-rational curve is `∫ |C^(k)|² du = Σ_ij G_ij P_i·P_j`. Used by
//! the local energy fairing ([`super::fairing`], Eck & Hadenfeld), where moving one control point to
//! the minimiser of this quadratic form is a closed-form step. Integrated exactly, span by span, with
//! Gauss–Legendre nodes strictly inside each span.

use crate::diffgeo::quadrature::GaussLegendre;
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::knots::find_span;

/// A dense symmetric Gram matrix (banded: `G_ij = 0` when `|i − j| > p`).
#[derive(Clone, Debug, PartialEq)]
pub struct Gram {
    n: usize,
    g: Vec<f64>,
}

impl Gram {
    /// The Gram matrix of order-`k` derivatives of the degree-`p` basis on `knots` (`n` functions).
    /// Orders above `p` give the zero matrix.
    pub fn new(p: usize, knots: &[f64], n: usize, k: usize) -> Self {
        let mut g = vec![0.0; n * n];
        if k > p || n == 0 {
            return Gram { n, g };
        }
        let p1 = p + 1;
        let rule = GaussLegendre::new(p + 1);
        let (mut left, mut right) = (vec![0.0; p1], vec![0.0; p1]);
        let (mut ndu, mut a) = (vec![0.0; p1 * p1], vec![0.0; 2 * p1]);
        let mut ders = vec![0.0; (k + 1) * p1];
        let lo = knots[p];
        let hi = knots[n];
        for s in p..n {
            let (ua, ub) = (knots[s], knots[s + 1]);
            if ub <= ua || ua < lo || ub > hi {
                continue;
            }
            let (c, h) = (0.5 * (ua + ub), 0.5 * (ub - ua));
            for (x, w) in rule.nodes().iter().zip(rule.weights()) {
                let u = c + h * x;
                let span = find_span(n - 1, p, u, knots);
                ders_basis_funs_into(
                    span, u, p, k, knots, &mut left, &mut right, &mut ndu, &mut a, &mut ders,
                );
                let row = &ders[k * p1..k * p1 + p1];
                for (r1, d1) in row.iter().enumerate() {
                    for (r2, d2) in row.iter().enumerate() {
                        g[(span - p + r1) * n + span - p + r2] += w * h * d1 * d2;
                    }
                }
            }
        }
        // exact symmetry (the two triangles accumulate in different orders)
        for i in 0..n {
            for j in i + 1..n {
                let m = 0.5 * (g[i * n + j] + g[j * n + i]);
                g[i * n + j] = m;
                g[j * n + i] = m;
            }
        }
        Gram { n, g }
    }

    /// Number of basis functions.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True for an empty basis.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// `G_ij`.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.g[i * self.n + j]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::uniform_clamped;
    use crate::nurbs::{NurbsCurve, Vec3};

    #[test]
    fn quadratic_form_equals_integral_of_squared_derivative() {
        let n = 9;
        let knots = vec![
            0.0, 0.0, 0.0, 0.0, 0.1, 0.3, 0.35, 0.6, 0.8, 1.0, 1.0, 1.0, 1.0,
        ];
        let pts: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64, ((i * 7) % 5) as f64 * 0.3, (i as f64).sqrt()))
            .collect();
        let c = NurbsCurve::bspline(3, knots.clone(), pts.clone()).unwrap();
        for k in 1..=3 {
            let g = Gram::new(3, &knots, n, k);
            let mut e = 0.0;
            for i in 0..n {
                for j in 0..n {
                    e += g.get(i, j) * pts[i].dot(pts[j]);
                }
            }
            // independent: composite Gauss–Legendre of |C^(k)|² inside each span
            let rule = GaussLegendre::new(10);
            let breaks = crate::nurbs::knots::distinct_breakpoints(&knots, 3);
            let mut ref_e = 0.0;
            for w in breaks.windows(2) {
                ref_e += rule.integrate(w[0], w[1], |u| c.derivatives(u, k)[k].norm_squared());
            }
            assert!((e - ref_e).abs() < 1e-10 * ref_e, "k={k}: {e} vs {ref_e}");
            // symmetric and banded
            for i in 0..n {
                for j in 0..n {
                    assert_eq!(g.get(i, j), g.get(j, i));
                    if i.abs_diff(j) > 3 {
                        assert_eq!(g.get(i, j), 0.0);
                    }
                }
            }
        }
        assert!(Gram::new(2, &uniform_clamped(2, 5), 5, 3)
            .g
            .iter()
            .all(|&x| x == 0.0));
    }
}
