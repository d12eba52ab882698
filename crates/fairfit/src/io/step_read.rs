//! B-spline and NURBS curves and surfaces, and the length unit, from a parsed STEP file
//! ([`super::p21`]).
//!
//! Read: `B_SPLINE_CURVE_WITH_KNOTS` and `B_SPLINE_SURFACE_WITH_KNOTS` as simple instances and in the
//! complex-instance form (`( BOUNDED_CURVE() B_SPLINE_CURVE(...) B_SPLINE_CURVE_WITH_KNOTS(...)
//! RATIONAL_B_SPLINE_CURVE(...) ... )`, the only form rational B-splines have), the knot-free forms
//! `BEZIER_CURVE`, `UNIFORM_CURVE`, `QUASI_UNIFORM_CURVE` (and their surface counterparts) with the
//! knots ISO 10303-42 implies, and `CARTESIAN_POINT` with 2 or 3 coordinates (z = 0 for 2). Knots come
//! as distinct values plus multiplicities and are expanded. Curves that only describe a trim in a
//! surface's parameter space (items of a `DEFINITIONAL_REPRESENTATION`, the `PCURVE`s CAD systems write
//! beside every face) are skipped. `CIRCLE` and `ELLIPSE` are read as exact rational quadratic B-splines
//! (`io/step_conic.rs`, [`super::cad_conic`]): alone as the whole conic, as the basis of a
//! `TRIMMED_CURVE` as the arc between its trims. A `TRIMMED_CURVE` of a B-spline or a conic is cut at its
//! trims, exactly: `PARAMETER_VALUE`s (conic angles in the file's plane-angle unit) or `CARTESIAN_POINT`s
//! (taken at their projection onto the basis; `master_representation .CARTESIAN.` prefers them when
//! both are given), `sense_agreement .F.` running from the first trim backwards to the second. An
//! `EDGE_CURVE` whose vertices lie inside its curve stands for the piece between them
//! (`io/step_edge.rs`). The length unit is the one of the file's
//! `GLOBAL_UNIT_ASSIGNED_CONTEXT`: an `SI_UNIT` metre with any prefix, or a `CONVERSION_BASED_UNIT`
//! (inch, foot, ...) followed through its `LENGTH_MEASURE_WITH_UNIT` to the SI unit. Coordinates are
//! returned as written; [`super::cad_read`] converts them.

use super::cad_read::{CadContents, CadUnit};
use super::p21::{Exchange, Instance, Value};
use super::step_composite::Composite;
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use std::collections::BTreeSet;

/// Curve entities that are not B-splines, named in the "no B-spline curve" error.
const OTHER_CURVES: &[&str] = &[
    "LINE",
    "PARABOLA",
    "HYPERBOLA",
    "POLYLINE",
    "OFFSET_CURVE_3D",
    "CLOTHOID",
];

/// Surface entities that are not B-splines, named in the "no B-spline surface" error.
const OTHER_SURFACES: &[&str] = &[
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
];

/// How a B-spline entity gives its knots.
#[derive(Clone, Copy, Debug, PartialEq)]
enum KnotForm<'a> {
    /// The `..._WITH_KNOTS` attributes (multiplicities and distinct values).
    Explicit(&'a [Value]),
    Bezier,
    Uniform,
    QuasiUniform,
}

pub(super) fn err(inst_id: u64, inst: &Instance, msg: impl std::fmt::Display) -> Error {
    Error::Cad(format!("line {} (#{inst_id}): {msg}", inst.line))
}

fn number(v: &Value, what: &str, id: u64, inst: &Instance) -> Result<f64> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| err(id, inst, format!("{what} is not a number")))
}

fn count(v: &Value, what: &str, id: u64, inst: &Instance) -> Result<usize> {
    let x = number(v, what, id, inst)?;
    if x >= 0.0 && x.fract() == 0.0 && x < 1e9 {
        Ok(x as usize)
    } else {
        Err(err(id, inst, format!("{what} {x} is not a whole number")))
    }
}

fn list<'a>(v: &'a Value, what: &str, id: u64, inst: &Instance) -> Result<&'a [Value]> {
    v.as_list()
        .ok_or_else(|| err(id, inst, format!("{what} is not a list")))
}

/// The attributes of a B-spline entity across the simple and the complex form: the `B_SPLINE_CURVE` /
/// `B_SPLINE_SURFACE` attributes (without the name), the knot form and the weights, if rational.
struct BsplineAttrs<'a> {
    base: &'a [Value],
    knots: KnotForm<'a>,
    weights: Option<&'a Value>,
}

