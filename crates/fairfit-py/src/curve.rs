//! The Python `Curve`: a NURBS curve of the library with the dimension of its input (2 or 3) and, for
//! a fitted curve, the report of its fit. Evaluation is vectorised (one call for any number of
//! parameters, without the GIL); pickling goes through the curve's JSON, which round-trips every
//! number exactly.

use crate::convert::{json_to_py, parameter_array, parameters, points_array, vector};
use fairfit::diffgeo::curvature;
use fairfit::errors::try_vec;
use fairfit::fair::try_curve_fairness;
use fairfit::io::{curve_to_json, Geometry};
use fairfit::report::curve::exact_shape_json;
use fairfit::{NurbsCurve, Vec3};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde_json::Value;

/// A NURBS curve (see the `fairfit` package's documentation of `Curve`).
#[pyclass(module = "fairfit._fairfit", frozen)]
pub struct Curve {
    /// The curve.
    pub inner: NurbsCurve,
    /// Coordinates per point of the arrays it returns (2 or 3).
    pub dim: usize,
    /// The fit's report, when fitted.
    pub report: Option<Value>,
}

impl Curve {
    /// A curve of dimension `dim` with an optional report.
    pub fn new(inner: NurbsCurve, dim: usize, report: Option<Value>) -> Self {
        Curve { inner, dim, report }
    }

    /// Every parameter of `us` checked against the domain (the library's message for the first
    /// outside it).
    fn check(&self, us: &[f64]) -> PyResult<()> {
        for &u in us {
            self.inner.check_parameter(u).map_err(crate::lib_err)?;
        }
        Ok(())
    }
}

/// The zeroed output of `derivatives(u, k)` for `m` parameters (`m * (k + 1)` points), reserved
/// fallibly together with the evaluator's work buffers (about `(k + 1) * (degree + 6)` numbers):
/// a `k` no memory can hold is a one-line error, not an abort.
fn derivative_buffer(m: usize, k: usize, degree: usize) -> fairfit::Result<Vec<Vec3>> {
    let what = format!("derivatives of order {k} at {m} parameter(s)");
    // a size past the address space is refused by `try_vec` like one past the memory
    let orders = k.saturating_add(1);
    let n = m.saturating_mul(orders);
    let work = orders.saturating_mul(degree.saturating_add(6));
    // the work buffers are allocated by the evaluator: make sure they fit beside the output
    drop(try_vec::<f64>(work, &what)?);
    let mut out = try_vec::<Vec3>(n, &what)?;
    out.resize(n, Vec3::ZERO);
    Ok(out)
}

/// The dimension a read curve gets: 2 when every control point has z = 0.
pub fn dim_of(points: &[Vec3]) -> usize {
    if points.iter().all(|p| p.z() == 0.0) {
        2
    } else {
        3
    }
}

#[pymethods]
impl Curve {
    /// Curve(degree, knots, control_points, weights=None)
    ///
    /// A NURBS curve from its parts: `control_points` is an (n, 2) or (n, 3) array, `knots` the full
    /// clamped or unclamped knot vector (n + degree + 1 values), `weights` n positive numbers (all 1
    /// when omitted: a B-spline).
    #[new]
    #[pyo3(signature = (degree, knots, control_points, weights=None))]
    fn py_new(
        degree: usize,
        knots: Vec<f64>,
        control_points: &Bound<'_, PyAny>,
        weights: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let cps = crate::convert::array2(control_points, "control_points")?;
        let (pts, dim) = crate::convert::points_from_array(&cps, "control_points")?;
        let c = NurbsCurve::new(degree, knots, pts, weights).map_err(crate::lib_err)?;
        Ok(Curve::new(c, dim, None))
    }

    /// The degree p.
    #[getter]
    fn degree(&self) -> usize {
        self.inner.degree()
    }

