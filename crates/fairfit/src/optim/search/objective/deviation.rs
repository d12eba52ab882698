//! The orthogonal deviation of the data from the candidate curve: Newton projection of each point
//! from its own parameter (a planar fast path for flat data), with max and RMS totals and an early
//! exit once a bound is exceeded.

use super::power_form::{power_eval2, power_span_from};
use super::{EvalWorkspace, FitData};
use crate::nurbs::Vec3;

/// Max and RMS orthogonal deviation: Newton projection started at each point's own parameter
/// (fills `ws.foot_params` and `ws.dev2`).
pub(super) fn deviations(data: &FitData, start: &[f64], ws: &mut EvalWorkspace) -> (f64, f64) {
    deviations_bounded(data, start, f64::INFINITY, None, ws)
        .unwrap_or((f64::INFINITY, f64::INFINITY))
}

/// [`deviations`], giving up (`Err(bound)`) once `min(floor, max so far)` is certain to exceed the
/// violation `v` of `give_up = Some((tol, v))`: `bound / tol − 1 > v` (`floor` is the maximum
/// deviation the caller keeps if this pass is worse).
pub(super) fn deviations_bounded(
    data: &FitData,
    start: &[f64],
    floor: f64,
    give_up: Option<(f64, f64)>,
    ws: &mut EvalWorkspace,
) -> Result<(f64, f64), f64> {
    let m = data.points.len();
    ws.foot_params.clear();
    ws.foot_params.extend_from_slice(start);
    ws.dev2.clear();
    ws.dev2.resize(m, 0.0);
    with_projection!(data, ws, |proj| deviation_pass(
        data, start, floor, give_up, ws, proj
    ))
}

/// The loop of [`deviations_bounded`] with the projection `proj(k, u, ws, hint)` of point `k` from
/// `u` (`hint`: the span of the last evaluation).
#[inline(always)]
pub(super) fn deviation_pass(
    data: &FitData,
    start: &[f64],
    floor: f64,
    give_up: Option<(f64, f64)>,
    ws: &mut EvalWorkspace,
    proj: impl Fn(usize, f64, &EvalWorkspace, &mut usize) -> (f64, f64),
) -> Result<(f64, f64), f64> {
    let m = data.points.len();
    let mut hint = 0;
    let mut worst2 = 0.0f64;
    for k in 1..m.saturating_sub(1) {
        let (mut best, best_u) = proj(k, start[k], ws, &mut hint);
        if !data.bands.is_none() {
            // the weighted deviation (`PointBands`)
            best *= data.bands.factor(k).powi(2);
        }
        ws.foot_params[k] = best_u;
        ws.dev2[k] = best;
        if best > worst2 {
            worst2 = best;
            if let Some((tol, v)) = give_up {
                let bound = floor.min(worst2.sqrt());
                if bound / tol - 1.0 > v {
                    return Err(bound);
                }
            }
        }
    }
    Ok(deviation_totals(&ws.dev2))
}

/// `(max, rms)` of the distances whose squares are `dev2` (ends included as zeros).
pub(super) fn deviation_totals(dev2: &[f64]) -> (f64, f64) {
    let m = dev2.len();
    let (mut max_d, mut sum2) = (0.0f64, 0.0);
    for &d in dev2.iter().take(m.saturating_sub(1)).skip(1) {
        max_d = max_d.max(d);
        sum2 += d;
    }
    (max_d.sqrt(), (sum2 / m as f64).sqrt())
}

