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

use super::curve_args::{CurveArgs, DegreeArg, EndsArg, KnotArg, Method, OutliersArg, ParamArg};
use super::curve_optim::{run_fit_then_fair, run_integrated, with_pool};
use super::files::{check_outputs, commit, Inputs, Output, OutputFolder};
use super::outputs::{check_output_formats, prepare_outputs, OutputGeometry};
use super::{CliError, CmdResult};
use fairfit::fit::cad_fit::{fit_to_exact, Fitted};
use fairfit::fit::method::{Method as LibMethod, MethodOption};
use fairfit::fit::points::absolute_tolerance;
use fairfit::fit::screening::{self, screen_input, OutlierMode, Screening};
use fairfit::fit::SmoothingOrder;
use fairfit::io::curve_to_json;
use fairfit::prelude::{fit_to_tolerance, FitOptions, FitResult, NurbsCurve, Tolerance, Vec3};
use fairfit::report::curve::{add_screening, lsq_report, shape_report, with_method};
use serde_json::json;
use std::time::Instant;

/// Runs `fairfit curve`.
pub fn run(args: CurveArgs) -> CmdResult {
    let wall = Instant::now();
    check_curve_outputs(&args)?;
    check_options(&args)?;
    let want_report = args.report.is_some() || args.outputs.html.is_some();
    let new_folder = args.pareto_curves.as_ref().filter(|d| !d.exists());
    let (curve, report, points, pareto) = fit_input(&args, want_report, wall)?;
    // Every file is made in memory first and written all or none.
    let mut files = vec![Output::geometry(
        args.output.clone().unwrap_or_else(|| "-".into()),
        curve_to_json(&curve).into_bytes(),
    )];
    if let (Some(rp), Some(report)) = (&args.report, &report) {
        let body = super::json_pretty(report)?;
        files.push(Output::new(rp, body.into_bytes()));
    }
    files.extend(pareto);
    if args.outputs.any() {
        files.extend(
            prepare_outputs(
                OutputGeometry::Curve(&curve),
                Some(&points),
                report.as_ref(),
                &args.outputs,
            )?
            .into_iter()
            .map(|(p, b)| Output::new(p, b)),
        );
    }
    if let Some(d) = new_folder {
        std::fs::create_dir_all(d)
            .map_err(|e| CliError::new(fairfit::Error::io(d, &e).to_string()))?;
    }
    commit(files).inspect_err(|_| {
        if let Some(d) = new_folder {
            let _ = std::fs::remove_dir(d); // the folder made for the front's curves, if still empty
        }
    })
}

/// Refuses option values and combinations `fairfit curve` does not accept (usage errors), before any
/// input is read.
pub fn check_options(args: &CurveArgs) -> CmdResult {
    check_method_options(args)?;
    super::curve_points::check_options(args)?;
    fairfit::fit::shape::check_corner_angle(args.corner_angle)
        .map_err(|e| CliError::usage(format!("--corner-angle {}", super::setting_reason(e))))?;
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
    if args.ends == EndsArg::Free && args.method != Method::Integrated {
        return Err(CliError::usage("--ends free needs --method integrated"));
    }
    Ok(())
}

