//! The optimising methods of `fairfit curve`: `--method integrated` (knots by particle swarm
//! optimisation, `fairfit::optim`) with `--span-fairness`, `--pareto` and `--pareto-curves`, and
//! `--method fit-then-fair` (the least-squares fit, then fairing held to the same tolerance).
//!
//! Runs inside a local rayon pool of `--threads` workers (results do not depend on the count) and shows
//! a progress spinner on stderr only when it is a terminal.

use super::curve_args::{CurveArgs, DegreeArg, AUTO_MAX_DEGREE};
use super::files::Output;
use super::CliError;
use fairfit::fair::fair_curve;
use fairfit::fit::max_orthogonal_deviation;
use fairfit::io::curve_to_json;
use fairfit::optim::{pareto_csv, pareto_front_of_result, ParetoCurve};
use fairfit::prelude::{
    fit_integrated_with_stages, fit_to_tolerance, FitOptions, IntegratedOptions, IntegratedResult,
    NurbsCurve, Vec3,
};
use fairfit::report::curve::{fit_then_fair_report, integrated_report, integrated_warning};
use fairfit::report::end_conditions::{held_fairing, integrated_end_conditions};
use serde_json::{json, Value};

/// A fitted curve and the method-specific part of its report.
pub struct MethodOutput {
    /// The curve.
    pub curve: NurbsCurve,
    /// Report fields of the method (merged into the report).
    pub report: Value,
    /// Files of the method (the Pareto front and its curves), written with the others.
    pub files: Vec<Output>,
}

/// Runs `f` inside a rayon pool of `threads` workers (0 = one per core, or `RAYON_NUM_THREADS`),
/// capped as [`super::threads::pool_threads`] says.
pub fn with_pool<T: Send>(
    threads: usize,
    f: impl FnOnce() -> Result<T, CliError> + Send,
) -> Result<T, CliError> {
    let threads = super::threads::pool_threads(threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::new(format!("cannot start {threads} worker threads: {e}")))?;
    pool.install(f)
}

/// The library's options for the integrated method as `args` ask for them.
pub fn integrated_options(args: &CurveArgs) -> IntegratedOptions {
    let degree = args.degree();
    IntegratedOptions::new(args.tolerance())
        .degree(degree.lowest())
        .degree_search((degree == DegreeArg::Auto).then_some(AUTO_MAX_DEGREE))
        .span_fairness(args.span_fairness)
        .seed(args.seed)
        .control_points(args.control_points)
        .corner_angle((!args.no_corners).then_some(args.corner_angle))
        .closed(args.closed_mode())
        .band_fairing(!args.no_band_fairing)
        .ends(args.ends.into())
        .start(args.end_conditions().start)
        .end(args.end_conditions().end)
        .point_constraints(args.search_constraints.clone())
}

/// The command-line flag of a library setting named in an [`fairfit::Error::InvalidSetting`].
fn flag_of(option: &str, args: &CurveArgs) -> Option<&'static str> {
    Some(match option {
        "tolerance" if args.tol.is_some() => "--tol",
        "tolerance" => "--rel-tol",
        "degree" | "degree_search" => "--degree",
        "control_points" => "--control-points",
        "span_fairness" => "--span-fairness",
        "corner_angle" => "--corner-angle",
        "ends" => "--ends",
        "start" if args.start_tangent.is_some() => "--start-tangent",
        "start" if args.start_from.is_some() => "--start-from",
        "start" => "--start",
        "end" if args.end_tangent.is_some() => "--end-tangent",
        "end" if args.end_from.is_some() => "--end-from",
        "end" => "--end",
        "seed" => "--seed",
        _ => return None,
    })
}

/// A library error as the CLI prints it: a refused setting names its flag (a usage error).
pub fn cli_error(e: fairfit::Error, args: &CurveArgs) -> CliError {
    match e {
        fairfit::Error::InvalidSetting { option, reason } => match flag_of(option, args) {
            Some(flag) => CliError::usage(format!("invalid option {flag}: {reason}")),
            None => CliError::from(fairfit::Error::InvalidSetting { option, reason }),
        },
        e => CliError::from(e),
    }
}

/// `--method integrated`.
pub fn run_integrated(args: &CurveArgs, points: &[Vec3]) -> Result<MethodOutput, CliError> {
    let opts = integrated_options(args);
    let bar = crate::progress::FitBar::new();
    let r = fit_integrated_with_stages(points, &opts, &|stage, done, total| {
        bar.update(stage, done, total)
    });
    bar.finish();
    let r: IntegratedResult = r.map_err(|e| cli_error(e, args))?;
    let mut report = integrated_report(&r, r.closure.is_closed(), args.span_fairness, args.seed);
    let mut files = Vec::new();
    if !opts.end_conditions.is_none() {
        report["end_conditions"] = integrated_end_conditions(points, &opts, &r);
    }
    if let Some(path) = &args.pareto {
        let front = pareto_front_of_result(points, &opts, &r).map_err(|e| cli_error(e, args))?;
        files = pareto_files(path, args, &front)?;
        report["pareto_members"] = json!(front.len());
    }
    if let Some(w) = integrated_warning(&r, args.span_fairness) {
        diag!("warning: {w}");
    }
    Ok(MethodOutput {
        curve: r.curve,
        report,
        files,
    })
}

/// The front as CSV at `path`, and every member as a curve JSON in `--pareto-curves` (the folder is
/// made by the command just before its commit).
fn pareto_files(
    path: &std::path::Path,
    args: &CurveArgs,
    front: &[ParetoCurve],
) -> Result<Vec<Output>, CliError> {
    let mut files = vec![Output::new(path, pareto_csv(front).into_bytes())];
    if let Some(dir) = &args.pareto_curves {
        for (i, c) in front.iter().enumerate() {
            files.push(Output::geometry(
                dir.join(format!("front_{i:03}.json")),
                curve_to_json(&c.curve).into_bytes(),
            ));
        }
    }
    Ok(files)
}

/// `--method fit-then-fair`: the least-squares fit, then fairing within the same tolerance.
pub fn run_fit_then_fair(
    args: &CurveArgs,
    points: &[Vec3],
    fit_opts: &FitOptions,
) -> Result<MethodOutput, CliError> {
    let fit = fit_to_tolerance(points, fit_opts).map_err(|e| cli_error(e, args))?;
    // the control points that carry end conditions never move (a tangent holds two, a curvature three)
    let conditions = args.end_conditions();
    let fairing = held_fairing(&conditions);
    let faired = fair_curve(&fit.curve, points, fit.tolerance, &fairing)?;
    // measured afresh by projection on the faired curve, started at the least-squares parameters
    // (the fairing's own distances came from an unhinted projection that can stop at a far local
    // minimum on long spans)
    let dev = max_orthogonal_deviation(&faired.curve, &fit.points, &fit.params);
    let mut report = fit_then_fair_report(&fit, &faired.curve, faired.iterations, &dev, args.seed);
    if !conditions.is_none() {
        report["end_conditions"] = super::curve_ends::lsq_end_conditions_report(
            points,
            fit_opts,
            &conditions,
            &faired.curve,
            Some(&fairing),
        );
    }
    Ok(MethodOutput {
        curve: faired.curve,
        report,
        files: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pool_is_capped_at_four_workers_per_core() {
        let cap = super::super::threads::max_threads();
        let workers = with_pool(1_000_000, || Ok(rayon::current_num_threads())).unwrap();
        assert_eq!(workers, cap);
        let two = with_pool(2, || Ok(rayon::current_num_threads())).unwrap();
        assert_eq!(two, 2.min(cap));
    }
}
