//! The piecewise power form of the B-spline in the workspace (Taylor coefficients at each span
//! start) and its Horner evaluation, so points and derivatives cost one Horner scheme instead of a
//! basis-function recursion.

use super::{EvalWorkspace, P1};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::Vec3;

/// Converts the B-spline in `ws` to its piecewise power form (Taylor coefficients at each span start),
/// so points and derivatives cost one Horner scheme instead of a basis-function recursion.
pub(super) fn build_power_form(p: usize, ws: &mut EvalWorkspace) {
    let n = ws.ctrl.len() - 1;
    ws.breaks.clear();
    ws.coef.clear();
    ws.break_knot.clear();
    ensure_span_ders(p, ws);
    for s in p..=n {
        let u0 = ws.knots[s];
        if ws.knots[s + 1] <= u0 {
            continue;
        }
        ws.breaks.push(u0);
        ws.break_knot.push(s);
        ws.coef.extend(std::iter::repeat_n(Vec3::default(), p + 1));
        span_power_coefs_cached(p, s, ws.coef.len() - (p + 1), ws);
    }
}

/// Rebuilds `ws.span_ders` (the basis derivatives at every span start) when the knots or the
/// degree changed since it was built; [`span_power_coefs_cached`] reads it.
pub(super) fn ensure_span_ders(p: usize, ws: &mut EvalWorkspace) {
    let q = (p + 1) * (p + 1);
    if ws.span_ders.degree != p || ws.span_ders.knots != ws.knots {
        let cache = &mut ws.span_ders;
        cache.knots.clone_from(&ws.knots);
        cache.degree = p;
        cache.ders.resize(ws.knots.len() * q, 0.0);
        let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
        let (mut ndu, mut a) = ([0.0; P1 * P1], [0.0; 2 * P1]);
        for k in p..ws.knots.len().saturating_sub(p + 1) {
            let ders = &mut cache.ders[k * q..(k + 1) * q];
            ders_basis_funs_into(
                k,
                ws.knots[k],
                p,
                p,
                &ws.knots,
                &mut left,
                &mut right,
                &mut ndu,
                &mut a,
                ders,
            );
        }
    }
}

/// Writes the `p + 1` Taylor coefficients of knot span `s` at `ws.coef[at..]`, with the basis
/// derivatives at the span starts from `ws.span_ders` (made current by [`ensure_span_ders`] once
/// before a run of spans): a candidate's parameter correction, band fairing's and the polish's
/// measurements reuse them on the same knots.
pub(super) fn span_power_coefs_cached(p: usize, s: usize, at: usize, ws: &mut EvalWorkspace) {
    let q = (p + 1) * (p + 1);
    let ders = &ws.span_ders.ders[s * q..(s + 1) * q];
    taylor_coefs(p, &ws.ctrl[s - p..=s], ders, &mut ws.coef[at..=at + p]);
}

/// The `p + 1` Taylor coefficients `C^(k)(u_0) / k!` of a span from its `p + 1` control points and
/// the basis derivatives `ders[k (p + 1) + j] = N_j^(k)(u_0)` at the span's start.
#[inline]
pub(super) fn taylor_coefs(p: usize, ctrl: &[Vec3], ders: &[f64], coef: &mut [Vec3]) {
    if p == 3 {
        // the usual cubic: the same loops with a constant degree, unrolled by the compiler
        taylor_coefs_any(3, ctrl, ders, coef);
    } else {
        taylor_coefs_any(p, ctrl, ders, coef);
    }
}

/// [`taylor_coefs`] for any degree (always inlined so a constant `p` unrolls the loops).
#[inline(always)]
pub(super) fn taylor_coefs_any(p: usize, ctrl: &[Vec3], ders: &[f64], coef: &mut [Vec3]) {
    let mut fact = 1.0;
    for k in 0..=p {
        if k > 0 {
            fact *= k as f64;
        }
        let mut c = Vec3::default();
        for j in 0..=p {
            c += ctrl[j] * ders[k * (p + 1) + j];
        }
        coef[k] = c / fact;
    }
}

/// The point and derivatives 1..=3 at `u` from the power form, in span `j` (index into `breaks`).
#[inline]
pub(super) fn power_eval(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    if p == 3 {
        // the usual cubic: `power_eval_any` inlined with a constant degree, unrolled by the compiler
        power_eval_any(coef, 3, j, t, out);
    } else {
        power_eval_any(coef, p, j, t, out);
    }
}

/// [`power_eval`] for any degree (always inlined so a constant `p` unrolls the Horner loop).
#[inline(always)]
pub(super) fn power_eval_any(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    // Horner for the value and the first three derivatives
    let (mut v0, mut v1, mut v2, mut v3) =
        (c[p], Vec3::default(), Vec3::default(), Vec3::default());
    for k in (0..p).rev() {
        v3 = v3 * t + v2;
        v2 = v2 * t + v1;
        v1 = v1 * t + v0;
        v0 = v0 * t + c[k];
    }
    out[0] = v0;
    out[1] = v1;
    out[2] = v2 * 2.0;
    out[3] = v3 * 6.0;
}

/// The point and derivatives 1..=2 at `u` from the power form, in span `j` (`out[3]` untouched):
/// what a projection needs, bit-identical to [`power_eval`]'s first three entries.
#[inline]
pub(super) fn power_eval2(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    if p == 3 {
        power_eval2_any(coef, 3, j, t, out);
    } else {
        power_eval2_any(coef, p, j, t, out);
    }
}

/// [`power_eval2`] for any degree (always inlined so a constant `p` unrolls the Horner loop).
#[inline(always)]
pub(super) fn power_eval2_any(coef: &[Vec3], p: usize, j: usize, t: f64, out: &mut [Vec3; 4]) {
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    let (mut v0, mut v1, mut v2) = (c[p], Vec3::default(), Vec3::default());
    for k in (0..p).rev() {
        v2 = v2 * t + v1;
        v1 = v1 * t + v0;
        v0 = v0 * t + c[k];
    }
    out[0] = v0;
    out[1] = v1;
    out[2] = v2 * 2.0;
}

/// The span index in `breaks` holding `u` (last span for `u` at the end).
#[cfg(test)]
pub(super) fn power_span(breaks: &[f64], u: f64) -> usize {
    match breaks.binary_search_by(|b| b.total_cmp(&u)) {
        Ok(i) => i,
        Err(i) => i.saturating_sub(1),
    }
}

/// [`power_span`] by walking from the span `hint` (same result; cheap for ordered queries).
#[inline]
pub(super) fn power_span_from(breaks: &[f64], u: f64, hint: usize) -> usize {
    // plain comparisons: `breaks[j]` for `j > 0` is positive, so they order as `total_cmp` does
    // for every `u` but NaN (whose evaluation is NaN in any span and never kept)
    let mut j = hint.min(breaks.len().saturating_sub(1));
    while j + 1 < breaks.len() && breaks[j + 1] <= u {
        j += 1;
    }
    while j > 0 && breaks[j] > u {
        j -= 1;
    }
    j
}