/// `surface`: false for curves. `None` when the instance is no B-spline of that kind.
fn bspline_attrs(inst: &Instance, surface: bool) -> Option<BsplineAttrs<'_>> {
    let (base, with_knots, bezier, uniform, quasi, rational) = if surface {
        (
            "B_SPLINE_SURFACE",
            "B_SPLINE_SURFACE_WITH_KNOTS",
            "BEZIER_SURFACE",
            "UNIFORM_SURFACE",
            "QUASI_UNIFORM_SURFACE",
            "RATIONAL_B_SPLINE_SURFACE",
        )
    } else {
        (
            "B_SPLINE_CURVE",
            "B_SPLINE_CURVE_WITH_KNOTS",
            "BEZIER_CURVE",
            "UNIFORM_CURVE",
            "QUASI_UNIFORM_CURVE",
            "RATIONAL_B_SPLINE_CURVE",
        )
    };
    // number of B_SPLINE_CURVE / _SURFACE attributes
    let n_base = if surface { 7 } else { 5 };
    let n_knots = if surface { 5 } else { 3 };
    if inst.is_complex() {
        let b = inst.part(base)?;
        if b.params.len() < n_base {
            return None;
        }
        let knots = if let Some(k) = inst.part(with_knots) {
            KnotForm::Explicit(&k.params)
        } else if inst.part(bezier).is_some() {
            KnotForm::Bezier
        } else if inst.part(uniform).is_some() {
            KnotForm::Uniform
        } else if inst.part(quasi).is_some() {
            KnotForm::QuasiUniform
        } else {
            return None;
        };
        if let KnotForm::Explicit(k) = knots {
            if k.len() < n_knots {
                return None;
            }
        }
        let weights = inst.part(rational).and_then(|r| r.params.last());
        return Some(BsplineAttrs {
            base: &b.params[..n_base],
            knots,
            weights,
        });
    }
    let part = &inst.parts[0];
    let p = &part.params;
    let knots = match part.name.as_str() {
        n if n == with_knots && p.len() > n_base + n_knots => KnotForm::Explicit(&p[1 + n_base..]),
        n if n == bezier => KnotForm::Bezier,
        n if n == uniform => KnotForm::Uniform,
        n if n == quasi => KnotForm::QuasiUniform,
        _ => return None,
    };
    (p.len() > n_base).then(|| BsplineAttrs {
        base: &p[1..1 + n_base],
        knots,
        weights: None,
    })
}

/// Expands distinct values and multiplicities, or makes the implied knots of a knot-free form for `n`
/// control points of degree `p`.
fn knot_vector(
    form: KnotForm<'_>,
    mults_at: usize,
    values_at: usize,
    p: usize,
    n: usize,
    id: u64,
    inst: &Instance,
) -> Result<Vec<f64>> {
    match form {
        KnotForm::Explicit(attrs) => {
            let mults = list(&attrs[mults_at], "knot multiplicities", id, inst)?;
            let values = list(&attrs[values_at], "knot values", id, inst)?;
            if mults.len() != values.len() {
                return Err(err(
                    id,
                    inst,
                    format!(
                        "{} knot multiplicities for {} knot values",
                        mults.len(),
                        values.len()
                    ),
                ));
            }
            let mut out = Vec::new();
            for (m, v) in mults.iter().zip(values) {
                let m = count(m, "a knot multiplicity", id, inst)?;
                let v = number(v, "a knot value", id, inst)?;
                if out.len() + m > 1_000_000 {
                    return Err(err(id, inst, "more than a million knots"));
                }
                out.extend(std::iter::repeat_n(v, m));
            }
            Ok(out)
        }
        KnotForm::Uniform => Ok((0..n + p + 1).map(|i| i as f64 - p as f64).collect()),
        KnotForm::QuasiUniform => {
            let inner = n.saturating_sub(p + 1);
            let mut k = vec![0.0; p + 1];
            k.extend((1..=inner).map(|i| i as f64));
            k.extend(std::iter::repeat_n((inner + 1) as f64, p + 1));
            Ok(k)
        }
        KnotForm::Bezier => {
            let segments = (n.saturating_sub(1) / p.max(1)).max(1);
            let mut k = vec![0.0; p + 1];
            for s in 1..segments {
                k.extend(std::iter::repeat_n(s as f64, p));
            }
            k.extend(std::iter::repeat_n(segments as f64, p + 1));
            Ok(k)
        }
    }
}

/// The coordinates of the `CARTESIAN_POINT` `#r` (z = 0 for a 2D point).
pub(super) fn point(x: &Exchange, v: &Value, id: u64, inst: &Instance) -> Result<Vec3> {
    let r = v
        .as_ref_id()
        .ok_or_else(|| err(id, inst, "a control point is not a reference #n"))?;
    let target = x
        .data
        .get(&r)
        .ok_or_else(|| err(id, inst, format!("control point #{r} is not defined")))?;
    let cp = target.part("CARTESIAN_POINT").ok_or_else(|| {
        err(
            id,
            inst,
            format!(
                "control point #{r} is a {}, not a CARTESIAN_POINT",
                target.parts[0].name
            ),
        )
    })?;
    let coords = cp
        .params
        .iter()
        .rev()
        .find_map(Value::as_list)
        .ok_or_else(|| err(r, target, "CARTESIAN_POINT without coordinates"))?;
    if !(1..=3).contains(&coords.len()) {
        return Err(err(
            r,
            target,
            "a CARTESIAN_POINT must have 1 to 3 coordinates",
        ));
    }
    let mut c = [0.0; 3];
    for (k, v) in coords.iter().enumerate() {
        c[k] = number(v, "a coordinate", r, target)?;
    }
    Ok(Vec3(c))
}

