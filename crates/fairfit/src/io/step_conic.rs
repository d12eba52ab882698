//! STEP `CIRCLE` and `ELLIPSE` ([`super::step_read`]) with their `AXIS2_PLACEMENT_3D` or
//! `AXIS2_PLACEMENT_2D`, the file's plane-angle unit, and the trims of a `TRIMMED_CURVE` (parameter
//! values and/or `CARTESIAN_POINT`s, `sense_agreement`, `master_representation`).
//!
//! ISO 10303-42: a circle is `C(t) = location + r (cos t ref_direction + sin t (axis × ref_direction))`,
//! an ellipse has `semi_axis_1` along `ref_direction` and `semi_axis_2` across; `t` is an angle in the
//! file's plane-angle unit (`SI_UNIT(.RADIAN.)`, or a `CONVERSION_BASED_UNIT` such as `'DEGREE'`
//! followed through its `PLANE_ANGLE_MEASURE_WITH_UNIT`). The placement's `axis` defaults to
//! `(0, 0, 1)`, its `ref_direction` to `(1, 0, 0)` (or `(0, 1, 0)` when the axis is x), and only the
//! part of `ref_direction` across the axis counts. The curves become exact rational quadratic
//! B-splines ([`super::cad_conic`]). A `PARABOLA` (`location + f (t² x + 2 t y)`) or `HYPERBOLA`
//! (`location + a cosh t x + b sinh t y`) is read only trimmed ([`trimmed_open_conic`]): one rational
//! quadratic Bezier between its trims.

use super::cad_conic::{arc_between, Conic};
use super::p21::{Exchange, Instance, Value};
use super::step_read::{err, point};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, Vec3};
use std::f64::consts::PI;

/// The unit vector of the `DIRECTION` `v` refers to; `None` for `$`. Shared with the trimmed `LINE`s
/// of composite curves ([`super::step_composite`]).
pub(super) fn direction(
    x: &Exchange,
    v: Option<&Value>,
    id: u64,
    inst: &Instance,
) -> Result<Option<Vec3>> {
    let Some(r) = v.and_then(Value::as_ref_id) else {
        return Ok(None);
    };
    let d = x
        .data
        .get(&r)
        .and_then(|d| d.part("DIRECTION"))
        .ok_or_else(|| err(id, inst, format!("#{r} is not a DIRECTION")))?;
    let ratios = d
        .params
        .iter()
        .rev()
        .find_map(Value::as_list)
        .ok_or_else(|| err(id, inst, format!("the DIRECTION #{r} has no ratios")))?;
    if !(2..=3).contains(&ratios.len()) {
        return Err(err(
            id,
            inst,
            format!("the DIRECTION #{r} needs 2 or 3 ratios"),
        ));
    }
    let mut c = [0.0; 3];
    for (k, v) in ratios.iter().enumerate() {
        c[k] = v.as_f64().unwrap_or(f64::NAN);
    }
    let v = Vec3(c);
    let n = v.norm();
    if !(n.is_finite() && n > 1e-12 * v.max_abs().max(f64::MIN_POSITIVE) && n > 0.0) {
        return Err(err(
            id,
            inst,
            format!("the DIRECTION #{r} is zero or not finite"),
        ));
    }
    Ok(Some(v * (1.0 / n)))
}

/// The origin and the two in-plane axes (`x` = ref_direction, `y` = axis × x) of the placement `v`.
fn placement(
    x: &Exchange,
    v: Option<&Value>,
    id: u64,
    inst: &Instance,
) -> Result<(Vec3, Vec3, Vec3)> {
    let r = v
        .and_then(Value::as_ref_id)
        .ok_or_else(|| err(id, inst, "the position is not a reference #n"))?;
    let p = x
        .data
        .get(&r)
        .ok_or_else(|| err(id, inst, format!("the position #{r} is not defined")))?;
    let (origin, z, refd) = if let Some(a) = p.part("AXIS2_PLACEMENT_3D") {
        (
            point(x, a.params.get(1).unwrap_or(&Value::Unset), r, p)?,
            direction(x, a.params.get(2), r, p)?,
            direction(x, a.params.get(3), r, p)?,
        )
    } else if let Some(a) = p.part("AXIS2_PLACEMENT_2D") {
        (
            point(x, a.params.get(1).unwrap_or(&Value::Unset), r, p)?,
            None,
            direction(x, a.params.get(2), r, p)?,
        )
    } else {
        return Err(err(
            id,
            inst,
            format!(
                "the position #{r} is a {}, not an AXIS2_PLACEMENT_3D or _2D",
                p.parts[0].name
            ),
        ));
    };
    let z = z.unwrap_or(Vec3::new(0.0, 0.0, 1.0));
    let refd = refd.unwrap_or(if z == Vec3::new(1.0, 0.0, 0.0) {
        Vec3::new(0.0, 1.0, 0.0)
    } else {
        Vec3::new(1.0, 0.0, 0.0)
    });
    let across = refd - z * refd.dot(z);
    let n = across.norm();
    if n.is_nan() || n <= 1e-9 {
        return Err(err(
            r,
            p,
            "the placement's ref_direction is parallel to its axis (degenerate)",
        ));
    }
    let xa = across * (1.0 / n);
    Ok((origin, xa, z.cross(xa)))
}

