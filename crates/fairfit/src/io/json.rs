//! The fairfit JSON geometry format (stable: other tools and the benchmarks read it).
//!
//! - curve: `{"kind": "curve", "degree": p, "knots": [...], "control_points": [[x, y, z], ...], "weights": [...]}`
//! - surface: `{"kind": "surface", "degree_u": p, "degree_v": q, "knots_u": [...], "knots_v": [...],
//!   "control_points": [[[x, y, z], ... n_v], ... n_u rows], "weights": [[... n_v], ... n_u]}`
//!
//! `weights` may be omitted (all 1). Reading validates the geometry; errors name the offending field.

use super::limits::ReadLimits;
use super::numbers::{unsigned_zero, unsigned_zeros};
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A curve or a surface read from JSON.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A NURBS curve.
    Curve(NurbsCurve),
    /// A NURBS surface.
    Surface(NurbsSurface),
}

/// The on-disk form of a curve.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CurveJson {
    /// Degree p.
    pub degree: usize,
    /// Full knot vector.
    pub knots: Vec<f64>,
    /// Control points `[x, y, z]`.
    pub control_points: Vec<[f64; 3]>,
    /// Weights (all 1 when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
}

/// The on-disk form of a surface.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SurfaceJson {
    /// Degree in u.
    pub degree_u: usize,
    /// Degree in v.
    pub degree_v: usize,
    /// Knot vector in u.
    pub knots_u: Vec<f64>,
    /// Knot vector in v.
    pub knots_v: Vec<f64>,
    /// Control net, `n_u` rows of `n_v` points.
    pub control_points: Vec<Vec<[f64; 3]>>,
    /// Weights, `n_u` rows of `n_v` (all 1 when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<Vec<f64>>>,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
enum Tagged {
    Curve(CurveJson),
    Surface(SurfaceJson),
}

impl From<&NurbsCurve> for CurveJson {
    fn from(c: &NurbsCurve) -> Self {
        CurveJson {
            degree: c.degree(),
            knots: c.knots().iter().map(|&k| unsigned_zero(k)).collect(),
            control_points: c
                .control_points()
                .iter()
                .map(|p| unsigned_zeros(p.0))
                .collect(),
            weights: Some(c.weights().to_vec()),
        }
    }
}

impl From<&NurbsSurface> for SurfaceJson {
    fn from(s: &NurbsSurface) -> Self {
        SurfaceJson {
            degree_u: s.degree_u(),
            degree_v: s.degree_v(),
            knots_u: s.knots_u().iter().map(|&k| unsigned_zero(k)).collect(),
            knots_v: s.knots_v().iter().map(|&k| unsigned_zero(k)).collect(),
            control_points: s
                .control_net()
                .into_iter()
                .map(|r| r.into_iter().map(|p| unsigned_zeros(p.0)).collect())
                .collect(),
            weights: Some(s.weight_net()),
        }
    }
}

impl CurveJson {
    /// Validates and builds the curve.
    pub fn into_curve(self) -> Result<NurbsCurve> {
        let pts = self.control_points.into_iter().map(Vec3).collect();
        NurbsCurve::new(self.degree, self.knots, pts, self.weights).map_err(field_context)
    }
}

impl SurfaceJson {
    /// Validates and builds the surface.
    pub fn into_surface(self) -> Result<NurbsSurface> {
        let net = self
            .control_points
            .into_iter()
            .map(|r| r.into_iter().map(Vec3).collect())
            .collect();
        NurbsSurface::new(
            self.degree_u,
            self.degree_v,
            self.knots_u,
            self.knots_v,
            net,
            self.weights,
        )
        .map_err(field_context)
    }
}

/// Prefixes geometry validation errors with the JSON field they concern.
fn field_context(e: Error) -> Error {
    let field = match &e {
        Error::InvalidKnots(m) if m.contains("v direction") => "knots_v",
        Error::InvalidKnots(m) if m.contains("u direction") => "knots_u",
        Error::InvalidKnots(_) => "knots",
        Error::InvalidWeights(_) => "weights",
        Error::InvalidControlPoints(_) => "control_points",
        Error::InvalidDegree { .. } => "degree",
        _ => return e,
    };
    Error::Json(format!("field `{field}`: {e}"))
}