/// Builds the curve of instance `#id`, or `None` when it is no B-spline curve.
pub(super) fn curve(x: &Exchange, id: u64, inst: &Instance) -> Result<Option<NurbsCurve>> {
    let Some(a) = bspline_attrs(inst, false) else {
        return Ok(None);
    };
    let p = count(&a.base[0], "the degree", id, inst)?;
    let refs = list(&a.base[1], "the control points", id, inst)?;
    let pts = refs
        .iter()
        .map(|v| point(x, v, id, inst))
        .collect::<Result<Vec<_>>>()?;
    let knots = knot_vector(a.knots, 0, 1, p, pts.len(), id, inst)?;
    let weights = match a.weights {
        Some(w) => Some(
            list(w, "the weights", id, inst)?
                .iter()
                .map(|v| number(v, "a weight", id, inst))
                .collect::<Result<Vec<_>>>()?,
        ),
        None => None,
    };
    NurbsCurve::new(p, knots, pts, weights)
        .map(Some)
        .map_err(|e| err(id, inst, e))
}

/// A list of lists of numbers or point references, as rows.
fn rows<'a>(v: &'a Value, what: &str, id: u64, inst: &Instance) -> Result<Vec<&'a [Value]>> {
    list(v, what, id, inst)?
        .iter()
        .map(|r| list(r, what, id, inst))
        .collect()
}

/// Builds the surface of instance `#id`, or `None` when it is no B-spline surface.
fn surface(x: &Exchange, id: u64, inst: &Instance) -> Result<Option<NurbsSurface>> {
    let Some(a) = bspline_attrs(inst, true) else {
        return Ok(None);
    };
    let pu = count(&a.base[0], "the u degree", id, inst)?;
    let pv = count(&a.base[1], "the v degree", id, inst)?;
    let net = rows(&a.base[2], "the control net", id, inst)?
        .into_iter()
        .map(|r| r.iter().map(|v| point(x, v, id, inst)).collect())
        .collect::<Result<Vec<Vec<Vec3>>>>()?;
    let n_u = net.len();
    let n_v = net.first().map_or(0, Vec::len);
    let ku = knot_vector(a.knots, 0, 2, pu, n_u, id, inst)?;
    let kv = knot_vector(a.knots, 1, 3, pv, n_v, id, inst)?;
    let weights = match a.weights {
        Some(w) => Some(
            rows(w, "the weights", id, inst)?
                .into_iter()
                .map(|r| r.iter().map(|v| number(v, "a weight", id, inst)).collect())
                .collect::<Result<Vec<Vec<f64>>>>()?,
        ),
        None => None,
    };
    NurbsSurface::new(pu, pv, ku, kv, net, weights)
        .map(Some)
        .map_err(|e| err(id, inst, e))
}

const SI_PREFIXES: &[(&str, f64)] = &[
    ("EXA", 1e18),
    ("PETA", 1e15),
    ("TERA", 1e12),
    ("GIGA", 1e9),
    ("MEGA", 1e6),
    ("KILO", 1e3),
    ("HECTO", 1e2),
    ("DECA", 1e1),
    ("DECI", 1e-1),
    ("CENTI", 1e-2),
    ("MILLI", 1e-3),
    ("MICRO", 1e-6),
    ("NANO", 1e-9),
    ("PICO", 1e-12),
    ("FEMTO", 1e-15),
    ("ATTO", 1e-18),
];

/// Millimetres per unit of the length unit `#r`, following conversion-based units (depth-limited).
fn mm_per_unit(x: &Exchange, r: u64, depth: usize) -> Option<f64> {
    let inst = x.data.get(&r)?;
    if depth > 8 {
        return None;
    }
    if let Some(si) = inst.part("SI_UNIT") {
        let n = si.params.len();
        if n < 2 || !matches!(&si.params[n - 1], Value::Enum(e) if e == "METRE") {
            return None;
        }
        let prefix = match &si.params[n - 2] {
            Value::Enum(p) => SI_PREFIXES.iter().find(|(name, _)| name == p)?.1,
            _ => 1.0,
        };
        // 1e3 * 1e-3 is exactly 1 in floating point; keep the common cases exact
        return Some(if prefix == 1e-3 { 1.0 } else { 1e3 * prefix });
    }
    if let Some(cb) = inst.part("CONVERSION_BASED_UNIT") {
        let name = match cb.params.first() {
            Some(Value::Str(s)) => s.to_ascii_uppercase(),
            _ => String::new(),
        };
        let factor = cb.params.get(1).and_then(Value::as_ref_id).and_then(|m| {
            let mi = x.data.get(&m)?;
            let mwu = mi
                .parts
                .iter()
                .find(|p| p.name.ends_with("MEASURE_WITH_UNIT") && p.params.len() >= 2)?;
            let value = mwu.params[0].as_f64()?;
            let unit = mwu.params[1].as_ref_id()?;
            Some(value * mm_per_unit(x, unit, depth + 1)?)
        });
        let by_name = match name.as_str() {
            "INCH" | "IN" => Some(25.4),
            "FOOT" | "FT" => Some(304.8),
            "MILLIMETRE" | "MILLIMETER" | "MM" => Some(1.0),
            _ => None,
        };
        return factor.filter(|f| f.is_finite() && *f > 0.0).or(by_name);
    }
    None
}