/// The `CIRCLE` or `ELLIPSE` of instance `#id`, or `None` when it is neither.
pub(super) fn conic(x: &Exchange, id: u64, inst: &Instance) -> Result<Option<Conic>> {
    let (part, a, b) = if let Some(c) = inst.part("CIRCLE") {
        let r = c.params.get(2).and_then(Value::as_f64).unwrap_or(f64::NAN);
        (c, r, r)
    } else if let Some(e) = inst.part("ELLIPSE") {
        let a = e.params.get(2).and_then(Value::as_f64).unwrap_or(f64::NAN);
        let b = e.params.get(3).and_then(Value::as_f64).unwrap_or(f64::NAN);
        (e, a, b)
    } else {
        return Ok(None);
    };
    let (origin, xa, ya) = placement(x, part.params.get(1), id, inst)?;
    Conic::new(origin, xa, ya, a, b)
        .map(Some)
        .map_err(|e| err(id, inst, format!("{}: {e}", part.name)))
}

/// Radians per unit of the plane-angle unit `#r` (depth-limited through conversion-based units).
fn radians_per(x: &Exchange, r: u64, depth: usize) -> Option<f64> {
    let inst = x.data.get(&r)?;
    if depth > 8 {
        return None;
    }
    if let Some(si) = inst.part("SI_UNIT") {
        let n = si.params.len();
        if n < 2 || !matches!(&si.params[n - 1], Value::Enum(e) if e == "RADIAN") {
            return None;
        }
        return match &si.params[n - 2] {
            Value::Enum(p) if p == "MILLI" => Some(1e-3),
            Value::Enum(p) if p == "MICRO" => Some(1e-6),
            Value::Enum(_) => None,
            _ => Some(1.0),
        };
    }
    let cb = inst.part("CONVERSION_BASED_UNIT")?;
    let name = match cb.params.first() {
        Some(Value::Str(s)) => s.to_ascii_uppercase(),
        _ => String::new(),
    };
    let factor = cb.params.get(1).and_then(Value::as_ref_id).and_then(|m| {
        let mwu = x
            .data
            .get(&m)?
            .parts
            .iter()
            .find(|p| p.name.ends_with("MEASURE_WITH_UNIT") && p.params.len() >= 2)?
            .clone();
        Some(mwu.params[0].as_f64()? * radians_per(x, mwu.params[1].as_ref_id()?, depth + 1)?)
    });
    let by_name = match name.as_str() {
        "DEGREE" | "DEGREES" | "DEG" => Some(PI / 180.0),
        "RADIAN" | "RADIANS" | "RAD" => Some(1.0),
        "GRAD" | "GON" => Some(PI / 200.0),
        _ => None,
    };
    factor.filter(|f| f.is_finite() && *f > 0.0).or(by_name)
}

/// Radians per unit of the file's plane-angle unit (the first `PLANE_ANGLE_UNIT` of a
/// `GLOBAL_UNIT_ASSIGNED_CONTEXT`); 1 when the file declares none. A declared unit fairfit does not
/// know is an error (angles would be misread).
pub(super) fn radians_per_angle_unit(x: &Exchange) -> Result<f64> {
    for inst in x.data.values() {
        let Some(units) = inst
            .part("GLOBAL_UNIT_ASSIGNED_CONTEXT")
            .and_then(|c| c.params.first())
            .and_then(Value::as_list)
        else {
            continue;
        };
        for u in units.iter().filter_map(Value::as_ref_id) {
            let Some(ui) = x
                .data
                .get(&u)
                .filter(|i| i.part("PLANE_ANGLE_UNIT").is_some())
            else {
                continue;
            };
            return radians_per(x, u, 0).ok_or_else(|| {
                err(
                    u,
                    ui,
                    "the plane-angle unit is not one fairfit knows (SI radian, or a conversion-based \
                     unit such as degree)",
                )
            });
        }
    }
    Ok(1.0)
}

