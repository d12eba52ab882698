//! `fairfit plot FILE.json [--points POINTS.csv] -o out.svg|out.png [--width W --height H] [--kind K]`:
//! curvature combs, curvature against arc length, deviations, deviation maps and iso-curve curvature.

use super::files::{check_outputs, commit, Inputs, Output};
use super::outputs::{check_plot_format, main_plot, plot_bytes, OutputGeometry};
use super::{CliError, CmdResult};
use clap::{Args, ValueEnum};
use fairfit::io::{read_points, Geometry};
use fairfit::plot::curve_plots::{curvature_svg, deviation_svg};
use fairfit::plot::surface_plots::{deviation_map_svg, iso_curvature_svg, IsoDirection};
use fairfit::plot::PlotSize;
use std::path::PathBuf;

/// Which plot to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PlotKind {
    /// Curve: curve, data points and curvature comb. Surface: deviation map with points, else iso-u.
    Auto,
    /// Curve: curvature against arc length with the knots marked.
    Curvature,
    /// Curve: distance of each data point to the curve. Surface: deviation map over (u, v).
    Deviation,
    /// Surface: curvature of iso-curves running along u (v fixed).
    IsoU,
    /// Surface: curvature of iso-curves running along v (u fixed).
    IsoV,
}

/// Arguments of `fairfit plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// Curve or surface file (JSON, STEP or IGES).
    pub input: PathBuf,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Data points (CSV/text, 2 or 3 columns).
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    /// Output file, .svg or .png.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Width in pixels.
    #[arg(long, default_value_t = 900, allow_hyphen_values = true)]
    pub width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 600, allow_hyphen_values = true)]
    pub height: u32,
    /// Which plot.
    #[arg(long, value_enum, default_value_t = PlotKind::Auto)]
    pub kind: PlotKind,
    /// Number of iso-curves in iso plots.
    #[arg(long, default_value_t = 5, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u64).range(1..=50))]
    pub iso: u64,
}

/// Runs `fairfit plot`.
pub fn run(args: PlotArgs) -> CmdResult {
    let size = PlotSize::new(args.width, args.height)?;
    let mut inputs = vec![args.input.as_path()];
    inputs.extend(args.points.as_deref());
    check_outputs(&[("-o", &args.output)], &[], &Inputs::files(inputs))?;
    check_plot_format("-o", &args.output)?;
    let geometry = super::cad_input::read_input(&args.input, &args.cad)?;
    super::work::check_spans(&geometry, &args.input)?;
    let points = match &args.points {
        Some(p) => Some(read_points(p)?.points),
        None => None,
    };
    let pts = points.as_deref();
    let need_points = || {
        pts.filter(|p| !p.is_empty())
            .ok_or_else(|| CliError::usage("--kind deviation needs --points"))
    };
    let iso = args.iso as usize;
    let svg = match (&geometry, args.kind) {
        (Geometry::Curve(c), PlotKind::Auto) => main_plot(OutputGeometry::Curve(c), pts, size)?,
        (Geometry::Curve(c), PlotKind::Curvature) => curvature_svg(c, size)?,
        (Geometry::Curve(c), PlotKind::Deviation) => deviation_svg(c, need_points()?, size)?,
        (Geometry::Surface(s), PlotKind::Auto) => main_plot(OutputGeometry::Surface(s), pts, size)?,
        (Geometry::Surface(s), PlotKind::Deviation) => deviation_map_svg(s, need_points()?, size)?,
        (Geometry::Surface(s), PlotKind::IsoU) => {
            iso_curvature_svg(s, IsoDirection::FixedV, iso, size)?
        }
        (Geometry::Surface(s), PlotKind::IsoV) => {
            iso_curvature_svg(s, IsoDirection::FixedU, iso, size)?
        }
        (g, k) => {
            let what = match g {
                Geometry::Curve(_) => "curve",
                Geometry::Surface(_) => "surface",
            };
            let name = k
                .to_possible_value()
                .map(|v| v.get_name().to_string())
                .unwrap_or_default();
            return Err(CliError::usage(format!(
                "--kind {name} does not apply to a {what}"
            )));
        }
    };
    // checked finite as SVG text, before a PNG is made of it
    super::files::check_finite_output(&args.output, svg.as_bytes(), false)?;
    let bytes = plot_bytes(&args.output, svg, size)?;
    commit(vec![Output::new(&args.output, bytes)])
}
