//! Reading B-spline / NURBS curves and surfaces (and circles and ellipses, as exact rational quadratic
//! B-splines) from CAD files: the format by extension (`.step`,
//! `.stp`: [`super::step_read`]; `.igs`, `.iges`: [`super::iges_read`]), the choice of one entity, the
//! unit conversion. Dense sampling of a curve for re-fitting is [`crate::fit::sampling`].
//!
//! Units: fairfit's geometry carries no unit; its CAD writers declare millimetres unless told otherwise
//! (`--units`). Read coordinates are therefore converted to millimetres (as OpenCASCADE does), so that
//! `fairfit export part.igs --step out.step` keeps the part's size. A file in millimetres, or one that
//! declares no unit, is read bit for bit.
//!
//! Choice: a file usually holds several entities (a face's surface and its boundary edges, several
//! edges). [`CadKind::Any`] takes a surface when the file holds one, else a curve; the `index`-th
//! (0-based, in file order) of that kind is returned with the count of its kind, so the caller can say
//! how many there were.

use super::cad_chain::{join_segments, orient_segments, CadComposite};
use super::json::Geometry;
use crate::errors::{Error, Result};
use crate::nurbs::scale::{scaled_curve, scaled_surface};
use crate::nurbs::{NurbsCurve, NurbsSurface};
use std::collections::BTreeSet;
use std::path::Path;

/// The CAD formats fairfit reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CadFormat {
    /// STEP, ISO 10303-21 (`.step`, `.stp`).
    Step,
    /// IGES 5.x fixed format (`.igs`, `.iges`).
    Iges,
}

impl CadFormat {
    /// The format a file name's extension names (case-insensitive), if any.
    pub fn from_path(path: impl AsRef<Path>) -> Option<CadFormat> {
        let ext = path.as_ref().extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "step" | "stp" => Some(CadFormat::Step),
            "igs" | "iges" => Some(CadFormat::Iges),
            _ => None,
        }
    }
}

/// The length unit a CAD file declares.
#[derive(Clone, Debug, PartialEq)]
pub struct CadUnit {
    /// Short name: `mm`, `m`, `inch`, ... or the factor (`0.5 mm`).
    pub name: String,
    /// Millimetres per file unit.
    pub mm_per_unit: f64,
    /// False when the file declares no unit (millimetres are assumed).
    pub declared: bool,
}

impl CadUnit {
    /// A declared unit of `mm` millimetres, named when it is a common one.
    pub fn from_mm_per_unit(mm: f64) -> CadUnit {
        let known = [
            (1.0, "mm"),
            (1000.0, "m"),
            (10.0, "cm"),
            (1e6, "km"),
            (1e-3, "micron"),
            (25.4, "inch"),
            (304.8, "foot"),
            (0.0254, "mil"),
            (1_609_344.0, "mile"),
            (2.54e-5, "microinch"),
        ];
        let name = known
            .iter()
            .find(|(f, _)| ((f - mm) / f).abs() < 1e-12)
            .map_or_else(|| format!("{mm} mm"), |(_, n)| n.to_string());
        CadUnit {
            name,
            mm_per_unit: mm,
            declared: true,
        }
    }

    /// No unit in the file: millimetres assumed.
    pub fn undeclared() -> CadUnit {
        CadUnit {
            name: "mm".into(),
            mm_per_unit: 1.0,
            declared: false,
        }
    }
}

impl Default for CadUnit {
    fn default() -> Self {
        CadUnit::undeclared()
    }
}

/// Everything fairfit reads from a CAD file, coordinates as written in the file's unit.
#[derive(Clone, Debug, Default)]
pub struct CadContents {
    /// B-spline curves in file order, each with where it is (`#12` in STEP, `DE 7` in IGES), without
    /// the segments of the composites.
    pub curves: Vec<(String, NurbsCurve)>,
    /// Composite curves of B-spline segments, in file order.
    pub composites: Vec<CadComposite>,
    /// B-spline surfaces in file order, with where they are.
    pub surfaces: Vec<(String, NurbsSurface)>,
    /// Names of the other curve entities seen (`LINE`, `CIRCLE`, `110 (line)`, ...).
    pub other_curves: BTreeSet<String>,
    /// Names of the other surface entities seen (`PLANE`, ...).
    pub other_surfaces: BTreeSet<String>,
    /// The length unit.
    pub unit: CadUnit,
}