/// One end of a `TRIMMED_CURVE`: its parameter value and/or its point.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Trim {
    /// The `PARAMETER_VALUE`, as written.
    pub param: Option<f64>,
    /// The `CARTESIAN_POINT`.
    pub point: Option<Vec3>,
}

/// Which end of a trim is used.
#[derive(Clone, Copy, Debug)]
pub(super) enum TrimBy {
    /// The parameter value, as written.
    Param(f64),
    /// The point.
    Point(Vec3),
}

impl Trim {
    /// The parameter, or the point when there is no parameter or `points_first` and a point.
    pub fn by(&self, points_first: bool) -> TrimBy {
        match (self.param, self.point) {
            (_, Some(p)) if points_first => TrimBy::Point(p),
            (Some(u), _) => TrimBy::Param(u),
            (None, Some(p)) => TrimBy::Point(p),
            (None, None) => TrimBy::Param(f64::NAN),
        }
    }
}

/// The trim select list `v` (`(#5, PARAMETER_VALUE(0.2))`).
pub(super) fn trim(x: &Exchange, v: Option<&Value>, id: u64, inst: &Instance) -> Result<Trim> {
    let mut t = Trim::default();
    for item in v.and_then(Value::as_list).unwrap_or(&[]) {
        match item {
            Value::Typed(name, inner) if name == "PARAMETER_VALUE" => {
                let u = inner.as_f64().filter(|u| u.is_finite()).ok_or_else(|| {
                    err(id, inst, "a PARAMETER_VALUE trim is not a finite number")
                })?;
                t.param = Some(u);
            }
            Value::Ref(_) => t.point = Some(point(x, item, id, inst)?),
            _ => {}
        }
    }
    if t.param.is_none() && t.point.is_none() {
        return Err(err(
            id,
            inst,
            "a trim of the TRIMMED_CURVE is neither a PARAMETER_VALUE nor a CARTESIAN_POINT",
        ));
    }
    Ok(t)
}

/// True when the `TRIMMED_CURVE`'s `master_representation` is `.CARTESIAN.` (points win over
/// parameters when both are given; otherwise parameters do).
pub(super) fn points_are_master(v: Option<&Value>) -> bool {
    matches!(v, Some(Value::Enum(e)) if e == "CARTESIAN")
}

/// A `TRIMMED_CURVE` `#id` of the conic `c`: the arc between its trims (angles in the file's unit,
/// `rad` radians each, or the angles of the trimming points), in the sense `forward`; the curve and
/// its kind (`circular arc`, `circle`, ...).
pub(super) fn trimmed_conic(
    c: &Conic,
    ends: [Trim; 2],
    forward: bool,
    points_first: bool,
    rad: f64,
    id: u64,
    inst: &Instance,
) -> Result<(NurbsCurve, &'static str)> {
    let size = c.a.max(c.b);
    let mut t = [0.0; 2];
    for (k, e) in ends.iter().enumerate() {
        t[k] = match e.by(points_first) {
            TrimBy::Param(u) => u * rad,
            TrimBy::Point(p) => {
                let (a, d) = c.angle_of(p);
                on_conic(k, d, size, c.kind(true), id, inst)?;
                a
            }
        };
    }
    let (curve, full) = arc_between(c, t[0], t[1], forward).map_err(|e| err(id, inst, e))?;
    Ok((curve, c.kind(full)))
}

/// Fails unless trimming point `k` (0 or 1) lies within 1e-6 of `size` of the conic `kind` (`d` is
/// its distance from it; not a number fails too).
fn on_conic(k: usize, d: f64, size: f64, kind: &str, id: u64, inst: &Instance) -> Result<()> {
    if d.is_nan() || d > 1e-6 * size {
        return Err(err(
            id,
            inst,
            format!(
                "trimming point {} lies {d:.3e} off the {kind} (more than 1e-6 of its size)",
                k + 1
            ),
        ));
    }
    Ok(())
}

