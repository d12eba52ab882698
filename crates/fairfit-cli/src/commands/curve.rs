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

use super::curve_optim::{run_fit_then_fair, run_integrated, with_pool};
use super::info::exact_shape_json;
use super::outputs::{check_output_paths, prepare_outputs, OutputArgs, OutputGeometry};
use super::{CliError, CmdResult};
use clap::{Args, ValueEnum};
use fairfit::fair::curve_fairness;
use fairfit::fit::cad_fit::{fit_to_exact, Fitted};
use fairfit::fit::tolerance::{
    fit_to_tolerance, ClosedMode, FitOptions, FitResult, KnotRule, Tolerance,
};
use fairfit::fit::{Parameterization, SmoothingOrder};
use fairfit::io::atomic::write_all_atomic;
use fairfit::io::curve_to_json;
use fairfit::Vec3;
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// The fitting method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Least squares with a tolerance-driven knot count (fast baseline).
    Lsq,
    /// Integrated fitting and fairing (knots by particle swarm optimisation).
    Integrated,
    /// Least squares, then fairing of the fitted curve.
    FitThenFair,
}

/// Parameterisation choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ParamArg {
    /// Equal parameter steps.
    Uniform,
    /// Steps proportional to chord length.
    Chord,
    /// Steps proportional to the square root of chord length (default).
    Centripetal,
}

impl From<ParamArg> for Parameterization {
    fn from(p: ParamArg) -> Self {
        match p {
            ParamArg::Uniform => Parameterization::Uniform,
            ParamArg::Chord => Parameterization::ChordLength,
            ParamArg::Centripetal => Parameterization::Centripetal,
        }
    }
}

/// Knot placement choices of `--method lsq`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum KnotArg {
    /// Split spans where the error is largest, then remove unneeded knots (default, fewest points).
    Refine,
    /// Symmetric averaging rule; smallest count meeting the tolerance.
    Averaging,
    /// Curvature-adaptive rule (more knots where the data turn fast); smallest count meeting it.
    Adaptive,
}

impl From<KnotArg> for KnotRule {
    fn from(k: KnotArg) -> Self {
        match k {
            KnotArg::Refine => KnotRule::Refine,
            KnotArg::Averaging => KnotRule::Averaging,
            KnotArg::Adaptive => KnotRule::Adaptive,
        }
    }
}

/// `--ends`: the end condition of an open curve (integrated method).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EndsArg {
    /// The curve starts and ends exactly at the first and last points.
    Pinned,
    /// The curve's end points may move within the tolerance of the first and last points, like
    /// every other point (fairer curves where the data end at high curvature).
    Free,
}

impl From<EndsArg> for fairfit::optim::EndCondition {
    fn from(e: EndsArg) -> Self {
        match e {
            EndsArg::Pinned => Self::Pinned,
            EndsArg::Free => Self::Free,
        }
    }
}

/// `--degree`: a fixed degree, or `auto` (the integrated method's degree search).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DegreeArg {
    /// One degree.
    Fixed(usize),
    /// Every degree from 3 to [`AUTO_MAX_DEGREE`], one kept (`fairfit::optim::stages::degree_search`).
    Auto,
}

/// The highest degree `--degree auto` tries.
pub const AUTO_MAX_DEGREE: usize = 5;

impl DegreeArg {
    /// The fixed degree, or the lowest (reference) degree of the search.
    pub fn lowest(self) -> usize {
        match self {
            DegreeArg::Fixed(d) => d,
            DegreeArg::Auto => 3,
        }
    }
}

/// Parses `auto` or a degree from 1 to 15.
fn parse_degree(s: &str) -> Result<DegreeArg, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(DegreeArg::Auto);
    }
    match s.trim().parse::<usize>() {
        Ok(d) if (1..=15).contains(&d) => Ok(DegreeArg::Fixed(d)),
        _ => Err(format!(
            "expected `auto` or a degree from 1 to 15, got `{s}`"
        )),
    }
}

/// Parses `X,Y` or `X,Y,Z` into a vector.
fn parse_vector(s: &str) -> Result<Vec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected X,Y or X,Y,Z: {e}"))?;
    match v[..] {
        [x, y] => Ok(Vec3::new(x, y, 0.0)),
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("expected X,Y or X,Y,Z, got {} values", v.len())),
    }
}

