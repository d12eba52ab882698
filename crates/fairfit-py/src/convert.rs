//! Conversions between numpy arrays / Python objects and the library's types.

use fairfit::Vec3;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// The points of an `(n, 2)` or `(n, 3)` float array (z = 0 for two columns) and their dimension;
/// a non-finite value is refused with its row, as a point file's line would be.
pub fn points_from_array(
    a: &PyReadonlyArray2<'_, f64>,
    source: &str,
) -> PyResult<(Vec<Vec3>, usize)> {
    let v = a.as_array();
    let (n, dim) = v.dim();
    if dim != 2 && dim != 3 {
        return Err(data_err(format!(
            "{source}: expected 2 or 3 coordinates per point, found {dim} (an array of shape ({n}, {dim}))"
        )));
    }
    let mut out = Vec::with_capacity(n);
    for (i, row) in v.outer_iter().enumerate() {
        if let Some(x) = row.iter().find(|x| !x.is_finite()) {
            return Err(data_err(format!(
                "{source}: point {i}: value '{x}' is not a finite number"
            )));
        }
        out.push(Vec3::new(
            row[0],
            row[1],
            if dim == 3 { row[2] } else { 0.0 },
        ));
    }
    Ok((out, dim))
}

/// Anything `np.asarray` takes, as a C-contiguous float64 2-d array (`what` names it in the error).
pub fn array2<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("asarray", (obj,))
        .map_err(|e| crate::py_err(format!("{what} must be an array of numbers: {e}")))?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    let ndim: usize = a.getattr("ndim")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") || ndim != 2 {
        return Err(crate::py_err(format!(
            "{what} must be an (n, 2) or (n, 3) array of numbers, got {} of dtype {}",
            a.getattr("shape")?.str()?,
            a.getattr("dtype")?.str()?
        )));
    }
    np.call_method1("ascontiguousarray", (a, "float64"))?
        .extract()
}

/// The library's invalid-data error with `message`, as the Python exception.
pub fn data_err(message: String) -> PyErr {
    crate::lib_err(fairfit::Error::InvalidData(message))
}

/// Points as an `(m, dim)` array (the first `dim` coordinates).
pub fn points_array<'py>(py: Python<'py>, pts: &[Vec3], dim: usize) -> Bound<'py, PyArray2<f64>> {
    let mut flat = Vec::with_capacity(pts.len() * dim);
    for p in pts {
        flat.extend_from_slice(&p.0[..dim]);
    }
    Array2::from_shape_vec((pts.len(), dim), flat)
        .expect("shape matches the buffer")
        .into_pyarray(py)
}

/// Points as an `(a, b, dim)` array, row-major.
pub fn points_array3<'py>(
    py: Python<'py>,
    pts: &[Vec3],
    (a, b): (usize, usize),
    dim: usize,
) -> Bound<'py, PyArray3<f64>> {
    let mut flat = Vec::with_capacity(pts.len() * dim);
    for p in pts {
        flat.extend_from_slice(&p.0[..dim]);
    }
    Array3::from_shape_vec((a, b, dim), flat)
        .expect("shape matches the buffer")
        .into_pyarray(py)
}

/// Numbers as a 1-d array.
pub fn vector<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    Array1::from_vec(v).into_pyarray(py)
}

/// A JSON value as the Python object `json.loads` makes of it.
pub fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (v.to_string(),))
}

/// A Python sequence of parameters as floats, or one scalar (`true` in the second field).
pub fn parameters(u: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, bool)> {
    if let Ok(x) = u.extract::<f64>() {
        return Ok((vec![x], true));
    }
    let arr = parameter_array(u)?;
    Ok((arr.as_slice()?.to_vec(), false))
}

/// A Python sequence of parameters as a flat, contiguous float64 array (the array itself, not a
/// copy, when it already is one).
pub fn parameter_array<'py>(u: &Bound<'py, PyAny>) -> PyResult<numpy::PyReadonlyArray1<'py, f64>> {
    if let Ok(a) = u.extract::<numpy::PyReadonlyArray1<'py, f64>>() {
        if a.is_contiguous() {
            return Ok(a);
        }
    }
    let np = u.py().import("numpy")?;
    let a = np.call_method1("asarray", (u,))?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(crate::py_err(format!(
            "parameters must be numbers, got an array of dtype {}",
            a.getattr("dtype")?.str()?
        )));
    }
    np.call_method1("ascontiguousarray", (a, "float64"))?
        .call_method0("ravel")?
        .extract()
}
