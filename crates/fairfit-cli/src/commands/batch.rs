//! `fairfit batch DIR|LIST -o OUTDIR`: `fairfit curve` on many point files.
//!
//! Every input (the point files of a folder, sorted by name, or the paths listed in a text file, one
//! a line) is fitted with the curve command's options; `OUTDIR/NAME.json` is its curve and
//! `OUTDIR/NAME.report.json` its report, the bytes `fairfit curve INPUT -o ... --report ...` writes
//! (the report's timings aside). `OUTDIR/summary.jsonl` gets one line per input, in input order
//! ([`Row`]). A failed input is an error row and does not stop the others; the exit code is 1 when
//! any input failed, else 0.
//!
//! `--jobs N` fits N inputs at once, each fit on one thread: the results do not depend on N.
//! `--shard K/N` keeps every N-th input from the K-th (1-based), so that N processes (a Slurm array,
//! GNU parallel) share one list; each writes its own `summary.K-of-N.jsonl`.

use super::curve::{check_options, fit_input};
use super::curve_args::CurveArgs;
use super::files::{check_outputs, Inputs};
use super::{CliError, CmdResult};
use clap::Args;
use fairfit::io::atomic::write_all_atomic;
use fairfit::io::curve_to_json;
use fairfit::io::sections::expand_section_inputs;
use fairfit::optim::distinct_control_points;
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `fairfit batch`: the curve command's, with INPUT a folder or a list and `-o` a folder.
#[derive(Args, Debug, Clone)]
#[command(
    mut_arg("input", |a| a.value_name("DIR|LIST").help(
        "A folder of point files (.csv, .txt, .dat, .xyz; sorted by name), or a text file listing \
         point files, one a line (relative paths from the current folder; blank lines and # comments \
         skipped)")),
    mut_arg("output", |a| a.value_name("OUTDIR").required(true).help(
        "Output folder (made if missing): NAME.json and NAME.report.json per input, and \
         summary.jsonl")),
    mut_arg("report", |a| a.hide(true)),
    mut_arg("pareto", |a| a.hide(true)),
    mut_arg("pareto_curves", |a| a.hide(true)),
    mut_arg("threads", |a| a.hide(true)),
    mut_arg("step", |a| a.hide(true)),
    mut_arg("iges", |a| a.hide(true)),
    mut_arg("mesh", |a| a.hide(true)),
    mut_arg("plot", |a| a.hide(true)),
    mut_arg("html", |a| a.hide(true)),
    mut_arg("chord_tol", |a| a.hide(true)),
    mut_arg("units", |a| a.hide(true)),
    after_help = "Exit code: 0 when every input was fitted, 1 when any failed (its summary row says \
        why), 2 for a usage error.\n\n\
        Many machines: give each process one shard of the same list, e.g. a Slurm array \
        (`#SBATCH --array=1-10`, then `fairfit batch list.txt -o out --shard \
        $SLURM_ARRAY_TASK_ID/10`) or GNU parallel (`parallel fairfit batch list.txt -o out \
        --shard {}/4 ::: 1 2 3 4`); each shard writes its own summary.K-of-N.jsonl \
        (`cat out/summary.*.jsonl` joins them)."
)]
pub struct BatchArgs {
    /// The curve command's options (input, `-o` and the fitting options).
    #[command(flatten)]
    pub curve: CurveArgs,
    /// Inputs fitted at once (each fit on one thread; results do not depend on it); at most four
    /// per core are started, like `--threads`.
    #[arg(long, default_value_t = 1, value_parser = jobs)]
    pub jobs: usize,
    /// Fit only the K-th of N shares of the inputs (K from 1 to N; inputs K, K+N, K+2N, ... in
    /// input order), for Slurm arrays and GNU parallel.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
}

/// `--shard K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This share, 1 to `of`.
    pub k: usize,
    /// The number of shares.
    pub of: usize,
}

/// clap value parser of `--jobs`: a whole number >= 1.
fn jobs(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("expected a whole number >= 1, got {s}")),
    }
}

/// clap value parser of `--shard K/N`.
fn parse_shard(s: &str) -> Result<Shard, String> {
    let bad = || format!("expected K/N with 1 <= K <= N (e.g. 2/8), got {s}");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, of) = (
        k.trim().parse::<usize>().map_err(|_| bad())?,
        n.trim().parse::<usize>().map_err(|_| bad())?,
    );
    if k == 0 || k > of {
        return Err(bad());
    }
    Ok(Shard { k, of })
}

