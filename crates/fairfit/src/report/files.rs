//! The bytes of every output file of a curve or surface: fairfit JSON, STEP, IGES, meshes, SVG/PNG
//! plots and the HTML report, made in memory ([`file_bytes`]); the format is the caller's choice
//! (`--step FILE`) or the file's extension ([`Format::from_path`], [`output_bytes`]).
//!
//! Nothing is written here: a caller makes every file first, so invalid geometry or options fail
//! before any file exists, then writes them all or none ([`crate::io::atomic::write_all_atomic`]).

use crate::io::cad_common::{validate_curve, validate_surface, LengthUnit};
use crate::io::iges::{curve_to_iges, surface_to_iges, IgesOptions};
use crate::io::mesh_write::{mesh_bytes, MeshFormat};
use crate::io::step::{curve_to_step, surface_to_step, StepOptions};
use crate::io::tessellate::{tessellate_curve, tessellate_surface, TessellationOptions};
use crate::io::{curve_to_json, surface_to_json};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use crate::plot::curve_plots::{curvature_svg, curve_comb_svg, deviation_svg};
use crate::plot::html::{html_report as render_html, rows_from_json, Report};
use crate::plot::png::svg_to_png;
use crate::plot::surface_plots::{deviation_map_svg, iso_curvature_svg, IsoDirection};
use crate::plot::PlotSize;
use crate::{Error, Result};
use serde_json::Value;
use std::path::Path;

/// The geometry of an output file.
#[derive(Clone, Copy, Debug)]
pub enum Shape<'a> {
    /// A curve.
    Curve(&'a NurbsCurve),
    /// A surface.
    Surface(&'a NurbsSurface),
}

/// An output file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// fairfit's JSON geometry.
    Json,
    /// STEP AP214 (a face for a surface, a wireframe curve for a curve).
    Step,
    /// IGES 5.3 (entity 126 or 128).
    Iges,
    /// A mesh (curves become polylines).
    Mesh(MeshFormat),
    /// The main plot as SVG (curve: curvature comb; surface: deviation map, else iso-curvature).
    Svg,
    /// The main plot as PNG.
    Png,
    /// The self-contained HTML report with metrics and plots.
    Html,
}

impl Format {
    /// The format a file name's extension names (any case): `.json`, `.step`/`.stp`, `.iges`/`.igs`,
    /// `.obj`/`.stl`/`.ply`, `.svg`, `.png`, `.html`/`.htm`.
    ///
    /// ```
    /// use fairfit::report::files::Format;
    /// use std::path::Path;
    /// assert_eq!(Format::from_path(Path::new("wing.STP")).unwrap(), Format::Step);
    /// assert!(Format::from_path(Path::new("wing.txt")).is_err());
    /// ```
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        Ok(match ext.as_str() {
            "json" => Format::Json,
            "step" | "stp" => Format::Step,
            "iges" | "igs" => Format::Iges,
            "obj" | "stl" | "ply" => Format::Mesh(MeshFormat::from_path(path)?),
            "svg" => Format::Svg,
            "png" => Format::Png,
            "html" | "htm" => Format::Html,
            _ => {
                return Err(Error::InvalidOption(format!(
                    "{}: unknown format, expected a .json, .step, .stp, .iges, .igs, .obj, .stl, \
                     .ply, .svg, .png or .html file name",
                    path.display()
                )))
            }
        })
    }
}

/// What an output file is made with besides its geometry.
#[derive(Clone, Copy, Debug)]
pub struct FileInputs<'a> {
    /// The data points (drawn by plots and reports, measured by the deviation plots).
    pub points: Option<&'a [Vec3]>,
    /// The fit's report (the metrics of the HTML report).
    pub report: Option<&'a Value>,
    /// The length unit declared in STEP and IGES files.
    pub unit: LengthUnit,
    /// The mesh's largest chord height in model units (`None`: 8 samples per knot span).
    pub chord_tol: Option<f64>,
}

/// The bytes of the file `path` in `format`: STEP and IGES files name their entity after the file
/// name, and error messages name `path`. Fails on invalid options, and on a surface whose mesh has no
/// area.
pub fn file_bytes(
    shape: Shape<'_>,
    format: Format,
    path: &Path,
    inputs: &FileInputs<'_>,
) -> Result<Vec<u8>> {
    let size = PlotSize::default();
    Ok(match format {
        Format::Json => match shape {
            Shape::Curve(c) => curve_to_json(c),
            Shape::Surface(s) => surface_to_json(s),
        }
        .into_bytes(),
        Format::Step => {
            let opts = StepOptions {
                unit: inputs.unit,
                name: entity_name(path),
                ..Default::default()
            };
            match shape {
                Shape::Curve(c) => curve_to_step(c, &opts)?,
                Shape::Surface(s) => surface_to_step(s, &opts)?,
            }
            .into_bytes()
        }
        Format::Iges => {
            let opts = IgesOptions {
                unit: inputs.unit,
                name: entity_name(path),
                ..Default::default()
            };
            match shape {
                Shape::Curve(c) => curve_to_iges(c, &opts)?,
                Shape::Surface(s) => surface_to_iges(s, &opts)?,
            }
            .into_bytes()
        }
        Format::Mesh(format) => mesh_file(shape, format, path, inputs.chord_tol)?,
        Format::Svg => main_plot(shape, inputs.points, size)?.into_bytes(),
        Format::Png => svg_to_png(
            &main_plot(shape, inputs.points, size)?,
            size.width,
            size.height,
        )?,
        Format::Html => html_report(shape, inputs.points, inputs.report)?.into_bytes(),
    })
}

