//! STEP `COMPOSITE_CURVE`s ([`super::step_read`]): the segments (`COMPOSITE_CURVE_SEGMENT` and
//! `REPARAMETRISED_COMPOSITE_CURVE_SEGMENT`) in order, each parent curve a B-spline, a `CIRCLE` or an
//! `ELLIPSE` (exact rational quadratics), a `TRIMMED_CURVE` of any of these (by parameters or points,
//! `step_read::trimmed_curve`), a straight piece (a trimmed `LINE` or a `POLYLINE`, as a
//! B-spline of degree 1), or a nested composite, reversed where `same_sense` is `.F.`. A
//! `REPARAMETRISED_COMPOSITE_CURVE_SEGMENT` spans its `param_length` of the composite's parameter
//! (ISO 10303-42): its parent's parameter range is stretched linearly to that length (the same curve,
//! knots mapped affinely); a `param_length` that is not a positive number is refused.
//! Composite curves on surfaces and boundary curves (subtypes that bound a face in its parameter space
//! or on it) are not read; a composite with any other segment (an untrimmed `LINE`, a `PARABOLA`, ...)
//! is named in the "found:" list of errors instead.
//!
//! A trimmed `LINE` reads its `DIRECTION` and its trims with the conics' code ([`super::step_conic`]):
//! 2 or 3 ratios, not zero; trims by `PARAMETER_VALUE` (finite) and/or `CARTESIAN_POINT`, the points
//! taken when `master_representation` is `.CARTESIAN.`.

use super::p21::{Exchange, Instance, Value};
use super::step_conic::conic;
use super::step_conic::{direction, points_are_master, trim, TrimBy};
use super::step_read::{curve, point, trimmed_curve};
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, Vec3};
use std::collections::{BTreeMap, BTreeSet};

/// Subtypes of `COMPOSITE_CURVE` that are not read.
const SKIPPED: &[&str] = &[
    "COMPOSITE_CURVE_ON_SURFACE",
    "BOUNDARY_CURVE",
    "OUTER_BOUNDARY_CURVE",
];

/// What a composite curve instance gives.
pub(super) enum Composite {
    /// Its segments in order, oriented along it, and every instance they came from (segments, parent
    /// curves, trimmed bases, nested composites).
    Read(Vec<NurbsCurve>, BTreeSet<u64>),
    /// It has a segment of a kind fairfit does not read (the entity's name).
    Unsupported(String),
}

fn is_composite(inst: &Instance) -> bool {
    inst.part("COMPOSITE_CURVE").is_some()
        && !inst
            .parts
            .iter()
            .any(|p| SKIPPED.contains(&p.name.as_str()))
}

fn err(id: u64, inst: &Instance, msg: impl std::fmt::Display) -> Error {
    Error::Cad(format!("line {} (#{id}): {msg}", inst.line))
}

/// A straight segment as a B-spline of degree 1: a `TRIMMED_CURVE` of a `LINE` by parameter values (or,
/// without them, by its trimming points), from the first trim to the second, or a `POLYLINE` (knots
/// 0, 1, ..., n - 1 as ISO 10303-42 parametrises it). `None` for anything else.
fn straight(x: &Exchange, id: u64, inst: &Instance) -> Result<Option<NurbsCurve>> {
    let to_curve = |pts: Vec<Vec3>| {
        let n = pts.len();
        let mut knots = vec![0.0];
        knots.extend((0..n).map(|i| i as f64));
        knots.push((n - 1) as f64);
        NurbsCurve::bspline(1, knots, pts).map_err(|e| err(id, inst, e))
    };
    if let Some(p) = inst.part("POLYLINE") {
        let refs = p
            .params
            .get(1)
            .and_then(Value::as_list)
            .ok_or_else(|| err(id, inst, "POLYLINE without points"))?;
        let pts = refs
            .iter()
            .map(|v| point(x, v, id, inst))
            .collect::<Result<Vec<_>>>()?;
        if pts.len() < 2 {
            return Err(err(id, inst, "a POLYLINE needs at least 2 points"));
        }
        return to_curve(pts).map(Some);
    }
    let Some(t) = inst.part("TRIMMED_CURVE") else {
        return Ok(None);
    };
    let Some(line) = t
        .params
        .get(1)
        .and_then(Value::as_ref_id)
        .and_then(|b| x.data.get(&b))
        .and_then(|b| b.part("LINE"))
    else {
        return Ok(None);
    };
    let origin = point(x, line.params.get(1).unwrap_or(&Value::Unset), id, inst)?;
    let no_vector = || {
        err(
            id,
            inst,
            "the LINE has no VECTOR with a DIRECTION and a magnitude",
        )
    };
    let vector = line
        .params
        .get(2)
        .and_then(Value::as_ref_id)
        .and_then(|v| x.data.get(&v))
        .and_then(|v| v.part("VECTOR"))
        .ok_or_else(no_vector)?;
    let magnitude = vector
        .params
        .get(2)
        .and_then(Value::as_f64)
        .filter(|m| m.is_finite())
        .ok_or_else(no_vector)?;
    // the DIRECTION as a circle's placement reads it: 2 or 3 ratios, not zero, normalised
    let dir = direction(x, vector.params.get(1), id, inst)?.ok_or_else(no_vector)? * magnitude;
    // the trims as a conic's: parameters and/or points, `.CARTESIAN.` preferring the points
    let points_first = points_are_master(t.params.get(5));
    let end = |v: Option<&Value>| -> Result<Vec3> {
        Ok(match trim(x, v, id, inst)?.by(points_first) {
            TrimBy::Param(u) => origin + dir * u,
            TrimBy::Point(p) => p,
        })
    };
    let (a, b) = (end(t.params.get(2))?, end(t.params.get(3))?);
    to_curve(vec![a, b]).map(Some)
}