/// The shape of a STEP `PARABOLA` or `HYPERBOLA` in its placement's plane.
#[derive(Clone, Copy, Debug)]
enum OpenShape {
    /// `PARABOLA(focal_dist)`: `(f t², 2 f t)` (ISO 10303-42).
    Parabola(f64),
    /// `HYPERBOLA(semi_axis, semi_imag_axis)`: `(a cosh t, b sinh t)`.
    Hyperbola(f64, f64),
}

/// A STEP `PARABOLA` or `HYPERBOLA`: unbounded, so read only as the basis of a `TRIMMED_CURVE`, whose
/// arc becomes one exact rational quadratic Bezier ([`super::cad_conic::bezier_arc`] in the
/// placement's plane, its control points then placed in 3D: an affine map, exact for a rational curve).
#[derive(Clone, Copy, Debug)]
pub(super) struct OpenConic {
    origin: Vec3,
    x: Vec3,
    y: Vec3,
    shape: OpenShape,
}

impl OpenConic {
    /// The point at the ISO parameter `t`, in the placement's plane coordinates.
    fn local(&self, t: f64) -> (f64, f64) {
        match self.shape {
            OpenShape::Parabola(f) => (f * t * t, 2.0 * f * t),
            OpenShape::Hyperbola(a, b) => (a * t.cosh(), b * t.sinh()),
        }
    }

    /// The point at the ISO parameter `t`.
    pub(super) fn at(&self, t: f64) -> Vec3 {
        let (u, v) = self.local(t);
        self.origin + self.x * u + self.y * v
    }

    /// The parameter of the point of the conic nearest `p` along the placement's y (exact for a point
    /// on the conic), and the distance of `p` from the conic's point there.
    fn param_of(&self, p: Vec3) -> (f64, f64) {
        let v = (p - self.origin).dot(self.y);
        let t = match self.shape {
            OpenShape::Parabola(f) => v / (2.0 * f),
            OpenShape::Hyperbola(_, b) => (v / b).asinh(),
        };
        (t, (self.at(t) - p).norm())
    }

    /// The parameter of the point of the conic nearest `p` and the distance of `p` from it: damped
    /// Newton on `|C(t) - p|²` from [`Self::param_of`]'s parameter (which can be off by far more than
    /// the distance where the conic runs nearly along its x axis).
    pub(super) fn nearest(&self, p: Vec3) -> (f64, f64) {
        let d = p - self.origin;
        let (qu, qv) = (d.dot(self.x), d.dot(self.y));
        // the squared distance in the plane, its first and second derivatives in t
        let phi = |t: f64| {
            let (u, v) = self.local(t);
            let (du, dv, ddu, ddv) = match self.shape {
                OpenShape::Parabola(f) => (2.0 * f * t, 2.0 * f, 2.0 * f, 0.0),
                OpenShape::Hyperbola(a, b) => (a * t.sinh(), b * t.cosh(), u, v),
            };
            let (eu, ev) = (u - qu, v - qv);
            let g = eu * du + ev * dv;
            let h = du * du + dv * dv + eu * ddu + ev * ddv;
            (eu * eu + ev * ev, g, h, du * du + dv * dv)
        };
        let (mut t, _) = self.param_of(p);
        for _ in 0..100 {
            let (f0, g, h, speed2) = phi(t);
            if !(f0.is_finite() && g.is_finite()) || g == 0.0 {
                break;
            }
            let mut step = -g / if h > 0.0 { h } else { speed2 };
            // halved until the distance does not grow (a NaN counts as growing)
            let grows = |x: f64| x.is_nan() || x > f0;
            while step.abs() > 1e-300 && grows(phi(t + step).0) {
                step *= 0.5;
            }
            if step.is_nan() || step.abs() <= 1e-16 * t.abs().max(1.0) {
                break;
            }
            t += step;
        }
        let (t_y, d_y) = self.param_of(p);
        let d = (self.at(t) - p).norm();
        if d <= d_y {
            (t, d)
        } else {
            (t_y, d_y)
        }
    }

    /// The size of an arc of the conic reaching the points `ps`: the conic's own size or the largest
    /// distance of a point from its placement's origin, whichever is larger.
    pub(super) fn size_with(&self, ps: &[Vec3]) -> f64 {
        ps.iter()
            .fold(self.size(), |s, &p| s.max((p - self.origin).norm()))
    }