/// The geometry checked ([`validate_curve`], [`validate_surface`]) and the bytes of the file `path`
/// in the format its extension names ([`Format::from_path`]).
pub fn output_bytes(shape: Shape<'_>, path: &Path, inputs: &FileInputs<'_>) -> Result<Vec<u8>> {
    let format = Format::from_path(path)?;
    validate(shape)?;
    file_bytes(shape, format, path, inputs)
}

/// Checks that the geometry can be written (finite numbers, valid knots and weights).
pub fn validate(shape: Shape<'_>) -> Result<()> {
    match shape {
        Shape::Curve(c) => validate_curve(c),
        Shape::Surface(s) => validate_surface(s),
    }
}

/// The entity name of STEP and IGES files: the file's name without its folder.
pub(crate) fn entity_name(path: &Path) -> String {
    path.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fairfit".into())
}

/// The mesh file of `shape`; a mesh with a non-finite vertex or normal is refused, and a surface whose
/// every triangle is degenerate has no mesh.
fn mesh_file(
    shape: Shape<'_>,
    format: MeshFormat,
    path: &Path,
    chord_tol: Option<f64>,
) -> Result<Vec<u8>> {
    let opts = TessellationOptions {
        chord_tol,
        ..Default::default()
    };
    let mesh = match shape {
        Shape::Curve(c) => tessellate_curve(c, &opts)?,
        Shape::Surface(s) => tessellate_surface(s, &opts)?,
    };
    if mesh
        .vertices
        .iter()
        .chain(&mesh.normals)
        .any(|v| !v.is_finite())
    {
        return Err(Error::InvalidData(format!(
            "{}: the mesh has points beyond the floating-point range at this geometry's scale; \
             nothing was written; rescale the geometry",
            path.display()
        )));
    }
    if matches!(shape, Shape::Surface(_)) && mesh.triangles.is_empty() {
        return Err(Error::InvalidData(format!(
            "{}: the surface has no area (every triangle of its mesh is degenerate, e.g. all \
             control points at one place), so there is no mesh to write",
            path.display()
        )));
    }
    mesh_bytes(&mesh, format)
}

/// The main plot as SVG: a curve's curvature comb (with the points), a surface's deviation map when
/// there are points, else the curvature of its iso-curves.
pub fn main_plot(shape: Shape<'_>, points: Option<&[Vec3]>, size: PlotSize) -> Result<String> {
    match (shape, points) {
        (Shape::Curve(c), _) => curve_comb_svg(c, points, size),
        (Shape::Surface(s), Some(p)) if !p.is_empty() => deviation_map_svg(s, p, size),
        (Shape::Surface(s), _) => iso_curvature_svg(s, IsoDirection::FixedV, 5, size),
    }
}

/// The HTML report: the geometry's parameters, its plots and `metrics` (the fit's report) as rows.
pub fn html_report(
    shape: Shape<'_>,
    points: Option<&[Vec3]>,
    metrics: Option<&Value>,
) -> Result<String> {
    let size = PlotSize::default();
    let mut r = Report {
        title: "fairfit report".into(),
        ..Default::default()
    };
    let pts = points.unwrap_or(&[]);
    r.inputs.push(("data points".into(), pts.len().to_string()));
    match shape {
        Shape::Curve(c) => {
            r.parameters.push(("kind".into(), "curve".into()));
            r.parameters.push(("degree".into(), c.degree().to_string()));
            r.parameters
                .push(("control points".into(), c.n_control_points().to_string()));
            r.parameters
                .push(("knots".into(), c.knots().len().to_string()));
            r.plots.push((
                "Curve, data and curvature comb".into(),
                curve_comb_svg(c, points, size)?,
            ));
            r.plots.push((
                "Curvature against arc length".into(),
                curvature_svg(c, size)?,
            ));
            if !pts.is_empty() {
                r.plots
                    .push(("Deviation per point".into(), deviation_svg(c, pts, size)?));
            }
        }
        Shape::Surface(s) => {
            let (n_u, n_v) = s.net_size();
            r.parameters.push(("kind".into(), "surface".into()));
            r.parameters.push((
                "degrees".into(),
                format!("{} x {}", s.degree_u(), s.degree_v()),
            ));
            r.parameters
                .push(("control net".into(), format!("{n_u} x {n_v}")));
            if !pts.is_empty() {
                r.plots
                    .push(("Deviation map".into(), deviation_map_svg(s, pts, size)?));
            }
            for (name, dir) in [("u", IsoDirection::FixedV), ("v", IsoDirection::FixedU)] {
                let caption = format!("Curvature of iso-curves along {name}");
                r.plots.push((caption, iso_curvature_svg(s, dir, 5, size)?));
            }
        }
    }
    if let Some(m) = metrics {
        r.metrics = rows_from_json(m);
    }
    Ok(render_html(&r))
}
