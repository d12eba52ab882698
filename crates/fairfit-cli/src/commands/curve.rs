//! `fairfit curve`: fit a curve to ordered points within a tolerance.
//!
//! `--method integrated` (the default) is fairfit's integrated fitting and fairing (knot vector by
//! particle swarm optimisation, see `curve_optim.rs`); `--method lsq` is the least-squares pipeline of
//! `fairfit::fit` (parameterisation, knots added where the orthogonal error is largest, parameter
//! correction, knot removal, corners and closed curves); `--method fit-then-fair` fairs the
//! least-squares fit afterwards within the same tolerance. Writes the curve JSON (`-o`, else stdout) and an optional JSON report with
//! deviation, fairness and timing. A STEP or IGES curve is fitted through its dense samples and held to
//! the tolerance of the exact curve (`fairfit::fit::cad_fit`: refitted with points of it added while it
//! strays between the samples; a note and the report's `exact_curve` say how far it is).

use super::curve_args::{CurveArgs, DegreeArg, EndsArg, Method};
use super::curve_optim::{run_fit_then_fair, run_integrated, with_pool};
use super::info::exact_shape_json;
use super::outputs::{check_output_paths, prepare_outputs, OutputGeometry};
use super::{CliError, CmdResult};
use fairfit::fair::curve_fairness;
use fairfit::fit::cad_fit::{fit_to_exact, Fitted};
use fairfit::fit::SmoothingOrder;
use fairfit::io::atomic::write_all_atomic;
use fairfit::io::curve_to_json;
use fairfit::prelude::{fit_to_tolerance, FitOptions, FitResult, NurbsCurve, Tolerance, Vec3};
use serde_json::json;
use std::time::Instant;

/// Runs `fairfit curve`.
pub fn run(args: CurveArgs) -> CmdResult {
    let wall = Instant::now();
    let mut outputs: Vec<(&str, &std::path::Path)> = args
        .output
        .as_deref()
        .map(|p| ("-o", p))
        .into_iter()
        .collect();
    outputs.extend(args.report.as_deref().map(|p| ("--report", p)));
    outputs.extend(args.outputs.named());
    check_output_paths(&outputs, &[args.input.as_path()])?;
    if !(args.corner_angle.is_finite() && args.corner_angle > 0.0 && args.corner_angle <= 180.0) {
        return Err(CliError::usage(format!(
            "--corner-angle must be in (0, 180] degrees, got {}",
            args.corner_angle
        )));
    }
    if !(args.smoothing.is_finite() && args.smoothing >= 0.0) {
        return Err(CliError::usage(format!(
            "--smoothing must be a finite number >= 0, got {}",
            args.smoothing
        )));
    }
    if args.degree() == DegreeArg::Auto && args.method != Method::Integrated {
        return Err(CliError::usage("--degree auto needs --method integrated"));
    }
    if args.control_points.is_some() && args.method != Method::Integrated {
        return Err(CliError::usage(
            "--control-points needs --method integrated",
        ));
    }
    let conditions = args.end_conditions();
    for (c, flag) in [(&conditions.start, "--start"), (&conditions.end, "--end")] {
        if args.method != Method::Integrated && (c.point.is_some() || c.curvature.is_some()) {
            return Err(CliError::usage(format!(
                "{flag} with a point or a curvature needs --method integrated (lsq and fit-then-fair take tangent:X,Y[,Z])"
            )));
        }
    }
    if args.ends == EndsArg::Free && args.method != Method::Integrated {
        return Err(CliError::usage("--ends free needs --method integrated"));
    }
    let (set, cad) = super::cad_input::read_curve_points(&args.input, &args.cad)?;
    if set.dropped_duplicates > 0 {
        eprintln!(
            "warning: {}: dropped {} consecutive duplicate point(s)",
            args.input.display(),
            set.dropped_duplicates
        );
    }
    // more control points than data points leave the fit undetermined (and a huge count would run
    // the search for ever)
    if let Some(n) = args.control_points.filter(|&n| n > set.points.len()) {
        return Err(CliError::usage(format!(
            "--control-points {n} exceeds the {} distinct input points",
            set.points.len()
        )));
    }
    let opts = FitOptions {
        degree: args.degree().lowest(),
        parameterization: args.param.into(),
        tolerance: args.tolerance(),
        closed: args.closed_mode(),
        corner_angle_deg: (!args.no_corners).then_some(args.corner_angle),
        correction_rounds: args.correction_rounds,
        smoothing: args.smoothing,
        smoothing_order: if args.smoothing_order == 3 {
            SmoothingOrder::Third
        } else {
            SmoothingOrder::Second
        },
        knot_rule: args.knots.into(),
        start_tangent: conditions.start.tangent,
        end_tangent: conditions.end.tangent,
        ..FitOptions::default()
    };
    let want_report = args.report.is_some() || args.outputs.html.is_some();
    let (curve, report, points) = match cad {
        None => {
            let fit = fit_points(&args, &opts, &set.points, want_report, wall)?;
            (fit.curve, fit.extra, set.points)
        }
        Some(cad) => fit_cad(&args, &opts, cad, want_report, wall)?,
    };
    // Every file is made in memory first and written all or none.
    let mut files = Vec::new();
    let text = curve_to_json(&curve);
    let stdout_text = match &args.output {
        Some(p) => {
            files.push((p.clone(), text.into_bytes()));
            None
        }
        None => Some(text),
    };
    if let (Some(rp), Some(report)) = (&args.report, &report) {
        let body = super::json_pretty(report)?;
        files.push((rp.clone(), body.into_bytes()));
    }
    if args.outputs.any() {
        files.extend(prepare_outputs(
            OutputGeometry::Curve(&curve),
            Some(&points),
            report.as_ref(),
            &args.outputs,
        )?);
    }
    write_all_atomic(&files)?;
    if let Some(text) = stdout_text {
        super::print_stdout(&text)?;
    }
    Ok(())
}