    /// The knot vector (n + p + 1 values).
    #[getter]
    fn knots<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        vector(py, self.inner.knots().to_vec())
    }

    /// The control points, an (n, dim) array.
    #[getter]
    fn control_points<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        points_array(py, self.inner.control_points(), self.dim)
    }

    /// The weights (n values; all 1 for a B-spline).
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        vector(py, self.inner.weights().to_vec())
    }

    /// Coordinates per point (2 or 3).
    #[getter]
    fn dim(&self) -> usize {
        self.dim
    }

    /// True when the curve is rational (some weight differs from 1).
    #[getter]
    fn rational(&self) -> bool {
        self.inner.is_rational()
    }

    /// The parameter domain (a, b).
    #[getter]
    fn domain(&self) -> (f64, f64) {
        self.inner.domain()
    }

    /// True when the curve is closed: it ends where it starts (to 1e-9 of its control points' extent).
    #[getter]
    fn closed(&self) -> bool {
        let (a, b) = self.inner.domain();
        let ext = fairfit::fit::points::bounding_box_extent(self.inner.control_points());
        self.inner.point(a).distance(self.inner.point(b)) <= 1e-9 * ext.max(f64::MIN_POSITIVE)
    }

    /// The report of the fit (the keys of `fairfit curve --report`), or None for a curve not fitted.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.report.as_ref().map(|r| json_to_py(py, r)).transpose()
    }

    /// curve(u) -> ndarray: the points C(u), an (m, dim) array for m parameters, (dim,) for a scalar.
    ///
    /// The points are written straight into the new array without the GIL (no copy of the
    /// parameters when they are a contiguous float64 array); sorted parameters find their knot
    /// spans incrementally.
    fn __call__<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        if let Ok(x) = u.extract::<f64>() {
            self.check(&[x])?;
            let p = self.inner.point(x);
            return Ok(vector(py, p.0[..self.dim].to_vec()).into_any());
        }
        let us = parameter_array(u)?;
        let us = us.as_slice()?;
        self.check(us)?;
        let dim = self.dim;
        let out = numpy::PyArray2::<f64>::zeros(py, [us.len(), dim], false);
        {
            let mut rw = out.readwrite();
            let buf = rw.as_slice_mut()?;
            let c = &self.inner;
            crate::guarded(py, || {
                c.points_into_rows(us, dim, buf);
                Ok(())
            })?;
        }
        Ok(out.into_any())
    }

    /// derivatives(u, k) -> ndarray: C(u) and its derivatives up to order k, an (m, k + 1, dim) array
    /// (`[:, j]` is the j-th derivative), (k + 1, dim) for a scalar u.
    fn derivatives<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        k: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (us, scalar) = parameters(u)?;
        self.check(&us)?;
        let c = &self.inner;
        let d = crate::guarded(py, || {
            let mut out = derivative_buffer(us.len(), k, c.degree()).map_err(|e| e.to_string())?;
            c.derivatives_batch_into(&us, k, &mut out);
            Ok(out)
        })?;
        let dim = self.dim;
        let flat: Vec<f64> = d.iter().flat_map(|p| p.0[..dim].to_vec()).collect();
        let a = Array3::from_shape_vec((us.len(), k + 1, dim), flat)
            .expect("shape matches the buffer")
            .into_pyarray(py);
        if scalar {
            return a.get_item(0);
        }
        Ok(a.into_any())
    }

    /// curvature(u) -> ndarray: the unsigned curvature κ(u), an (m,) array, a float for a scalar u.
    fn curvature<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (us, scalar) = parameters(u)?;
        self.check(&us)?;
        let c = &self.inner;
        let k = crate::guarded(py, || {
            Ok(us.iter().map(|&u| curvature(c, u)).collect::<Vec<_>>())
        })?;
        if scalar {
            return Ok(k[0].into_pyobject(py)?.into_any());
        }
        Ok(vector(py, k).into_any())
    }

    /// fairness() -> dict: the fairness measures `fairfit info` prints: length L, energy
    /// E = ∫(dκ/ds)² ds, fairness F = L³E, span_fairness (the F_j, an array), max_span_fairness,
    /// bending_energy ∫κ² ds, curvature_extrema and inflections (sampled counts), and their exact
    /// counts curvature_extrema_exact / inflections_exact (None where only sampling counts them).
    fn fairness<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let c = &self.inner;
        let (f, exact) = crate::guarded(py, || {
            // the fallible twin (same numbers): its sample buffers grow with the span count
            let f = try_curve_fairness(c).map_err(|e| e.to_string())?;
            let exact = exact_shape_json(c, f.length);
            Ok((f, exact))
        })?;
        let d = PyDict::new(py);
        d.set_item("length", f.length)?;
        d.set_item("energy", f.energy)?;
        d.set_item("fairness", f.fairness)?;
        d.set_item("span_fairness", vector(py, f.span_fairness))?;
        d.set_item("max_span_fairness", f.max_span_fairness)?;
        d.set_item("bending_energy", f.bending_energy)?;
        d.set_item("curvature_extrema", f.curvature_extrema)?;
        d.set_item("curvature_extrema_exact", json_to_py(py, &exact.0)?)?;
        d.set_item("inflections", f.inflections)?;
        d.set_item("inflections_exact", json_to_py(py, &exact.1)?)?;
        Ok(d.into_any())
    }

    /// to_json() -> str: the curve in fairfit's JSON format, byte for byte what `fairfit curve -o`
    /// writes.
    fn to_json(&self) -> String {
        curve_to_json(&self.inner)
    }

    /// save(path, points=None, *, units="mm", chord_tol=None): writes the curve, its format chosen by
    /// the extension: .json, .step/.stp, .iges/.igs, .obj/.stl/.ply (a polyline mesh), .svg/.png (the
    /// curvature comb, with `points` drawn when given), .html (a report). Written atomically.
    #[pyo3(signature = (path, points=None, *, units="mm", chord_tol=None))]
    fn save(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        points: Option<Bound<'_, PyAny>>,
        units: &str,
        chord_tol: Option<f64>,
    ) -> PyResult<()> {
        let pts = points
            .map(|p| {
                let a = crate::convert::array2(&p, "points")?;
                crate::convert::points_from_array(&a, "points").map(|x| x.0)
            })
            .transpose()?;
        let c = &self.inner;
        let report = self.report.as_ref();
        crate::guarded(py, || {
            crate::output::save(
                crate::output::Shape::Curve(c),
                &path,
                pts.as_deref(),
                report,
                units,
                chord_tol,
            )
        })
    }

    /// to_scipy() -> scipy.interpolate.BSpline: the same curve for scipy (non-rational curves only),
    /// with (n, dim) coefficients.
    fn to_scipy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        if self.inner.is_rational() {
            return Err(crate::py_err(
                "to_scipy: the curve is rational (its weights differ), and scipy's BSpline is not",
            ));
        }
        let bspline = py.import("scipy.interpolate")?.getattr("BSpline")?;
        bspline.call1((self.knots(py), self.control_points(py), self.inner.degree()))
    }

    /// Curve.from_scipy(spline) -> Curve: a curve from a scipy.interpolate.BSpline whose coefficients
    /// are an (n, 2) or (n, 3) array (extra trailing coefficients, which scipy ignores, are dropped).
    #[staticmethod]
    fn from_scipy(spline: &Bound<'_, PyAny>) -> PyResult<Self> {
        let degree: usize = spline.getattr("k")?.extract()?;
        let knots: PyReadonlyArray1<'_, f64> = spline
            .py()
            .import("numpy")?
            .call_method1("ascontiguousarray", (spline.getattr("t")?, "float64"))?
            .extract()?;
        let knots = knots.as_slice()?.to_vec();
        let n = knots.len().saturating_sub(degree + 1);
        let c = spline
            .py()
            .import("numpy")?
            .call_method1("ascontiguousarray", (spline.getattr("c")?, "float64"))?;
        let ndim: usize = c.getattr("ndim")?.extract()?;
        if ndim != 2 {
            return Err(crate::py_err(format!(
                "from_scipy: expected (n, 2) or (n, 3) coefficients, got an array of {ndim} dimension(s)"
            )));
        }
        let c = c.get_item(pyo3::types::PySlice::new(spline.py(), 0, n as isize, 1))?;
        Self::py_new(degree, knots, &c, None)
    }

    /// Pickling: the curve's JSON, its dimension and its report.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let f = py
            .import("fairfit._fairfit")?
            .getattr("_curve_from_state")?;
        let state = (
            self.to_json(),
            self.dim,
            self.report.as_ref().map(|r| r.to_string()),
        );
        PyTuple::new(py, [f.into_any(), state.into_pyobject(py)?.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "Curve(degree={}, control_points={}, dim={}{})",
            self.inner.degree(),
            self.inner.n_control_points(),
            self.dim,
            if self.inner.is_rational() {
                ", rational"
            } else {
                ""
            }
        )
    }
}

/// Rebuilds a pickled curve.
#[pyfunction]
#[pyo3(name = "_curve_from_state")]
pub fn curve_from_state(json: &str, dim: usize, report: Option<String>) -> PyResult<Curve> {
    let c = match fairfit::io::json::geometry_from_str(json).map_err(crate::lib_err)? {
        Geometry::Curve(c) => c,
        Geometry::Surface(_) => return Err(crate::py_err("_curve_from_state: not a curve")),
    };
    let report = report
        .map(|r| serde_json::from_str(&r))
        .transpose()
        .map_err(|e| crate::py_err(format!("_curve_from_state: {e}")))?;
    Ok(Curve::new(c, dim, report))
}