/// Squared orthogonal distance and foot parameter of data point `k` by at most three Newton steps
/// from `u`; `hint` is the span of the last evaluation (updated).
#[inline]
pub(super) fn project(
    data: &FitData,
    k: usize,
    mut u: f64,
    ws: &EvalWorkspace,
    hint: &mut usize,
) -> (f64, f64) {
    let p = data.degree;
    let (breaks, coef) = (&ws.breaks, &ws.coef);
    let mut eval = |u: f64, d: &mut [Vec3; 4]| {
        let j = power_span_from(breaks, u, *hint);
        *hint = j;
        power_eval2(coef, p, j, u - breaks[j], d);
    };
    let mut d = [Vec3::default(); 4];
    let qk = data.points[k];
    eval(u, &mut d);
    // any curve point bounds the orthogonal distance from above; Newton steps tighten it
    let mut best = (d[0] - qk).norm_squared();
    let mut best_u = u;
    for _ in 0..3 {
        let diff = d[0] - qk;
        let f = d[1].dot(diff);
        let fp = d[2].dot(diff) + d[1].norm_squared();
        if fp.is_nan() || fp <= 0.0 {
            break;
        }
        let step = (-f / fp).clamp(-0.05, 0.05);
        u = (u + step).clamp(0.0, 1.0);
        eval(u, &mut d);
        let dist2 = (d[0] - qk).norm_squared();
        if dist2 < best {
            best = dist2;
            best_u = u;
        }
        // Newton converges quadratically: after a step this small the foot is exact to ~1e-12
        if step.abs() < 1e-6 {
            break;
        }
    }
    (best, best_u)
}

/// Whether the curve in `ws` lies in the xy plane with the data (every power-form coefficient has
/// `z = 0`), so that [`project_planar_any`] gives what [`project`] gives.
pub(super) fn is_flat(data: &FitData, ws: &EvalWorkspace) -> bool {
    data.planar && ws.coef.iter().all(|c| c[2] == 0.0)
}

/// Value, first and second derivative (x, y) at `u` of the planar power form by Horner, as
/// [`power_eval2`]; `hint` is the span of the last evaluation (updated).
#[inline(always)]
pub(super) fn planar_eval2(
    breaks: &[f64],
    coef: &[Vec3],
    p: usize,
    u: f64,
    hint: &mut usize,
) -> [[f64; 2]; 3] {
    let j = power_span_from(breaks, u, *hint);
    *hint = j;
    let t = u - breaks[j];
    let c = &coef[j * (p + 1)..(j + 1) * (p + 1)];
    let mut v = [[c[p][0], c[p][1]], [0.0; 2], [0.0; 2]];
    for ck in c[..p].iter().rev() {
        for a in 0..2 {
            v[2][a] = v[2][a] * t + v[1][a];
            v[1][a] = v[1][a] * t + v[0][a];
            v[0][a] = v[0][a] * t + ck[a];
        }
    }
    v[2] = [v[2][0] * 2.0, v[2][1] * 2.0];
    v
}

/// [`project`] for a curve and data in the xy plane: the same Newton steps on two coordinates (the
/// z terms it leaves out are exact zeros, so the feet and distances are the same), for degree `p`
/// (always inlined, so a constant `p` unrolls the Horner loops; the arithmetic is the same for a
/// constant and a run-time `p`).
#[inline(always)]
pub(super) fn project_planar_any(
    data: &FitData,
    p: usize,
    k: usize,
    mut u: f64,
    ws: &EvalWorkspace,
    hint: &mut usize,
) -> (f64, f64) {
    let (breaks, coef) = (&ws.breaks[..], &ws.coef[..]);
    let q = data.points[k];
    let (qx, qy) = (q[0], q[1]);
    let mut d = planar_eval2(breaks, coef, p, u, hint);
    let dist2 = |d: &[[f64; 2]; 3]| {
        let (x, y) = (d[0][0] - qx, d[0][1] - qy);
        x * x + y * y
    };
    let mut best = dist2(&d);
    let mut best_u = u;
    for _ in 0..3 {
        let (x, y) = (d[0][0] - qx, d[0][1] - qy);
        let f = d[1][0] * x + d[1][1] * y;
        let fp = (d[2][0] * x + d[2][1] * y) + (d[1][0] * d[1][0] + d[1][1] * d[1][1]);
        if fp.is_nan() || fp <= 0.0 {
            break;
        }
        let step = (-f / fp).clamp(-0.05, 0.05);
        u = (u + step).clamp(0.0, 1.0);
        d = planar_eval2(breaks, coef, p, u, hint);
        let d2 = dist2(&d);
        if d2 < best {
            best = d2;
            best_u = u;
        }
        if step.abs() < 1e-6 {
            break;
        }
    }
    (best, best_u)
}
