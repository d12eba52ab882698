//! Output flags shared by `fairfit export`, `fairfit curve` and `fairfit surface`: `--step`, `--iges`,
//! `--mesh`, `--plot`, `--html` (with `--chord-tol` and `--units`). Subcommands `#[command(flatten)]`
//! [`OutputArgs`] and call [`prepare_outputs`], then write them together with their own files by
//! `files::commit`.
//!
//! Every output is produced in memory first, so invalid geometry or options fail before any file is
//! written; the files are then written all or none (temporary files renamed into place only when all
//! were written: a failed write leaves no partial file and no half of the outputs). A mesh whose
//! vertices are not all finite (huge control points, evaluated beyond the floating-point range) is
//! refused before it is written.

use super::{CliError, CmdResult};
use clap::Args;
use fairfit::io::cad_common::{validate_curve, validate_surface, LengthUnit};
use fairfit::io::mesh_write::MeshFormat;
use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use fairfit::plot::png::svg_to_png;
use fairfit::plot::PlotSize;
use fairfit::report::files::{file_bytes, html_report, FileInputs, Format, Shape};
use std::path::{Path, PathBuf};

/// The geometry to write.
#[derive(Clone, Copy, Debug)]
pub enum OutputGeometry<'a> {
    /// A curve.
    Curve(&'a NurbsCurve),
    /// A surface.
    Surface(&'a NurbsSurface),
}

/// Output files for a curve or surface.
#[derive(Args, Debug, Clone, Default)]
pub struct OutputArgs {
    /// Write the geometry as STEP (AP214): a face for a surface, a wireframe curve for a curve.
    #[arg(long, value_name = "FILE")]
    pub step: Option<PathBuf>,
    /// Write the geometry as IGES 5.3 (entity 126 or 128).
    #[arg(long, value_name = "FILE")]
    pub iges: Option<PathBuf>,
    /// Write a mesh: .obj, .stl (surfaces only) or .ply; curves become polylines.
    #[arg(long, value_name = "FILE")]
    pub mesh: Option<PathBuf>,
    /// Write a plot, .svg or .png (curve: curvature comb; surface: deviation map with points, else
    /// iso-curve curvature).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Write a self-contained HTML report with metrics and plots.
    #[arg(long, value_name = "FILE")]
    pub html: Option<PathBuf>,
    /// Maximum chord height of the mesh, in model units (default: 8 samples per knot span).
    #[arg(long, value_name = "T", allow_hyphen_values = true, value_parser = super::finite_positive)]
    pub chord_tol: Option<f64>,
    /// Length unit declared in STEP and IGES files.
    #[arg(long, default_value = "mm", value_parser = ["mm", "m"])]
    pub units: String,
}

impl OutputArgs {
    /// True when at least one output file was asked for.
    pub fn any(&self) -> bool {
        self.step.is_some()
            || self.iges.is_some()
            || self.mesh.is_some()
            || self.plot.is_some()
            || self.html.is_some()
    }
}

impl OutputArgs {
    /// Every output file asked for, with its flag.
    pub fn named(&self) -> Vec<(&'static str, &Path)> {
        [
            ("--step", &self.step),
            ("--iges", &self.iges),
            ("--mesh", &self.mesh),
            ("--plot", &self.plot),
            ("--html", &self.html),
        ]
        .into_iter()
        .filter_map(|(flag, p)| p.as_deref().map(|p| (flag, p)))
        .collect()
    }
}

/// Fails (a usage error) when the file name of a `--plot` or `--mesh` output has no extension the
/// writer knows, so a long fit does not end with that error. The writers check again.
fn check_format(flag: &str, path: &Path) -> CmdResult {
    match flag {
        "--plot" => check_plot_format(flag, path),
        "--mesh" => check_extension(flag, path, &["obj", "stl", "ply"], "a .obj, .stl or .ply"),
        _ => Ok(()),
    }
}

/// Fails (a usage error, like `--plot`'s) when the plot file `path`, given by `flag` (`-o` of
/// `fairfit plot`), is not a .svg or .png file name.
pub fn check_plot_format(flag: &str, path: &Path) -> CmdResult {
    check_extension(flag, path, &["svg", "png"], "a .svg or .png")
}

fn check_extension(flag: &str, path: &Path, known: &[&str], expected: &str) -> CmdResult {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext.as_deref().is_some_and(|e| known.contains(&e)) {
        return Ok(());
    }
    Err(CliError::usage(format!(
        "{flag} {}: unknown format, expected {expected} file name",
        path.display()
    )))
}

/// Fails (a usage error), before any work, when a `--plot`/`--mesh` file name of `outputs` (flag,
/// path) has an unknown extension. The paths themselves are checked by `files::check_outputs`.
pub fn check_output_formats(outputs: &[(&str, &Path)]) -> CmdResult {
    for (flag, path) in outputs {
        check_format(flag, path)?;
    }
    Ok(())
}

impl<'a> From<OutputGeometry<'a>> for Shape<'a> {
    fn from(g: OutputGeometry<'a>) -> Self {
        match g {
            OutputGeometry::Curve(c) => Shape::Curve(c),
            OutputGeometry::Surface(s) => Shape::Surface(s),
        }
    }
}

/// The main plot of a geometry as SVG.
pub fn main_plot(
    g: OutputGeometry<'_>,
    points: Option<&[Vec3]>,
    size: PlotSize,
) -> Result<String, CliError> {
    Ok(fairfit::report::files::main_plot(g.into(), points, size)?)
}

/// SVG or PNG bytes of `svg` as the extension of `path` asks.
pub fn plot_bytes(path: &Path, svg: String, size: PlotSize) -> Result<Vec<u8>, CliError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("svg") => Ok(svg.into_bytes()),
        Some("png") => Ok(svg_to_png(&svg, size.width, size.height)?),
        _ => Err(CliError::usage(format!(
            "{}: unknown plot format, expected a .svg or .png file name",
            path.display()
        ))),
    }
}

/// Every output asked for in `args` as (path, bytes), made in memory; nothing is written. Fails on
/// invalid geometry or options.
pub fn prepare_outputs(
    geometry: OutputGeometry<'_>,
    points: Option<&[Vec3]>,
    report_json: Option<&serde_json::Value>,
    args: &OutputArgs,
) -> Result<Vec<(PathBuf, Vec<u8>)>, CliError> {
    match geometry {
        OutputGeometry::Curve(c) => validate_curve(c)?,
        OutputGeometry::Surface(s) => validate_surface(s)?,
    }
    let unit: LengthUnit = args.units.parse()?;
    let inputs = FileInputs {
        points,
        report: report_json,
        unit,
        chord_tol: args.chord_tol,
    };
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    if let Some(p) = &args.step {
        files.push((
            p.clone(),
            file_bytes(geometry.into(), Format::Step, p, &inputs)?,
        ));
    }
    if let Some(p) = &args.iges {
        files.push((
            p.clone(),
            file_bytes(geometry.into(), Format::Iges, p, &inputs)?,
        ));
    }
    if let Some(p) = &args.mesh {
        let format = Format::Mesh(MeshFormat::from_path(p)?);
        files.push((p.clone(), file_bytes(geometry.into(), format, p, &inputs)?));
    }
    if let Some(p) = &args.plot {
        let size = PlotSize::default();
        files.push((
            p.clone(),
            plot_bytes(p, main_plot(geometry, points, size)?, size)?,
        ));
    }
    if let Some(p) = &args.html {
        let html = html_report(geometry.into(), points, report_json)?;
        files.push((p.clone(), html.into_bytes()));
    }
    Ok(files)
}
