//! Circles and ellipses of CAD files (STEP `CIRCLE` / `ELLIPSE`, IGES 100 / 104) as exact rational
//! quadratic B-splines, so that everything downstream (evaluation, plots, export, sampling for
//! `fairfit curve`) sees the exact geometry.
//!
//! A conic here is `C(t) = centre + a cos(t) X + b sin(t) Y` with orthonormal `X`, `Y` (a circle has
//! `a = b = r`); `t` is the angle in radians, as ISO 10303-42 parametrises `CIRCLE` and `ELLIPSE`. An
//! arc `t0 <= t <= t1` is the unit-circle arc of [`NurbsCurve::arc`] (NURBS Book A7.1: pieces of at
//! most 90 degrees, middle weights `cos(half the piece's angle)`) mapped by the affine map
//! `(x, y) -> centre + a x X + b y Y`: rational B-splines are invariant under affine maps, so the
//! result is the conic exactly (to rounding). Its domain is `[t0, t1]`, the knots between pieces at
//! their angles, so the B-spline parameter equals the angle at every knot.

use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, Vec3};
use std::f64::consts::TAU;

/// A circle or an ellipse in space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Conic {
    /// The centre.
    pub centre: Vec3,
    /// Unit vector towards angle 0 (the first semi-axis).
    pub x: Vec3,
    /// Unit vector towards angle 90 degrees, orthogonal to `x`.
    pub y: Vec3,
    /// Semi-axis along `x` (the radius of a circle).
    pub a: f64,
    /// Semi-axis along `y` (the radius of a circle).
    pub b: f64,
}

impl Conic {
    /// A conic after checking its data: finite positive semi-axes, finite centre, `x` and `y` unit
    /// and orthogonal (to 1e-9). Errors are one line.
    pub fn new(centre: Vec3, x: Vec3, y: Vec3, a: f64, b: f64) -> Result<Conic> {
        for (what, r) in [("radius / semi-axis", a), ("radius / semi-axis", b)] {
            if !(r.is_finite() && r > 0.0) {
                return Err(Error::Cad(format!(
                    "the {what} {r} is not a finite positive length"
                )));
            }
        }
        if !centre.is_finite() {
            return Err(Error::Cad("the centre is not finite".into()));
        }
        let unit = |v: Vec3| v.is_finite() && (v.norm() - 1.0).abs() < 1e-9;
        if !(unit(x) && unit(y) && x.dot(y).abs() < 1e-9) {
            return Err(Error::Cad(
                "the axes are degenerate (not two orthogonal unit directions)".into(),
            ));
        }
        Ok(Conic { centre, x, y, a, b })
    }

    /// True for a circle (`a == b`).
    pub fn is_circle(&self) -> bool {
        self.a == self.b
    }

    /// What an arc of it is called: `circle`, `circular arc`, `ellipse`, `elliptical arc`.
    pub fn kind(&self, full: bool) -> &'static str {
        match (self.is_circle(), full) {
            (true, true) => "circle",
            (true, false) => "circular arc",
            (false, true) => "ellipse",
            (false, false) => "elliptical arc",
        }
    }

    /// The point at angle `t` (radians).
    pub fn at(&self, t: f64) -> Vec3 {
        self.centre + self.x * (self.a * t.cos()) + self.y * (self.b * t.sin())
    }

    /// The angle in `(-π, π]` of the point of the conic nearest in angle to `p` (the angle of `p`
    /// projected into the conic's plane and scaled to the unit circle), and the distance from `p` to
    /// the conic's point at that angle.
    pub fn angle_of(&self, p: Vec3) -> (f64, f64) {
        let d = p - self.centre;
        let t = (d.dot(self.y) / self.b).atan2(d.dot(self.x) / self.a);
        (t, (self.at(t) - p).norm())
    }

    /// The arc from angle `t0` to `t1` (radians, `0 < t1 - t0 <= 2π`) as a rational quadratic
    /// B-spline on `[t0, t1]` (see the module documentation).
    pub fn arc(&self, t0: f64, t1: f64) -> Result<NurbsCurve> {
        let span = t1 - t0;
        if !(t0.is_finite() && span.is_finite() && span > 0.0 && span <= TAU * (1.0 + 1e-12)) {
            return Err(Error::Cad(format!(
                "the arc from angle {t0} to {t1} (radians) is empty or more than a full turn"
            )));
        }
        let unit = NurbsCurve::arc(Vec3::ZERO, 1.0, t0, t0 + span.min(TAU))
            .map_err(|e| Error::Cad(e.to_string()))?;
        let pts: Vec<Vec3> = unit
            .control_points()
            .iter()
            .map(|q| self.centre + self.x * (self.a * q[0]) + self.y * (self.b * q[1]))
            .collect();
        let n = unit.knots().len();
        let knots: Vec<f64> = unit
            .knots()
            .iter()
            .enumerate()
            .map(|(i, &k)| match i {
                _ if i < 3 => t0,
                _ if i >= n - 3 => t1,
                _ => t0 + span * k,
            })
            .collect();
        NurbsCurve::new(2, knots, pts, Some(unit.weights().to_vec()))
    }

    /// The whole conic, from angle `start` once round counter-clockwise (about `x × y`).
    pub fn full(&self, start: f64) -> Result<NurbsCurve> {
        self.arc(start, start + TAU)
    }
}

