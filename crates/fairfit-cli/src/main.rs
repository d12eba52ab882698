//! `fairfit`: fair NURBS curves and surfaces from measured points, on the command line.
//!
//! Every subcommand lives in its own file under `commands/`. Errors print as one line on stderr with a
//! non-zero exit code; the library's typed errors already name what is wrong.

mod commands;
mod progress;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Fair NURBS curves and surfaces from measured points.
#[derive(Parser, Debug)]
#[command(name = "fairfit", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Evaluate a curve or surface JSON file at given parameters (points, derivatives, curvature).
    Eval(commands::eval::EvalArgs),
    /// Summarise a curve or surface JSON file (size, domain, length, fairness).
    Info(commands::info::InfoArgs),
    /// Fit a fair curve to ordered points.
    Curve(commands::curve::CurveArgs),
    /// Fit a fair surface to sections or a point cloud.
    Surface(commands::surface::SurfaceArgs),
    /// Plot a curve or surface JSON file.
    Plot(commands::plot::PlotArgs),
    /// Export a curve or surface JSON file to STEP, IGES or a mesh.
    Export(commands::export::ExportArgs),
}

fn main() -> ExitCode {
    // Last line of defence: a bug must still print one line, never a backtrace.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        eprintln!("error: internal error ({msg}); please report it with the input that caused it");
    }));
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Eval(a) => commands::eval::run(a),
        Command::Info(a) => commands::info::run(a),
        Command::Curve(a) => commands::curve::run(a),
        Command::Surface(a) => commands::surface::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Export(a) => commands::export::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
