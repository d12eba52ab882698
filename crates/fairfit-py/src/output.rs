//! Files: `save` (the format chosen by the extension, made as `fairfit export` / `--step`, `--iges`,
//! `--mesh`, `--plot` and `--html` make them) and `read` (fairfit JSON, STEP and IGES, as the CLI's
//! `info` and `eval` read them).

use crate::curve::{dim_of, Curve};
use crate::surface::Surface;
use fairfit::io::cad_common::LengthUnit;
use fairfit::io::cad_read::{read_cad, CadFormat, CadKind};
use fairfit::io::{read_geometry, write_atomic, Geometry};
use fairfit::nurbs::Vec3;
pub use fairfit::report::files::Shape;
use fairfit::report::files::{output_bytes, FileInputs};
use pyo3::prelude::*;
use std::path::Path;

/// Writes `shape` to `path` in the format its extension names.
pub fn save(
    shape: Shape<'_>,
    path: &Path,
    points: Option<&[Vec3]>,
    report: Option<&serde_json::Value>,
    units: &str,
    chord_tol: Option<f64>,
) -> Result<(), String> {
    let bytes = units
        .parse::<LengthUnit>()
        .and_then(|unit| {
            let inputs = FileInputs {
                points,
                report,
                unit,
                chord_tol,
            };
            output_bytes(shape, path, &inputs)
        })
        .map_err(|e| e.to_string())?;
    write_atomic(path, &bytes).map_err(|e| e.to_string())
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
