//! The minimum-variation (MVC) integrand at one parameter (method reconstruction §2.2): from
//! `r = C'`, `a = C''`, `b = C'''` it gives the speed `v = ds/du`, the curvature and `dκ/du`, so that
//!
//! - `(dκ/ds)² ds = (dκ/du)² / v du` (the MVC energy density per du),
//! - `κ² ds = κ² v du` (bending energy density),
//! - `ds = v du` (arc length).
//!
//! Planar curves (all control points in one plane with unit normal `n`, see [`plane_normal`]) use the
//! signed curvature `κ_s = (r × a)·n / v³`, `dκ_s/du = (r × b)·n / v³ − 3 ((r × a)·n)(r·a)/v⁵`, which is
//! smooth through inflections (for the xy plane, `n = +z`: `κ_s = (r_x a_y − r_y a_x)/v³`). Spatial curves use the unsigned
//! `dκ/du = [(c·(r×b)) v² − 3 |c|² (r·a)] / (|c| v⁵)` with `c = r × a`, guarded where `|c| → 0` by the
//! one-sided limit `d|c|/du → |r × b|`. This is the allocation-free hot-path twin of
//! [`crate::diffgeo::differentials_from`] (tests check they agree).

use crate::diffgeo::is_xy_planar;
use crate::nurbs::{NurbsCurve, Vec3};

/// `|c|` below this fraction of `v |a|` counts as zero (as in `diffgeo::curvature`).
const PARALLEL_EPS: f64 = 1e-12;

/// The MVC integrand pieces at one parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MvcPoint {
    /// Speed `|C'|`.
    pub speed: f64,
    /// Curvature: signed for planar curves, unsigned otherwise.
    pub kappa: f64,
    /// `dκ/du` of the same curvature.
    pub dkappa_du: f64,
}

impl MvcPoint {
    /// `(dκ/ds)² · ds/du`, the MVC energy density per unit parameter.
    #[inline]
    pub fn energy_density(&self) -> f64 {
        if self.speed > 0.0 {
            self.dkappa_du * self.dkappa_du / self.speed
        } else {
            0.0
        }
    }

    /// `κ² · ds/du`, the bending energy density per unit parameter.
    #[inline]
    pub fn bending_density(&self) -> f64 {
        self.kappa * self.kappa * self.speed
    }

    /// `dκ/ds`.
    #[inline]
    pub fn dkappa_ds(&self) -> f64 {
        if self.speed > 0.0 {
            self.dkappa_du / self.speed
        } else {
            0.0
        }
    }
}

/// The unit normal of the plane holding every control point of `curve` (so the whole curve), or `None`
/// for a spatial curve. Curves in a plane `z = const` get `+z` (the sign convention of
/// [`crate::diffgeo::CurveDifferentials::signed_curvature`]); other planes get the normal of the
/// control polygon's widest triangle (its orientation only flips the sign of `κ_s`). A curve whose
/// control points are collinear is a line and gets any normal of it. Tolerance: `1e-12` times the extent
/// of the control polygon, so the test is invariant under scaling and rigid motion up to rounding.
pub fn plane_normal(curve: &NurbsCurve) -> Option<Vec3> {
    if is_xy_planar(curve) {
        return Some(Vec3::new(0.0, 0.0, 1.0));
    }
    let pts = curve.control_points();
    let p0 = pts[0];
    let (far, ext2) = pts
        .iter()
        .map(|&p| (p, (p - p0).norm_squared()))
        .fold((p0, 0.0), |m, x| if x.1 > m.1 { x } else { m });
    let ext = ext2.sqrt();
    if ext.is_nan() || ext <= 0.0 {
        return Some(Vec3::new(0.0, 0.0, 1.0));
    }
    let e1 = (far - p0) / ext;
    let (best, area) = pts
        .iter()
        .map(|&p| {
            let c = e1.cross(p - p0);
            (c, c.norm())
        })
        .fold((Vec3::ZERO, 0.0), |m, x| if x.1 > m.1 { x } else { m });
    let tol = 1e-12 * ext;
    if area.is_nan() || area <= tol {
        // collinear: a line lies in every plane containing it
        let t = if e1.x().abs() < 0.9 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let n = e1.cross(t);
        return Some(n / n.norm());
    }
    let n = best / area;
    pts.iter()
        .all(|&p| (p - p0).dot(n).abs() <= tol)
        .then_some(n)
}

/// The integrand from `[C, C', C'', C''']`; `normal` is the plane normal of a planar curve (signed
/// formula) or `None` (guarded unsigned spatial formula).
/// A point of (numerically) zero speed gives all zeros.
#[inline]
pub(crate) fn mvc_point(d: &[Vec3; 4], normal: Option<Vec3>) -> MvcPoint {
    let (r, a, b) = (d[1], d[2], d[3]);
    let v2 = r.norm_squared();
    let v = v2.sqrt();
    if v.is_nan() || v <= f64::MIN_POSITIVE.sqrt() || !v.is_finite() {
        return MvcPoint::default();
    }
    let v3 = v2 * v;
    let v5 = v3 * v2;
    let ra = r.dot(a);
    if let Some(n) = normal {
        let cz = r.cross(a).dot(n);
        let bz = r.cross(b).dot(n);
        return MvcPoint {
            speed: v,
            kappa: cz / v3,
            dkappa_du: bz / v3 - 3.0 * cz * ra / v5,
        };
    }
    let c = r.cross(a);
    let cn = c.norm();
    let rxb = r.cross(b);
    let dcn = if cn <= PARALLEL_EPS * v * a.norm() || cn == 0.0 {
        rxb.norm()
    } else {
        c.dot(rxb) / cn
    };
    MvcPoint {
        speed: v,
        kappa: cn / v3,
        dkappa_du: dcn / v3 - 3.0 * cn * ra / v5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diffgeo::differentials_from;

    #[test]
    fn agrees_with_diffgeo_differentials() {
        // C(u) = (2 cos u, sin u, 0.3 u²) and its planar shadow
        for &u in &[0.1, 0.8, 2.0, 3.3] {
            let d = [
                Vec3::new(2.0 * f64::cos(u), f64::sin(u), 0.3 * u * u),
                Vec3::new(-2.0 * f64::sin(u), f64::cos(u), 0.6 * u),
                Vec3::new(-2.0 * f64::cos(u), -f64::sin(u), 0.6),
                Vec3::new(2.0 * f64::sin(u), -f64::cos(u), 0.0),
            ];
            let g = differentials_from(u, &d);
            let m = mvc_point(&d, None);
            assert!((m.kappa - g.curvature).abs() < 1e-14);
            assert!((m.dkappa_ds() - g.dkappa_ds).abs() < 1e-13);
            assert!((m.speed - g.speed).abs() < 1e-14);
            let flat = d.map(|p| Vec3::new(p.x(), p.y(), 0.0));
            let gp = differentials_from(u, &flat);
            let mp = mvc_point(&flat, Some(Vec3::new(0.0, 0.0, 1.0)));
            assert!((mp.kappa - gp.signed_curvature).abs() < 1e-14);
            assert!((mp.dkappa_ds() - gp.dkappa_signed_ds).abs() < 1e-13);
            // the ellipse turns counter-clockwise: positive signed curvature
            assert!(mp.kappa > 0.0);
        }
    }

    #[test]
    fn zero_speed_is_all_zero() {
        let d = [Vec3::ZERO; 4];
        assert_eq!(
            mvc_point(&d, Some(Vec3::new(0.0, 0.0, 1.0))),
            MvcPoint::default()
        );
        assert_eq!(mvc_point(&d, None).energy_density(), 0.0);
    }
}
