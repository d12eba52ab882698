//! The polynomial numerators of curvature, its derivative and the signed planar curvature of one
//! knot span of a (rational, planar or spatial) B-spline, from the span's hodograph
//! ([`super::span_hodograph`]: `C' = D / w²`, `E = D'`), by exact Bernstein arithmetic.
//!
//! With `G = D × E` (a scalar, the plane-normal component, for a planar curve; a vector in space),
//! `G' = D × E'`, `|D|²` and `D·E`:
//!
//! - **planar**: `κ = w² G / |D|³` (signed), `dκ/ds = w³ M / |D|⁶` with
//!   `M = w (|D|² G' − 3 G (D·E)) + 2 w' |D|² G` (degree `9p − 6` as stored for a rational piece;
//!   for a polynomial piece `w = 1` and `M = |D|² G' − 3 G (D·E)`, degree `4p − 6`, the numerator
//!   of [`super::exact_extrema`]);
//! - **spatial**: `κ = w² |G| / |D|³` (unsigned, the measurer's), and from
//!   `d(κ²)/du = 2 w³ H / |D|⁸`, `dκ/ds = w³ H / (|G| |D|⁶)` with
//!   `H = w (G·G' |D|² − 3 |G|² (D·E)) + 2 w' |G|² |D|²` (degree `13p − 9` rational,
//!   `6p − 9` polynomial). Where `κ > 0`, `sign dκ/ds = sign H`; at an isolated zero of `κ`
//!   (`G` crosses `0`) `H` has a simple root and changes sign, as the unsigned `κ` has a minimum
//!   there; on a straight stretch `G ≡ 0` and `H ≡ 0`.
//!
//! The derivations: `C' × C'' = G / w⁴`, `C' × C''' = (w G' − 4 w' G) / w⁵`,
//! `C' · C'' = (w D·E − 2 w' |D|²) / w⁵`, `|C'|² = |D|² / w⁴`, substituted into
//! `dκ/ds = [(C' × C''') |C'|² − 3 (C' × C'') (C' · C'')] / |C'|⁶` (planar) and
//! `d(κ²)/du = [2 (C'×C'')·(C'×C''') |C'|² − 6 |C'×C''|² (C'·C'')] / |C'|⁸` (spatial).
//!
//! Every numerator comes with its **scale**, the largest coefficient magnitude of the products it
//! is the sum of (a polynomial that vanishes identically, a line or a circular arc, whose
//! `dκ/ds ≡ 0`, has coefficients of rounding size relative to it; see [`super::exact_nurbs`] for
//! why the count does not prune by it).

use super::bernstein::{combine, eval, mul};
use super::span_hodograph::SpanHodograph;

/// A numerator polynomial and the scale of its rounding noise.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Numerator {
    /// Bernstein coefficients on the span parameter `[0, 1]`.
    pub coeffs: Vec<f64>,
    /// Largest coefficient magnitude of the products summed into it.
    pub scale: f64,
}

/// The curvature numerators of one span, ready for evaluation.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SpanCurvature {
    /// `G` (planar, one entry) or its components (spatial, three).
    pub g: Vec<Vec<f64>>,
    /// `|D|²`.
    pub dd: Vec<f64>,
    /// The weight `w` (`None` for a polynomial piece).
    pub w: Option<Vec<f64>>,
    /// `M` (planar) or `H` (spatial), the numerator of `dκ/ds`.
    pub dkds: Numerator,
}