/// The file's length unit: the first length unit of a `GLOBAL_UNIT_ASSIGNED_CONTEXT`.
fn length_unit(x: &Exchange) -> Result<CadUnit> {
    for inst in x.data.values() {
        let Some(ctx) = inst.part("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
            continue;
        };
        let Some(units) = ctx.params.first().and_then(Value::as_list) else {
            continue;
        };
        for u in units.iter().filter_map(Value::as_ref_id) {
            let is_length = x
                .data
                .get(&u)
                .is_some_and(|i| i.part("LENGTH_UNIT").is_some());
            if !is_length {
                continue;
            }
            return match mm_per_unit(x, u, 0) {
                Some(mm) => Ok(CadUnit::from_mm_per_unit(mm)),
                None => Err(Error::Cad(format!(
                    "line {}: the length unit #{u} is not one fairfit knows (SI metre with a prefix, \
                     or a conversion-based unit such as inch)",
                    x.data[&u].line
                ))),
            };
        }
    }
    Ok(CadUnit::undeclared())
}

/// Every curve id referenced as an item of a `DEFINITIONAL_REPRESENTATION` (parameter-space curves).
fn parameter_space_items(x: &Exchange) -> BTreeSet<u64> {
    let mut out = BTreeSet::new();
    for inst in x.data.values() {
        if let Some(d) = inst.part("DEFINITIONAL_REPRESENTATION") {
            if let Some(items) = d.params.get(1).and_then(Value::as_list) {
                out.extend(items.iter().filter_map(Value::as_ref_id));
            }
        }
    }
    out
}

/// A `TRIMMED_CURVE` read: its basis curve's id, the trimmed curve, and its kind (`trimmed` for a
/// B-spline basis, `circular arc`, `circle`, `elliptical arc`, `ellipse` for a conic).
pub(super) struct Trimmed {
    pub basis: u64,
    pub curve: NurbsCurve,
    pub kind: &'static str,
}

/// A `TRIMMED_CURVE` of a B-spline, a `CIRCLE` or an `ELLIPSE`, cut at its trims, or `None` for other
/// trimmed curves (and for a B-spline trimmed across its seam: the basis is then read uncut). Trims
/// are parameter values or points (`master_representation .CARTESIAN.` prefers the points); a point
/// is taken at its projection onto the basis curve. `.F.` sense runs the curve from the first trim
/// backwards to the second. `rad`: radians per unit of the file's plane-angle unit (conic trims).
pub(super) fn trimmed_curve(
    x: &Exchange,
    id: u64,
    inst: &Instance,
    rad: f64,
) -> Result<Option<Trimmed>> {
    let Some(t) = inst.part("TRIMMED_CURVE") else {
        return Ok(None);
    };
    let Some(basis) = t.params.get(1).and_then(Value::as_ref_id) else {
        return Ok(None);
    };
    let Some(b) = x.data.get(&basis) else {
        return Ok(None);
    };
    let conic = super::step_conic::conic(x, basis, b)?;
    let open = match conic {
        Some(_) => None,
        None => super::step_conic::open_conic(x, basis, b)?,
    };
    let bspline = match (conic, open) {
        (None, None) => curve(x, basis, b)?,
        _ => None,
    };
    if conic.is_none() && open.is_none() && bspline.is_none() {
        return Ok(None);
    }
    let ends = [
        super::step_conic::trim(x, t.params.get(2), id, inst)?,
        super::step_conic::trim(x, t.params.get(3), id, inst)?,
    ];
    let sense = !matches!(t.params.get(4), Some(Value::Enum(e)) if e == "F");
    let points_first = super::step_conic::points_are_master(t.params.get(5));
    if let Some(c) = open {
        let (curve, kind) =
            super::step_conic::trimmed_open_conic(&c, ends, points_first, id, inst)?;
        return Ok(Some(Trimmed { basis, curve, kind }));
    }
    if let Some(c) = conic {
        let (curve, kind) =
            super::step_conic::trimmed_conic(&c, ends, sense, points_first, rad, id, inst)?;
        return Ok(Some(Trimmed { basis, curve, kind }));
    }
    let Some(c) = bspline else {
        return Ok(None);
    };
    // built only when a trim is taken by its point
    let projector = std::cell::OnceCell::new();
    let size = crate::fit::sampling::control_extent(c.control_points());
    let mut u = [0.0; 2];
    for (k, e) in ends.iter().enumerate() {
        u[k] = match e.by(points_first) {
            super::step_conic::TrimBy::Param(v) => {
                let (a, b) = c.domain();
                let slack = 1e-9 * (b - a).abs().max(a.abs()).max(b.abs());
                if !(v >= a - slack && v <= b + slack) {
                    return Err(err(
                        id,
                        inst,
                        format!(
                            "trim parameter {v} lies outside the domain [{a}, {b}] of the B-spline \
                             #{basis}"
                        ),
                    ));
                }
                v.clamp(a, b)
            }
            super::step_conic::TrimBy::Point(p) => {
                let pr = projector
                    .get_or_init(|| crate::diffgeo::CurveProjector::new(&c, 16))
                    .project(p);
                if pr.distance.is_nan() || pr.distance > 1e-6 * size {
                    return Err(err(
                        id,
                        inst,
                        format!(
                            "trimming point {} lies {:.3e} off the B-spline #{basis} (more than 1e-6 \
                             of its size)",
                            k + 1,
                            pr.distance
                        ),
                    ));
                }
                pr.u
            }
        };
    }
    let (lo, hi) = if sense { (u[0], u[1]) } else { (u[1], u[0]) };
    if lo >= hi {
        // a trim across the seam of a periodic curve: read the whole basis curve
        return Ok(None);
    }
    let c = super::cad_read::trimmed(c, lo, hi).map_err(|e| err(id, inst, e))?;
    Ok(Some(Trimmed {
        basis,
        curve: if sense { c } else { c.reversed() },
        kind: "trimmed",
    }))
}