    fn implicit(&self) -> super::cad_conic::Implicit {
        match self.shape {
            // y² = 4 f x
            OpenShape::Parabola(f) => [0.0, 0.0, 1.0, -4.0 * f, 0.0, 0.0],
            // x² / a² - y² / b² = 1
            OpenShape::Hyperbola(a, b) => [1.0 / (a * a), 0.0, -1.0 / (b * b), 0.0, 0.0, -1.0],
        }
    }

    fn size(&self) -> f64 {
        match self.shape {
            OpenShape::Parabola(f) => f,
            OpenShape::Hyperbola(a, b) => a.max(b),
        }
    }

    fn kind(&self) -> &'static str {
        match self.shape {
            OpenShape::Parabola(_) => "parabolic arc",
            OpenShape::Hyperbola(..) => "hyperbolic arc",
        }
    }
}

/// The `PARABOLA` or `HYPERBOLA` of instance `#id`, or `None` when it is neither.
pub(super) fn open_conic(x: &Exchange, id: u64, inst: &Instance) -> Result<Option<OpenConic>> {
    let num = |part: &super::p21::Part, k: usize| {
        part.params
            .get(k)
            .and_then(Value::as_f64)
            .unwrap_or(f64::NAN)
    };
    let (part, shape) = if let Some(p) = inst.part("PARABOLA") {
        (p, OpenShape::Parabola(num(p, 2)))
    } else if let Some(h) = inst.part("HYPERBOLA") {
        (h, OpenShape::Hyperbola(num(h, 2), num(h, 3)))
    } else {
        return Ok(None);
    };
    let good = |v: f64| v.is_finite() && v > 0.0;
    let ok = match shape {
        OpenShape::Parabola(f) => good(f),
        OpenShape::Hyperbola(a, b) => good(a) && good(b),
    };
    if !ok {
        return Err(err(
            id,
            inst,
            format!(
                "{}: the focal distance or a semi-axis is not a finite positive length",
                part.name
            ),
        ));
    }
    let (origin, xa, ya) = placement(x, part.params.get(1), id, inst)?;
    Ok(Some(OpenConic {
        origin,
        x: xa,
        y: ya,
        shape,
    }))
}

/// A `TRIMMED_CURVE` `#id` of the parabola or hyperbola `c`: the arc from its first trim to its second
/// (ISO parameters as written, no angle unit; or the parameters of the trimming points, also when a
/// trim's parameter does not give its point), and its kind. The
/// arc between two points of an open conic is one, so the sense only says which way the trims are
/// ordered along it.
pub(super) fn trimmed_open_conic(
    c: &OpenConic,
    ends: [Trim; 2],
    points_first: bool,
    id: u64,
    inst: &Instance,
) -> Result<(NurbsCurve, &'static str)> {
    let mut t = [0.0; 2];
    for (k, e) in ends.iter().enumerate() {
        // a parameter whose point is not the trimming point given with it: the point wins (OpenCASCADE
        // writes a parabola's own parameter, 2 f t, as the PARAMETER_VALUE)
        let by = match (e.by(points_first), e.point) {
            (TrimBy::Param(u), Some(p))
                if (c.at(u) - p).norm() > 1e-6 * c.size().max(p.max_abs()) =>
            {
                TrimBy::Point(p)
            }
            (by, _) => by,
        };
        t[k] = match by {
            TrimBy::Param(u) => u,
            TrimBy::Point(p) => {
                let (u, d) = c.param_of(p);
                on_conic(k, d, c.size().max(p.max_abs()), c.kind(), id, inst)?;
                u
            }
        };
    }
    let bad = |why: String| err(id, inst, format!("the {}: {why}", c.kind()));
    if !(t[0].is_finite() && t[1].is_finite()) || t[0] == t[1] {
        return Err(bad(format!("the trims {} and {} give no arc", t[0], t[1])));
    }
    let (p0, p2) = (c.local(t[0]), c.local(t[1]));
    let local =
        super::cad_conic::bezier_arc(&c.implicit(), p0, p2, 0.0).map_err(|e| bad(e.to_string()))?;
    let pts: Vec<Vec3> = local
        .control_points()
        .iter()
        .map(|q| c.origin + c.x * q.x() + c.y * q.y())
        .collect();
    let curve = NurbsCurve::new(
        2,
        local.knots().to_vec(),
        pts,
        Some(local.weights().to_vec()),
    )
    .map_err(|e| bad(e.to_string()))?;
    Ok((curve, c.kind()))
}
