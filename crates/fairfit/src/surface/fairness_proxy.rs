//! Per-span fairness of curves, `F_j = L³ ∫_{span j} (dκ/ds)² ds` (method reconstruction §2.3, global
//! length normalisation), integrated by 8-point Gauss-Legendre with nodes strictly inside each span.
//!
//! A private stand-in for the fairness engineer's `fair` module so the surface pipeline can rank knot
//! vectors and report iso-curve fairness on its own; it uses the guarded dκ/ds of [`crate::diffgeo`].

#![allow(clippy::excessive_precision)]

use crate::diffgeo::curvature::differentials_from;
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsCurve, Vec3};

const GX: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329_0,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329_0,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GW: [f64; 8] = [
    0.101_228_536_290_376_3,
    0.222_381_034_453_374_5,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362_0,
    0.362_683_783_378_362_0,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// Fairness of one curve: total `F` and the per-span values `F_j` (same normalisation, `Σ F_j = F`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurveFairness {
    /// `F = L³ ∫ (dκ/ds)² ds`.
    pub total: f64,
    /// `F_j` per non-empty knot span.
    pub per_span: Vec<f64>,
}

impl CurveFairness {
    /// The largest per-span value.
    pub fn max_span(&self) -> f64 {
        self.per_span.iter().copied().fold(0.0, f64::max)
    }
}

/// `F` and `F_j` of `curve`; each span is split into `sub` equal pieces for the quadrature.
pub fn curve_fairness(curve: &NurbsCurve, sub: usize) -> CurveFairness {
    let sub = sub.max(1);
    let breaks = distinct_breakpoints(curve.knots(), curve.degree());
    let mut d = [Vec3::ZERO; 4];
    let mut length = 0.0;
    let mut raw = Vec::with_capacity(breaks.len().saturating_sub(1));
    for w in breaks.windows(2) {
        let mut e = 0.0;
        for s in 0..sub {
            let a = w[0] + (w[1] - w[0]) * s as f64 / sub as f64;
            let b = w[0] + (w[1] - w[0]) * (s + 1) as f64 / sub as f64;
            for (x, gw) in GX.iter().zip(GW) {
                let u = 0.5 * (a + b) + 0.5 * (b - a) * x;
                curve.derivatives_into(u, 3, &mut d);
                let g = differentials_from(u, &d);
                let jac = 0.5 * (b - a) * gw;
                length += jac * g.speed;
                e += jac * g.dkappa_ds * g.dkappa_ds * g.speed;
            }
        }
        raw.push(e);
    }
    let l3 = length * length * length;
    let per_span: Vec<f64> = raw.iter().map(|e| e * l3).collect();
    CurveFairness {
        total: per_span.iter().sum(),
        per_span,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_arc_is_fair_and_scale_free() {
        // exact rational quarter circle: F = 0
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            Some(vec![1.0, s, 1.0]),
        )
        .unwrap();
        assert!(curve_fairness(&c, 2).total < 1e-18);
        // a cubic: F is invariant under scaling by 3
        let pts = |k: f64| {
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(k, 2.0 * k, 0.0),
                Vec3::new(2.0 * k, -k, 0.0),
                Vec3::new(3.0 * k, 0.5 * k, 0.0),
            ]
        };
        let kn = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let a = curve_fairness(&NurbsCurve::bspline(3, kn.clone(), pts(1.0)).unwrap(), 4).total;
        let b = curve_fairness(&NurbsCurve::bspline(3, kn, pts(3.0)).unwrap(), 4).total;
        assert!(a > 1.0 && ((a - b) / a).abs() < 1e-9, "{a} {b}");
    }
}
