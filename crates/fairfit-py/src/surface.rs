//! The Python `Surface` and the surface fits: `fit_surface` (sections given as arrays) and
//! `fit_surface_from_mesh` (a mesh or point cloud sliced into planar sections), with the options,
//! checks and report of `fairfit surface` (`crates/fairfit-cli/src/commands/surface.rs`).
//!
//! The section curves are not independent fits: one knot vector is searched for all sections at once
//! (its control-point count grows until the worst section is within tolerance, and its candidates are
//! ranked by the worst span fairness over all sections, `fairfit::surface::compatible`), so a surface
//! is one task, never a fan-out of per-section fits followed by a skinning step.

use crate::convert::{json_to_py, parameters, points_array3, vector};
use fairfit::errors::try_vec;
use fairfit::io::limits::DEFAULT_MAX_SECTIONS;
use fairfit::io::mesh_read::read_mesh;
use fairfit::io::surface_to_json;
use fairfit::report::surface::{surface_report, SectionNotes};
use fairfit::surface::orient::extent;
use fairfit::surface::slicing::{slice_mesh, SliceOptions};
use fairfit::surface::{reconstruct_surface, Section, SurfaceOptions, VParams};
use fairfit::{NurbsSurface, Tolerance, Vec3};
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use serde_json::Value;

/// A NURBS surface (see the `fairfit` package's documentation of `Surface`).
#[pyclass(module = "fairfit._fairfit", frozen)]
pub struct Surface {
    /// The surface.
    pub inner: NurbsSurface,
    /// The fit's report, when fitted.
    pub report: Option<Value>,
}

impl Surface {
    /// A surface with an optional report.
    pub fn new(inner: NurbsSurface, report: Option<Value>) -> Self {
        Surface { inner, report }
    }
}

#[pymethods]
impl Surface {
    /// The degrees (p_u, p_v).
    #[getter]
    fn degree(&self) -> (usize, usize) {
        (self.inner.degree_u(), self.inner.degree_v())
    }

