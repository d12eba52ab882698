//! `fairfit curve A.csv B.csv ... --chain g1|g2`: several point files fitted as one fair chain of
//! curves joining with G1 or G2 continuity (`fairfit::optim::chain`: the joins where the fairest
//! single curve through every point passes, every piece the fairer of its integrated fit under
//! them and the single curve's part between them).
//!
//! Outputs, all made in memory and written all or none: `-o FILE` (required) holds the joined
//! chain, one B-spline on `[0, N]` (piece `k` on `[k − 1, k]`) whose joins are knots of full
//! multiplicity (`fairfit::report::chain::joined_curve`: exact, G1/G2 there as the pieces are),
//! and piece `k` (1-based, in input order)
//! goes to `FILE` with `_k` before its extension; `--step`, `--iges`, `--mesh`, `--plot` and `--html`
//! show the joined chain; `--report` lists every piece (its own report, as a single fit's) and the
//! continuity measured at every join on the written pieces, with the chain's F beside the single
//! curve's.
//!
//! `fairfit curve AIRFOIL --split-at-le` is a chain of two made from one file: the points split at
//! the leading edge (the point farthest from the trailing edge, the midpoint of the first and last
//! points; both halves hold it), fitted as a G2 chain and written as the joined curve on `[0, 1]`
//! (to `-o`, else stdout): the pieces each on `[0, 1]` before joining, so the leading edge is at
//! the parameter 0.5 exactly, a knot of full multiplicity, in every section fitted so.
//!
//! Only the integrated method fits chains; options that index one point set or fix one curve's
//! shape (`--closed`, `--control-points`, `--ends free`, `--weights`, `--interpolate`, `--pareto`)
//! are usage errors with `--chain` and `--split-at-le`, as are CAD inputs (exit 2). Nothing here
//! runs without `--chain`, `--split-at-le` or a second input: single-curve runs never reach this
//! module.

use super::curve_args::{ChainArg, CurveArgs, EndsArg, Method, OutliersArg};
use super::files::{check_outputs, commit, Inputs, Output};
use super::outputs::{check_output_formats, prepare_outputs, OutputGeometry};
use super::{CliError, CmdResult};
use fairfit::fit::airfoil::leading_edge;
use fairfit::fit::screening::OutlierMode;
use fairfit::io::cad_read::CadFormat;
use fairfit::io::curve_to_json;
use fairfit::optim::chain::{fit_chain, ChainResult};
use fairfit::prelude::{NurbsCurve, Vec3};
use fairfit::report::chain::{joined_curve, unit_domain, ChainReportInputs};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Runs `fairfit curve ... --chain` or `--split-at-le` (module doc).
pub fn run(args: CurveArgs) -> CmdResult {
    let wall = Instant::now();
    check_options(&args)?;
    if args.split_at_le {
        return run_split(args, wall);
    }
    let output = args.output.clone().ok_or_else(|| {
        CliError::usage(
            "--chain needs -o FILE (the joined chain; the pieces go to FILE_1, FILE_2, ...)",
        )
    })?;
    let inputs = inputs(&args);
    let piece_paths: Vec<PathBuf> = (1..=inputs.len()).map(|k| piece_path(&output, k)).collect();
    check_chain_outputs(&args, &output, &piece_paths, &inputs)?;
    let resolved = super::curve_ends::with_ends_from_files(&args)?;
    let args = resolved.as_ref().unwrap_or(&args);
    let pieces: Vec<Vec<Vec3>> = inputs
        .iter()
        .map(|p| read_piece(p, args))
        .collect::<Result<_, _>>()?;
    let continuity = args.chain.unwrap_or(ChainArg::G2);
    let r = fit_pieces(args, &pieces, continuity)?;
    let joined = joined_curve(&r)?;
    let names: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
    let report = wants_report(args)
        .then(|| chain_report(args, &r, &names, Some(&piece_paths), &pieces, wall));
    let mut files = vec![Output::geometry(
        &output,
        curve_to_json(&joined).into_bytes(),
    )];
    for (path, piece) in piece_paths.iter().zip(&r.pieces) {
        files.push(Output::geometry(
            path,
            curve_to_json(&piece.curve).into_bytes(),
        ));
    }
    write_all(args, files, &joined, &pieces, report)
}

