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
//! beside every face) are skipped. A `TRIMMED_CURVE` of a B-spline with `PARAMETER_VALUE` trims gives the
//! B-spline cut there exactly (an edge's sub-range given only by its vertices is not cut). The length unit is the one of the file's
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
    "CIRCLE",
    "ELLIPSE",
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

fn err(inst_id: u64, inst: &Instance, msg: impl std::fmt::Display) -> Error {
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

/// The parameter of a trimming select list (`(#5, PARAMETER_VALUE(0.2))`), if it has one.
pub(super) fn trim_parameter(v: Option<&Value>) -> Option<f64> {
    v?.as_list()?.iter().find_map(|t| match t {
        Value::Typed(name, inner) if name == "PARAMETER_VALUE" => inner.as_f64(),
        _ => None,
    })
}

/// A `TRIMMED_CURVE` of a B-spline curve trimmed by parameters: the basis curve cut exactly at them
/// (reversed for sense `.F.`), or `None` for other trimmed curves (the basis is then read uncut).
pub(super) fn trimmed_curve(
    x: &Exchange,
    id: u64,
    inst: &Instance,
) -> Result<Option<(u64, NurbsCurve)>> {
    let Some(t) = inst.part("TRIMMED_CURVE") else {
        return Ok(None);
    };
    let Some(basis) = t.params.get(1).and_then(Value::as_ref_id) else {
        return Ok(None);
    };
    let Some(b) = x.data.get(&basis) else {
        return Ok(None);
    };
    let (Some(t1), Some(t2)) = (
        trim_parameter(t.params.get(2)),
        trim_parameter(t.params.get(3)),
    ) else {
        return Ok(None);
    };
    let Some(c) = curve(x, basis, b)? else {
        return Ok(None);
    };
    let sense = !matches!(t.params.get(4), Some(Value::Enum(e)) if e == "F");
    let (lo, hi) = if sense { (t1, t2) } else { (t2, t1) };
    if lo >= hi {
        // a trim across the seam of a periodic curve: read the whole basis curve
        return Ok(None);
    }
    let c = super::cad_read::trimmed(c, lo, hi).map_err(|e| err(id, inst, e))?;
    Ok(Some((basis, if sense { c } else { c.reversed() })))
}

/// Reads every B-spline curve and surface of a parsed STEP file, in instance order, with the unit.
/// A `TRIMMED_CURVE` of a B-spline by parameter values stands for its basis curve, cut to the trim. A
/// `COMPOSITE_CURVE` of such curves ([`super::step_composite`]) stands for its segments (segments that
/// run against the chain are turned, [`super::cad_chain::orient_segments`]).
pub fn contents(x: &Exchange) -> Result<CadContents> {
    let mut out = CadContents {
        unit: length_unit(x)?,
        ..CadContents::default()
    };
    let skip = parameter_space_items(x);
    let mut composites = super::step_composite::composites(x, &skip)?;
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
            if let Some((basis, c)) = trimmed_curve(x, id, inst)? {
                trims.insert(id, (basis, c));
            }
        }
    }
    let cut: BTreeSet<u64> = trims.values().map(|(basis, _)| *basis).collect();
    for (&id, inst) in &x.data {
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
        if let Some((basis, c)) = trims.remove(&id) {
            out.curves.push((format!("#{id} (trimmed #{basis})"), c));
            continue;
        }
        if let Some(c) = curve(x, id, inst)? {
            out.curves.push((format!("#{id}"), c));
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
