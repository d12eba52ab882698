//! The `--report` JSON of a curve fit: the shape measures every method shares ([`shape_report`]) and
//! each method's own keys ([`lsq_report`], [`integrated_report`], [`fit_then_fair_report`]), merged by
//! [`with_method`].
//!
//! Key names are a public contract (scripts read them); a new key may be added, none renamed.

use crate::fair::{count_shape_exact, curve_fairness};
use crate::fit::screening::{OutlierMode, Screening};
use crate::fit::tolerance::FitResult;
use crate::fit::Deviation;
use crate::nurbs::NurbsCurve;
use crate::optim::{distinct_control_points, IntegratedResult};
use serde_json::{json, Value};

/// The exact curvature-extrema and inflection counts of `c` (`length` its arc length), each `null`
/// where only the sampled fallback exists (spatial curves: inflections are binormal reversals,
/// counted only by sampling), made in one pass ([`count_shape_exact`]).
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::report::curve::exact_shape_json;
/// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0)];
/// let parabola = NurbsCurve::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], pts.to_vec(), None).unwrap();
/// let (extrema, inflections) = exact_shape_json(&parabola, 2.96);
/// assert_eq!((extrema, inflections), (serde_json::json!(1), serde_json::json!(0)));
/// ```
pub fn exact_shape_json(c: &NurbsCurve, length: f64) -> (Value, Value) {
    let p = c.control_points();
    if p.iter().all(|q| *q == p[0]) {
        // a point: no curvature, so no extrema and no inflections (and no plane to count them in)
        return (json!(0), json!(0));
    }
    let exact = count_shape_exact(c, length);
    (
        if exact.extrema.exact {
            json!(exact.extrema.curvature_extrema)
        } else {
            Value::Null
        },
        if exact.inflections.exact {
            json!(exact.inflections.inflections)
        } else {
            Value::Null
        },
    )
}

/// The keys every method reports: the input's name, the degree, the point count, the length, F, the
/// largest F_j, the curvature extrema and inflections (sampled and exact) and the wall time.
pub fn shape_report(curve: &NurbsCurve, input: &str, points: usize, wall_seconds: f64) -> Value {
    let f = curve_fairness(curve);
    let (extrema_exact, inflections_exact) = exact_shape_json(curve, f.length);
    json!({
        "input": input,
        "degree": curve.degree(),
        "points": points,
        "length": f.length,
        "fairness": f.fairness,
        "max_span_fairness": f.max_span_fairness,
        "curvature_extrema": f.curvature_extrema,
        "curvature_extrema_exact": extrema_exact,
        "inflections": f.inflections,
        "inflections_exact": inflections_exact,
        "wall_seconds": wall_seconds,
    })
}

/// `base` with every key of `method` added (a key of both takes `method`'s value).
pub fn with_method(mut base: Value, method: &Value) -> Value {
    if let (Some(obj), Some(extra)) = (base.as_object_mut(), method.as_object()) {
        for (k, v) in extra {
            obj.insert(k.clone(), v.clone());
        }
    }
    base
}

/// The whole report of a least-squares fit (`--method lsq`); `knots` names the knot rule.
pub fn lsq_report(fit: &FitResult, input: &str, knots: &str, wall_seconds: f64) -> Value {
    let mut method = json!({
        "method": "lsq",
        "knots": knots,
        "closed": fit.closed,
        "corners": fit.corners,
        "control_points": fit.n_control_points,
        "tolerance": fit.tolerance,
        "max_deviation": fit.deviation.max,
        "rms_deviation": fit.deviation.rms,
        "solves": fit.solves,
        "smoothing_used": fit.smoothing_used,
        "fit_seconds": fit.fit_seconds,
    });
    if let Some(gap) = fit.closed_by_gap {
        method["closed_by_gap"] = json!(gap);
    }
    with_method(
        shape_report(&fit.curve, input, fit.points.len(), wall_seconds),
        &method,
    )
}