    /// The knot vectors (U, V).
    #[getter]
    fn knots<'py>(
        &self,
        py: Python<'py>,
    ) -> (
        Bound<'py, numpy::PyArray1<f64>>,
        Bound<'py, numpy::PyArray1<f64>>,
    ) {
        (
            vector(py, self.inner.knots_u().to_vec()),
            vector(py, self.inner.knots_v().to_vec()),
        )
    }

    /// The control net, an (n_u, n_v, 3) array.
    #[getter]
    fn control_points<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        points_array3(
            py,
            self.inner.control_points_flat(),
            self.inner.net_size(),
            3,
        )
    }

    /// The weights, an (n_u, n_v) array.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (a, b) = self.inner.net_size();
        vector(py, self.inner.weights_flat().to_vec()).call_method1("reshape", (a, b))
    }

    /// The parameter domains ((u0, u1), (v0, v1)).
    #[getter]
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.inner.domain_u(), self.inner.domain_v())
    }

    /// (closed in u, closed in v): whether opposite boundary curves coincide (to 1e-9 of the control
    /// net's extent, at 11 points each).
    #[getter]
    fn closed(&self) -> (bool, bool) {
        let s = &self.inner;
        let ext = fairfit::fit::points::bounding_box_extent(s.control_points_flat());
        let eps = 1e-9 * ext.max(f64::MIN_POSITIVE);
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        let at = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let ts = (0..=10).map(|i| i as f64 / 10.0);
        let cu = ts.clone().all(|t| {
            s.point(u0, at(v0, v1, t))
                .distance(s.point(u1, at(v0, v1, t)))
                <= eps
        });
        let cv = ts.into_iter().all(|t| {
            s.point(at(u0, u1, t), v0)
                .distance(s.point(at(u0, u1, t), v1))
                <= eps
        });
        (cu, cv)
    }

    /// The report of the fit (the keys of `fairfit surface --report`), or None.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.report.as_ref().map(|r| json_to_py(py, r)).transpose()
    }

    /// surface(u, v, grid=True) -> ndarray: with grid, the points S(u_i, v_j) for every pair, an
    /// (m, k, 3) array; without, S(u_i, v_i) for equally long u and v, an (m, 3) array.
    #[pyo3(signature = (u, v, grid=true))]
    fn __call__<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        grid: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (us, _) = parameters(u)?;
        let (vs, _) = parameters(v)?;
        let uv: Vec<(f64, f64)> = if grid {
            // a grid's size is a product of two argument lengths: reserved fallibly, so that one
            // no memory holds is a one-line error, not an abort
            let n = us.len().saturating_mul(vs.len());
            let mut uv = try_vec(n, "surface(u, v, grid=True)").map_err(crate::lib_err)?;
            uv.extend(us.iter().flat_map(|&a| vs.iter().map(move |&b| (a, b))));
            uv
        } else {
            if us.len() != vs.len() {
                return Err(crate::py_err(format!(
                    "surface(u, v, grid=False) needs as many u as v values, got {} and {}",
                    us.len(),
                    vs.len()
                )));
            }
            us.iter().copied().zip(vs.iter().copied()).collect()
        };
        for &(a, b) in &uv {
            self.inner.check_parameter(a, b).map_err(crate::lib_err)?;
        }
        let s = &self.inner;
        let pts = crate::guarded(py, || {
            let mut out = try_vec(uv.len(), "surface(u, v)").map_err(|e| e.to_string())?;
            out.resize(uv.len(), Vec3::ZERO);
            s.points_into(&uv, &mut out);
            Ok(out)
        })?;
        if grid {
            Ok(points_array3(py, &pts, (us.len(), vs.len()), 3).into_any())
        } else {
            Ok(crate::convert::points_array(py, &pts, 3).into_any())
        }
    }

    /// to_json() -> str: the surface in fairfit's JSON format, what `fairfit surface -o` writes.
    fn to_json(&self) -> String {
        surface_to_json(&self.inner)
    }

    /// save(path, points=None, *, units="mm", chord_tol=None): writes the surface, its format chosen
    /// by the extension (.json, .step/.stp, .iges/.igs, .obj/.stl/.ply, .svg/.png, .html).
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
        let s = &self.inner;
        let report = self.report.as_ref();
        crate::guarded(py, || {
            crate::output::save(
                crate::output::Shape::Surface(s),
                &path,
                pts.as_deref(),
                report,
                units,
                chord_tol,
            )
        })
    }

    /// Pickling: the surface's JSON and its report.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let f = py
            .import("fairfit._fairfit")?
            .getattr("_surface_from_state")?;
        let state = (self.to_json(), self.report.as_ref().map(|r| r.to_string()));
        PyTuple::new(py, [f.into_any(), state.into_pyobject(py)?.into_any()])
    }

    fn __repr__(&self) -> String {
        let (a, b) = self.inner.net_size();
        format!(
            "Surface(degree=({}, {}), net=({a}, {b}))",
            self.inner.degree_u(),
            self.inner.degree_v()
        )
    }
}

/// Rebuilds a pickled surface.
#[pyfunction]
#[pyo3(name = "_surface_from_state")]
pub fn surface_from_state(json: &str, report: Option<String>) -> PyResult<Surface> {
    let s = match fairfit::io::json::geometry_from_str(json).map_err(crate::lib_err)? {
        fairfit::io::Geometry::Surface(s) => s,
        fairfit::io::Geometry::Curve(_) => {
            return Err(crate::py_err("_surface_from_state: not a surface"))
        }
    };
    let report = report
        .map(|r| serde_json::from_str(&r))
        .transpose()
        .map_err(|e| crate::py_err(format!("_surface_from_state: {e}")))?;
    Ok(Surface::new(s, report))
}

