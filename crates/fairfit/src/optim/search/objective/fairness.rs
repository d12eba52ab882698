//! The fast fairness measure `F = L³ ∫ (dκ/ds)² ds` with its per-span parts `F_j`, by the fixed
//! 8-node Gauss–Legendre rule per knot span (nodes strictly inside spans, so C''' is never taken at
//! a knot).

use super::power_form::power_eval;
use super::{EvalWorkspace, FitData, GL_W, GL_X};
use crate::nurbs::Vec3;

/// `(F, max_j F_j)` by 8-point Gauss–Legendre per span; fills `ws.span_fairness`.
pub(super) fn fairness(data: &FitData, ws: &mut EvalWorkspace) -> (f64, f64) {
    ws.span_energy.clear();
    ws.span_length.clear();
    for j in 0..ws.breaks.len() {
        let (e, len) = span_energy_length(data, ws, j);
        ws.span_energy.push(e);
        ws.span_length.push(len);
    }
    fairness_totals(ws)
}

/// `(∫ (dκ/du)² / |C'| du, ∫ |C'| du)` over power-form span `j`.
pub(super) fn span_energy_length(data: &FitData, ws: &EvalWorkspace, j: usize) -> (f64, f64) {
    let a = ws.breaks[j];
    let b = ws.breaks.get(j + 1).copied().unwrap_or(1.0);
    let (mid, half) = (0.5 * (a + b) - a, 0.5 * (b - a));
    let (mut e, mut length) = (0.0, 0.0);
    let mut d = [Vec3::default(); 4];
    for i in 0..8 {
        let t = if i < 4 { -GL_X[i] } else { GL_X[i - 4] };
        let w = GL_W[i % 4] * half;
        power_eval(&ws.coef, data.degree, j, mid + half * t, &mut d);
        let (speed, dk) = speed_and_dkappa_du(&d, data.planar);
        length += w * speed;
        if speed > 0.0 {
            e += w * dk * dk / speed;
        }
    }
    (e, length)
}

/// `(F, max_j F_j)` from `ws.span_energy` and `ws.span_length`; fills `ws.span_fairness`.
pub(super) fn fairness_totals(ws: &mut EvalWorkspace) -> (f64, f64) {
    let length: f64 = ws.span_length.iter().sum();
    let l3 = length * length * length;
    ws.span_fairness.clear();
    let (mut total, mut fmax) = (0.0, 0.0f64);
    for &e in &ws.span_energy {
        let fj = l3 * e;
        ws.span_fairness.push(fj);
        total += fj;
        fmax = fmax.max(fj);
    }
    if !total.is_finite() {
        return (f64::INFINITY, f64::INFINITY);
    }
    (total, fmax)
}

/// Speed `|C'|` and `dκ/du` (signed planar curvature when `planar`), guarded near zero.
#[inline]
pub(crate) fn speed_and_dkappa_du(d: &[Vec3; 4], planar: bool) -> (f64, f64) {
    let (r, a, b) = (d[1], d[2], d[3]);
    let v2 = r.norm_squared();
    let v = v2.sqrt();
    if v.is_nan() || v <= 0.0 {
        return (0.0, 0.0);
    }
    let v3 = v2 * v;
    let v5 = v3 * v2;
    let ra = r.dot(a);
    if planar {
        let cz = r[0] * a[1] - r[1] * a[0];
        let bz = r[0] * b[1] - r[1] * b[0];
        return (v, bz / v3 - 3.0 * cz * ra / v5);
    }
    let c = r.cross(a);
    let cn = c.norm();
    let rb = r.cross(b);
    let dc = if cn > 1e-12 * v * a.norm() && cn > 0.0 {
        c.dot(rb) / cn
    } else {
        rb.norm()
    };
    (v, dc / v3 - 3.0 * cn * ra / v5)
}
