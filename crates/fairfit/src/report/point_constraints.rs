//! The report keys of a fit under weights and points to interpolate
//! ([`crate::fit::point_constraints`]): the constrained curve's shape and deviation replace the
//! method's, and `point_constraints` (each point to interpolate and its distance) and
//! `point_constraint_fit` (tolerances, refits, moves, the tightest weighted point, the points of
//! weight 0) are added. Indices are the caller's (its file rows or array rows).

use super::curve::shape_report;
use crate::fit::point_constraints::PointConstraintReport;
use crate::nurbs::NurbsCurve;
use serde_json::{json, Value};

/// Adds the keys of the constrained `curve` to the method's report `rep` (module doc): `pr` is
/// what the constraints achieved, `index[i]` the caller's index of fitted point `i`, `ignored` the
/// caller's indices of the points of weight 0, `input` the input's name.
pub fn add_point_constraints(
    rep: &mut Value,
    input: &str,
    curve: &NurbsCurve,
    pr: &PointConstraintReport,
    index: &[usize],
    ignored: &[usize],
) {
    let n_points = rep.get("points").and_then(|v| v.as_u64()).unwrap_or(0) as usize;
    let shape = shape_report(curve, input, n_points, 0.0);
    let Some(obj) = rep.as_object_mut() else {
        return;
    };
    if let Some(s) = shape.as_object() {
        for (k, v) in s.iter().filter(|(k, _)| *k != "wall_seconds") {
            obj.insert(k.clone(), v.clone());
        }
    }
    // the tolerance asked for (a refit's report has its tighter one)
    obj.insert("tolerance".into(), json!(pr.tolerance));
    obj.insert("max_deviation".into(), json!(pr.max_deviation));
    obj.insert("rms_deviation".into(), json!(pr.rms_deviation));
    obj.insert(
        "point_constraints".into(),
        json!(pr
            .interpolated
            .iter()
            .map(|&(i, d)| json!({"index": index[i], "distance": d}))
            .collect::<Vec<_>>()),
    );
    obj.insert(
        "point_constraint_fit".into(),
        json!({
            "tolerance": pr.tolerance,
            "fit_tolerance": pr.fit_tolerance,
            "refits": pr.refits,
            "moves": pr.moves,
            "weighted_ratio": pr.weighted_ratio,
            "ignored": ignored,
            "tightest": pr.tightest.map(|(i, d, allowed)| json!({
                "index": index[i], "distance": d, "allowed": allowed
            })),
        }),
    );
}