/// Parses a curve or surface from JSON text.
pub fn geometry_from_str(text: &str) -> Result<Geometry> {
    let text = super::points::without_bom(text);
    if text.trim().is_empty() {
        return Err(Error::Json(
            "the file is empty (expected a fairfit curve or surface, e.g. written by `fairfit curve -o`)"
                .into(),
        ));
    }
    check_element_count(text)?;
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| Error::Json(e.to_string()))?;
    let kind = value
        .get("kind")
        .ok_or_else(|| Error::Json("missing field `kind` (\"curve\" or \"surface\")".into()))?
        .as_str()
        .ok_or_else(|| {
            Error::Json("field `kind` must be the string \"curve\" or \"surface\"".into())
        })?
        .to_string();
    let mut value = value;
    if let Some(obj) = value.as_object_mut() {
        obj.remove("kind");
    }
    match kind.as_str() {
        "curve" => Ok(Geometry::Curve(typed::<CurveJson>(value)?.into_curve()?)),
        "surface" => Ok(Geometry::Surface(
            typed::<SurfaceJson>(value)?.into_surface()?,
        )),
        other => Err(Error::Json(format!(
            "field `kind`: unknown kind \"{other}\", expected \"curve\" or \"surface\""
        ))),
    }
}

/// Array elements per control point a fairfit JSON holds at most: three coordinates, the point's own
/// array, its weight and about one knot.
const ELEMENTS_PER_POINT: usize = 6;

/// Refuses a JSON text whose arrays hold more elements than [`ELEMENTS_PER_POINT`] per allowed control
/// point ([`ReadLimits::max_points`]), before it is parsed: parsed, every element costs about 32 bytes,
/// so a text of `[0,0,0,...]` would otherwise cost 16 times its size. Elements are counted as the
/// commas outside strings, plus one per array.
fn check_element_count(text: &str) -> Result<()> {
    let limits = ReadLimits::current();
    let allowed = limits.max_points.saturating_mul(ELEMENTS_PER_POINT);
    let (mut elements, mut in_string, mut escaped) = (0usize, false, false);
    for &b in text.as_bytes() {
        if in_string {
            match b {
                _ if escaped => escaped = false,
                b'\\' => escaped = true,
                b'"' => in_string = false,
                _ => {}
            }
            continue;
        }
        match b {
            b'"' => in_string = true,
            b',' | b'[' => elements += 1,
            _ => {}
        }
    }
    if elements > allowed {
        return Err(Error::Json(format!(
            "{elements} array elements, over the limit of {allowed} ({ELEMENTS_PER_POINT} per allowed \
             control point; raise it with --max-points N, or ReadLimits::max_points in the library)"
        )));
    }
    Ok(())
}

/// The kind (`"curve"` or `"surface"`) of a fairfit geometry JSON text, `Some("JSON")` for other JSON
/// objects, `None` for text that does not start with `{`: readers of point and section files use it to
/// refuse a geometry file with one line naming it instead of its first line.
pub fn json_kind_of(text: &str) -> Option<&'static str> {
    let text = super::points::without_bom(text).trim_start();
    if !text.starts_with('{') {
        return None;
    }
    let kind = serde_json::from_str::<serde_json::Value>(text)
        .ok()
        .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(str::to_string));
    Some(match kind.as_deref() {
        Some("curve") => "curve",
        Some("surface") => "surface",
        _ => "JSON",
    })
}

/// The error of a point or section reader given a JSON file (see [`json_kind_of`]), naming the file,
/// what it is and which commands take it.
pub(crate) fn not_points_error(source: &str, kind: &str) -> Error {
    if kind == "JSON" {
        Error::InvalidData(format!(
            "{source}: a JSON file, not a point file (points are 2 or 3 numbers per line)"
        ))
    } else {
        Error::InvalidData(format!(
            "{source}: already a fairfit {kind} (JSON), not a point file; `fairfit info|eval|plot|export` \
             take it (to re-fit it, write it as STEP with `fairfit export --step` first)"
        ))
    }
}

/// Deserialises `value` as `T`, naming the path of the offending field in the error.
fn typed<T: serde::de::DeserializeOwned>(value: serde_json::Value) -> Result<T> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        if path == "." || path.is_empty() {
            Error::Json(inner.to_string())
        } else {
            Error::Json(format!("field `{path}`: {inner}"))
        }
    })
}