/// One fit of `points` by the method asked for, with its report when `want_report`.
fn fit_points(
    args: &CurveArgs,
    opts: &FitOptions,
    points: &[Vec3],
    want_report: bool,
    wall: Instant,
) -> Result<Fitted<Option<serde_json::Value>>, CliError> {
    match args.method {
        Method::Lsq => {
            let fit = fit_to_tolerance(points, opts)?;
            if fit.smoothing_used != opts.smoothing {
                eprintln!(
                    "warning: the smoothing {:e} kept the tolerance out of reach; used {:e}",
                    opts.smoothing, fit.smoothing_used
                );
            }
            let report = want_report.then(|| report_json(args, &fit, wall.elapsed().as_secs_f64()));
            Ok(Fitted {
                tolerance: fit.tolerance,
                max_deviation: fit.deviation.max,
                curve: fit.curve,
                extra: report,
            })
        }
        Method::Integrated | Method::FitThenFair => {
            let out = with_pool(args.threads, || match args.method {
                Method::Integrated => run_integrated(args, points),
                _ => run_fit_then_fair(args, points, opts),
            })?;
            let field = |k: &str| out.report[k].as_f64().unwrap_or(f64::NAN);
            let (tolerance, max_deviation) = (field("tolerance"), field("max_deviation"));
            let report = want_report.then(|| {
                let f = curve_fairness(&out.curve);
                let (extrema_exact, inflections_exact) = exact_shape_json(&out.curve, f.length);
                let mut r = json!({
                    "input": args.input.display().to_string(),
                    "degree": out.curve.degree(),
                    "points": points.len(),
                    "length": f.length,
                    "fairness": f.fairness,
                    "max_span_fairness": f.max_span_fairness,
                    "curvature_extrema": f.curvature_extrema,
                    "curvature_extrema_exact": extrema_exact,
                    "inflections": f.inflections,
                    "inflections_exact": inflections_exact,
                    "wall_seconds": wall.elapsed().as_secs_f64(),
                });
                if let (Some(obj), Some(extra)) = (r.as_object_mut(), out.report.as_object()) {
                    for (k, v) in extra {
                        obj.insert(k.clone(), v.clone());
                    }
                }
                r
            });
            Ok(Fitted {
                curve: out.curve,
                tolerance,
                max_deviation,
                extra: report,
            })
        }
    }
}

