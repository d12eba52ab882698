//! `fairfit export FILE.json --step out.step --iges out.igs --mesh out.obj|.stl|.ply [--chord-tol T]
//! [--units mm|m] [--samples S.json]`: any curve or surface JSON file to CAD files, meshes, plots or a
//! report; `--samples` writes parameters and fairfit's points for checking the CAD file elsewhere.

use super::files::{check_outputs, commit, Inputs, Output};
use super::outputs::{check_output_formats, prepare_outputs, OutputArgs, OutputGeometry};
use super::{CliError, CmdResult};
use clap::Args;
use fairfit::io::samples::{curve_samples_json, surface_samples_json};
use fairfit::io::{read_points, Geometry};
use std::path::PathBuf;

/// Arguments of `fairfit export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Curve or surface file (JSON, STEP or IGES).
    pub input: PathBuf,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Data points (CSV/text) for the plot and the report.
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    /// Write sample parameters and fairfit's points (JSON) for checking a CAD file elsewhere.
    #[arg(long, value_name = "FILE")]
    pub samples: Option<PathBuf>,
    /// The output files.
    #[command(flatten)]
    pub outputs: OutputArgs,
}

/// Runs `fairfit export`.
pub fn run(args: ExportArgs) -> CmdResult {
    if !args.outputs.any() && args.samples.is_none() {
        return Err(CliError::usage(
            "nothing to export: give --step, --iges, --mesh, --plot, --html or --samples",
        ));
    }
    let mut outputs = args.outputs.named();
    if let Some(p) = &args.samples {
        outputs.push(("--samples", p));
    }
    let mut inputs = vec![args.input.as_path()];
    inputs.extend(args.points.as_deref());
    check_outputs(&outputs, &[], &Inputs::files(inputs))?;
    check_output_formats(&outputs)?;
    let geometry = super::cad_input::read_input(&args.input, &args.cad)?;
    // STEP and IGES copy the geometry as it is; meshes, plots, reports and samples sample it per span
    let o = &args.outputs;
    if o.mesh.is_some() || o.plot.is_some() || o.html.is_some() || args.samples.is_some() {
        super::work::check_spans(&geometry, &args.input)?;
    }
    let points = match &args.points {
        Some(p) => Some(read_points(p)?.points),
        None => None,
    };
    let g = match &geometry {
        Geometry::Curve(c) => OutputGeometry::Curve(c),
        Geometry::Surface(s) => OutputGeometry::Surface(s),
    };
    let mut files: Vec<Output> = prepare_outputs(g, points.as_deref(), None, &args.outputs)?
        .into_iter()
        .map(|(p, b)| Output::new(p, b))
        .collect();
    if let Some(p) = &args.samples {
        let text = match &geometry {
            Geometry::Curve(c) => curve_samples_json(c, 120),
            Geometry::Surface(s) => surface_samples_json(s, 12, 10),
        };
        files.push(Output::geometry(p, text.into_bytes()));
    }
    commit(files)
}