/// Reads a curve or surface from a JSON file, or from a STEP / IGES file by its extension (the first
/// B-spline surface, else the first curve, in millimetres: see [`super::cad_read`]); errors name the
/// file.
pub fn read_geometry(path: impl AsRef<Path>) -> Result<Geometry> {
    let path = path.as_ref();
    if super::cad_read::CadFormat::from_path(path).is_some() {
        let kind = super::cad_read::CadKind::Any;
        return super::cad_read::read_cad(path, kind, 0).map(|g| g.geometry);
    }
    let not_text = || Error::Io {
        path: path.display().to_string(),
        message: "not a UTF-8 text file (expected fairfit JSON)".into(),
    };
    let bytes = super::limits::read_bounded_text_or(path, not_text)?;
    let text = std::str::from_utf8(&bytes).map_err(|_| not_text())?;
    let start = super::points::without_bom(text).trim_start();
    if !start.is_empty() && !start.starts_with('{') {
        return Err(Error::Json(format!(
            "{}: not a fairfit curve or surface (expected fairfit JSON, STEP .step/.stp or IGES \
             .igs/.iges; a point list is fitted first, e.g. by `fairfit curve`)",
            path.display()
        )));
    }
    geometry_from_str(text).map_err(|e| match e {
        Error::Json(m) => Error::Json(format!("{}: {m}", path.display())),
        other => other,
    })
}

/// The JSON text of a curve (pretty-printed, weights included).
pub fn curve_to_json(c: &NurbsCurve) -> String {
    let t = Tagged::Curve(c.into());
    serde_json::to_string_pretty(&t).unwrap_or_default()
}

/// The JSON text of a surface (pretty-printed, weights included).
pub fn surface_to_json(s: &NurbsSurface) -> String {
    let t = Tagged::Surface(s.into());
    serde_json::to_string_pretty(&t).unwrap_or_default()
}

/// Writes a curve as JSON, atomically.
pub fn write_curve(path: impl AsRef<Path>, c: &NurbsCurve) -> Result<()> {
    super::write_atomic(path, curve_to_json(c).as_bytes())
}

/// Writes a surface as JSON, atomically.
pub fn write_surface(path: impl AsRef<Path>, s: &NurbsSurface) -> Result<()> {
    super::write_atomic(path, surface_to_json(s).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    const CURVE: &str = r#"{"kind": "curve", "degree": 2, "knots": [0,0,0,1,1,1],
        "control_points": [[0,0,0],[1,1,0],[2,0,0]]}"#;

    #[test]
    fn curve_round_trip() {
        let Geometry::Curve(c) = geometry_from_str(CURVE).unwrap() else {
            panic!("expected a curve")
        };
        assert!((c.point(0.5) - Vec3::new(1.0, 0.5, 0.0)).norm() < 1e-15);
        let again = geometry_from_str(&curve_to_json(&c)).unwrap();
        assert_eq!(again, Geometry::Curve(c));
    }

    #[test]
    fn a_byte_order_mark_is_ignored() {
        let with_bom = format!("\u{feff}{CURVE}");
        assert_eq!(
            geometry_from_str(&with_bom).unwrap(),
            geometry_from_str(CURVE).unwrap()
        );
    }

    #[test]
    fn errors_name_the_field() {
        let bad = CURVE.replace("[0,0,0,1,1,1]", "[0,0,1,1,1]");
        let e = geometry_from_str(&bad).unwrap_err().to_string();
        assert!(e.contains("knots") && e.contains("expected 6 knots"), "{e}");
        let bad = CURVE.replace("}", r#", "weights": [1, -1, 1]}"#);
        let e = geometry_from_str(&bad).unwrap_err().to_string();
        assert!(e.contains("weights") && e.contains("-1"), "{e}");
        let bad = CURVE.replace("[1,1,0]", r#"[1,"a",0]"#);
        let e = geometry_from_str(&bad).unwrap_err().to_string();
        assert!(e.contains("control_points[1]"), "{e}");
        let e = geometry_from_str(&CURVE[..40]).unwrap_err().to_string();
        assert!(e.contains("EOF"), "{e}");
        for empty in ["", "  \n", "\u{feff}"] {
            let e = geometry_from_str(empty).unwrap_err().to_string();
            assert!(e.contains("the file is empty"), "{e}");
        }
        let e = geometry_from_str(r#"{"kind": "cone"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown kind"), "{e}");
    }

    #[test]
    fn a_point_list_is_named_as_such() {
        let path = std::env::temp_dir().join(format!("fairfit-json-{}.csv", std::process::id()));
        std::fs::write(&path, "x,y\n0,0\n1,1\n").unwrap();
        let e = read_geometry(&path).unwrap_err().to_string();
        std::fs::remove_file(&path).ok();
        assert!(e.contains("not a fairfit curve or surface"), "{e}");
        assert!(e.contains("STEP") && e.contains("IGES"), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}
