//! `fit_curve`: one curve fit by the method asked for, with the report `fairfit curve --report` writes
//! (the same keys, made the same way), run without the GIL in a local rayon pool.

use crate::constrained::{constraints_of_points, fit_constrained};
use crate::convert::points_from_array;
use crate::curve::Curve;
use crate::options::{
    fit_options, integrated_options, parse_degree, parse_end, parse_ends, parse_knots,
    parse_method, parse_outliers, parse_param, CurveSettings, Method,
};
use fairfit::fair::fair_curve;
use fairfit::fit::max_orthogonal_deviation;
use fairfit::fit::points::{drop_consecutive_duplicates, kept_point_of_each};
use fairfit::fit::screening::{screen_input, spikes_note, OutlierMode};
use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions};
use fairfit::io::limits::{ReadLimits, DEFAULT_MAX_POINTS};
use fairfit::io::points::MIN_POINTS;
use fairfit::optim::{
    distinct_control_points, fit_integrated, pareto_front_of_result, ParetoCurve,
};
use fairfit::report::curve::{
    add_screening, fit_then_fair_report, integrated_report, integrated_warning, lsq_report,
    shape_report, with_method,
};
use fairfit::report::end_conditions::{
    held_fairing, integrated_end_conditions, lsq_end_conditions,
};
use fairfit::{NurbsCurve, Vec3};
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;
use serde_json::Value;
use std::time::Instant;

/// A fitted curve, its report and the warnings the CLI prints on stderr.
pub struct Fitted {
    /// The curve.
    pub curve: NurbsCurve,
    /// The report (the keys of `fairfit curve --report`).
    pub report: Value,
    /// Warnings (`warning: ` lines of the CLI, without the prefix).
    pub warnings: Vec<String>,
    /// The Pareto front of (max deviation, F) when asked for (`fairfit curve --pareto`), by
    /// increasing deviation; empty otherwise.
    pub front: Vec<ParetoCurve>,
}

/// The extension's `fit_curve` (the Python wrapper `fairfit.fit_curve` documents it): returns the
/// curve, the warnings and the Pareto front.
#[pyfunction]
#[pyo3(signature = (points, tol, rel_tol, method, degree, control_points, closed, corner_angle,
    ends, seed, threads, band_fairing, span_fairness, param, knots, correction_rounds, smoothing,
    smoothing_order, start_tangent, end_tangent, input_name, pareto=false, outliers="auto",
    start=None, end=None, max_points=DEFAULT_MAX_POINTS, weights=None, interpolate=None))]