/// The settings of a surface fit (the options of `fairfit surface`).
#[derive(Clone, Debug)]
pub struct SurfaceSettings {
    /// `tol`.
    pub tol: Option<f64>,
    /// `rel_tol` (of the largest section's extent).
    pub rel_tol: f64,
    /// `degree` (of the sections, in u).
    pub degree: usize,
    /// `degree_v`.
    pub degree_v: usize,
    /// `max_ctrl`.
    pub max_ctrl: usize,
    /// `v_params`: centripetal when true, chord length otherwise.
    pub centripetal_v: bool,
    /// `approximate_v`.
    pub approximate_v: Option<usize>,
    /// `smooth_v`.
    pub smooth_v: f64,
    /// `clamped_seam`.
    pub clamped_seam: bool,
    /// `threads`.
    pub threads: Option<usize>,
    /// `start_tangent_v`: the direction of `∂S/∂v` along the first section.
    pub start_tangent_v: Option<[f64; 3]>,
    /// `end_tangent_v`: the same along the last section.
    pub end_tangent_v: Option<[f64; 3]>,
    /// `corner_angle`: the sections' corner angle in degrees (`--corner-angle`); `None` smooths
    /// inner corners over (`--no-corners`; seams keep the default angle).
    pub corner_angle: Option<f64>,
    /// `split_at_le`: every section's leading edge pinned to u = 0.5 (`--split-at-le`).
    pub split_at_le: bool,
    /// `open_sections`: no section closed across a gap at the tolerance's scale
    /// (`--open-sections`).
    pub open_sections: bool,
}

/// `fairfit surface`'s checks of the counts, with its messages (named by the Python keywords).
fn check_counts(s: &SurfaceSettings) -> Result<(), String> {
    let need = s.degree.saturating_add(1);
    if s.degree >= 1 && s.max_ctrl < need {
        return Err(format!(
            "max_ctrl {} is below the {need} control points a degree-{} section needs; give max_ctrl={need} or more",
            s.max_ctrl, s.degree
        ));
    }
    if let Some(n) = s.approximate_v.filter(|&n| n < 2) {
        return Err(format!(
            "approximate_v {n}: approximation across the sections needs at least 2 control points"
        ));
    }
    if !(s.smooth_v.is_finite() && s.smooth_v >= 0.0) {
        return Err(format!(
            "smooth_v must be a finite number >= 0, got {}",
            s.smooth_v
        ));
    }
    crate::options::check_corner_angle(s.corner_angle)?;
    check_tangents(s)
}

/// `fairfit surface`'s checks of `--start-tangent-v` / `--end-tangent-v`, named by the keywords: a
/// finite non-zero direction, a degree in v of at least 2, enough control points to approximate.
fn check_tangents(s: &SurfaceSettings) -> Result<(), String> {
    for (what, d) in [
        ("start_tangent_v", s.start_tangent_v),
        ("end_tangent_v", s.end_tangent_v),
    ] {
        if let Some(d) = d {
            let v = Vec3::new(d[0], d[1], d[2]);
            if !(v.is_finite() && v.norm() > 0.0) {
                return Err(format!(
                    "{what} must be a finite non-zero vector X,Y,Z, got {d:?}"
                ));
            }
        }
    }
    let tangents =
        usize::from(s.start_tangent_v.is_some()) + usize::from(s.end_tangent_v.is_some());
    if tangents > 0 && s.degree_v < 2 {
        return Err(format!(
            "start_tangent_v / end_tangent_v need degree_v 2 or more, got {}",
            s.degree_v
        ));
    }
    if let Some(n) = s
        .approximate_v
        .filter(|&n| tangents > 0 && n < 2 + tangents)
    {
        return Err(format!(
            "approximate_v {n}: with {tangents} v end tangent(s) it needs at least {} control points",
            2 + tangents
        ));
    }
    Ok(())
}

/// The library's surface options, as `fairfit surface` builds them.
fn surface_options(s: &SurfaceSettings, tol: f64) -> SurfaceOptions {
    let mut opts = SurfaceOptions::default();
    opts.sections.degree = s.degree;
    opts.sections.tolerance = tol;
    opts.sections.max_control_points = s.max_ctrl;
    opts.sections.periodic_closed = !s.clamped_seam;
    opts.sections.corner_angle_deg = s
        .corner_angle
        .unwrap_or(fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG);
    opts.sections.hold_corners = s.corner_angle.is_some();
    opts.sections.split_at_le = s.split_at_le;
    opts.open_sections = s.open_sections;
    opts.skin.degree_v = s.degree_v;
    opts.skin.params = if s.centripetal_v {
        VParams::Centripetal
    } else {
        VParams::ChordLength
    };
    opts.skin.approximate_with = s.approximate_v;
    opts.skin.smoothing = s.smooth_v;
    opts.skin.start_tangent_v = s.start_tangent_v.map(|[x, y, z]| Vec3::new(x, y, z));
    opts.skin.end_tangent_v = s.end_tangent_v.map(|[x, y, z]| Vec3::new(x, y, z));
    opts.iso_curves = fairfit::fair::DEFAULT_ISO_CURVES;
    opts
}

