//! `fairfit`: fair NURBS curves and surfaces from measured points, on the command line.
//!
//! Every subcommand lives in its own file under `commands/`. Errors print as one line on stderr with a
//! non-zero exit code: 2 for usage errors (unknown or missing arguments, option values or combinations
//! the command does not accept, whether clap or the command finds them, including the library's
//! `Error::InvalidOption` and `Error::InvalidSetting`, whose setting is named by its flag; the line ends with the `--help` to read), 1 for everything else
//! (unreadable or invalid input, failed writes); the library's typed errors already name what is wrong. `--help` and `--version` print
//! normally and exit 0; `fairfit` without a subcommand prints the help on stderr and exits 2. A closed
//! stdout (`fairfit info x.json | head -c 10`) ends the run quietly with exit 0. The `warning:` and
//! `note:` lines of a run are printed when it succeeds; a failed run prints only its error line, the
//! warnings folded in (`commands::messages`). SIGINT and SIGTERM remove the temporary files of the
//! outputs not yet in place (`commands::files`) and end the run with exit code 128 + the signal.

mod commands;
mod progress;

use clap::error::ErrorKind;
use clap::{CommandFactory, Parser, Subcommand};
use std::process::ExitCode;

/// Fair NURBS curves and surfaces from measured points.
#[derive(Parser, Debug)]
#[command(name = "fairfit", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Most points (or mesh vertices, or control points) an input may hold; larger inputs are refused
    /// with one line.
    #[arg(long, global = true, value_name = "N", default_value_t = fairfit::io::limits::DEFAULT_MAX_POINTS)]
    max_points: usize,
    /// Largest JSON, STEP, IGES or mesh file read, in MiB (point files are streamed and bounded by
    /// --max-points instead).
    #[arg(long, global = true, value_name = "MIB", default_value_t = fairfit::io::limits::DEFAULT_MAX_FILE_BYTES >> 20)]
    max_file_mb: u64,
    /// Most knot spans (u × v for a surface) `info`, `plot` and `export` analyse or sample; their work
    /// grows with the spans.
    #[arg(long, global = true, value_name = "N", default_value_t = commands::work::DEFAULT_MAX_SPANS)]
    max_spans: usize,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Evaluate a curve or surface (JSON, STEP or IGES) at given parameters (points, derivatives, curvature).
    Eval(commands::eval::EvalArgs),
    /// Summarise a curve or surface (JSON, STEP or IGES): size, domain, length, fairness.
    Info(commands::info::InfoArgs),
    /// Fit a fair curve to ordered points, or re-fair a STEP/IGES curve.
    #[command(after_help = commands::files::OUTPUT_RULES)]
    Curve(commands::curve_args::CurveArgs),
    /// Fit a fair curve to every point file of a folder or a list (`fairfit curve` on each, in
    /// parallel), with a JSONL summary.
    Batch(commands::batch::BatchArgs),
    /// Fit a fair surface to sections or a point cloud.
    #[command(after_help = commands::files::OUTPUT_RULES)]
    Surface(commands::surface::SurfaceArgs),
    /// Plot a curve or surface (JSON, STEP or IGES).
    #[command(after_help = commands::files::OUTPUT_RULES)]
    Plot(commands::plot::PlotArgs),
    /// Export a curve or surface (JSON, STEP or IGES) to STEP, IGES or a mesh.
    #[command(after_help = commands::files::OUTPUT_RULES)]
    Export(commands::export::ExportArgs),
}

/// Exit code of usage errors (clap's convention).
const USAGE_ERROR: u8 = 2;