#[allow(clippy::too_many_arguments)] // one argument per keyword of the Python signature
pub fn fit_curve(
    py: Python<'_>,
    points: PyReadonlyArray2<'_, f64>,
    tol: Option<f64>,
    rel_tol: f64,
    method: &str,
    degree: &str,
    control_points: Option<usize>,
    closed: Option<bool>,
    corner_angle: Option<f64>,
    ends: &str,
    seed: u64,
    threads: Option<usize>,
    band_fairing: bool,
    span_fairness: Option<f64>,
    param: &str,
    knots: &str,
    correction_rounds: usize,
    smoothing: f64,
    smoothing_order: u8,
    start_tangent: Option<[f64; 3]>,
    end_tangent: Option<[f64; 3]>,
    input_name: Option<String>,
    pareto: bool,
    outliers: &str,
    start: Option<&str>,
    end: Option<&str>,
    max_points: usize,
    weights: Option<Vec<f64>>,
    interpolate: Option<Vec<usize>>,
) -> PyResult<(Curve, Vec<String>, Vec<Curve>)> {
    let wall = Instant::now();
    let settings = CurveSettings {
        method: parse_method(method).map_err(crate::py_err)?,
        tol,
        rel_tol,
        degree: parse_degree(degree).map_err(crate::py_err)?,
        control_points,
        closed,
        corner_angle,
        free_ends: parse_ends(ends).map_err(crate::py_err)?,
        seed,
        band_fairing,
        span_fairness,
        param: parse_param(param).map_err(crate::py_err)?,
        knots: parse_knots(knots).map_err(crate::py_err)?,
        knots_name: knots.to_string(),
        correction_rounds,
        smoothing,
        smoothing_order,
        start: parse_end("start", start, start_tangent).map_err(crate::py_err)?,
        end: parse_end("end", end, end_tangent).map_err(crate::py_err)?,
        outliers: parse_outliers(outliers).map_err(crate::py_err)?,
        pareto,
        search_constraints: Default::default(),
    };
    settings.check().map_err(crate::py_err)?;
    let input = input_name.unwrap_or_else(|| "<array>".into());
    let limits = ReadLimits {
        max_points,
        ..ReadLimits::current()
    };
    limits
        .check_points(&input, points.as_array().nrows(), "points")
        .map_err(|e| crate::py_err(e.to_string().replace("--max-points N", "max_points=N")))?;
    let (raw, dim) = points_from_array(&points, &input)?;
    let constrained = weights.is_some() || interpolate.as_ref().is_some_and(|i| !i.is_empty());
    let fitted = crate::guarded(py, move || {
        let (points, dropped) = drop_consecutive_duplicates(&raw);
        if points.len() < MIN_POINTS {
            return Err(fairfit::Error::InvalidData(format!(
                "{input}: at least {MIN_POINTS} distinct points are needed, found {}",
                points.len()
            ))
            .to_string());
        }
        settings.check_points(points.len())?;
        let mut fitted = if constrained {
            let kept = kept_point_of_each(&raw);
            let pc = constraints_of_points(weights, interpolate, raw.len(), &kept)?;
            let mut rows = vec![0usize; points.len()];
            for (r, &k) in kept.iter().enumerate().rev() {
                rows[k] = r;
            }
            fit_constrained(&settings, &input, &points, &pc, &rows, wall, threads)?
        } else {
            fit_screened(&settings, &input, points, wall, threads)?
        };
        if dropped > 0 {
            fitted.warnings.insert(
                0,
                format!("{input}: dropped {dropped} consecutive duplicate point(s)"),
            );
        }
        Ok(fitted)
    })?;
    let front = fitted
        .front
        .into_iter()
        .map(|m| {
            let report = pareto_member_report(&m);
            Curve::new(m.curve, dim, Some(report))
        })
        .collect();
    Ok((
        Curve::new(fitted.curve, dim, Some(fitted.report)),
        fitted.warnings,
        front,
    ))
}

/// The screening stage of `fairfit curve` (`fairfit::fit::screening::screen_input`: noise
/// measured, spikes excluded with `outliers="auto"`, a tolerance below the noise raised), then the
/// fit of the kept points, with the CLI's report keys and warnings; with `outliers="off"`, a fit
/// that misses the tolerance because of spikes names them (in its error, or in a warning).
pub fn fit_screened(
    s: &CurveSettings,
    input: &str,
    points: Vec<Vec3>,
    wall: Instant,
    threads: Option<usize>,
) -> Result<Fitted, String> {
    let screened = screen_input(points, s.tolerance(), s.outliers);
    let mut warnings: Vec<String> = screened
        .warning()
        .map(|w| w.trim_start_matches("warning: ").to_string())
        .into_iter()
        .collect();
    let opts = fit_options(s, screened.fit_tolerance());
    let points = &screened.points;
    let spikes = |tol: f64| {
        (s.outliers == OutlierMode::Off)
            .then(|| spikes_note(points, tol))
            .flatten()
            .map(|n| format!("{n}; outliers='auto' excludes them"))
    };
    let mut fitted = fit_points(s, input, &opts, points, wall, threads).map_err(|e| {
        // a refused setting is the caller's (the CLI's usage error), not the data's
        let setting = e.starts_with("invalid option ");
        match screened
            .absolute_tolerance()
            .filter(|_| !setting)
            .and_then(spikes)
        {
            Some(note) => format!("{e}; {note}"),
            None => e,
        }
    })?;
    warnings.append(&mut fitted.warnings);
    let field = |k: &str| fitted.report[k].as_f64().unwrap_or(f64::NAN);
    let (tolerance, max_deviation) = (field("tolerance"), field("max_deviation"));
    if max_deviation > tolerance {
        warnings.extend(spikes(tolerance));
    }
    if let Some(sc) = &screened.screening {
        add_screening(&mut fitted.report, s.outliers, sc);
    }
    fitted.warnings = warnings;
    Ok(fitted)
}