/// Arguments of `fairfit curve`.
#[derive(Args, Debug, Clone)]
pub struct CurveArgs {
    /// Point file: CSV/TSV/whitespace with 2 or 3 columns, or a Selig/Lednicer airfoil .dat file; or a
    /// STEP/IGES file whose B-spline curve is sampled densely and re-fitted (re-faired).
    #[arg(required = true)]
    pub input: PathBuf,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Fitting method.
    #[arg(long, value_enum, default_value_t = Method::Integrated)]
    pub method: Method,
    /// Absolute tolerance on the maximum orthogonal deviation.
    #[arg(long, conflicts_with = "rel_tol", allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// Tolerance relative to the largest side of the points' bounding box (default 1e-3).
    #[arg(long, allow_hyphen_values = true)]
    pub rel_tol: Option<f64>,
    /// Degree of the curve (1 to 15), or `auto` (integrated method, its default): the cubic's count
    /// search, then degrees 4 and 5 at the cubic's control points. The quartic also tries more
    /// points: up to the least-squares count (one above it where the cubic kept that count) when the
    /// cubic's fewest-extrema choice cost much F or its extra points still paid, and one above the
    /// least-squares count (at most a quarter of the points) when the cubic's curve has 6 or more
    /// curvature extrema. The fairest with no more curvature extrema than the cubic's is kept
    /// [default: auto for integrated, 3 for lsq and fit-then-fair]
    #[arg(long, value_parser = parse_degree, allow_hyphen_values = true)]
    pub degree: Option<DegreeArg>,
    /// Parameterisation of the points.
    #[arg(long = "param", value_enum, default_value_t = ParamArg::Centripetal)]
    pub param: ParamArg,
    /// Treat the points as a closed curve (otherwise closed only when the last point repeats the first).
    #[arg(long)]
    pub closed: bool,
    /// Turning angle (degrees) above which a point is a corner kept as a C0 knot.
    #[arg(long, default_value_t = fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG, allow_hyphen_values = true)]
    pub corner_angle: f64,
    /// Do not detect corners.
    #[arg(long)]
    pub no_corners: bool,
    /// Integrated method: skip the band fairing of the final control points (sequential convex
    /// programming inside the tolerance band).
    #[arg(long)]
    pub no_band_fairing: bool,
    /// Integrated method, open curves: whether the curve's end points stay on the first and last
    /// points (`pinned`) or, in a last fairing pass, may move within the tolerance of them (`free`);
    /// closed curves have no ends, and a curve with corners keeps its ends pinned (the report's
    /// "ends" says which was used).
    #[arg(long, value_enum, default_value_t = EndsArg::Pinned)]
    pub ends: EndsArg,
    /// Parameter-correction rounds per least-squares fit.
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub correction_rounds: usize,
    /// Scale-free smoothing weight λ (0 = plain least squares).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub smoothing: f64,
    /// Derivative order of the smoothing term: 2 for ∫|C''|², 3 for ∫|C'''|².
    #[arg(long, default_value_t = 2, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u8).range(2..=3))]
    pub smoothing_order: u8,
    /// Knot placement (lsq and fit-then-fair methods).
    #[arg(long, value_enum, default_value_t = KnotArg::Refine)]
    pub knots: KnotArg,
    /// Tangent direction X,Y or X,Y,Z at the first point (open curves; lsq and fit-then-fair methods).
    #[arg(long, value_parser = parse_vector, allow_hyphen_values = true)]
    pub start_tangent: Option<Vec3>,
    /// Tangent direction X,Y or X,Y,Z at the last point (open curves; lsq and fit-then-fair methods).
    #[arg(long, value_parser = parse_vector, allow_hyphen_values = true)]
    pub end_tangent: Option<Vec3>,
    /// Per-span fairness target F*: every knot span must reach F_j <= F* (integrated method).
    #[arg(long, allow_hyphen_values = true)]
    pub span_fairness: Option<f64>,
    /// Fixed number of control points instead of the fewest meeting the tolerance (integrated method).
    #[arg(long, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub control_points: Option<usize>,
    /// Write the Pareto front of (max deviation, F) as CSV (integrated method).
    #[arg(long)]
    pub pareto: Option<PathBuf>,
    /// Also write every Pareto front member as a curve JSON into this directory.
    #[arg(long)]
    pub pareto_curves: Option<PathBuf>,
    /// Random seed (methods with a stochastic search).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number_u64)]
    pub seed: u64,
    /// Worker threads (0 = all cores; capped at 4 per core; results do not depend on it).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub threads: usize,
    /// Output curve JSON file (stdout when absent).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write a JSON report (deviation, fairness, timing) to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// CAD, mesh, plot and HTML outputs.
    #[command(flatten)]
    pub outputs: OutputArgs,
}

impl CurveArgs {
    /// `--degree`, or the method's default: `auto` for the integrated method, 3 otherwise.
    pub fn degree(&self) -> DegreeArg {
        self.degree.unwrap_or(match self.method {
            Method::Integrated => DegreeArg::Auto,
            _ => DegreeArg::Fixed(3),
        })
    }
}

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
    if (args.start_tangent.is_some() || args.end_tangent.is_some())
        && args.method == Method::Integrated
    {
        return Err(CliError::usage(
            "--start-tangent and --end-tangent need --method lsq or --method fit-then-fair",
        ));
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
        tolerance: match (args.tol, args.rel_tol) {
            (Some(t), _) => Tolerance::Absolute(t),
            (None, Some(r)) => Tolerance::Relative(r),
            (None, None) => Tolerance::Relative(1e-3),
        },
        closed: if args.closed {
            ClosedMode::Closed
        } else {
            ClosedMode::Auto
        },
        corner_angle_deg: (!args.no_corners).then_some(args.corner_angle),
        correction_rounds: args.correction_rounds,
        smoothing: args.smoothing,
        smoothing_order: if args.smoothing_order == 3 {
            SmoothingOrder::Third
        } else {
            SmoothingOrder::Second
        },
        knot_rule: args.knots.into(),
        start_tangent: args.start_tangent,
        end_tangent: args.end_tangent,
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
type FitOutput = (fairfit::NurbsCurve, Option<serde_json::Value>, Vec<Vec3>);

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