/// `--split-at-le`: the one input split at its leading edge, fitted as a G2 chain and written as
/// the joined curve on `[0, 1]`, the leading edge at 0.5 (to `-o`, else stdout).
fn run_split(args: CurveArgs, wall: Instant) -> CmdResult {
    let output = args.output.clone().unwrap_or_else(|| "-".into());
    check_chain_outputs(&args, &output, &[], std::slice::from_ref(&args.input))?;
    let resolved = super::curve_ends::with_ends_from_files(&args)?;
    let args = resolved.as_ref().unwrap_or(&args);
    let points = read_piece(&args.input, args)?;
    let le = leading_edge(&points).ok_or_else(|| {
        CliError::new(format!(
            "{}: no leading edge to split at: the point farthest from the trailing edge (the midpoint of the first and last points) is an end point",
            args.input.display()
        ))
    })?;
    let pieces = vec![points[..=le].to_vec(), points[le..].to_vec()];
    let r = fit_pieces(args, &pieces, ChainArg::G2)?;
    let joined = unit_domain(&joined_curve(&r)?)?;
    let input = args.input.display().to_string();
    let names = [
        format!("{input} (to the leading edge)"),
        format!("{input} (from the leading edge)"),
    ];
    let report = wants_report(args).then(|| {
        let mut v = chain_report(args, &r, &names, None, &pieces, wall);
        v["split_at_le"] = json!({"index": le, "point": points[le].0, "parameter": 0.5});
        v
    });
    let files = vec![Output::geometry(
        &output,
        curve_to_json(&joined).into_bytes(),
    )];
    write_all(args, files, &joined, &pieces, report)
}

/// The chain fitted by the integrated method with `args`' options (screening as `--outliers`).
fn fit_pieces(
    args: &CurveArgs,
    pieces: &[Vec<Vec3>],
    continuity: ChainArg,
) -> Result<ChainResult, CliError> {
    let opts = super::curve_optim::integrated_options(args).outliers(match args.outliers {
        OutliersArg::Off => OutlierMode::Off,
        OutliersArg::Auto => OutlierMode::Auto,
    });
    let r = super::curve_optim::with_pool(args.threads, || {
        crate::progress::with_spinner("chain", || fit_chain(pieces, continuity.into(), &opts))
            .map_err(|e| super::curve_optim::cli_error(e, args))
    })?;
    if let Some(w) = r.warning() {
        diag!("warning: {w}");
    }
    Ok(r)
}

/// Whether a report is made (`--report` or `--html`).
fn wants_report(args: &CurveArgs) -> bool {
    args.report.is_some() || args.outputs.html.is_some()
}

/// `files` with the report and the CAD, mesh, plot and HTML outputs of the joined curve, written
/// all or none.
fn write_all(
    args: &CurveArgs,
    mut files: Vec<Output>,
    joined: &NurbsCurve,
    pieces: &[Vec<Vec3>],
    report: Option<Value>,
) -> CmdResult {
    if let (Some(rp), Some(report)) = (&args.report, &report) {
        files.push(Output::new(rp, super::json_pretty(report)?.into_bytes()));
    }
    if args.outputs.any() {
        let all: Vec<Vec3> = pieces.iter().flatten().copied().collect();
        files.extend(
            prepare_outputs(
                OutputGeometry::Curve(joined),
                Some(&all),
                report.as_ref(),
                &args.outputs,
            )?
            .into_iter()
            .map(|(p, b)| Output::new(p, b)),
        );
    }
    commit(files)
}

/// Whether `args` ask for a chain (`--chain`, more than one input, or `--split-at-le`): `fairfit
/// curve` then runs [`run`] instead of `curve::run`.
pub fn asked(args: &CurveArgs) -> bool {
    args.chain.is_some() || !args.more_inputs.is_empty() || args.split_at_le
}

/// Every input file of the chain, in order.
fn inputs(args: &CurveArgs) -> Vec<PathBuf> {
    std::iter::once(args.input.clone())
        .chain(args.more_inputs.iter().cloned())
        .collect()
}

/// Where piece `k` (1-based) goes: `output` with `_k` before its extension (`out.json` →
/// `out_1.json`; `out` → `out_1`).
pub fn piece_path(output: &Path, k: usize) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match output.extension() {
        Some(e) => format!("{stem}_{k}.{}", e.to_string_lossy()),
        None => format!("{stem}_{k}"),
    };
    output.with_file_name(name)
}