/// One fit of `points` by the method of `s` with the least-squares options `opts`, with its report
/// (`fairfit curve`'s `fit_points`).
pub fn fit_points(
    s: &CurveSettings,
    input: &str,
    opts: &FitOptions,
    points: &[Vec3],
    wall: Instant,
    threads: Option<usize>,
) -> Result<Fitted, String> {
    if s.method == Method::Lsq {
        return fit_lsq(s, input, opts, points, wall);
    }
    let (curve, method_report, warnings, front) = crate::with_pool(threads, || match s.method {
        Method::Integrated => run_integrated(s, points),
        _ => run_fit_then_fair(s, points, opts),
    })?;
    let base = shape_report(&curve, input, points.len(), wall.elapsed().as_secs_f64());
    let report = with_method(base, &method_report);
    Ok(Fitted {
        curve,
        report,
        warnings,
        front,
    })
}

/// `method="lsq"`.
fn fit_lsq(
    s: &CurveSettings,
    input: &str,
    opts: &FitOptions,
    points: &[Vec3],
    wall: Instant,
) -> Result<Fitted, String> {
    let fit = fit_to_tolerance(points, opts).map_err(|e| e.to_string())?;
    let mut warnings = Vec::new();
    if fit.smoothing_used != opts.smoothing {
        warnings.push(format!(
            "the smoothing {:e} kept the tolerance out of reach; used {:e}",
            opts.smoothing, fit.smoothing_used
        ));
    }
    let mut report = lsq_report(&fit, input, &s.knots_name, wall.elapsed().as_secs_f64());
    let conditions = s.end_conditions();
    if !conditions.is_none() {
        report["end_conditions"] = lsq_end_conditions(points, opts, &conditions, &fit.curve, None);
    }
    Ok(Fitted {
        curve: fit.curve,
        report,
        warnings,
        front: Vec::new(),
    })
}

/// The curve, the method part of its report, the warnings and the Pareto front (empty unless asked).
type MethodOutput = (NurbsCurve, Value, Vec<String>, Vec<ParetoCurve>);

/// `method="integrated"` (`fairfit curve`'s `run_integrated`), with the Pareto front when
/// `s.pareto` (the report's `pareto_members` its size, as `--pareto` writes it).
fn run_integrated(s: &CurveSettings, points: &[Vec3]) -> Result<MethodOutput, String> {
    let opts = integrated_options(s);
    let r = fit_integrated(points, &opts).map_err(|e| e.to_string())?;
    let mut report = integrated_report(&r, r.closure.is_closed(), s.span_fairness, s.seed);
    if !opts.end_conditions.is_none() {
        report["end_conditions"] = integrated_end_conditions(points, &opts, &r);
    }
    let front = if s.pareto {
        let front = pareto_front_of_result(points, &opts, &r).map_err(|e| e.to_string())?;
        report["pareto_members"] = front.len().into();
        front
    } else {
        Vec::new()
    };
    let warnings = integrated_warning(&r, s.span_fairness)
        .into_iter()
        .collect();
    Ok((r.curve, report, warnings, front))
}

/// `method="fit-then-fair"` (`fairfit curve`'s `run_fit_then_fair`): the control points that carry
/// end conditions never move.
fn run_fit_then_fair(
    s: &CurveSettings,
    points: &[Vec3],
    fit_opts: &FitOptions,
) -> Result<MethodOutput, String> {
    let fit = fit_to_tolerance(points, fit_opts).map_err(|e| e.to_string())?;
    let conditions = s.end_conditions();
    let fairing = held_fairing(&conditions);
    let faired =
        fair_curve(&fit.curve, points, fit.tolerance, &fairing).map_err(|e| e.to_string())?;
    let dev = max_orthogonal_deviation(&faired.curve, &fit.points, &fit.params);
    let mut report = fit_then_fair_report(&fit, &faired.curve, faired.iterations, &dev, s.seed);
    if !conditions.is_none() {
        report["end_conditions"] =
            lsq_end_conditions(points, fit_opts, &conditions, &faired.curve, Some(&fairing));
    }
    Ok((faired.curve, report, Vec::new(), Vec::new()))
}

/// The report of a Pareto front member: the columns of `fairfit curve --pareto`'s CSV.
fn pareto_member_report(m: &ParetoCurve) -> Value {
    serde_json::json!({
        "control_points": distinct_control_points(&m.curve),
        "max_deviation": m.quality.max_deviation,
        "rms_deviation": m.quality.rms_deviation,
        "fairness": m.quality.fairness,
        "max_span_fairness": m.quality.max_span_fairness,
    })
}