/// One line of `summary.jsonl`: how the fit of one input went.
#[derive(Serialize, Debug)]
pub struct Row {
    /// The output name (the input's file name without its extension).
    pub name: String,
    /// The input file, as given.
    pub input: String,
    /// `ok` or `error`.
    pub status: &'static str,
    /// The one-line error of a failed input (`null` when ok).
    pub error: Option<String>,
    /// The curve's control points (distinct, as the report's `control_points`).
    pub control_points: Option<usize>,
    /// The curve's fairness F.
    pub fairness: Option<f64>,
    /// The largest orthogonal deviation from the points.
    pub max_deviation: Option<f64>,
    /// The tolerance it was held to.
    pub tolerance: Option<f64>,
    /// Wall time of this input, in seconds.
    pub seconds: f64,
}

/// Runs `fairfit batch`.
pub fn run(args: BatchArgs) -> CmdResult {
    let c = &args.curve;
    refuse_single_file_options(c)?;
    check_options(c)?;
    let outdir = c
        .output
        .clone()
        .ok_or_else(|| CliError::usage("-o OUTDIR is required"))?;
    let inputs = shard_of(list_inputs(&c.input)?, args.shard);
    let names = output_names(&inputs)?;
    refuse_outdir_in_input(&c.input, &outdir)?;
    std::fs::create_dir_all(&outdir)
        .map_err(|e| CliError::new(fairfit::Error::io(&outdir, &e).to_string()))?;
    crate::progress::hide_fit_bars();
    let bar = crate::progress::batch_bar(inputs.len() as u64, "batch");
    // capped like `--threads` (results do not depend on the count): `--jobs 99999999999` would
    // otherwise spend minutes starting threads before the first fit
    let jobs = args.jobs.min(super::threads::max_threads());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| CliError::new(format!("cannot start {jobs} worker threads: {e}")))?;
    let rows: Vec<Row> = pool.install(|| {
        inputs
            .par_iter()
            .zip(names.par_iter())
            .map(|(input, name)| {
                let row = fit_one(c, input, name, &outdir);
                bar.inc(1);
                row
            })
            .collect()
    });
    bar.finish_and_clear();
    let summary = match args.shard {
        Some(s) => format!("summary.{}-of-{}.jsonl", s.k, s.of),
        None => "summary.jsonl".into(),
    };
    let mut text = String::new();
    for row in &rows {
        let line = serde_json::to_string(row)
            .map_err(|e| CliError::new(format!("internal: cannot format JSON: {e}")))?;
        text.push_str(&line);
        text.push('\n');
    }
    write_all_atomic(&[(outdir.join(summary), text.into_bytes())])?;
    let failed = rows.iter().filter(|r| r.status != "ok").count();
    if failed > 0 {
        return Err(CliError::new(format!(
            "{failed} of {} input(s) failed; their rows in the summary say why",
            rows.len()
        )));
    }
    Ok(())
}

/// Usage error for the options of `fairfit curve` that name one output file.
fn refuse_single_file_options(c: &CurveArgs) -> CmdResult {
    if c.chain.is_some() || c.split_at_le || !c.more_inputs.is_empty() {
        return Err(CliError::usage(
            "--chain, --split-at-le and further inputs: not available in batch (it fits every \
             input on its own; use `fairfit curve A B ... --chain g1|g2` for a chain)",
        ));
    }
    let given = [
        ("--report", c.report.is_some()),
        ("--pareto", c.pareto.is_some()),
        ("--pareto-curves", c.pareto_curves.is_some()),
        ("--step, --iges, --mesh, --plot and --html", c.outputs.any()),
    ];
    match given.iter().find(|(_, on)| *on) {
        Some((flag, _)) => Err(CliError::usage(format!(
            "{flag}: not available in batch (every input gets NAME.json and NAME.report.json in \
             OUTDIR; use `fairfit export` on them for other formats)"
        ))),
        None => Ok(()),
    }
}

/// Usage error when OUTDIR is the input folder or lies inside it (by path, `..` or a symbolic link):
/// the results would be written among, or below, the files the run reads.
fn refuse_outdir_in_input(input: &Path, outdir: &Path) -> CmdResult {
    if !input.is_dir() {
        return Ok(());
    }
    let (folder, out) = (deep_canonical(input), deep_canonical(outdir));
    if !out.starts_with(&folder) {
        return Ok(());
    }
    let place = if out == folder { "is" } else { "lies inside" };
    Err(CliError::usage(format!(
        "-o {} {place} the input folder {}; write the results outside it",
        outdir.display(),
        input.display()
    )))
}

/// `path` made absolute with every link resolved: its longest existing ancestor canonicalized and the
/// missing rest (made by the run) appended with its `.` and `..` resolved, so that a folder not made
/// yet compares too.
fn deep_canonical(path: &Path) -> PathBuf {
    use std::path::Component;
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    for head in abs.ancestors() {
        let (Ok(mut out), Ok(rest)) = (head.canonicalize(), abs.strip_prefix(head)) else {
            continue;
        };
        // the missing rest has no links: its `..` is resolved by name
        for part in rest.components() {
            match part {
                Component::ParentDir => {
                    out.pop();
                }
                Component::Normal(name) => out.push(name),
                _ => {}
            }
        }
        return out;
    }
    abs
}

