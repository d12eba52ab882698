//! `fairfit export FILE.json --step out.step --iges out.igs --mesh out.obj|.stl|.ply [--chord-tol T]
//! [--units mm|m]`: any curve or surface JSON file to CAD files, meshes, plots or a report.

use super::outputs::{write_outputs, OutputArgs, OutputGeometry};
use super::{CliError, CmdResult};
use clap::Args;
use fairfit::io::{read_geometry, read_points, Geometry};
use std::path::PathBuf;

/// Arguments of `fairfit export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Curve or surface JSON file.
    pub input: PathBuf,
    /// Data points (CSV/text) for the plot and the report.
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    /// The output files.
    #[command(flatten)]
    pub outputs: OutputArgs,
}

/// Runs `fairfit export`.
pub fn run(args: ExportArgs) -> CmdResult {
    if !args.outputs.any() {
        return Err(CliError(
            "nothing to export: give --step, --iges, --mesh, --plot or --html".into(),
        ));
    }
    let geometry = read_geometry(&args.input)?;
    let points = match &args.points {
        Some(p) => Some(read_points(p)?.points),
        None => None,
    };
    let g = match &geometry {
        Geometry::Curve(c) => OutputGeometry::Curve(c),
        Geometry::Surface(s) => OutputGeometry::Surface(s),
    };
    write_outputs(g, points.as_deref(), None, &args.outputs)
}
