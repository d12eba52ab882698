//! Exact sign intervals of `dκ/ds` and of the signed planar `κ` for any B-spline curve: rational
//! or polynomial, planar or spatial, from the real roots of the span numerators of
//! [`super::curvature_numerators`] (no sampling).
//!
//! Per knot span: the sign changes of the numerator in the open span by Bernstein subdivision and
//! Descartes' rule ([`super::bernstein::sign_changes`]); between consecutive roots an interval of
//! one sign, with its peak `|signal|` on [`super::exact_extrema::PEAK_NODES`] Chebyshev nodes (the
//! sign is taken from the signal there, not from the reported roots). The intervals are counted by
//! [`super::exact_extrema::alternations`] with the measurer's floor.
//!
//! **No coefficient threshold**: unlike the planar polynomial count, only an exactly zero piece is
//! skipped as noise. A rational or spatial numerator can be legitimately tiny in part of a span
//! (`dκ/ds = w³ H / (|G| |D|⁶)`: where the weight or the speed is small, `H` is small by many
//! orders of magnitude while `dκ/ds` is not): on random spatial rational cubics and quartics with
//! weights between 0.1 and 10, `H` had real, accurately computed roots where it was `1e-17` of its
//! largest product coefficient, which the planar count's `1e-12` threshold dropped (2 of 300
//! curves). The floor decides instead, on the signal: a numerator that vanishes identically (a
//! line, a circular arc) has roots of rounding noise, and the intervals between them a peak of
//! rounding size, far below the floor.
//!
//! A numerator of degree above [`MAX_NUMERATOR_DEGREE`] (a spatial rational curve of degree 14
//! or more) is not formed: the callers fall back to dense sampling.

use super::bernstein;
use super::curvature_numerators::span_curvature;
use super::exact_extrema::{SignInterval, PEAK_NODES};
use super::span_hodograph::curve_hodographs;
use crate::nurbs::{NurbsCurve, Vec3};

/// Largest numerator degree formed exactly.
pub const MAX_NUMERATOR_DEGREE: usize = 160;

/// Which signal's sign intervals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signal {
    /// `dκ/ds` (curvature extrema; unsigned `κ` in space).
    DkappaDs,
    /// The signed curvature `κ` of a planar curve (inflections).
    Kappa,
}

/// The sign intervals (in parameter order) of `signal` on `curve`, planar in the plane with unit
/// normal `normal` or spatial for `None`, with peaks in the curve's units (`dκ/ds` or `κ`).
/// `None` when the count cannot be made exactly (degenerate curve, numerator degree above
/// [`MAX_NUMERATOR_DEGREE`], or [`Signal::Kappa`] in space).
pub fn sign_intervals_nurbs(
    curve: &NurbsCurve,
    normal: Option<Vec3>,
    signal: Signal,
) -> Option<Vec<SignInterval>> {
    let want = [signal == Signal::DkappaDs, signal == Signal::Kappa];
    let [dkds, kappa] = sign_intervals_nurbs_both(curve, normal, want);
    match signal {
        Signal::DkappaDs => dkds,
        Signal::Kappa => kappa,
    }
}

/// [`sign_intervals_nurbs`] of [`Signal::DkappaDs`] and of [`Signal::Kappa`] (those `want`ed, in
/// this order) from one construction of the span hodographs and curvature numerators: each entry
/// is what [`sign_intervals_nurbs`] gives for its signal, `None` for a signal not wanted.
pub(crate) fn sign_intervals_nurbs_both(
    curve: &NurbsCurve,
    normal: Option<Vec3>,
    want: [bool; 2],
) -> [Option<Vec<SignInterval>>; 2] {
    let signals = [Signal::DkappaDs, Signal::Kappa];
    // a signal stays `Some` while every span's numerator could be formed
    let mut out = [0, 1]
        .map(|i| (want[i] && !(signals[i] == Signal::Kappa && normal.is_none())).then(Vec::new));
    if out.iter().all(Option::is_none) {
        return out;
    }
    let Some(hod) = curve_hodographs(curve, normal) else {
        return [None, None];
    };
    let unit = |signal: Signal| match signal {
        Signal::DkappaDs => 1.0 / (hod.extent * hod.extent),
        Signal::Kappa => 1.0 / hod.extent,
    };
    let mut roots = Vec::new();
    for h in &hod.spans {
        let sc = span_curvature(h);
        for (signal, slot) in signals.into_iter().zip(out.iter_mut()) {
            let Some(iv) = slot else {
                continue;
            };
            let num = match signal {
                Signal::DkappaDs => Some(sc.dkds.clone()),
                Signal::Kappa => sc.kappa_numerator(),
            };
            let Some(num) = num.filter(|n| n.coeffs.len() <= MAX_NUMERATOR_DEGREE + 1) else {
                *slot = None;
                continue;
            };
            let value = |t: f64| match signal {
                Signal::DkappaDs => sc.dkappa_ds(t),
                Signal::Kappa => sc.kappa(t),
            };
            push_intervals(
                &num.coeffs,
                0.0,
                h.a,
                h.b,
                value,
                unit(signal),
                &mut roots,
                iv,
            );
        }
    }
    out
}

/// Appends the sign intervals of the span `[a, b]` whose numerator has the Bernstein coefficients
/// `num` (coefficients within `zero` of 0 count as 0) and whose signal at span parameter `t` is
/// `value(t)` (times `unit` in the curve's units; NaN where undefined).
#[allow(clippy::too_many_arguments)]
pub(super) fn push_intervals(
    num: &[f64],
    zero: f64,
    a: f64,
    b: f64,
    value: impl Fn(f64) -> f64,
    unit: f64,
    roots: &mut Vec<f64>,
    out: &mut Vec<SignInterval>,
) {
    roots.clear();
    bernstein::sign_changes(num, zero, roots);
    let mut t0 = 0.0;
    for k in 0..=roots.len() {
        let t1 = roots.get(k).copied().unwrap_or(1.0);
        if t1 > t0 {
            if let Some((sign, peak)) = interval_peak(&value, t0, t1) {
                out.push(SignInterval {
                    u0: a + (b - a) * t0,
                    u1: a + (b - a) * t1,
                    sign,
                    peak: peak * unit,
                });
            }
        }
        t0 = t1;
    }
}

/// Sign and peak `|value|` on Chebyshev nodes inside `(t0, t1)`; `None` when the value is zero
/// or undefined at every node.
fn interval_peak(value: &impl Fn(f64) -> f64, t0: f64, t1: f64) -> Option<(i8, f64)> {
    let mut best: Option<(i8, f64)> = None;
    for k in 0..PEAK_NODES {
        let c = (std::f64::consts::PI * (k as f64 + 0.5) / PEAK_NODES as f64).cos();
        let v = value(t0 + (t1 - t0) * 0.5 * (1.0 - c));
        if !v.is_finite() || v == 0.0 {
            continue;
        }
        if best.is_none_or(|(_, m)| v.abs() > m) {
            best = Some((if v > 0.0 { 1 } else { -1 }, v.abs()));
        }
    }
    best
}