/// The arc of a conic between two angles (radians): counter-clockwise from `t0` to `t1` when
/// `forward`, else clockwise from `t0` to `t1` (the counter-clockwise arc from `t1` to `t0`, reversed);
/// `t1` is moved by whole turns to lie within one turn of `t0` in that direction, and equal angles
/// (to 1e-12 of a turn) give the full conic. Returns the curve and whether it is the full conic.
pub(crate) fn arc_between(
    c: &Conic,
    t0: f64,
    t1: f64,
    forward: bool,
) -> Result<(NurbsCurve, bool)> {
    if !(t0.is_finite() && t1.is_finite()) || t0.abs() > 1e6 || t1.abs() > 1e6 {
        return Err(Error::Cad(format!(
            "the trim angles {t0:e}, {t1:e} (radians) are not usable angles"
        )));
    }
    let (lo, hi) = if forward { (t0, t1) } else { (t1, t0) };
    let mut d = (hi - lo).rem_euclid(TAU);
    let full = d < 1e-12 * TAU || TAU - d < 1e-12 * TAU;
    if full {
        d = TAU;
    }
    let arc = c.arc(lo, lo + d)?;
    let arc = if forward { arc } else { arc.reversed() };
    Ok((arc, full))
}

/// The conic `A x² + B xy + C y² + D x + E y + F = 0` of a plane (coefficients in that order).
pub(crate) type Implicit = [f64; 6];

fn implicit_value(q: &Implicit, x: f64, y: f64) -> f64 {
    q[0] * x * x + q[1] * x * y + q[2] * y * y + q[3] * x + q[4] * y + q[5]
}

fn implicit_gradient(q: &Implicit, x: f64, y: f64) -> (f64, f64) {
    (
        2.0 * q[0] * x + q[1] * y + q[3],
        q[1] * x + 2.0 * q[2] * y + q[4],
    )
}

/// `p` moved onto the conic `q` by Newton steps in x (y kept), or along the gradient where the conic
/// runs nearly along x there; `p` itself when that does not converge.
fn onto(q: &Implicit, p: (f64, f64)) -> (f64, f64) {
    let mut r = p;
    for _ in 0..8 {
        let f = implicit_value(q, r.0, r.1);
        let g = implicit_gradient(q, r.0, r.1);
        let gn2 = g.0 * g.0 + g.1 * g.1;
        if f == 0.0 || gn2 == 0.0 {
            break;
        }
        r = if g.0 * g.0 >= 1e-6 * gn2 {
            (r.0 - f / g.0, r.1)
        } else {
            (r.0 - f * g.0 / gn2, r.1 - f * g.1 / gn2)
        };
    }
    let moved = (r.0 - p.0).hypot(r.1 - p.1);
    if moved.is_finite() && moved <= 1e-6 * p.0.hypot(p.1).max(1.0) {
        r
    } else {
        p
    }
}