/// `c` with its parameter range stretched by `factor` from its start (knots `a + (k - a) factor`): the
/// same curve, linearly reparametrised.
fn stretched(c: &NurbsCurve, factor: f64) -> Result<NurbsCurve> {
    let a = c.domain().0;
    let knots = c.knots().iter().map(|&k| a + (k - a) * factor).collect();
    let w = c.is_rational().then(|| c.weights().to_vec());
    NurbsCurve::new(c.degree(), knots, c.control_points().to_vec(), w)
}

/// Reads the composite `#id` (depth-limited for nested composites).
fn composite(x: &Exchange, id: u64, inst: &Instance, depth: usize, rad: f64) -> Result<Composite> {
    if depth > 8 {
        return Err(err(id, inst, "composite curves nested more than 8 deep"));
    }
    let Some(refs) = inst
        .part("COMPOSITE_CURVE")
        .and_then(|c| c.params.get(1))
        .and_then(Value::as_list)
    else {
        return Err(err(id, inst, "COMPOSITE_CURVE without a list of segments"));
    };
    let mut segments = Vec::new();
    let mut members = BTreeSet::new();
    for r in refs {
        let sid = r
            .as_ref_id()
            .ok_or_else(|| err(id, inst, "a segment is not a reference #n"))?;
        let sinst = x
            .data
            .get(&sid)
            .ok_or_else(|| err(id, inst, format!("segment #{sid} is not defined")))?;
        let seg = sinst
            .part("COMPOSITE_CURVE_SEGMENT")
            .or_else(|| sinst.part("REPARAMETRISED_COMPOSITE_CURVE_SEGMENT"))
            .ok_or_else(|| {
                err(
                    id,
                    inst,
                    format!("#{sid} is a {}, not a segment", sinst.parts[0].name),
                )
            })?;
        let same_sense = !matches!(seg.params.get(1), Some(Value::Enum(e)) if e == "F");
        let pid = seg
            .params
            .get(2)
            .and_then(Value::as_ref_id)
            .ok_or_else(|| err(sid, sinst, "the parent curve is not a reference #n"))?;
        let pinst = x
            .data
            .get(&pid)
            .ok_or_else(|| err(sid, sinst, format!("parent curve #{pid} is not defined")))?;
        members.extend([sid, pid]);
        let mut part: Vec<NurbsCurve> = if let Some(t) = trimmed_curve(x, pid, pinst, rad)? {
            members.insert(t.basis);
            vec![t.curve]
        } else if let Some(c) = curve(x, pid, pinst)? {
            vec![c]
        } else if let Some(c) = conic(x, pid, pinst)? {
            vec![c.full(0.0).map_err(|e| err(pid, pinst, e))?]
        } else if let Some(c) = straight(x, pid, pinst)? {
            vec![c]
        } else if is_composite(pinst) {
            match composite(x, pid, pinst, depth + 1, rad)? {
                Composite::Read(s, m) => {
                    members.extend(m);
                    s
                }
                unsupported => return Ok(unsupported),
            }
        } else {
            let name = match pinst.part("TRIMMED_CURVE") {
                Some(t) => {
                    let basis = t.params.get(1).and_then(Value::as_ref_id);
                    let b = basis.and_then(|b| x.data.get(&b));
                    format!(
                        "a TRIMMED_CURVE of a {}",
                        b.map_or("curve", |b| b.parts[0].name.as_str())
                    )
                }
                None => format!("a {}", pinst.parts[0].name),
            };
            return Ok(Composite::Unsupported(format!(
                "COMPOSITE_CURVE (with {name} segment)"
            )));
        };
        if !same_sense {
            part.reverse();
            for c in &mut part {
                *c = c.reversed();
            }
        }
        if let Some(r) = sinst.part("REPARAMETRISED_COMPOSITE_CURVE_SEGMENT") {
            let length = r.params.get(3).and_then(Value::as_f64);
            let Some(length) = length.filter(|l| l.is_finite() && *l > 0.0) else {
                return Err(err(
                    sid,
                    sinst,
                    "the param_length of a REPARAMETRISED_COMPOSITE_CURVE_SEGMENT must be a \
                     positive number",
                ));
            };
            let own: f64 = part.iter().map(|c| c.domain().1 - c.domain().0).sum();
            let factor = length / own;
            if !(factor.is_finite() && factor > 0.0) {
                return Err(err(
                    sid,
                    sinst,
                    format!("cannot give the parent #{pid} the param_length {length}"),
                ));
            }
            for c in &mut part {
                *c = stretched(c, factor).map_err(|e| err(sid, sinst, e))?;
            }
        }
        segments.extend(part);
    }
    if segments.is_empty() {
        return Err(err(id, inst, "COMPOSITE_CURVE without segments"));
    }
    Ok(Composite::Read(segments, members))
}

/// Every composite curve of the file that is not in `skip` (parameter-space items) and not itself a
/// segment's parent of another composite, by instance id.
pub(super) fn composites(
    x: &Exchange,
    skip: &BTreeSet<u64>,
    rad: f64,
) -> Result<BTreeMap<u64, Composite>> {
    let mut out = BTreeMap::new();
    let mut nested = BTreeSet::new();
    for (&id, inst) in &x.data {
        if skip.contains(&id) || !is_composite(inst) {
            continue;
        }
        let c = composite(x, id, inst, 0, rad)?;
        if let Composite::Read(_, m) = &c {
            nested.extend(m.iter().copied());
        }
        out.insert(id, c);
    }
    out.retain(|id, _| !nested.contains(id));
    Ok(out)
}