fn max_abs(c: &[f64]) -> f64 {
    c.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn dot(u: &[Vec<f64>], v: &[Vec<f64>]) -> Vec<f64> {
    let mut acc = mul(&u[0], &v[0]);
    for (a, b) in u.iter().zip(v).skip(1) {
        acc = combine(1.0, &acc, 1.0, &mul(a, b));
    }
    acc
}

/// `u × v`: the scalar `u₀v₁ − u₁v₀` for two coordinates, the vector for three.
fn cross(u: &[Vec<f64>], v: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let c = |i: usize, j: usize| combine(1.0, &mul(&u[i], &v[j]), -1.0, &mul(&u[j], &v[i]));
    if u.len() == 2 {
        vec![c(0, 1)]
    } else {
        vec![c(1, 2), c(2, 0), c(0, 1)]
    }
}

/// `w X + 2 w' Y` (rational) or `X` (polynomial), with the scale of the products.
fn weighted(h: &SpanHodograph, x: Vec<f64>, x_scale: f64, y: &[f64]) -> Numerator {
    match &h.weight {
        None => Numerator {
            coeffs: x,
            scale: x_scale,
        },
        Some((w, w1)) => {
            let wx = mul(w, &x);
            let wy = mul(w1, y);
            let wmax = max_abs(w);
            let scale = (x_scale * wmax).max(2.0 * max_abs(&wy));
            Numerator {
                coeffs: combine(1.0, &wx, 2.0, &wy),
                scale,
            }
        }
    }
}

/// The numerators of span `h` (planar when its hodograph has two coordinates).
pub(crate) fn span_curvature(h: &SpanHodograph) -> SpanCurvature {
    let dd = dot(&h.d, &h.d);
    let de = dot(&h.d, &h.e);
    let g = cross(&h.d, &h.e);
    let g1 = cross(&h.d, &h.e1);
    let dkds = if g.len() == 1 {
        // M = w (|D|² G' − 3 G (D·E)) + 2 w' |D|² G
        let (p1, p2) = (mul(&dd, &g1[0]), mul(&g[0], &de));
        let scale = max_abs(&p1).max(3.0 * max_abs(&p2));
        let x = combine(1.0, &p1, -3.0, &p2);
        weighted(h, x, scale, &mul(&dd, &g[0]))
    } else {
        // H = w (G·G' |D|² − 3 |G|² (D·E)) + 2 w' |G|² |D|²
        let (gg, gg1) = (dot(&g, &g), dot(&g, &g1));
        let (p1, p2) = (mul(&gg1, &dd), mul(&gg, &de));
        let scale = max_abs(&p1).max(3.0 * max_abs(&p2));
        let x = combine(1.0, &p1, -3.0, &p2);
        weighted(h, x, scale, &mul(&gg, &dd))
    };
    SpanCurvature {
        g,
        dd,
        w: h.weight.as_ref().map(|(w, _)| w.clone()),
        dkds,
    }
}

impl SpanCurvature {
    /// `(w, |D|², |G|, signed G for a planar piece)` at span parameter `t`.
    fn parts(&self, t: f64) -> (f64, f64, f64, f64) {
        let w = self.w.as_ref().map_or(1.0, |w| eval(w, t));
        let dd = eval(&self.dd, t);
        let gs: Vec<f64> = self.g.iter().map(|g| eval(g, t)).collect();
        let gn = gs.iter().map(|v| v * v).sum::<f64>().sqrt();
        (w, dd, gn, gs[0])
    }

    /// `dκ/ds` of the local piece at span parameter `t` (NaN where the speed or, in space, `κ`
    /// vanishes).
    pub fn dkappa_ds(&self, t: f64) -> f64 {
        let (w, dd, gn, _) = self.parts(t);
        let m = eval(&self.dkds.coeffs, t);
        let den = dd * dd * dd * if self.g.len() == 1 { 1.0 } else { gn };
        if !(dd > 0.0 && den > 0.0) {
            return f64::NAN;
        }
        w * w * w * m / den
    }

    /// `κ` of the local piece at span parameter `t` (signed for a planar piece; NaN where the
    /// speed vanishes).
    pub fn kappa(&self, t: f64) -> f64 {
        let (w, dd, gn, g0) = self.parts(t);
        if dd <= 0.0 || !dd.is_finite() {
            return f64::NAN;
        }
        let g = if self.g.len() == 1 { g0 } else { gn };
        w * w * g / (dd * dd.sqrt())
    }

    /// The numerator of the signed planar `κ` (`G`) with its scale; `None` in space.
    pub fn kappa_numerator(&self) -> Option<Numerator> {
        (self.g.len() == 1).then(|| Numerator {
            coeffs: self.g[0].clone(),
            scale: max_abs(&self.g[0]),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::span_hodograph::span_hodograph;

    #[test]
    fn a_twisted_cubic_has_the_closed_form_curvature_derivative() {
        // C(t) = (t, t², t³) on [0, 1]: κ² = 4 f / g³, f = 9t⁴ + 9t² + 1, g = 9t⁴ + 4t² + 1,
        // so dκ/ds = (d(κ²)/dt) / (2 κ |C'|) with d(κ²)/dt = 4 (f' g − 3 f g') / g⁴
        let coords = vec![
            vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0],
            vec![0.0, 0.0, 1.0 / 3.0, 1.0],
            vec![0.0, 0.0, 0.0, 1.0],
        ];
        let sc = span_curvature(&span_hodograph(0.0, 1.0, &coords, None));
        for &t in &[0.05, 0.3, 0.77, 0.99] {
            let t2: f64 = t * t;
            let (f, g) = (
                9.0 * t2 * t2 + 9.0 * t2 + 1.0,
                9.0 * t2 * t2 + 4.0 * t2 + 1.0,
            );
            let (f1, g1) = (36.0 * t2 * t + 18.0 * t, 36.0 * t2 * t + 8.0 * t);
            let kappa = 2.0 * f.sqrt() / g.powf(1.5);
            let dk2 = 4.0 * (f1 * g - 3.0 * f * g1) / g.powi(4);
            let want = dk2 / (2.0 * kappa * g.sqrt());
            assert!((sc.kappa(t) - kappa).abs() < 1e-14, "{t}");
            assert!(
                (sc.dkappa_ds(t) - want).abs() < 1e-12 * want.abs().max(1.0),
                "{t}"
            );
        }
    }

    #[test]
    fn a_rational_circle_arc_has_a_vanishing_numerator() {
        // the quarter circle (1,0) → (1,1) → (0,1), middle weight 1/√2: κ = 1, dκ/ds ≡ 0
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let w = vec![1.0, h, 1.0];
        let coords = vec![vec![1.0, h, 0.0], vec![0.0, h, 1.0]];
        let sc = span_curvature(&span_hodograph(0.0, 1.0, &coords, Some(w)));
        let n = &sc.dkds;
        assert!(max_abs(&n.coeffs) < 1e-15 * n.scale, "{n:?}");
        for &t in &[0.0, 0.3, 0.5, 1.0] {
            assert!((sc.kappa(t) - 1.0).abs() < 1e-15);
        }
    }
}
