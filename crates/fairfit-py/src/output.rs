//! Files: `save` (the format chosen by the extension, made as `fairfit export` / `--step`, `--iges`,
//! `--mesh`, `--plot` and `--html` make them) and `read` (fairfit JSON, STEP and IGES, as the CLI's
//! `info` and `eval` read them).

use crate::curve::{dim_of, Curve};
use crate::surface::Surface;
use fairfit::io::cad_common::LengthUnit;
use fairfit::io::cad_read::{read_cad, CadFormat, CadKind};
use fairfit::io::iges::{curve_to_iges, surface_to_iges, IgesOptions};
use fairfit::io::mesh_write::{mesh_bytes, MeshFormat};
use fairfit::io::step::{curve_to_step, surface_to_step, StepOptions};
use fairfit::io::tessellate::{tessellate_curve, tessellate_surface, TessellationOptions};
use fairfit::io::{curve_to_json, read_geometry, surface_to_json, write_atomic, Geometry};
use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use fairfit::plot::curve_plots::{curvature_svg, curve_comb_svg, deviation_svg};
use fairfit::plot::html::{html_report, rows_from_json, Report};
use fairfit::plot::png::svg_to_png;
use fairfit::plot::surface_plots::{deviation_map_svg, iso_curvature_svg, IsoDirection};
use fairfit::plot::PlotSize;
use pyo3::prelude::*;
use std::path::Path;

/// The geometry to write.
#[derive(Clone, Copy)]
pub enum Shape<'a> {
    /// A curve.
    Curve(&'a NurbsCurve),
    /// A surface.
    Surface(&'a NurbsSurface),
}

/// Writes `shape` to `path` in the format its extension names.
pub fn save(
    shape: Shape<'_>,
    path: &Path,
    points: Option<&[Vec3]>,
    report: Option<&serde_json::Value>,
    units: &str,
    chord_tol: Option<f64>,
) -> Result<(), String> {
    let bytes =
        bytes_for(shape, path, points, report, units, chord_tol).map_err(|e| e.to_string())?;
    write_atomic(path, &bytes).map_err(|e| e.to_string())
}

/// The file's name without its folder (the entity name of STEP and IGES files).
fn stem(path: &Path) -> String {
    path.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fairfit".into())
}

fn bytes_for(
    shape: Shape<'_>,
    path: &Path,
    points: Option<&[Vec3]>,
    report: Option<&serde_json::Value>,
    units: &str,
    chord_tol: Option<f64>,
) -> fairfit::Result<Vec<u8>> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let unit: LengthUnit = units.parse()?;
    let size = PlotSize::default();
    Ok(match ext.as_str() {
        "json" => match shape {
            Shape::Curve(c) => curve_to_json(c),
            Shape::Surface(s) => surface_to_json(s),
        }
        .into_bytes(),
        "step" | "stp" => {
            let opts = StepOptions {
                unit,
                name: stem(path),
                ..Default::default()
            };
            match shape {
                Shape::Curve(c) => curve_to_step(c, &opts)?,
                Shape::Surface(s) => surface_to_step(s, &opts)?,
            }
            .into_bytes()
        }
        "iges" | "igs" => {
            let opts = IgesOptions {
                unit,
                name: stem(path),
                ..Default::default()
            };
            match shape {
                Shape::Curve(c) => curve_to_iges(c, &opts)?,
                Shape::Surface(s) => surface_to_iges(s, &opts)?,
            }
            .into_bytes()
        }
        "obj" | "stl" | "ply" => {
            let format = MeshFormat::from_path(path)?;
            let opts = TessellationOptions {
                chord_tol,
                ..Default::default()
            };
            let mesh = match shape {
                Shape::Curve(c) => tessellate_curve(c, &opts)?,
                Shape::Surface(s) => tessellate_surface(s, &opts)?,
            };
            mesh_bytes(&mesh, format)?
        }
        "svg" | "png" => {
            let svg = match (shape, points) {
                (Shape::Curve(c), _) => curve_comb_svg(c, points, size)?,
                (Shape::Surface(s), Some(p)) if !p.is_empty() => deviation_map_svg(s, p, size)?,
                (Shape::Surface(s), _) => iso_curvature_svg(s, IsoDirection::FixedV, 5, size)?,
            };
            if ext == "png" {
                svg_to_png(&svg, size.width, size.height)?
            } else {
                svg.into_bytes()
            }
        }
        "html" | "htm" => html(shape, points, report)?.into_bytes(),
        _ => {
            return Err(fairfit::Error::InvalidOption(format!(
                "{}: unknown format, expected a .json, .step, .stp, .iges, .igs, .obj, .stl, .ply, \
                 .svg, .png or .html file name",
                path.display()
            )))
        }
    })
}

/// The HTML report `--html` writes: the parameters, plots and the fit's report as metrics.
fn html(
    shape: Shape<'_>,
    points: Option<&[Vec3]>,
    metrics: Option<&serde_json::Value>,
) -> fairfit::Result<String> {
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
    Ok(html_report(&r))
}

/// read(path) -> Curve | Surface: a fairfit JSON, STEP or IGES file (STEP/IGES: the first B-spline
/// surface if the file holds one, else its first curve, in millimetres; `index` chooses another).
#[pyfunction]
#[pyo3(signature = (path, index=0))]
pub fn read(py: Python<'_>, path: std::path::PathBuf, index: usize) -> PyResult<PyObject> {
    let g = crate::guarded(py, || {
        let g = match CadFormat::from_path(&path) {
            Some(_) => read_cad(&path, CadKind::Any, index).map(|g| g.geometry),
            None => read_geometry(&path),
        };
        g.map_err(|e| e.to_string())
    })?;
    Ok(match g {
        Geometry::Curve(c) => {
            let dim = dim_of(c.control_points());
            Curve::new(c, dim, None)
                .into_pyobject(py)?
                .into_any()
                .unbind()
        }
        Geometry::Surface(s) => Surface::new(s, None).into_pyobject(py)?.into_any().unbind(),
    })
}

/// read_points(path) -> ndarray: the points of a point file as `fairfit curve` reads them (CSV, TSV or
/// whitespace columns, Selig or Lednicer airfoil files; consecutive duplicates dropped), an
/// (n, columns) array.
#[pyfunction]
pub fn read_points<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let set = crate::guarded(py, || {
        fairfit::io::read_points(&path).map_err(|e| e.to_string())
    })?;
    Ok(crate::convert::points_array(py, &set.points, set.columns))
}