/// Refuses (usage errors, before any input is read) what a chain cannot take.
fn check_options(args: &CurveArgs) -> CmdResult {
    if args.split_at_le && !args.more_inputs.is_empty() {
        return Err(CliError::usage(
            "--split-at-le fits one airfoil file; give the pieces of a chain with --chain",
        ));
    }
    if args.chain.is_none() && !args.split_at_le {
        return Err(CliError::usage(format!(
            "{} input files need --chain g1|g2 (one fair chain of curves); fit one file at a time otherwise",
            1 + args.more_inputs.len()
        )));
    }
    if args.more_inputs.is_empty() && !args.split_at_le {
        return Err(CliError::usage(
            "--chain needs at least two point files (the pieces, in order), got 1",
        ));
    }
    let refused = [
        (
            args.method != Method::Integrated,
            "--method lsq/fit-then-fair",
        ),
        (args.closed, "--closed"),
        (args.control_points.is_some(), "--control-points"),
        (args.ends == EndsArg::Free, "--ends free"),
        (args.weights.is_some(), "--weights"),
        (!args.interpolate.is_empty(), "--interpolate"),
        (args.pareto.is_some(), "--pareto"),
        (args.pareto_curves.is_some(), "--pareto-curves"),
    ];
    if let Some((_, flag)) = refused.iter().find(|(bad, _)| *bad) {
        let with = match args.split_at_le {
            true => "--split-at-le",
            false => "--chain",
        };
        return Err(CliError::usage(format!(
            "{flag} cannot be used with {with} (each piece is fitted by the integrated method, its count, ends and points chosen by the chain)"
        )));
    }
    super::curve::check_options(args)?;
    for p in inputs(args) {
        if CadFormat::from_path(&p).is_some() {
            return Err(CliError::usage(format!(
                "{} needs point files, not a STEP or IGES curve: {}",
                match args.split_at_le {
                    true => "--split-at-le",
                    false => "--chain",
                },
                p.display()
            )));
        }
    }
    Ok(())
}

/// The outputs of a chain checked before any work: no output overwrites an input or another
/// output; `-o` cannot be stdout.
fn check_chain_outputs(
    args: &CurveArgs,
    output: &Path,
    pieces: &[PathBuf],
    inputs: &[PathBuf],
) -> CmdResult {
    if super::files::is_stdout(output) && !args.split_at_le {
        return Err(CliError::usage(
            "--chain writes several curves: -o needs a file name, not stdout",
        ));
    }
    let mut outputs: Vec<(&str, &Path)> = vec![("-o", output)];
    outputs.extend(pieces.iter().map(|p| ("-o (a chain piece)", p.as_path())));
    outputs.extend(args.report.as_deref().map(|p| ("--report", p)));
    outputs.extend(args.outputs.named());
    let from: Vec<PathBuf> = [(&args.start_from, true), (&args.end_from, false)]
        .into_iter()
        .filter_map(|(f, d)| f.as_deref().map(|f| super::curve_args::split_from(f, d).0))
        .collect();
    check_outputs(
        &outputs,
        &[],
        &Inputs::files(
            inputs
                .iter()
                .chain(from.iter())
                .map(|p| p.as_path())
                .collect(),
        ),
    )?;
    check_output_formats(&outputs)
}

/// The points of one piece's file.
fn read_piece(path: &Path, args: &CurveArgs) -> Result<Vec<Vec3>, CliError> {
    let (set, _) = super::cad_input::read_curve_points(path, &args.cad)?;
    if set.dropped_duplicates > 0 {
        diag!(
            "warning: {}: dropped {} consecutive duplicate point(s)",
            path.display(),
            set.dropped_duplicates
        );
    }
    Ok(set.points)
}

/// The `--report` of a chain (`fairfit::report::chain::chain_report`, as Python's `fit_chain`
/// makes it): the chain's measures, every piece's own report and every join's measured continuity.
fn chain_report(
    args: &CurveArgs,
    r: &ChainResult,
    inputs: &[String],
    outputs: Option<&[PathBuf]>,
    pieces: &[Vec<Vec3>],
    wall: Instant,
) -> Value {
    let outputs: Option<Vec<String>> =
        outputs.map(|o| o.iter().map(|p| p.display().to_string()).collect());
    let points: Vec<usize> = pieces.iter().map(Vec::len).collect();
    fairfit::report::chain::chain_report(
        r,
        &ChainReportInputs {
            continuity: args.chain.unwrap_or(ChainArg::G2).into(),
            names: inputs,
            outputs: outputs.as_deref(),
            points: &points,
            span_fairness: args.span_fairness,
            seed: args.seed,
            wall_seconds: wall.elapsed().as_secs_f64(),
        },
    )
}