/// Reads every B-spline curve and surface of a parsed STEP file, in instance order, with the unit.
/// A `TRIMMED_CURVE` of a B-spline by parameter values stands for its basis curve, cut to the trim. A
/// `COMPOSITE_CURVE` of such curves (`io/step_composite.rs`) stands for its segments (segments that
/// run against the chain are turned, [`super::cad_chain::orient_segments`]).
pub fn contents(x: &Exchange) -> Result<CadContents> {
    let mut out = CadContents {
        unit: length_unit(x)?,
        ..CadContents::default()
    };
    let rad = super::step_conic::radians_per_angle_unit(x)?;
    let skip = parameter_space_items(x);
    let mut composites = super::step_composite::composites(x, &skip, rad)?;
    let members: BTreeSet<u64> = composites
        .values()
        .flat_map(|c| match c {
            Composite::Read(_, m) => m.iter().copied().collect(),
            Composite::Unsupported(_) => Vec::new(),
        })
        .collect();
    let mut trims = std::collections::BTreeMap::new();
    for (&id, inst) in &x.data {
        if !skip.contains(&id) && !members.contains(&id) {
            if let Some(t) = trimmed_curve(x, id, inst, rad)? {
                trims.insert(id, t);
            }
        }
    }
    let cut: BTreeSet<u64> = trims.values().map(|t| t.basis).collect();
    // curves that an edge cuts are listed as their edges, each in its place
    let mut edges = super::step_edge::edges(x, &trims, &skip)?;
    let by_edges: BTreeSet<u64> = edges
        .values()
        .filter(|e| !e.whole)
        .map(|e| e.basis)
        .collect();
    edges.retain(|_, e| by_edges.contains(&e.basis));
    for (&id, inst) in &x.data {
        if by_edges.contains(&id) {
            continue;
        }
        if let Some(e) = edges.remove(&id) {
            let label = match e.kind {
                "edge" => format!("#{id} (edge of #{})", e.basis),
                kind => format!("#{id} ({kind}, edge of #{})", e.basis),
            };
            out.curves.push((label, e.curve));
            continue;
        }
        if let Some(s) = surface(x, id, inst)? {
            out.surfaces.push((format!("#{id}"), s));
            continue;
        }
        if let Some(c) = composites.remove(&id) {
            let read = match c {
                Composite::Read(segments, _) => Ok(segments),
                Composite::Unsupported(name) => Err(name),
            };
            out.push_composite(&format!("#{id}"), read);
            continue;
        }
        if skip.contains(&id) || cut.contains(&id) || members.contains(&id) {
            continue;
        }
        if let Some(t) = trims.remove(&id) {
            let label = match t.kind {
                "trimmed" => format!("#{id} (trimmed #{})", t.basis),
                kind => format!("#{id} ({kind}, trimmed #{})", t.basis),
            };
            out.curves.push((label, t.curve));
            continue;
        }
        if let Some(c) = curve(x, id, inst)? {
            out.curves.push((format!("#{id}"), c));
            continue;
        }
        if let Some(c) = super::step_conic::conic(x, id, inst)? {
            let full = c.full(0.0).map_err(|e| err(id, inst, e))?;
            out.curves.push((format!("#{id} ({})", c.kind(true)), full));
            continue;
        }
        for part in &inst.parts {
            if OTHER_CURVES.contains(&part.name.as_str()) {
                out.other_curves.insert(part.name.clone());
            }
            if OTHER_SURFACES.contains(&part.name.as_str()) {
                out.other_surfaces.insert(part.name.clone());
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::p21::parse;
    use super::*;

    fn wrap(data: &str) -> String {
        format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n")
    }

    const POINTS: &str = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));\
                          #3=CARTESIAN_POINT('',(2.,0.,0.));";

    #[test]
    fn simple_and_complex_quadratics_agree_with_hand_values() {
        let simple = format!(
            "{POINTS}#4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);"
        );
        let c = contents(&parse(&wrap(&simple)).unwrap()).unwrap();
        assert_eq!(c.curves.len(), 1);
        assert_eq!(c.curves[0].0, "#4");
        // Bezier quadratic: C(1/2) = (P0 + 2 P1 + P2) / 4
        assert!((c.curves[0].1.point(0.5) - Vec3::new(1.0, 0.5, 0.0)).norm() < 1e-15);
        let complex = format!(
            "{POINTS}#4=( BOUNDED_CURVE() B_SPLINE_CURVE(2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.) \
             B_SPLINE_CURVE_WITH_KNOTS((3,3),(0.,1.),.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM() \
             RATIONAL_B_SPLINE_CURVE((1.,2.,1.)) REPRESENTATION_ITEM('') );"
        );
        let c = contents(&parse(&wrap(&complex)).unwrap()).unwrap();
        // weights 1, 2, 1: C(1/2) = (P0 + 4 P1 + P2) / 6 = (1, 2/3, 0)
        let q = c.curves[0].1.point(0.5);
        assert!((q - Vec3::new(1.0, 2.0 / 3.0, 0.0)).norm() < 1e-15, "{q:?}");
        assert_eq!(c.unit, CadUnit::undeclared());
    }

    #[test]
    fn implied_knots_of_the_knot_free_forms() {
        let bez = format!("{POINTS}#4=BEZIER_CURVE('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.);");
        let c = contents(&parse(&wrap(&bez)).unwrap()).unwrap();
        assert_eq!(c.curves[0].1.knots(), &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let uni = format!("{POINTS}#4=UNIFORM_CURVE('',1,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.);");
        let c = contents(&parse(&wrap(&uni)).unwrap()).unwrap();
        assert_eq!(c.curves[0].1.knots(), &[-1.0, 0.0, 1.0, 2.0, 3.0]);
        let q = format!("{POINTS}#4=QUASI_UNIFORM_CURVE('',1,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.);");
        let c = contents(&parse(&wrap(&q)).unwrap()).unwrap();
        assert_eq!(c.curves[0].1.knots(), &[0.0, 0.0, 1.0, 2.0, 2.0]);
    }

    #[test]
    fn units_metre_inch_and_prefixes() {
        let ctx = |len: &str| {
            wrap(&format!(
                "{len}\n#20=( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#10)) \
                 REPRESENTATION_CONTEXT('','') );"
            ))
        };
        let unit = |len: &str| contents(&parse(&ctx(len)).unwrap()).unwrap().unit;
        let mm = unit("#10=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );");
        assert_eq!((mm.mm_per_unit, mm.name.as_str()), (1.0, "mm"));
        let m = unit("#10=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) );");
        assert_eq!((m.mm_per_unit, m.name.as_str()), (1000.0, "m"));
        let inch = unit(
            "#8=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\
             #9=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#8);\
             #7=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\
             #10=( CONVERSION_BASED_UNIT('INCH',#9) LENGTH_UNIT() NAMED_UNIT(#7) );",
        );
        assert_eq!((inch.mm_per_unit, inch.name.as_str()), (25.4, "inch"));
        let e = contents(
            &parse(&ctx(
                "#10=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.GRAM.) );",
            ))
            .unwrap(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("#10") && e.contains("not one fairfit knows"),
            "{e}"
        );
    }

    #[test]
    fn parameter_space_curves_are_skipped_and_other_curves_named() {
        let data = format!(
            "{POINTS}#4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);\
             #5=DEFINITIONAL_REPRESENTATION('',(#4),#6);#7=LINE('',#1,#8);"
        );
        let c = contents(&parse(&wrap(&data)).unwrap()).unwrap();
        assert!(c.curves.is_empty());
        assert!(c.other_curves.contains("LINE"));
    }

    #[test]
    fn inconsistent_knots_name_the_instance() {
        let data = format!(
            "{POINTS}#4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,2),(0.,1.),.UNSPECIFIED.);"
        );
        let e = contents(&parse(&wrap(&data)).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("#4") && e.contains("expected 6 knots"), "{e}");
        let data = format!(
            "{POINTS}#4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#9),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);"
        );
        let e = contents(&parse(&wrap(&data)).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("#9 is not defined"), "{e}");
    }
}

#[cfg(test)]
mod conic_tests {
    use super::super::p21::parse;
    use super::*;
    use std::f64::consts::PI;

    fn wrap(data: &str) -> String {
        format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n")
    }

    /// A circle of radius 5 about (1, 2, 3) in the plane x + y + z = const (axis (1, 1, 1)/√3, ref
    /// direction (1, -1, 0)/√2), `extra` instances after it, and the plane-angle unit `unit`.
    fn circle_file(extra: &str, unit: &str) -> String {
        wrap(&format!(
            "#1=CARTESIAN_POINT('',(1.,2.,3.));#2=DIRECTION('',(1.,1.,1.));#3=DIRECTION('',(1.,-1.,0.));\
             #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=CIRCLE('',#4,5.);{extra}\
             #40=( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );{unit}\
             #50=( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#41)) \
             REPRESENTATION_CONTEXT('','') );"
        ))
    }

    const RADIAN: &str = "#41=( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );";
    const DEGREE: &str = "#42=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#40);\
                          #43=DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.);\
                          #41=( CONVERSION_BASED_UNIT('DEGREE',#42) NAMED_UNIT(#43) PLANE_ANGLE_UNIT() );";

    fn axes() -> (Vec3, Vec3, Vec3) {
        let z = Vec3::new(1.0, 1.0, 1.0) * (1.0 / 3f64.sqrt());
        let x = Vec3::new(1.0, -1.0, 0.0) * (1.0 / 2f64.sqrt());
        (Vec3::new(1.0, 2.0, 3.0), x, z.cross(x))
    }

    fn on_circle(t: f64) -> Vec3 {
        let (c, x, y) = axes();
        c + x * (5.0 * t.cos()) + y * (5.0 * t.sin())
    }

    fn assert_on_circle(c: &NurbsCurve) {
        let (centre, x, y) = axes();
        let n = x.cross(y);
        let (a, b) = c.domain();
        for i in 0..=1000 {
            let p = c.point(a + (b - a) * i as f64 / 1000.0);
            assert!(((p - centre).norm() - 5.0).abs() < 1e-12 * 5.0, "{p:?}");
            assert!((p - centre).dot(n).abs() < 1e-12 * 5.0);
        }
    }

    #[test]
    fn a_whole_circle_is_read_exactly() {
        let c = contents(&parse(&circle_file("", RADIAN)).unwrap()).unwrap();
        assert_eq!(c.curves.len(), 1);
        assert_eq!(c.curves[0].0, "#5 (circle)");
        let k = &c.curves[0].1;
        assert_eq!((k.degree(), k.domain()), (2, (0.0, 2.0 * PI)));
        assert_on_circle(k);
        // the parameter is the angle at the knots (quarter turns)
        for q in 0..4 {
            let t = q as f64 * PI / 2.0;
            assert!((k.point(t) - on_circle(t)).norm() < 1e-14 * 5.0, "{q}");
        }
    }

    #[test]
    fn arcs_trimmed_by_degrees_radians_and_points_agree() {
        let deg = "#6=CARTESIAN_POINT('',(0.,0.,0.));\
                   #7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(30.)),(PARAMETER_VALUE(200.)),.T.,.PARAMETER.);";
        let rad = format!(
            "#7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE({})),(PARAMETER_VALUE({})),.T.,.PARAMETER.);",
            30f64.to_radians(),
            200f64.to_radians()
        );
        let (p1, p2) = (
            on_circle(30f64.to_radians()),
            on_circle(200f64.to_radians()),
        );
        let pts = format!(
            "#8=CARTESIAN_POINT('',({:.17},{:.17},{:.17}));#9=CARTESIAN_POINT('',({:.17},{:.17},{:.17}));\
             #7=TRIMMED_CURVE('',#5,(#8,PARAMETER_VALUE(99.)),(#9),.T.,.CARTESIAN.);",
            p1[0], p1[1], p1[2], p2[0], p2[1], p2[2]
        );
        for (data, unit) in [
            (deg, DEGREE),
            (rad.as_str(), RADIAN),
            (pts.as_str(), DEGREE),
        ] {
            let c = contents(&parse(&circle_file(data, unit)).unwrap()).unwrap();
            assert_eq!(c.curves.len(), 1, "{data}");
            assert_eq!(c.curves[0].0, "#7 (circular arc, trimmed #5)");
            let arc = &c.curves[0].1;
            assert_on_circle(arc);
            let (a, b) = arc.domain();
            assert!((b - a - 170f64.to_radians()).abs() < 1e-14, "{a} {b}");
            assert!((arc.point(a) - p1).norm() < 1e-13 && (arc.point(b) - p2).norm() < 1e-13);
            // the middle of the arc is at 115 degrees
            let mid = crate::diffgeo::project_point(arc, on_circle(115f64.to_radians()));
            assert!(mid.distance < 1e-13, "{}", mid.distance);
        }
        // sense .F.: from 30 degrees backwards to 200 (the other 190 degrees)
        let back = "#7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(30.)),(PARAMETER_VALUE(200.)),.F.,.PARAMETER.);";
        let c = contents(&parse(&circle_file(back, DEGREE)).unwrap()).unwrap();
        let arc = &c.curves[0].1;
        let (a, b) = arc.domain();
        assert!((b - a - 190f64.to_radians()).abs() < 1e-14);
        assert!((arc.point(a) - p1).norm() < 1e-13 && (arc.point(b) - p2).norm() < 1e-13);
        let mid = crate::diffgeo::project_point(arc, on_circle(-65f64.to_radians()));
        assert!(mid.distance < 1e-13);
        assert_on_circle(arc);
        // equal trims: the full circle from there
        let full = "#7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(30.)),(PARAMETER_VALUE(390.)),.T.,.PARAMETER.);";
        let c = contents(&parse(&circle_file(full, DEGREE)).unwrap()).unwrap();
        assert_eq!(c.curves[0].0, "#7 (circle, trimmed #5)");
    }

    #[test]
    fn an_ellipse_in_a_2d_placement() {
        let data = "#1=CARTESIAN_POINT('',(1.,2.));#3=DIRECTION('',(0.,1.));\
                    #4=AXIS2_PLACEMENT_2D('',#1,#3);#5=ELLIPSE('',#4,4.,1.5);\
                    #7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(1.5707963267948966)),.T.,.PARAMETER.);";
        let c = contents(&parse(&wrap(data)).unwrap()).unwrap();
        assert_eq!(c.curves[0].0, "#7 (elliptical arc, trimmed #5)");
        let e = &c.curves[0].1;
        let (a, b) = e.domain();
        // from the end of the 4 semi-axis along +y to the end of the 1.5 semi-axis along -x
        assert!((e.point(a) - Vec3::new(1.0, 6.0, 0.0)).norm() < 1e-14);
        assert!((e.point(b) - Vec3::new(-0.5, 2.0, 0.0)).norm() < 1e-14);
        for i in 0..=1000 {
            let p = e.point(a + (b - a) * i as f64 / 1000.0);
            let (u, v) = ((p[1] - 2.0) / 4.0, (p[0] - 1.0) / 1.5);
            assert!((u * u + v * v - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn a_bspline_trimmed_by_points_is_cut_at_their_projections() {
        let data = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));\
                    #3=CARTESIAN_POINT('',(2.,0.,0.));\
                    #4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);\
                    #5=CARTESIAN_POINT('',(0.5,0.375,0.));#6=CARTESIAN_POINT('',(1.6,0.32,0.));\
                    #7=TRIMMED_CURVE('',#4,(#5),(#6),.T.,.CARTESIAN.);";
        // C(u) = (2u, 2u(1-u)): (0.5, 0.375) is u = 0.25, (1.6, 0.32) is u = 0.8
        let c = contents(&parse(&wrap(data)).unwrap()).unwrap();
        assert_eq!(c.curves.len(), 1);
        assert_eq!(c.curves[0].0, "#7 (trimmed #4)");
        let t = &c.curves[0].1;
        let (a, b) = t.domain();
        assert!(
            (a - 0.25).abs() < 1e-14 && (b - 0.8).abs() < 1e-14,
            "{a} {b}"
        );
        assert!((t.point(0.5) - Vec3::new(1.0, 0.5, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn malformed_conics_and_trims_give_one_line_errors() {
        let bad = [
            (
                "#5=CIRCLE('',#4,5.);",
                "#5=CIRCLE('',#4,0.);",
                "not a finite positive length",
            ),
            (
                "#5=CIRCLE('',#4,5.);",
                "#5=CIRCLE('',#4,-2.);",
                "not a finite positive length",
            ),
            (
                "#5=CIRCLE('',#4,5.);",
                "#5=CIRCLE('',#4,$);",
                "not a finite positive length",
            ),
            (
                "#3=DIRECTION('',(1.,-1.,0.));",
                "#3=DIRECTION('',(1.,1.,1.));",
                "degenerate",
            ),
            (
                "#2=DIRECTION('',(1.,1.,1.));",
                "#2=DIRECTION('',(0.,0.,0.));",
                "zero or not finite",
            ),
            (
                "#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);",
                "#4=AXIS2_PLACEMENT_3D('',#1,#2,#99);",
                "not a DIRECTION",
            ),
            (
                "#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);",
                "#4=CARTESIAN_POINT('',(0.,0.,0.));",
                "not an AXIS2_PLACEMENT",
            ),
        ];
        for (from, to, want) in bad {
            let text = circle_file("", RADIAN).replace(from, to);
            let e = contents(&parse(&text).unwrap()).unwrap_err().to_string();
            assert!(e.contains(want) && !e.contains('\n'), "{to}: {e}");
        }
        let trims = [
            ("#7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(1.)),(),.T.,.PARAMETER.);", "neither"),
            ("#8=CARTESIAN_POINT('',(100.,0.,0.));#7=TRIMMED_CURVE('',#5,(#8),(PARAMETER_VALUE(1.)),.T.,.CARTESIAN.);", "off the circle"),
            ("#7=TRIMMED_CURVE('',#5,(PARAMETER_VALUE(1.E300)),(PARAMETER_VALUE(1.)),.T.,.PARAMETER.);", "not usable angles"),
        ];
        for (data, want) in trims {
            let e = contents(&parse(&circle_file(data, RADIAN)).unwrap())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want) && e.contains("#7"), "{data}: {e}");
        }
        let e = contents(
            &parse(&circle_file(
                "",
                "#41=( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.STERADIAN.) );",
            ))
            .unwrap(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("plane-angle unit"), "{e}");
        let data = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));\
                    #3=CARTESIAN_POINT('',(2.,0.,0.));\
                    #4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);\
                    #7=TRIMMED_CURVE('',#4,(PARAMETER_VALUE(0.2)),(PARAMETER_VALUE(3.)),.T.,.PARAMETER.);";
        let e = contents(&parse(&wrap(data)).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("outside the domain [0, 1]"), "{e}");
    }
}