/// The one-line form of a clap usage error: its message (continuation lines joined, `tip:` lines in
/// parentheses) and the `--help` of the (sub)command it concerns, e.g.
/// `error: unexpected argument '--foo' found; see 'fairfit curve --help'`.
fn one_line_usage_error(err: &clap::Error, args: &[String]) -> String {
    let text = err.render().to_string();
    let mut message = String::new();
    let mut tips = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if line.is_empty() {
            continue;
        }
        if let Some(tip) = line.strip_prefix("tip:") {
            // "to pass '--foo' as a value, use '-- --foo'" is noise for this tool's arguments
            if !tip.contains("as a value") {
                tips.push(tip.trim().to_string());
            }
        } else {
            if !message.is_empty() {
                message.push(' ');
            }
            message.push_str(line);
        }
    }
    if !message.starts_with("error:") {
        message = format!("error: {message}");
    }
    if !tips.is_empty() {
        message = format!("{message} ({})", tips.join("; "));
    }
    format!("{message}; see '{} --help'", command_path(args))
}

/// `fairfit` or `fairfit SUBCOMMAND` for the first argument that names a subcommand.
fn command_path(args: &[String]) -> String {
    let cmd = Cli::command();
    let sub = args.iter().skip(1).find_map(|a| {
        cmd.get_subcommands()
            .find(|s| s.get_name() == a)
            .map(|s| s.get_name().to_string())
    });
    match sub {
        Some(s) => format!("fairfit {s}"),
        None => "fairfit".into(),
    }
}

/// On SIGINT or SIGTERM: removes the temporary files of outputs not yet in place, prints one line
/// and exits with 128 + the signal (the outputs of a run are all in place or none).
#[cfg(unix)]
fn remove_temporaries_on_signal() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return; // no handler: the default action ends the run, as before
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            fairfit::io::atomic::remove_pending_temporaries();
            let name = if sig == SIGINT { "SIGINT" } else { "SIGTERM" };
            eprintln!("error: interrupted by {name}; no partial output left");
            std::process::exit(128 + sig);
        }
    });
}

#[cfg(not(unix))]
fn remove_temporaries_on_signal() {}

fn main() -> ExitCode {
    // Last line of defence: a bug must still print one line, never a backtrace.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        let line = format!(
            "error: internal error ({msg}); please report it with the input that caused it"
        );
        eprintln!("{}", commands::messages::one_line(&line));
    }));
    remove_temporaries_on_signal();
    let args: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let cli = match Cli::try_parse_from(std::env::args_os()) {
        Ok(cli) => cli,
        Err(e) => {
            return match e.kind() {
                // help and version go to stdout with exit 0; a missing subcommand prints the help
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    let _ = e.print(); // a closed stdout is not an error here either
                    ExitCode::SUCCESS
                }
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    let _ = e.print();
                    ExitCode::from(USAGE_ERROR)
                }
                _ => {
                    let line = one_line_usage_error(&e, &args);
                    eprintln!("{}", commands::messages::one_line(&line));
                    ExitCode::from(USAGE_ERROR)
                }
            };
        }
    };
    fairfit::io::limits::ReadLimits {
        max_points: cli.max_points,
        max_file_bytes: cli.max_file_mb.saturating_mul(1 << 20),
    }
    .install();
    commands::work::set_max_spans(cli.max_spans);
    if let Err(e) = commands::threads::build_global_pool() {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Command::Eval(a) => commands::eval::run(a),
        Command::Info(a) => commands::info::run(a),
        // a chain (`--chain`, several inputs, `--split-at-le`) or one curve
        Command::Curve(a) if commands::curve_chain::asked(&a) => commands::curve_chain::run(a),
        Command::Curve(a) => commands::curve::run(a),
        Command::Batch(a) => commands::batch::run(a),
        Command::Surface(a) => commands::surface::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Export(a) => commands::export::run(a),
    };
    match result {
        Ok(()) => {
            commands::messages::flush();
            ExitCode::SUCCESS
        }
        Err(e) if e.usage => {
            let message = format!("{e}; see '{} --help'", command_path(&args));
            eprintln!("{}", commands::messages::failure_line(&message));
            ExitCode::from(USAGE_ERROR)
        }
        Err(e) => {
            eprintln!("{}", commands::messages::failure_line(&e.message));
            ExitCode::FAILURE
        }
    }
}