/// The fit of a CAD curve, held to the tolerance of the exact curve (`fairfit::fit::cad_fit`): refitted
/// at a tighter tolerance, with points of the exact curve added, while the exact curve strays beyond
/// the tolerance between the samples. A note on stderr says how far the exact curve is from the fit;
/// the report gets `exact_curve` and keeps the tolerance asked for.
fn fit_cad(
    args: &CurveArgs,
    opts: &FitOptions,
    cad: super::cad_input::CadCurve,
    want_report: bool,
    wall: Instant,
) -> Result<FitOutput, CliError> {
    let r = fit_to_exact(&cad.segments, cad.samples, |points, tol| match tol {
        None => fit_points(args, opts, points, want_report, wall),
        Some(t) => {
            let mut tighter = args.clone();
            (tighter.tol, tighter.rel_tol) = (Some(t), None);
            let opts = FitOptions {
                tolerance: Tolerance::Absolute(t),
                ..opts.clone()
            };
            fit_points(&tighter, &opts, points, want_report, wall)
        }
    })?;
    super::note_exact_deviation(
        &args.input,
        "the exact curve",
        false,
        "fit",
        "the fit",
        &super::ExactDeviation {
            max_deviation: r.max_deviation,
            tolerance: r.tolerance,
            met: r.met,
            checked: r.checked,
            refits: r.refits,
            added: r.added,
            first_max_deviation: r.first_max_deviation,
            fit_tolerance: r.fit.tolerance,
        },
    );
    let mut report = r.fit.extra;
    if let Some(obj) = report.as_mut().and_then(|v| v.as_object_mut()) {
        obj.insert("tolerance".into(), json!(r.tolerance));
        if let Some(met) = obj.get("tolerance_met").and_then(|v| v.as_bool()) {
            obj.insert("tolerance_met".into(), json!(met && r.met));
        }
        obj.insert(
            "exact_curve".into(),
            json!({
                "max_deviation": r.max_deviation,
                "within_tolerance": r.met,
                "checked_points": r.checked,
                "first_max_deviation": r.first_max_deviation,
                "refits": r.refits,
                "fit_tolerance": r.fit.tolerance,
                "added_points": r.added,
            }),
        );
    }
    Ok((r.fit.curve, report, r.points))
}

/// A fitted curve, its report and the points it fitted.
type FitOutput = (NurbsCurve, Option<serde_json::Value>, Vec<Vec3>);

fn report_json(args: &CurveArgs, fit: &FitResult, wall_seconds: f64) -> serde_json::Value {
    let f = curve_fairness(&fit.curve);
    let (extrema_exact, inflections_exact) = exact_shape_json(&fit.curve, f.length);
    json!({
        "input": args.input.display().to_string(),
        "method": "lsq",
        "knots": format!("{:?}", args.knots).to_lowercase(),
        "degree": fit.curve.degree(),
        "points": fit.points.len(),
        "closed": fit.closed,
        "corners": fit.corners,
        "control_points": fit.n_control_points,
        "tolerance": fit.tolerance,
        "max_deviation": fit.deviation.max,
        "rms_deviation": fit.deviation.rms,
        "length": f.length,
        "fairness": f.fairness,
        "max_span_fairness": f.max_span_fairness,
        "curvature_extrema": f.curvature_extrema,
        "curvature_extrema_exact": extrema_exact,
        "inflections": f.inflections,
        "inflections_exact": inflections_exact,
        "solves": fit.solves,
        "smoothing_used": fit.smoothing_used,
        "fit_seconds": fit.fit_seconds,
        "wall_seconds": wall_seconds,
    })
}
