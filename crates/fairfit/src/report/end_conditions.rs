//! The `end_conditions` part of a curve report (`fairfit curve --start/--end`, the Python package's
//! `start=`/`end=`): per constrained end the continuity order asked for and the continuity achieved
//! (tangent angle in radians, relative curvature difference, distance from a given point), and what
//! the conditions cost: F of the curve against F of the same fit without them.
//!
//! The fit without conditions is the same method: for the integrated method at the constrained
//! curve's degree and control-point count ([`integrated_end_conditions`]); for least squares with at
//! most its control points, faired with the default options after a fit-then-fair
//! ([`lsq_end_conditions`]). A fit without conditions that fails reports `null`.

use crate::fair::{curve_fairness, fair_curve, FairingOptions};
use crate::fit::end_constraints::{achieved, EndConstraint, EndConstraints};
use crate::fit::{fit_to_tolerance, FitOptions};
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::{distinct_control_points, fit_integrated, IntegratedOptions, IntegratedResult};
use serde_json::{json, Value};

/// The continuity `curve` achieves at its start (`at_end` false) or end against `c`: the order
/// asked for, the tangent angle (radians), the relative curvature difference and the distance
/// from a given point (`null` for what the condition does not ask); `null` without a condition.
pub fn end_json(curve: &NurbsCurve, at_end: bool, c: &EndConstraint) -> Value {
    if c.is_none() {
        return Value::Null;
    }
    let a = achieved(curve, at_end, c);
    json!({
        "order": format!("g{}", c.order()),
        "tangent_angle": c.tangent.map(|_| a.tangent_angle),
        "curvature_relative": c.curvature.map(|_| a.curvature_relative),
        "point_distance": c.point.map(|_| a.point_distance),
    })
}

/// The `end_conditions` report: both ends ([`end_json`]), F of `curve` and F of the same fit
/// without the conditions (`f_free`, `null` when that fit failed) and their ratio, and the
/// control points of the fit without them (`n_free`).
pub fn end_conditions_json(
    curve: &NurbsCurve,
    conditions: &EndConstraints,
    f: f64,
    f_free: Option<f64>,
    n_free: Option<usize>,
) -> Value {
    json!({
        "start": end_json(curve, false, &conditions.start),
        "end": end_json(curve, true, &conditions.end),
        "fairness": f,
        "fairness_without_conditions": f_free,
        "fairness_cost_ratio": f_free.map(|g| f / g),
        "control_points_without_conditions": n_free,
    })
}

/// The `end_conditions` report of the integrated method's result `r` for `points` under `opts`:
/// the fit without the conditions runs at `r`'s degree and control-point count.
pub fn integrated_end_conditions(
    points: &[Vec3],
    opts: &IntegratedOptions,
    r: &IntegratedResult,
) -> Value {
    let mut free = opts.at_degree(r.curve.degree());
    free.end_conditions = Default::default();
    let n = distinct_control_points(&r.curve);
    let free = free.control_points(Some(n));
    let f_free = fit_integrated(points, &free)
        .ok()
        .map(|f| f.quality.fairness);
    end_conditions_json(
        &r.curve,
        &opts.end_conditions,
        r.quality.fairness,
        f_free,
        f_free.map(|_| n),
    )
}

/// The `end_conditions` report of least squares (`fairing` `None`) or fit-then-fair (the fairing of
/// the constrained fit): the fit without conditions is the same method with at most the constrained
/// curve's control points (`FitOptions::max_control_points`; the tolerance search may need fewer,
/// the report says how many), then faired with the default options.
pub fn lsq_end_conditions(
    points: &[Vec3],
    opts: &FitOptions,
    conditions: &EndConstraints,
    curve: &NurbsCurve,
    fairing: Option<&FairingOptions>,
) -> Value {
    let n = distinct_control_points(curve);
    let free_opts = FitOptions {
        start_tangent: None,
        end_tangent: None,
        end_conditions: EndConstraints::default(),
        max_control_points: n,
        ..opts.clone()
    };
    let free = fit_to_tolerance(points, &free_opts).ok().and_then(|fit| {
        let c = match fairing {
            None => fit.curve,
            Some(_) => {
                fair_curve(
                    &fit.curve,
                    points,
                    fit.tolerance,
                    &FairingOptions::default(),
                )
                .ok()?
                .curve
            }
        };
        Some(c)
    });
    let f = curve_fairness(curve).fairness;
    let f_free = free.as_ref().map(|c| curve_fairness(c).fairness);
    let n_free = free.as_ref().map(distinct_control_points);
    end_conditions_json(curve, conditions, f, f_free, n_free)
}

/// The fairing options of fit-then-fair under `conditions`: the control points that carry an end
/// condition never move (a point holds one, a tangent two, a curvature three).
pub fn held_fairing(conditions: &EndConstraints) -> FairingOptions {
    let held = |c: &EndConstraint| if c.is_none() { 0 } else { c.fixed_points() };
    FairingOptions {
        held: (held(&conditions.start), held(&conditions.end)),
        ..FairingOptions::default()
    }
}