impl CadContents {
    /// Files the composite curve found at `at` (`#40` in STEP, `DE 7` in IGES): its segments
    /// (`Ok`, oriented along the chain here) as a composite after the single curves read so far, or
    /// (`Err`) the name of a member kind fairfit does not read among the other curves.
    pub(super) fn push_composite(
        &mut self,
        at: &str,
        read: std::result::Result<Vec<NurbsCurve>, String>,
    ) {
        match read {
            Ok(mut segments) => {
                orient_segments(&mut segments);
                self.composites.push(CadComposite {
                    source: format!("{at} (composite of {} segments)", segments.len()),
                    segments,
                    after: self.curves.len(),
                });
            }
            Err(name) => {
                self.other_curves.insert(name);
            }
        }
    }
}

/// Which kind of geometry to take from a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CadKind {
    /// A surface if the file holds one, else a curve.
    Any,
    /// A curve.
    Curve,
    /// A surface.
    Surface,
}

/// One curve or surface taken from a CAD file, in millimetres.
#[derive(Clone, Debug)]
pub struct CadGeometry {
    /// The geometry, converted to millimetres.
    pub geometry: Geometry,
    /// Where it was in the file (`#12`, `DE 7`).
    pub source: String,
    /// Its index among the entities of its kind (0-based).
    pub index: usize,
    /// How many entities of its kind the file holds.
    pub count: usize,
    /// The file's unit.
    pub unit: CadUnit,
    /// How many segments were joined into the curve (a composite curve), else 1.
    pub segments: usize,
}

/// One curve entity taken from a CAD file, in millimetres: a B-spline curve, or a composite curve's
/// segments in order.
#[derive(Clone, Debug)]
pub struct CadChain {
    /// The segments (one for a single B-spline curve), oriented along the curve, in millimetres.
    pub segments: Vec<NurbsCurve>,
    /// Where it was in the file (`#12`, `DE 7 (composite of 3 segments)`).
    pub source: String,
    /// Its index among the curve entities (0-based).
    pub index: usize,
    /// How many curve entities the file holds.
    pub count: usize,
    /// The file's unit.
    pub unit: CadUnit,
}

/// The kinds of exact conic curves in the sources the readers give (`#12 (circle)`, `DE 3 (circular
/// arc)`, `#20 (elliptical arc, trimmed #12)`).
const CONIC_KINDS: [&str; 6] = [
    "circular arc",
    "circle",
    "elliptical arc",
    "ellipse",
    "parabolic arc",
    "hyperbolic arc",
];

/// What kind of curve a curve's source label (as the readers give it) names: `circle`, `circular arc`,
/// `ellipse`, `elliptical arc`, `parabolic arc`, `hyperbolic arc` (conics, read as exact rational
/// quadratic B-splines), or `B-spline curve`.
///
/// ```
/// use fairfit::io::cad_read::curve_kind;
/// assert_eq!(curve_kind("#20 (circular arc, trimmed #12)"), "circular arc");
/// assert_eq!(curve_kind("DE 5 (ellipse)"), "ellipse");
/// assert_eq!(curve_kind("#12 (trimmed #9)"), "B-spline curve");
/// ```
pub fn curve_kind(source: &str) -> &'static str {
    source
        .split_once(" (")
        .and_then(|(_, rest)| CONIC_KINDS.into_iter().find(|k| rest.starts_with(k)))
        .unwrap_or("B-spline curve")
}

/// `segments` (in a file's unit, `mm_per_unit` millimetres each) scaled to millimetres; `file`
/// names the file in the error.
pub(crate) fn segments_in_mm(
    segments: Vec<NurbsCurve>,
    mm_per_unit: f64,
    file: &str,
) -> Result<Vec<NurbsCurve>> {
    if mm_per_unit == 1.0 {
        return Ok(segments);
    }
    segments
        .iter()
        .map(|c| scaled_curve(c, mm_per_unit))
        .collect::<Result<Vec<_>>>()
        .map_err(|e| Error::Cad(format!("{file}: converting to mm: {e}")))
}

