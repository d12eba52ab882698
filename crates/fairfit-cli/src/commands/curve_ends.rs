//! The end conditions of `fairfit curve` that are read from files (`--start-from FILE[:end]`,
//! `--end-from FILE[:start]` with `--continuity`), and the report of a fit under end conditions
//! (`end_conditions`: the continuity achieved at each constrained end and what the conditions cost
//! in fairness F).
//!
//! A condition taken from a curve's end is its position, unit tangent and curvature vector there
//! (`EndConstraint::from_curve_end`), up to the order `--continuity` asks for. The tangent is
//! oriented along the new curve's travel: a curve that starts where FILE's curve ends continues in
//! its direction; one that starts where FILE's curve starts leaves it, in the opposite direction.

use super::curve_args::{split_from, CurveArgs};
use super::CliError;
use fairfit::fair::{curve_fairness, fair_curve, FairingOptions};
use fairfit::fit::end_constraints::{achieved, EndConstraint, EndConstraints};
use fairfit::io::{read_geometry, Geometry};
use fairfit::optim::distinct_control_points;
use fairfit::prelude::{fit_to_tolerance, FitOptions, NurbsCurve, Vec3};
use serde_json::{json, Value};

/// `args` with `--start-from` / `--end-from` read into [`CurveArgs::resolved_ends`] (with the
/// other end's text condition), or `None` when neither is given. A file that cannot be read, or
/// holds no curve, is an input error (exit 1).
pub fn with_ends_from_files(args: &CurveArgs) -> Result<Option<CurveArgs>, CliError> {
    if args.start_from.is_none() && args.end_from.is_none() {
        return Ok(None);
    }
    let mut ends = args.end_conditions();
    let order = args.continuity.order();
    if let Some(s) = &args.start_from {
        ends.start = condition_from(s, true, false, order, "--start-from")?;
    }
    if let Some(s) = &args.end_from {
        ends.end = condition_from(s, false, true, order, "--end-from")?;
    }
    let mut out = args.clone();
    out.resolved_ends = Some(ends);
    Ok(Some(out))
}

/// The condition at the start (`at_new_end` false) or end of the new curve from the value `s`
/// (`FILE[:start|:end]`, `default_end` the end of FILE's curve taken without a suffix).
fn condition_from(
    s: &str,
    default_end: bool,
    at_new_end: bool,
    order: usize,
    flag: &str,
) -> Result<EndConstraint, CliError> {
    let (path, file_end) = split_from(s, default_end);
    let curve = match read_geometry(&path).map_err(|e| CliError::new(e.to_string()))? {
        Geometry::Curve(c) => c,
        Geometry::Surface(_) => {
            return Err(CliError::new(format!(
                "{flag} {}: holds a surface, not a curve",
                path.display()
            )))
        }
    };
    let mut c = EndConstraint::from_curve_end(&curve, file_end, order).ok_or_else(|| {
        CliError::new(format!(
            "{flag} {}: the curve has no tangent at its {} (zero derivative)",
            path.display(),
            if file_end { "end" } else { "start" }
        ))
    })?;
    // continuing (start at its end, or end at its start) keeps its direction; otherwise reversed
    if file_end == at_new_end {
        c.tangent = c.tangent.map(|t| -t);
    }
    Ok(c)
}

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

/// The `end_conditions` report of `--method lsq` (`fairing` `None`) or `fit-then-fair` (the
/// fairing of the constrained fit): the fit without conditions is the same method with at most
/// the constrained curve's control points (`FitOptions::max_control_points`; the tolerance search
/// may need fewer, the report says how many), then faired with the default options.
pub fn lsq_end_conditions_report(
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