/// The point files of a folder (sorted by name), or those a list file names.
fn list_inputs(input: &Path) -> Result<Vec<PathBuf>, CliError> {
    if input.is_dir() {
        return Ok(expand_section_inputs(&[input.to_path_buf()])?);
    }
    let text = std::fs::read_to_string(input)
        .map_err(|e| CliError::new(fairfit::Error::io(input, &e).to_string()))?;
    let files: Vec<PathBuf> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(PathBuf::from)
        .collect();
    if files.is_empty() {
        return Err(CliError::new(format!(
            "{}: the list names no point file (one path a line)",
            input.display()
        )));
    }
    Ok(files)
}

/// The inputs of `shard` (every input without one).
fn shard_of(inputs: Vec<PathBuf>, shard: Option<Shard>) -> Vec<PathBuf> {
    match shard {
        None => inputs,
        Some(s) => inputs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % s.of == s.k - 1)
            .map(|(_, p)| p)
            .collect(),
    }
}

/// Each input's output name, its file name without the extension; two inputs of one name fail.
fn output_names(inputs: &[PathBuf]) -> Result<Vec<String>, CliError> {
    let names: Vec<String> = inputs
        .iter()
        .map(|p| {
            p.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "input".into())
        })
        .collect();
    for (i, n) in names.iter().enumerate() {
        if let Some(j) = names[..i].iter().position(|m| m == n) {
            return Err(CliError::new(format!(
                "{} and {} would both be written as {n}.json; rename one",
                inputs[j].display(),
                inputs[i].display()
            )));
        }
    }
    Ok(names)
}

/// Fits `input` as `fairfit curve` would (on one thread) and writes its curve and report into
/// `outdir`; the summary row says how it went.
fn fit_one(c: &CurveArgs, input: &Path, name: &str, outdir: &Path) -> Row {
    let wall = Instant::now();
    let mut row = Row {
        name: name.to_string(),
        input: input.display().to_string(),
        status: "ok",
        error: None,
        control_points: None,
        fairness: None,
        max_deviation: None,
        tolerance: None,
        seconds: 0.0,
    };
    match fit_and_write(c, input, name, outdir, wall) {
        Ok(report) => {
            let num = |k: &str| report[k].as_f64();
            row.control_points = report["control_points"].as_u64().map(|n| n as usize);
            row.fairness = num("fairness");
            row.max_deviation = num("max_deviation");
            row.tolerance = num("tolerance");
        }
        Err(e) => {
            row.status = "error";
            row.error = Some(e.message);
        }
    }
    row.seconds = wall.elapsed().as_secs_f64();
    row
}

/// The fit of one input, its two files written (both or none); returns its report.
fn fit_and_write(
    c: &CurveArgs,
    input: &Path,
    name: &str,
    outdir: &Path,
    wall: Instant,
) -> Result<serde_json::Value, CliError> {
    let curve_path = outdir.join(format!("{name}.json"));
    let report_path = outdir.join(format!("{name}.report.json"));
    check_outputs(
        &[
            ("-o", curve_path.as_path()),
            ("--report", report_path.as_path()),
        ],
        &[],
        &Inputs::files(vec![input]),
    )?;
    let mut args = c.clone();
    args.input = input.to_path_buf();
    args.threads = 1;
    let (curve, report, _, _) = fit_input(&args, true, wall)?;
    let mut report = report.unwrap_or_default();
    if report.get("control_points").is_none() {
        report["control_points"] = distinct_control_points(&curve).into();
    }
    let body = super::json_pretty(&report)?;
    write_all_atomic(&[
        (curve_path, curve_to_json(&curve).into_bytes()),
        (report_path, body.into_bytes()),
    ])?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_split_the_inputs_round_robin_and_cover_each_once() {
        let inputs: Vec<PathBuf> = (0..7).map(|i| PathBuf::from(format!("{i}.csv"))).collect();
        let mut seen = Vec::new();
        for k in 1..=3 {
            let part = shard_of(inputs.clone(), Some(Shard { k, of: 3 }));
            seen.extend(part.iter().map(|p| p.display().to_string()));
            if k == 2 {
                assert_eq!(part, vec![PathBuf::from("1.csv"), PathBuf::from("4.csv")]);
            }
        }
        seen.sort();
        assert_eq!(seen, (0..7).map(|i| format!("{i}.csv")).collect::<Vec<_>>());
    }

    #[test]
    fn shard_values_outside_one_to_n_are_refused() {
        assert_eq!(parse_shard("2/8"), Ok(Shard { k: 2, of: 8 }));
        for bad in ["0/4", "5/4", "1", "a/b", "1/0"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }
}