/// The curve entities of a file in file order: single B-splines as chains of one segment, composites
/// as their segments (coordinates as written).
pub(crate) fn curve_chains(
    curves: Vec<(String, NurbsCurve)>,
    composites: Vec<CadComposite>,
) -> Vec<(String, Vec<NurbsCurve>)> {
    let mut out = Vec::with_capacity(curves.len() + composites.len());
    let mut comps = composites.into_iter().peekable();
    for (i, (src, c)) in curves.into_iter().enumerate() {
        while let Some(k) = comps.next_if(|k| k.after <= i) {
            out.push((k.source, k.segments));
        }
        out.push((src, vec![c]));
    }
    out.extend(comps.map(|k| (k.source, k.segments)));
    out
}

/// Parses the text of a STEP or IGES file.
pub fn parse_cad(text: &str, format: CadFormat) -> Result<CadContents> {
    match format {
        CadFormat::Step => super::step_read::contents(&super::p21::parse(text)?),
        CadFormat::Iges => super::iges_read::contents(text),
    }
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// What the file holds, for "has no ..." errors: `LINE, CIRCLE`, `1 B-spline surface`, `nothing fairfit reads`.
fn found(c: &CadContents) -> String {
    let mut parts: Vec<String> = Vec::new();
    if !c.curves.is_empty() {
        parts.push(plural(c.curves.len(), "B-spline curve"));
    }
    if !c.composites.is_empty() {
        parts.push(plural(c.composites.len(), "composite curve"));
    }
    if !c.surfaces.is_empty() {
        parts.push(plural(c.surfaces.len(), "B-spline surface"));
    }
    parts.extend(c.other_curves.iter().cloned());
    parts.extend(c.other_surfaces.iter().cloned());
    if parts.is_empty() {
        "no curve or surface entity".into()
    } else {
        parts.join(", ")
    }
}

fn no_entity(contents: &CadContents, kind: CadKind, file: &str) -> Error {
    let (what, advice) = if kind == CadKind::Curve {
        (
            "B-spline curve",
            "export the edge as a B-spline (NURBS) curve",
        )
    } else {
        (
            "B-spline surface",
            "export the face as a B-spline (NURBS) surface",
        )
    };
    Error::Cad(format!(
        "{file} has no {what} (found: {}); {advice}",
        found(contents)
    ))
}

fn out_of_range(n: usize, what: &str, index: usize, file: &str) -> Error {
    Error::InvalidOption(format!(
        "{file} holds {}; index {index} is out of range (0 to {})",
        plural(n, what),
        n - 1
    ))
}

/// Takes the `index`-th curve entity (B-spline or composite curve, in file order) of `contents` and
/// converts it to millimetres; `file` names the file in errors.
pub fn select_chain(contents: CadContents, index: usize, file: &str) -> Result<CadChain> {
    let n = contents.curves.len() + contents.composites.len();
    if n == 0 {
        return Err(no_entity(&contents, CadKind::Curve, file));
    }
    if index >= n {
        let what = if contents.composites.is_empty() {
            "B-spline curve"
        } else {
            "curve (B-spline or composite)"
        };
        return Err(out_of_range(n, what, index, file));
    }
    let (source, segments) = curve_chains(contents.curves, contents.composites).swap_remove(index);
    let segments = segments_in_mm(segments, contents.unit.mm_per_unit, file)?;
    Ok(CadChain {
        segments,
        source,
        index,
        count: n,
        unit: contents.unit,
    })
}

/// Takes the `index`-th entity of `kind` from `contents` and converts it to millimetres; `file` names
/// the file in errors. A composite curve is joined into one B-spline
/// ([`super::cad_chain::join_segments`]); one whose segments do not meet is an error.
pub fn select(
    contents: CadContents,
    kind: CadKind,
    index: usize,
    file: &str,
) -> Result<CadGeometry> {
    let has_curves = !(contents.curves.is_empty() && contents.composites.is_empty());
    let kind = match kind {
        CadKind::Any if contents.surfaces.is_empty() => CadKind::Curve,
        CadKind::Any => CadKind::Surface,
        k => k,
    };
    if kind == CadKind::Curve && has_curves {
        let c = select_chain(contents, index, file)?;
        let curve = match c.segments.len() {
            1 => c.segments[0].clone(),
            _ => join_segments(&c.segments).map_err(|e| {
                Error::Cad(format!(
                    "{file}: the composite curve {}: {e}; `fairfit curve` re-fits it as one chain of points",
                    c.source
                ))
            })?,
        };
        return Ok(CadGeometry {
            geometry: Geometry::Curve(curve),
            source: c.source,
            index,
            count: c.count,
            unit: c.unit,
            segments: c.segments.len(),
        });
    }
    let n = if kind == CadKind::Curve {
        0
    } else {
        contents.surfaces.len()
    };
    if n == 0 {
        return Err(no_entity(&contents, kind, file));
    }
    if index >= n {
        return Err(out_of_range(n, "B-spline surface", index, file));
    }
    let f = contents.unit.mm_per_unit;
    let (source, s) = { contents.surfaces }.swap_remove(index);
    let s = if f == 1.0 {
        s
    } else {
        scaled_surface(&s, f).map_err(|e| Error::Cad(format!("{file}: converting to mm: {e}")))?
    };
    Ok(CadGeometry {
        geometry: Geometry::Surface(s),
        source,
        index,
        count: n,
        unit: contents.unit,
        segments: 1,
    })
}

/// Reads the `index`-th curve or surface (see [`CadKind`]) of a STEP or IGES file, in millimetres.
/// Errors ([`Error::Cad`], or [`Error::InvalidOption`] for an index out of range) are one line and
/// name the file.
pub fn read_cad(path: impl AsRef<Path>, kind: CadKind, index: usize) -> Result<CadGeometry> {
    let path = path.as_ref();
    let contents = read_contents(path)?;
    select(contents, kind, index, &path.display().to_string())
}

/// Reads the `index`-th curve entity (a B-spline or a composite curve, see [`select_chain`]) of a STEP
/// or IGES file, in millimetres.
pub fn read_cad_chain(path: impl AsRef<Path>, index: usize) -> Result<CadChain> {
    let path = path.as_ref();
    let contents = read_contents(path)?;
    select_chain(contents, index, &path.display().to_string())
}

/// Reads and parses a STEP or IGES file: everything [`parse_cad`] finds, coordinates as written (the
/// unit not applied). Errors are one line and name the file.
pub fn read_contents(path: impl AsRef<Path>) -> Result<CadContents> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let format = CadFormat::from_path(path).ok_or_else(|| {
        Error::Cad(format!(
            "{file}: not a CAD file name (expected .step, .stp, .igs or .iges)"
        ))
    })?;
    let bytes = super::limits::read_bounded_text(path)?;
    // CAD files are ASCII; stray Latin-1 bytes in names or comments must not stop the read
    let text = String::from_utf8_lossy(&bytes);
    parse_cad(&text, format).map_err(|e| match e {
        Error::Cad(m) => Error::Cad(format!("{file}: {m}")),
        other => other,
    })
}