/// Reads `args.input` and fits it as `args` ask: the curve, its report when `want_report` (`wall`
/// started when the run did), the points it fitted and the Pareto files. Warnings are queued
/// (`diag!`).
pub fn fit_input(
    args: &CurveArgs,
    want_report: bool,
    wall: Instant,
) -> Result<FitOutput, CliError> {
    let resolved;
    let args = match super::curve_ends::with_ends_from_files(args)? {
        Some(a) => {
            resolved = a;
            &resolved
        }
        None => args,
    };
    let (set, cad, constraints) = super::curve_points::read_input(args)?;
    if set.dropped_duplicates > 0 {
        diag!(
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
    let conditions = args.end_conditions();
    // lsq and fit-then-fair: a tangent alone keeps the least-squares pipeline's end derivative (its
    // length from the data's speed); a point or a curvature makes every condition exact
    let exact = [&conditions.start, &conditions.end]
        .iter()
        .any(|c| c.point.is_some() || c.curvature.is_some());
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
        start_tangent: conditions.start.tangent.filter(|_| !exact),
        end_tangent: conditions.end.tangent.filter(|_| !exact),
        end_conditions: if exact {
            conditions
        } else {
            Default::default()
        },
        ..FitOptions::default()
    };
    match cad {
        None => {
            // the screening stage (`fairfit::fit::screening`): noise measured, spikes excluded
            // with `--outliers auto`; a tolerance below the noise: every method fits to the
            // meaningful one (the integrated method's own screening does the same). Point
            // constraints index the file's points, so they keep every point beside the screening.
            let constrained = !constraints.constraints.is_none();
            let all = constrained.then(|| set.points.clone());
            let screened = screen_input(set.points, args.tolerance(), outlier_mode(args));
            if let Some(w) = screened.warning() {
                diag!("{w}");
            }
            let opts = FitOptions {
                tolerance: screened.fit_tolerance(),
                ..opts
            };
            let (points, screening) = (screened.points, screened.screening);
            if let Some(all) = all {
                return fit_with_constraints(
                    args,
                    &opts,
                    &all,
                    screening,
                    &constraints,
                    want_report,
                    wall,
                );
            }
            let fit = fit_points(args, &opts, &points, want_report, wall);
            let fit = fit.map_err(|e| name_spikes(args, &points, e))?;
            if args.outliers == OutliersArg::Off && fit.max_deviation > fit.tolerance {
                if let Some(note) = spikes_note(&points, fit.tolerance) {
                    diag!("warning: {note}");
                }
            }
            let (mut report, pareto) = fit.extra;
            if let (Some(r), Some(sc)) = (report.as_mut(), screening.as_ref()) {
                add_screening(r, outlier_mode(args), sc);
            }
            Ok((fit.curve, report, points, pareto))
        }
        Some(cad) => fit_cad(args, &opts, cad, want_report, wall),
    }
}

/// The outputs of `fairfit curve`, checked before any work (`files::check_outputs`): `-o` (stdout
/// when absent), `--report`, `--pareto`, the CAD, mesh, plot and HTML outputs, and the folder
/// `--pareto-curves` (its `front_NNN.json` files).
fn check_curve_outputs(args: &CurveArgs) -> CmdResult {
    let stdout = std::path::Path::new("-");
    let mut outputs: Vec<(&str, &std::path::Path)> =
        vec![("-o", args.output.as_deref().unwrap_or(stdout))];
    outputs.extend(args.report.as_deref().map(|p| ("--report", p)));
    outputs.extend(args.pareto.as_deref().map(|p| ("--pareto", p)));
    outputs.extend(args.outputs.named());
    let from: Vec<std::path::PathBuf> = [(&args.start_from, true), (&args.end_from, false)]
        .into_iter()
        .filter_map(|(f, d)| f.as_deref().map(|f| super::curve_args::split_from(f, d).0))
        .chain(args.weights.clone())
        .collect();
    let folders: Vec<OutputFolder<'_>> = args
        .pareto_curves
        .as_deref()
        .map(|path| OutputFolder {
            flag: "--pareto-curves",
            path,
            writes: is_front_file,
        })
        .into_iter()
        .collect();
    check_outputs(
        &outputs,
        &folders,
        &Inputs::files(
            std::iter::once(args.input.as_path())
                .chain(from.iter().map(|p| p.as_path()))
                .collect(),
        ),
    )?;
    check_output_formats(&outputs)
}

/// Whether `--pareto-curves` writes a file of this name (`front_000.json`, ...).
fn is_front_file(name: &str) -> bool {
    name.strip_prefix("front_")
        .and_then(|r| r.strip_suffix(".json"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// Refuses (a usage error) an option the chosen method would ignore.
fn check_method_options(args: &CurveArgs) -> CmdResult {
    let given = |option: MethodOption, set: bool| set.then_some(option);
    let method = LibMethod::from(args.method);
    let ignored = method.first_ignored(
        [
            given(MethodOption::Knots, args.knots != KnotArg::Refine),
            given(MethodOption::Param, args.param != ParamArg::Centripetal),
            given(MethodOption::CorrectionRounds, args.correction_rounds != 0),
            given(MethodOption::Smoothing, args.smoothing != 0.0),
            given(MethodOption::SmoothingOrder, args.smoothing_order != 2),
            given(MethodOption::SpanFairness, args.span_fairness.is_some()),
            given(MethodOption::Pareto, args.pareto.is_some()),
            given(MethodOption::ParetoCurves, args.pareto_curves.is_some()),
            given(MethodOption::BandFairing, args.no_band_fairing),
        ]
        .into_iter()
        .flatten(),
    );
    if let Some(option) = ignored {
        let uses: Vec<String> = option
            .methods()
            .iter()
            .map(|m| format!("--method {m}"))
            .collect();
        return Err(CliError::usage(format!(
            "{} has no effect with --method {method}; it needs {}",
            flag(option),
            uses.join(" or ")
        )));
    }
    if args.pareto_curves.is_some() && args.pareto.is_none() {
        return Err(CliError::usage("--pareto-curves needs --pareto"));
    }
    Ok(())
}

/// The flag of a method-specific option.
fn flag(option: MethodOption) -> &'static str {
    match option {
        MethodOption::Knots => "--knots",
        MethodOption::Param => "--param",
        MethodOption::CorrectionRounds => "--correction-rounds",
        MethodOption::Smoothing => "--smoothing",
        MethodOption::SmoothingOrder => "--smoothing-order",
        MethodOption::SpanFairness => "--span-fairness",
        MethodOption::Pareto => "--pareto",
        MethodOption::ParetoCurves => "--pareto-curves",
        MethodOption::BandFairing => "--no-band-fairing",
    }
}

/// One fit of `points` by the method asked for, with its report when `want_report`.
fn fit_points(
    args: &CurveArgs,
    opts: &FitOptions,
    points: &[Vec3],
    want_report: bool,
    wall: Instant,
) -> Result<Fitted<MethodExtra>, CliError> {
    match args.method {
        Method::Lsq => {
            let fit =
                crate::progress::with_spinner("least squares", || fit_to_tolerance(points, opts))
                    .map_err(|e| super::curve_optim::cli_error(e, args))?;
            if fit.smoothing_used != opts.smoothing {
                diag!(
                    "warning: the smoothing {:e} kept the tolerance out of reach; used {:e}",
                    opts.smoothing,
                    fit.smoothing_used
                );
            }
            let mut report = match want_report {
                true => Some(report_json(args, &fit, wall.elapsed().as_secs_f64())?),
                false => None,
            };
            let conditions = args.end_conditions();
            if let Some(r) = report.as_mut().filter(|_| !conditions.is_none()) {
                r["end_conditions"] = super::curve_ends::lsq_end_conditions_report(
                    points,
                    opts,
                    &conditions,
                    &fit.curve,
                    None,
                );
            }
            Ok(Fitted {
                tolerance: fit.tolerance,
                max_deviation: fit.deviation.max,
                curve: fit.curve,
                extra: (report, Vec::new()),
            })
        }
        Method::Integrated | Method::FitThenFair => {
            let out = with_pool(args.threads, || match args.method {
                Method::Integrated => run_integrated(args, points),
                _ => crate::progress::with_spinner("fit then fair", || {
                    run_fit_then_fair(args, points, opts)
                }),
            })?;
            let field = |k: &str| out.report[k].as_f64().unwrap_or(f64::NAN);
            let (tolerance, max_deviation) = (field("tolerance"), field("max_deviation"));
            let report = want_report.then(|| {
                let input = args.input.display().to_string();
                let wall_seconds = wall.elapsed().as_secs_f64();
                checked_report(with_method(
                    shape_report(&out.curve, &input, points.len(), wall_seconds),
                    &out.report,
                ))
            });
            Ok(Fitted {
                curve: out.curve,
                tolerance,
                max_deviation,
                extra: (report.transpose()?, out.files),
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
    let r = fit_to_exact(&cad.segments, cad.samples, |points, tol| {
        fit_points_at(args, opts, points, tol, want_report, wall)
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
    let (mut report, pareto) = r.fit.extra;
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
    Ok((r.fit.curve, report, r.points, pareto))
}

/// [`fit_points`] at the absolute tolerance `tol` when given (a refit held tighter).
fn fit_points_at(
    args: &CurveArgs,
    opts: &FitOptions,
    points: &[Vec3],
    tol: Option<f64>,
    want_report: bool,
    wall: Instant,
) -> Result<Fitted<MethodExtra>, CliError> {
    let Some(t) = tol else {
        return fit_points(args, opts, points, want_report, wall);
    };
    let mut tighter = args.clone();
    (tighter.tol, tighter.rel_tol) = (Some(t), None);
    let opts = FitOptions {
        tolerance: Tolerance::Absolute(t),
        ..opts.clone()
    };
    fit_points(&tighter, &opts, points, want_report, wall)
}

/// The fit under weights and points to interpolate (`curve_points.rs`): the screening's spikes
/// dropped (never a point to interpolate), the method held to the constraints.
fn fit_with_constraints(
    args: &CurveArgs,
    opts: &FitOptions,
    all: &[Vec3],
    screening: Option<Screening>,
    ic: &super::curve_points::InputConstraints,
    want_report: bool,
    wall: Instant,
) -> Result<FitOutput, CliError> {
    let outliers: Vec<usize> = screening
        .as_ref()
        .map(|s| s.outliers.iter().map(|o| o.index).collect())
        .unwrap_or_default();
    let (points, ic, index) = super::curve_points::kept_after_screening(all, &outliers, ic);
    let fit = super::curve_points::fit_constrained(args, &points, &ic, &index, |pts, tol, pc| {
        // the integrated method holds the constraints in its search too
        let mut inside = args.clone();
        if args.method == Method::Integrated {
            inside.search_constraints = pc.clone();
        }
        fit_points_at(&inside, opts, pts, tol, want_report, wall)
            .map_err(super::curve_points::Failure::Method)
    })?;
    let (mut report, pareto) = fit.extra;
    if let (Some(r), Some(sc)) = (report.as_mut(), screening.as_ref()) {
        add_screening(r, outlier_mode(args), sc);
    }
    Ok((fit.curve, report, points, pareto))
}

/// What a method gives beside its curve: the report (when asked for) and its own files (the Pareto
/// front).
type MethodExtra = (Option<serde_json::Value>, Vec<Output>);

/// The tolerance of `args` in the units of `points` (`None` when it is not a usable number: the fit
/// refuses it with its own message).
fn usable_tolerance(args: &CurveArgs, points: &[Vec3]) -> Option<f64> {
    let t = absolute_tolerance(args.tolerance(), points);
    (t.is_finite() && t > 0.0).then_some(t)
}

/// The library's outlier mode of `--outliers`.
fn outlier_mode(args: &CurveArgs) -> OutlierMode {
    match args.outliers {
        OutliersArg::Off => OutlierMode::Off,
        OutliersArg::Auto => OutlierMode::Auto,
    }
}

/// The spikes that keep tolerance `tol` out of reach, as a sentence with the option that excludes
/// them (`None` when there are none).
fn spikes_note(points: &[Vec3], tol: f64) -> Option<String> {
    screening::spikes_note(points, tol).map(|s| format!("{s}; --outliers auto excludes them"))
}

/// A failed fit's error with the spikes that caused it named (`--outliers off`).
fn name_spikes(args: &CurveArgs, points: &[Vec3], e: CliError) -> CliError {
    if args.outliers != OutliersArg::Off || e.usage {
        return e;
    }
    match usable_tolerance(args, points).and_then(|t| spikes_note(points, t)) {
        Some(note) => CliError::new(format!("{}; {note}", e.message)),
        None => e,
    }
}

/// A fitted curve, its report, the points it fitted and the Pareto files.
pub type FitOutput = (
    NurbsCurve,
    Option<serde_json::Value>,
    Vec<Vec3>,
    Vec<Output>,
);

fn report_json(
    args: &CurveArgs,
    fit: &FitResult,
    wall_seconds: f64,
) -> Result<serde_json::Value, CliError> {
    let knots = format!("{:?}", args.knots).to_lowercase();
    checked_report(lsq_report(
        fit,
        &args.input.display().to_string(),
        &knots,
        wall_seconds,
    ))
}

/// The report, refused (one line, nothing written) when one of its measures is not a finite number:
/// the library's report holds `null` for it.
fn checked_report(report: serde_json::Value) -> Result<serde_json::Value, CliError> {
    const MEASURES: [(&str, &str); 5] = [
        ("max_deviation", "largest deviation"),
        ("rms_deviation", "rms deviation"),
        ("length", "curve's length"),
        ("fairness", "curve's fairness F"),
        ("max_span_fairness", "curve's largest span fairness"),
    ];
    for (key, what) in MEASURES {
        if report.get(key).is_some_and(|v| v.is_null()) {
            super::finite(what, f64::NAN)?;
        }
    }
    Ok(report)
}