/// The surface through `sections`, with the report of `fairfit surface --report`.
fn fit_sections(
    s: &SurfaceSettings,
    sections: Vec<Section>,
    notes: SectionNotes,
) -> Result<(NurbsSurface, Value), String> {
    check_counts(s)?;
    if sections.len() < 2 {
        return Err(format!(
            "a surface needs at least 2 sections, got {}",
            sections.len()
        ));
    }
    let largest = sections
        .iter()
        .map(|x| extent(&x.points))
        .fold(0.0, f64::max);
    let tol = match s.tol {
        Some(t) => t,
        None => s.rel_tol * largest,
    };
    if !tol.is_finite() || tol <= 0.0 {
        return Err(format!("the tolerance must be positive, got {tol}"));
    }
    let opts = surface_options(s, tol);
    let r = crate::with_pool(s.threads, || {
        reconstruct_surface(sections, &opts).map_err(|e| e.to_string())
    })?;
    let report = surface_report(&r, tol, &notes, None);
    Ok((r.surface, report))
}

/// Parses `v_params=`.
fn centripetal(v_params: &str) -> PyResult<bool> {
    match v_params {
        "chord" => Ok(false),
        "centripetal" => Ok(true),
        _ => Err(crate::py_err(format!(
            "v_params: expected `chord` or `centripetal`, got `{v_params}`"
        ))),
    }
}

/// Refuses more sections than `max_sections` (`fairfit surface --max-sections`), before any work.
fn check_section_count(n: usize, max_sections: usize) -> PyResult<()> {
    if n > max_sections {
        return Err(crate::py_err(format!(
            "{n} sections are above the limit of {max_sections}; raise it with max_sections=N"
        )));
    }
    Ok(())
}

/// The extension's `fit_surface` (documented by the wrapper `fairfit.fit_surface`).
#[pyfunction]
#[pyo3(signature = (sections, tol, rel_tol, degree, degree_v, max_ctrl, v_params, approximate_v,
    smooth_v, clamped_seam, threads, names, max_sections=DEFAULT_MAX_SECTIONS,
    start_tangent_v=None, end_tangent_v=None,
    corner_angle=Some(fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG), split_at_le=false,
    open_sections=false))]
#[allow(clippy::too_many_arguments)] // one argument per keyword of the Python signature
pub fn fit_surface(
    py: Python<'_>,
    sections: Vec<PyReadonlyArray2<'_, f64>>,
    tol: Option<f64>,
    rel_tol: f64,
    degree: usize,
    degree_v: usize,
    max_ctrl: usize,
    v_params: &str,
    approximate_v: Option<usize>,
    smooth_v: f64,
    clamped_seam: bool,
    threads: Option<usize>,
    names: Option<Vec<String>>,
    max_sections: usize,
    start_tangent_v: Option<[f64; 3]>,
    end_tangent_v: Option<[f64; 3]>,
    corner_angle: Option<f64>,
    split_at_le: bool,
    open_sections: bool,
) -> PyResult<Surface> {
    check_section_count(sections.len(), max_sections)?;
    let settings = SurfaceSettings {
        tol,
        rel_tol,
        degree,
        degree_v,
        max_ctrl,
        centripetal_v: centripetal(v_params)?,
        approximate_v,
        smooth_v,
        clamped_seam,
        threads,
        start_tangent_v,
        end_tangent_v,
        corner_angle,
        split_at_le,
        open_sections,
    };
    let names = names.unwrap_or_else(|| {
        (0..sections.len())
            .map(|k| format!("section {k}"))
            .collect()
    });
    let mut secs = Vec::with_capacity(sections.len());
    for (k, a) in sections.iter().enumerate() {
        let name = names
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("section {k}"));
        let (pts, _) = crate::convert::points_from_array(a, &name)?;
        if pts.len() < 3 {
            return Err(crate::py_err(format!(
                "{name}: a section needs at least 3 points, got {}",
                pts.len()
            )));
        }
        secs.push(Section::from_points(pts));
    }
    let notes = SectionNotes {
        dropped_chains: vec![0; secs.len()],
        names,
        ..Default::default()
    };
    let (surface, report) = crate::guarded(py, move || fit_sections(&settings, secs, notes))?;
    Ok(Surface::new(surface, Some(report)))
}