/// The arc of the plane conic `q` from `p0` to `p2` (both on it) as one rational quadratic Bezier
/// curve on `[0, 1]`, in the plane `z = z`: the middle control point is where the tangents at the ends
/// meet, and the middle weight `w = s / (1 - s)` puts the curve's midpoint on the conic where the median
/// from the chord's midpoint `M` towards that point crosses it (`M + s (P1 - M)`). Two points, their
/// tangents and a fifth point fix a conic, so this is the conic exactly. The ends are first moved onto
/// the conic (their y kept) to undo the rounding of the file. For arcs that turn by less
/// than 180 degrees: every parabola arc, every arc on one branch of a hyperbola (and ellipse arcs under
/// half a turn). Errors (one line) for ends off the conic (more than 1e-6 of the arc's size), ends
/// whose tangents do not meet, and a median that does not cross the conic between them (ends on two
/// branches).
pub fn bezier_arc(q: &Implicit, p0: (f64, f64), p2: (f64, f64), z: f64) -> Result<NurbsCurve> {
    let size = (p2.0 - p0.0).hypot(p2.1 - p0.1);
    if !(size.is_finite() && size > 0.0) || q.iter().any(|c| !c.is_finite()) {
        return Err(Error::Cad(
            "the conic arc's ends coincide or its data are not finite".into(),
        ));
    }
    for (name, p) in [("start", p0), ("end", p2)] {
        let g = implicit_gradient(q, p.0, p.1);
        let gn = g.0.hypot(g.1);
        let d = implicit_value(q, p.0, p.1).abs() / gn;
        if d.is_nan() || gn == 0.0 || d > 1e-6 * size {
            return Err(Error::Cad(format!(
                "the {name} point ({}, {}) is not on the conic",
                p.0, p.1
            )));
        }
    }
    // the ends as written (to 10 digits or so) lie off the conic by rounding: move each onto it
    // keeping its y (as OpenCASCADE does for a conic in standard position: its parameter comes from y)
    let (p0, p2) = (onto(q, p0), onto(q, p2));
    let (g0, g2) = (
        implicit_gradient(q, p0.0, p0.1),
        implicit_gradient(q, p2.0, p2.1),
    );
    let (t0, t2) = ((-g0.1, g0.0), (-g2.1, g2.0));
    let det = t0.0 * (-t2.1) - t0.1 * (-t2.0);
    let scale = t0.0.hypot(t0.1) * t2.0.hypot(t2.1);
    if det.is_nan() || det.abs() <= 1e-12 * scale {
        return Err(Error::Cad(
            "the tangents at the conic arc's ends are parallel: the arc turns by half a turn or more"
                .into(),
        ));
    }
    // p0 + a t0 = p2 + b t2
    let (rx, ry) = (p2.0 - p0.0, p2.1 - p0.1);
    let a = (rx * (-t2.1) - ry * (-t2.0)) / det;
    let p1 = (p0.0 + a * t0.0, p0.1 + a * t0.1);
    let m = (0.5 * (p0.0 + p2.0), 0.5 * (p0.1 + p2.1));
    let d = (p1.0 - m.0, p1.1 - m.1);
    // f(M + s d) = alpha s² + beta s + gamma
    let alpha = q[0] * d.0 * d.0 + q[1] * d.0 * d.1 + q[2] * d.1 * d.1;
    let gm = implicit_gradient(q, m.0, m.1);
    let beta = gm.0 * d.0 + gm.1 * d.1;
    let gamma = implicit_value(q, m.0, m.1);
    let roots: Vec<f64> = if alpha.abs() <= 1e-14 * (beta.abs() + gamma.abs()) {
        vec![-gamma / beta]
    } else {
        let disc = beta * beta - 4.0 * alpha * gamma;
        if disc < 0.0 {
            Vec::new()
        } else {
            // the numerically stable pair of roots
            let k = -0.5 * (beta + beta.signum() * disc.sqrt());
            vec![k / alpha, gamma / k]
        }
    };
    let s = roots
        .into_iter()
        .filter(|s| *s > 0.0 && *s < 1.0)
        .min_by(|a, b| (a - 0.5).abs().total_cmp(&(b - 0.5).abs()))
        .ok_or_else(|| {
            Error::Cad(
                "the conic does not run between the arc's ends on one branch (no point on the median)"
                    .into(),
            )
        })?;
    let w = s / (1.0 - s);
    let pt = |p: (f64, f64)| Vec3::new(p.0, p.1, z);
    NurbsCurve::new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![pt(p0), pt(p1), pt(p2)],
        Some(vec![1.0, w, 1.0]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn tilted() -> Conic {
        let n = Vec3::new(1.0, 2.0, 2.0) * (1.0 / 3.0);
        let x = Vec3::new(2.0, -1.0, 0.0) * (1.0 / 5f64.sqrt());
        Conic::new(Vec3::new(1.0, -2.0, 3.0), x, n.cross(x), 4.0, 4.0).unwrap()
    }

    #[test]
    fn arcs_lie_on_the_circle_and_start_and_end_at_the_angles() {
        let c = tilted();
        for (t0, t1) in [(0.3, 2.0), (-1.0, 5.0), (0.0, TAU), (2.0, 2.0 + 1e-3)] {
            let arc = c.arc(t0, t1).unwrap();
            assert_eq!(arc.domain(), (t0, t1));
            assert!((arc.point(t0) - c.at(t0)).norm() < 1e-14);
            assert!((arc.point(t1) - c.at(t1)).norm() < 1e-14);
            for i in 0..=1000 {
                let u = t0 + (t1 - t0) * i as f64 / 1000.0;
                let p = arc.point(u);
                assert!(((p - c.centre).norm() - 4.0).abs() < 1e-14 * 4.0, "{u}");
                // in the plane
                assert!((p - c.centre).dot(c.x.cross(c.y)).abs() < 1e-14 * 4.0);
            }
        }
        assert!(Conic::new(Vec3::ZERO, c.x, c.y, 0.0, 1.0).is_err());
        assert!(Conic::new(Vec3::ZERO, c.x, c.x, 1.0, 1.0).is_err());
        assert!(Conic::new(Vec3::ZERO, c.x, c.y, f64::NAN, 1.0).is_err());
        assert!(c.arc(1.0, 1.0).is_err());
        assert!(c.arc(0.0, 7.0).is_err());
    }

    #[test]
    fn ellipse_points_satisfy_the_implicit_equation() {
        let e = Conic::new(
            Vec3::ZERO,
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            5.0,
            2.0,
        )
        .unwrap();
        let arc = e.arc(-0.5, 4.0).unwrap();
        for i in 0..=1000 {
            let p = arc.point(-0.5 + 4.5 * i as f64 / 1000.0);
            let (u, v) = (p.dot(e.x) / 5.0, p.dot(e.y) / 2.0);
            assert!((u * u + v * v - 1.0).abs() < 1e-14);
        }
        let (t, d) = e.angle_of(Vec3::new(0.0, -5.0, 0.0));
        assert!((t.abs() - PI).abs() < 1e-15 && d < 1e-15);
    }

    #[test]
    fn parabola_and_hyperbola_arcs_are_exact() {
        // y = x²: -x² + y = 0, from (-1, 1) to (2, 4)
        let par = bezier_arc(
            &[-1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            (-1.0, 1.0),
            (2.0, 4.0),
            3.0,
        )
        .unwrap();
        assert!(
            (par.weights()[1] - 1.0).abs() < 1e-15,
            "{:?}",
            par.weights()
        );
        // x y = 1 (B = 1, F = -1), from (0.5, 2) to (4, 0.25)
        let hyp = bezier_arc(
            &[0.0, 1.0, 0.0, 0.0, 0.0, -1.0],
            (0.5, 2.0),
            (4.0, 0.25),
            0.0,
        )
        .unwrap();
        assert!(hyp.weights()[1] > 1.0);
        let mut xs = Vec::new();
        for i in 0..=1000 {
            let u = i as f64 / 1000.0;
            let p = par.point(u);
            assert!((p[1] - p[0] * p[0]).abs() < 1e-14 * 4.0, "{p:?}");
            assert!((p[2] - 3.0).abs() < 1e-15 * 3.0, "{p:?}");
            let h = hyp.point(u);
            assert!((h[0] * h[1] - 1.0).abs() < 1e-14, "{h:?}");
            xs.push(h[0]);
        }
        // the hyperbola arc runs monotonically from the start to the end
        assert!(xs.windows(2).all(|w| w[1] > w[0]));
        assert!((par.point(0.0) - Vec3::new(-1.0, 1.0, 3.0)).norm() < 1e-15);
        assert!((par.point(1.0) - Vec3::new(2.0, 4.0, 3.0)).norm() < 1e-15);
        // ends off the conic, on two branches, or with parallel tangents
        let hq = [0.0, 1.0, 0.0, 0.0, 0.0, -1.0];
        assert!(bezier_arc(&hq, (0.5, 2.5), (4.0, 0.25), 0.0).is_err());
        assert!(bezier_arc(&hq, (-1.0, -1.0), (1.0, 1.0), 0.0).is_err());
        let circle = [1.0, 0.0, 1.0, 0.0, 0.0, -1.0];
        assert!(bezier_arc(&circle, (1.0, 0.0), (-1.0, 0.0), 0.0).is_err());
        assert!(bezier_arc(&hq, (1.0, 1.0), (1.0, 1.0), 0.0).is_err());
        assert!(bezier_arc(
            &[f64::NAN, 1.0, 0.0, 0.0, 0.0, -1.0],
            (1.0, 1.0),
            (2.0, 0.5),
            0.0
        )
        .is_err());
    }

    #[test]
    fn arcs_between_angles_follow_the_sense() {
        let c = tilted();
        let (a, full) = arc_between(&c, 5.0, 1.0, true).unwrap();
        assert!(!full);
        // 5 -> 1 + 2π counter-clockwise
        assert!((a.domain().1 - a.domain().0 - (TAU - 4.0)).abs() < 1e-14);
        assert!((a.point(a.domain().0) - c.at(5.0)).norm() < 1e-13);
        let (b, _) = arc_between(&c, 5.0, 1.0, false).unwrap();
        assert!((b.domain().1 - b.domain().0 - 4.0).abs() < 1e-14);
        assert!((b.point(b.domain().0) - c.at(5.0)).norm() < 1e-13);
        assert!((b.point(b.domain().1) - c.at(1.0)).norm() < 1e-13);
        let (f, full) = arc_between(&c, 1.0, 1.0 + TAU, true).unwrap();
        assert!(full && (f.domain().1 - f.domain().0 - TAU).abs() < 1e-15);
        assert!(arc_between(&c, f64::NAN, 1.0, true).is_err());
    }
}