/// The keys of the integrated method: `closed` (whether the data were fitted as closed; with
/// `closed_by_gap`, the distance from the last point to the first, when they were closed across
/// that gap by [`crate::fit::closure`]), `span_fairness` the per-span target asked for and `seed` the
/// search's seed.
pub fn integrated_report(
    r: &IntegratedResult,
    closed: bool,
    span_fairness: Option<f64>,
    seed: u64,
) -> Value {
    let by_count: Vec<Value> = r
        .stats
        .fairness_by_count
        .iter()
        .map(|(n, f)| json!({"control_points": n, "fairness": f.is_finite().then_some(*f)}))
        .collect();
    let mut report = json!({
        "method": "integrated",
        "closed": closed,
        // a closed curve has no ends; a curve with corners keeps them pinned
        "ends": (!closed).then_some(if r.stats.free_ends { "free" } else { "pinned" }),
        "control_points": distinct_control_points(&r.curve),
        "tolerance": r.tolerance,
        "tolerance_met": r.met,
        "max_deviation": r.quality.max_deviation,
        "rms_deviation": r.quality.rms_deviation,
        "span_fairness_target": span_fairness,
        "log10_smoothing": r.log10_smoothing(),
        "lsq_baseline_control_points": r.baseline_control_points,
        "optimizer": {
            "seed": seed,
            "evaluations": r.stats.evaluations,
            "iterations": r.stats.iterations,
            "counts_tried": r.stats.counts_tried,
            "fairness_by_count": by_count,
            "polish_moves": r.stats.polish_moves,
            "seconds": r.stats.seconds,
        },
    });
    if !r.stats.degrees_tried.is_empty() {
        report["optimizer"]["degrees_tried"] = json!(r.stats.degrees_tried);
    }
    if let Some(gap) = r.closure.gap() {
        // closed although the last point does not repeat the first (`fit::closure`)
        report["closed_by_gap"] = json!(gap);
    }
    report
}

/// The warning of an integrated fit that missed what was asked (`None` when it met it): the
/// per-span fairness target when the curve is within the tolerance, else the tolerance.
pub fn integrated_warning(r: &IntegratedResult, span_fairness: Option<f64>) -> Option<String> {
    if r.met {
        return None;
    }
    Some(match span_fairness {
        Some(t) if r.quality.max_deviation <= r.tolerance => format!(
            "the span fairness target {t:.3e} was not met (largest F_j {:.3e})",
            r.quality.max_span_fairness
        ),
        _ => format!(
            "the tolerance {:.3e} was not met (max deviation {:.3e})",
            r.tolerance, r.quality.max_deviation
        ),
    })
}

/// The keys of `--method fit-then-fair`: `fit` the least-squares fit, `faired` the faired curve after
/// `moves` fairing moves, `deviation` its deviation from the fitted points.
pub fn fit_then_fair_report(
    fit: &FitResult,
    faired: &NurbsCurve,
    moves: usize,
    deviation: &Deviation,
    seed: u64,
) -> Value {
    let mut report = json!({
        "method": "fit-then-fair",
        "control_points": distinct_control_points(faired),
        "closed": fit.closed,
        "tolerance": fit.tolerance,
        "tolerance_met": deviation.max <= fit.tolerance,
        "max_deviation": deviation.max,
        "rms_deviation": deviation.rms,
        "lsq_fairness": curve_fairness(&fit.curve).fairness,
        "fairing_moves": moves,
        "seed": seed,
    });
    if let Some(gap) = fit.closed_by_gap {
        report["closed_by_gap"] = json!(gap);
    }
    report
}

/// The report's screening keys (`fit::screening`), added to `report` (an object): `noise_sigma`,
/// `noise_resolved` (whether the noise is white at two spacings, so that σ is credible),
/// `noise_limited`, `meaningful_tolerance` (the tolerance the noise allows, `null` when the
/// tolerance is above the noise), `tolerance` (the one asked for) and `tolerance_used` (the one
/// the fit holds, that `max_deviation` and `tolerance_met` refer to: the meaningful tolerance when
/// the asked one is noise limited, `fit::screening`), `outliers_mode` (`"auto"` or `"off"`) and `outliers` (`index` into
/// the distinct points, `distance`). The CLI and the Python package write the same keys.
pub fn add_screening(report: &mut Value, mode: OutlierMode, s: &Screening) {
    let Some(obj) = report.as_object_mut() else {
        return;
    };
    obj.insert("noise_sigma".into(), json!(s.noise_sigma));
    obj.insert("noise_resolved".into(), json!(s.noise_resolved));
    obj.insert("noise_limited".into(), json!(s.noise_limited.is_some()));
    obj.insert("meaningful_tolerance".into(), json!(s.noise_limited));
    // the method's `tolerance` is the one it held: the meaningful one when the asked one is below
    // the noise
    let held = obj.get("tolerance").cloned().unwrap_or(Value::Null);
    if s.noise_limited.is_some() {
        obj.insert("tolerance".into(), json!(s.tolerance));
    }
    obj.insert("tolerance_used".into(), held);
    let mode = match mode {
        OutlierMode::Off => "off",
        OutlierMode::Auto => "auto",
    };
    obj.insert("outliers_mode".into(), json!(mode));
    obj.insert("outliers".into(), json!(s.outliers));
}