/// The extension's `fit_surface_from_mesh` (documented by the wrapper).
#[pyfunction]
#[pyo3(signature = (path, slices, axis, normal, gap_factor, tol, rel_tol, degree, degree_v,
    max_ctrl, v_params, approximate_v, smooth_v, clamped_seam, threads,
    max_sections=DEFAULT_MAX_SECTIONS, start_tangent_v=None, end_tangent_v=None,
    corner_angle=Some(fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG), split_at_le=false,
    open_sections=false))]
#[allow(clippy::too_many_arguments)] // one argument per keyword of the Python signature
pub fn fit_surface_from_mesh(
    py: Python<'_>,
    path: std::path::PathBuf,
    slices: usize,
    axis: &str,
    normal: Option<[f64; 3]>,
    gap_factor: f64,
    tol: Option<f64>,
    rel_tol: f64,
    degree: usize,
    degree_v: usize,
    max_ctrl: usize,
    v_params: &str,
    approximate_v: Option<usize>,
    smooth_v: f64,
    clamped_seam: bool,
    threads: Option<usize>,
    max_sections: usize,
    start_tangent_v: Option<[f64; 3]>,
    end_tangent_v: Option<[f64; 3]>,
    corner_angle: Option<f64>,
    split_at_le: bool,
    open_sections: bool,
) -> PyResult<Surface> {
    if slices > max_sections {
        return Err(crate::py_err(format!(
            "slices {slices} is above the limit of {max_sections} sections; raise it with \
             max_sections=N"
        )));
    }
    let settings = SurfaceSettings {
        tol,
        rel_tol,
        degree,
        degree_v,
        max_ctrl,
        centripetal_v: centripetal(v_params)?,
        approximate_v,
        smooth_v,
        clamped_seam,
        threads,
        start_tangent_v,
        end_tangent_v,
        corner_angle,
        split_at_le,
        open_sections,
    };
    if slices < 2 {
        return Err(crate::py_err(format!(
            "slices {slices}: a surface needs at least 2 slices (slicing planes)"
        )));
    }
    let normal = match (normal, axis) {
        (Some([x, y, z]), _) => Vec3::new(x, y, z),
        (None, "x") => Vec3::new(1.0, 0.0, 0.0),
        (None, "y") => Vec3::new(0.0, 1.0, 0.0),
        (None, "z") => Vec3::new(0.0, 0.0, 1.0),
        (None, _) => {
            return Err(crate::py_err(format!(
                "axis: expected `x`, `y` or `z`, got `{axis}`"
            )))
        }
    };
    if !(normal.is_finite() && normal.norm() > 0.0) {
        return Err(crate::py_err("normal must be a non-zero vector"));
    }
    let (surface, report) = crate::guarded(py, move || {
        check_counts(&settings)?;
        let mesh = read_mesh(&path).map_err(|e| e.to_string())?;
        let opts = SliceOptions {
            slices,
            normal,
            gap_factor,
            tolerance: Some(match settings.tol {
                Some(t) => Tolerance::Absolute(t),
                None => Tolerance::Relative(settings.rel_tol),
            }),
            ..Default::default()
        };
        let s = slice_mesh(&mesh, &opts).map_err(|e| e.to_string())?;
        if s.sections.len() < 2 {
            return Err(format!(
                "slicing gave {} usable section(s) from {slices} planes ({} empty); a surface needs at least 2",
                s.sections.len(),
                s.empty_planes.len()
            ));
        }
        let notes = SectionNotes {
            names: s
                .offsets
                .iter()
                .map(|h| format!("plane at {h:.6}"))
                .collect(),
            gaps: s.gaps,
            empty_planes: s.empty_planes,
            dropped_chains: s.dropped_chains,
        };
        fit_sections(&settings, s.sections, notes)
    })?;
    Ok(Surface::new(surface, Some(report)))
}
