//! The optimising methods of `fairfit curve`: `--method integrated` (knots by particle swarm
//! optimisation, `fairfit::optim`) with `--span-fairness`, `--pareto` and `--pareto-curves`, and
//! `--method fit-then-fair` (the least-squares fit, then fairing held to the same tolerance).
//!
//! Runs inside a local rayon pool of `--threads` workers (results do not depend on the count) and shows
//! a progress spinner on stderr only when it is a terminal.

use super::curve_args::{CurveArgs, DegreeArg, AUTO_MAX_DEGREE};
use super::CliError;
use fairfit::fair::{curve_fairness, fair_curve, FairingOptions};
use fairfit::fit::max_orthogonal_deviation;
use fairfit::io::{curve_to_json, write_atomic};
use fairfit::optim::{
    distinct_control_points, is_closed, pareto_csv, pareto_front_of_result, ParetoCurve,
};
use fairfit::prelude::{
    fit_integrated_with_stages, fit_to_tolerance, FitOptions, IntegratedOptions, IntegratedResult,
    NurbsCurve, Stage, Vec3,
};
use serde_json::{json, Value};

/// A fitted curve and the method-specific part of its report.
pub struct MethodOutput {
    /// The curve.
    pub curve: NurbsCurve,
    /// Report fields of the method (merged into the report).
    pub report: Value,
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
fn integrated_options(args: &CurveArgs) -> IntegratedOptions {
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
        "seed" => "--seed",
        _ => return None,
    })
}

/// A library error as the CLI prints it: a refused setting names its flag (a usage error).
fn cli_error(e: fairfit::Error, args: &CurveArgs) -> CliError {
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
    let closed = is_closed(points, opts.closed);
    let bar = crate::progress::bar(0, "knot search");
    let r: IntegratedResult = fit_integrated_with_stages(points, &opts, &|stage| {
        bar.set_message(stage.to_string());
        if let Stage::KnotSearch { iteration, .. } = stage {
            bar.set_position(iteration as u64);
        }
    })
    .map_err(|e| cli_error(e, args))?;
    bar.finish_and_clear();
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
        "span_fairness_target": args.span_fairness,
        "log10_smoothing": r.log10_smoothing(),
        "lsq_baseline_control_points": r.baseline_control_points,
        "optimizer": {
            "seed": args.seed,
            "evaluations": r.stats.evaluations,
            "iterations": r.stats.iterations,
            "counts_tried": r.stats.counts_tried,
            "fairness_by_count": r.stats.fairness_by_count.iter()
                .map(|(n, f)| json!({"control_points": n, "fairness": if f.is_finite() { Some(*f) } else { None }}))
                .collect::<Vec<_>>(),
            "polish_moves": r.stats.polish_moves,
            "seconds": r.stats.seconds,
        },
    });
    if !r.stats.degrees_tried.is_empty() {
        report["optimizer"]["degrees_tried"] = json!(r.stats.degrees_tried);
    }
    if let Some(path) = &args.pareto {
        let front = pareto_front_of_result(points, &opts, &r).map_err(|e| cli_error(e, args))?;
        write_pareto(path, args, &front)?;
        report["pareto_members"] = json!(front.len());
    } else if args.pareto_curves.is_some() {
        return Err(CliError::usage("--pareto-curves needs --pareto"));
    }
    if !r.met {
        match args.span_fairness {
            // within the tolerance: what was missed is the per-span fairness target
            Some(t) if r.quality.max_deviation <= r.tolerance => eprintln!(
                "warning: the span fairness target {t:.3e} was not met (largest F_j {:.3e})",
                r.quality.max_span_fairness
            ),
            _ => eprintln!(
                "warning: the tolerance {:.3e} was not met (max deviation {:.3e})",
                r.tolerance, r.quality.max_deviation
            ),
        }
    }
    Ok(MethodOutput {
        curve: r.curve,
        report,
    })
}

/// Writes the front as CSV to `path`, and every member as a curve JSON into `--pareto-curves`.
fn write_pareto(
    path: &std::path::Path,
    args: &CurveArgs,
    front: &[ParetoCurve],
) -> Result<(), CliError> {
    write_atomic(path, pareto_csv(front).as_bytes())?;
    if let Some(dir) = &args.pareto_curves {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::new(fairfit::Error::io(dir, &e).to_string()))?;
        for (i, c) in front.iter().enumerate() {
            write_atomic(
                dir.join(format!("front_{i:03}.json")),
                curve_to_json(&c.curve).as_bytes(),
            )?;
        }
    }
    Ok(())
}

/// `--method fit-then-fair`: the least-squares fit, then fairing within the same tolerance.
pub fn run_fit_then_fair(
    args: &CurveArgs,
    points: &[Vec3],
    fit_opts: &FitOptions,
) -> Result<MethodOutput, CliError> {
    let fit = fit_to_tolerance(points, fit_opts)?;
    let faired = fair_curve(
        &fit.curve,
        points,
        fit.tolerance,
        &FairingOptions::default(),
    )?;
    let before = curve_fairness(&fit.curve);
    // measured afresh by projection on the faired curve, started at the least-squares parameters
    // (the fairing's own distances came from an unhinted projection that can stop at a far local
    // minimum on long spans)
    let dev = max_orthogonal_deviation(&faired.curve, &fit.points, &fit.params);
    let report = json!({
        "method": "fit-then-fair",
        "control_points": distinct_control_points(&faired.curve),
        "closed": fit.closed,
        "tolerance": fit.tolerance,
        "tolerance_met": dev.max <= fit.tolerance,
        "max_deviation": dev.max,
        "rms_deviation": dev.rms,
        "lsq_fairness": before.fairness,
        "fairing_moves": faired.iterations,
        "seed": args.seed,
    });
    Ok(MethodOutput {
        curve: faired.curve,
        report,
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