/// `c` restricted to `[a, b]` (exact, by knot insertion), when that lies strictly inside its domain
/// (IGES 126 `V(0), V(1)`, STEP `TRIMMED_CURVE` parameters); otherwise `c` as it is.
pub(crate) fn trimmed(c: NurbsCurve, a: f64, b: f64) -> Result<NurbsCurve> {
    let (u0, u1) = c.domain();
    let eps = 1e-12 * (u1 - u0);
    let cut_a = a > u0 + eps && a < u1;
    let cut_b = b < u1 - eps && b > u0;
    if !(cut_a || cut_b) || b <= a {
        return Ok(c);
    }
    cut(c, a, b, cut_a, cut_b)
}

/// `c` cut at `a` (when `cut_a`) and at `b` (when `cut_b`), `a < b` inside or at the ends of its domain,
/// by knot insertion to multiplicity `p` and dropping what lies outside (exact; also clamps an
/// unclamped end).
pub(crate) fn cut(c: NurbsCurve, a: f64, b: f64, cut_a: bool, cut_b: bool) -> Result<NurbsCurve> {
    let p = c.degree();
    let mut c = c;
    for (u, cut) in [(a, cut_a), (b, cut_b)] {
        let m = c.knots().iter().filter(|&&k| k == u).count();
        if cut && m < p {
            c = c.insert_knot(u, p - m)?;
        }
    }
    let k = c.knots();
    let pts = c.control_points();
    let w = c.weights();
    let lost = || Error::KnotOperation(format!("cannot cut the curve at [{a}, {b}]"));
    let first = if cut_a {
        let i = k.iter().position(|&x| x == a).ok_or_else(lost)?;
        i.checked_sub(1).ok_or_else(lost)?
    } else {
        0
    };
    let last = if cut_b {
        let i = k.iter().rposition(|&x| x == b).ok_or_else(lost)?;
        i.checked_sub(p).ok_or_else(lost)?
    } else {
        pts.len() - 1
    };
    if last < first {
        return Err(lost());
    }
    let mut knots = Vec::new();
    if cut_a {
        knots.push(a);
    }
    knots.extend_from_slice(&k[first + usize::from(cut_a)..=last + p + usize::from(!cut_b)]);
    if cut_b {
        knots.push(b);
    }
    NurbsCurve::new(
        p,
        knots,
        pts[first..=last].to_vec(),
        Some(w[first..=last].to_vec()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::Vec3;

    #[test]
    fn extensions_pick_the_format() {
        assert_eq!(CadFormat::from_path("a/b.STP"), Some(CadFormat::Step));
        assert_eq!(CadFormat::from_path("b.step"), Some(CadFormat::Step));
        assert_eq!(CadFormat::from_path("b.Iges"), Some(CadFormat::Iges));
        assert_eq!(CadFormat::from_path("b.igs"), Some(CadFormat::Iges));
        assert_eq!(CadFormat::from_path("b.json"), None);
    }

    #[test]
    fn units_are_named() {
        assert_eq!(CadUnit::from_mm_per_unit(25.4).name, "inch");
        assert_eq!(CadUnit::from_mm_per_unit(1000.0).name, "m");
        assert_eq!(CadUnit::from_mm_per_unit(2.0).name, "2 mm");
    }

    fn line_with_kink() -> NurbsCurve {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 0.5),
            Vec3::new(4.0, 0.0, 0.0),
        ];
        NurbsCurve::bspline(2, vec![0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0], pts).unwrap()
    }

    #[test]
    fn selection_counts_and_errors() {
        let contents = || CadContents {
            curves: vec![
                ("#1".into(), line_with_kink()),
                ("#2".into(), line_with_kink()),
            ],
            unit: CadUnit::from_mm_per_unit(25.4),
            ..CadContents::default()
        };
        let g = select(contents(), CadKind::Any, 1, "p.step").unwrap();
        assert_eq!((g.source.as_str(), g.count, g.index), ("#2", 2, 1));
        let Geometry::Curve(c) = g.geometry else {
            panic!("a curve")
        };
        assert!((c.point(1.0) - Vec3::new(101.6, 0.0, 0.0)).norm() < 1e-12);
        let e = select(contents(), CadKind::Any, 2, "p.step")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("holds 2 B-spline curves; index 2 is out of range"),
            "{e}"
        );
        let mut other = CadContents::default();
        other.other_curves.insert("CIRCLE".into());
        other.other_curves.insert("LINE".into());
        let e = select(other, CadKind::Curve, 0, "part.step")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "part.step has no B-spline curve (found: CIRCLE, LINE); export the edge as a B-spline (NURBS) curve"
        );
        let e = select(contents(), CadKind::Surface, 0, "p.step")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("has no B-spline surface (found: 2 B-spline curves)"),
            "{e}"
        );
    }

    #[test]
    fn trimming_by_knot_insertion_keeps_the_points() {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 0.5),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(5.0, 1.0, 1.0),
        ];
        let c = NurbsCurve::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
            pts,
            Some(vec![1.0, 2.0, 0.5, 1.0, 1.5]),
        )
        .unwrap();
        let t = trimmed(c.clone(), 0.2, 0.7).unwrap();
        assert_eq!(t.domain(), (0.2, 0.7));
        for i in 0..=50 {
            let u = 0.2 + 0.5 * i as f64 / 50.0;
            assert!((t.point(u) - c.point(u)).norm() < 1e-13, "{u}");
        }
        let t = trimmed(c.clone(), 0.0, 0.7).unwrap();
        assert_eq!(t.domain(), (0.0, 0.7));
        assert!((t.point(0.55) - c.point(0.55)).norm() < 1e-13);
        let t = trimmed(c.clone(), 0.4, 1.0).unwrap();
        assert_eq!(t.domain(), (0.4, 1.0));
        assert!((t.point(0.55) - c.point(0.55)).norm() < 1e-13);
    }
}
