//! Gaussian and mean curvature of NURBS surfaces from the first and second fundamental forms.
//!
//! With `E = S_u·S_u`, `F = S_u·S_v`, `G = S_v·S_v`, the unit normal `n = S_u × S_v / |S_u × S_v|` and
//! `L = S_uu·n`, `M = S_uv·n`, `N = S_vv·n`:
//! `K = (LN − M²)/(EG − F²)` and `H = (EN − 2FM + GL) / (2(EG − F²))`.
//! The sign of `H` follows the normal `S_u × S_v` (a sphere with outward normal has `H = −1/r`).
//! Where `|S_u × S_v|` vanishes (poles, collapsed edges) the normal is undefined and no value is given.

use crate::nurbs::{NurbsSurface, Vec3};

/// `|S_u × S_v|` below this fraction of `max(|S_u|, |S_v|)²` counts as a degenerate normal (parallel
/// partials, or one partial vanishing as at a pole).
const NORMAL_EPS: f64 = 1e-12;

/// Curvature of a surface at one parameter pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceCurvature {
    /// Gaussian curvature `K = κ1 κ2`.
    pub gaussian: f64,
    /// Mean curvature `H = (κ1 + κ2)/2`, signed with respect to `normal`.
    pub mean: f64,
    /// Unit normal `S_u × S_v / |S_u × S_v|`.
    pub normal: Vec3,
}

/// Curvature from the partial derivatives; `None` where the normal is degenerate.
pub fn surface_curvature_from(
    du: Vec3,
    dv: Vec3,
    duu: Vec3,
    duv: Vec3,
    dvv: Vec3,
) -> Option<SurfaceCurvature> {
    let cross = du.cross(dv);
    let cn = cross.norm();
    let big = du.norm().max(dv.norm());
    if !cn.is_finite() || cn == 0.0 || cn <= NORMAL_EPS * big * big {
        return None;
    }
    let n = cross / cn;
    let (e, f, g) = (du.dot(du), du.dot(dv), dv.dot(dv));
    let (l, m, nn) = (duu.dot(n), duv.dot(n), dvv.dot(n));
    // EG − F² = |S_u × S_v|², computed without cancellation
    let det = cn * cn;
    Some(SurfaceCurvature {
        gaussian: (l * nn - m * m) / det,
        mean: (e * nn - 2.0 * f * m + g * l) / (2.0 * det),
        normal: n,
    })
}

/// Gaussian and mean curvature of `surface` at `(u, v)`; `None` where the normal is degenerate.
///
/// ```
/// use fairfit::diffgeo::surface_curvature;
/// use fairfit::nurbs::{NurbsSurface, Vec3};
/// // a bilinear saddle z = x y on [0,1]²: at the origin K = -1, H = 0
/// let net = vec![
///     vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)],
///     vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)],
/// ];
/// let k = vec![0.0, 0.0, 1.0, 1.0];
/// let s = NurbsSurface::new(1, 1, k.clone(), k, net, None).unwrap();
/// let c = surface_curvature(&s, 0.0, 0.0).unwrap();
/// assert!((c.gaussian + 1.0).abs() < 1e-14 && c.mean.abs() < 1e-14);
/// ```
pub fn surface_curvature(surface: &NurbsSurface, u: f64, v: f64) -> Option<SurfaceCurvature> {
    let d = surface.derivatives(u, v, 2);
    // row-major [k * 3 + l] = S_{u^k v^l}
    surface_curvature_from(d[3], d[1], d[6], d[4], d[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    /// The surface of revolution of the xz-plane profile `profile` about the z axis (NURBS Book A8.1,
    /// full turn as the 9-point rational circle), exact for rational profiles.
    fn revolve(profile: &NurbsCurve) -> NurbsSurface {
        let circle = NurbsCurve::circle(Vec3::ZERO, 1.0).unwrap();
        let net = profile
            .control_points()
            .iter()
            .map(|p| {
                circle
                    .control_points()
                    .iter()
                    .map(|c| Vec3::new(p.x() * c.x(), p.x() * c.y(), p.z()))
                    .collect()
            })
            .collect();
        let w = profile
            .weights()
            .iter()
            .map(|wi| circle.weights().iter().map(|wj| wi * wj).collect())
            .collect();
        NurbsSurface::new(
            profile.degree(),
            2,
            profile.knots().to_vec(),
            circle.knots().to_vec(),
            net,
            Some(w),
        )
        .unwrap()
    }

    /// A meridian of the sphere of radius `r` from latitude `-lat` to `lat` in the xz plane.
    fn meridian(r: f64, lat: f64) -> NurbsCurve {
        let arc = NurbsCurve::arc(Vec3::ZERO, r, -lat, lat).unwrap();
        let pts: Vec<Vec3> = arc
            .control_points()
            .iter()
            .map(|p| Vec3::new(p.x(), 0.0, p.y()))
            .collect();
        NurbsCurve::new(2, arc.knots().to_vec(), pts, Some(arc.weights().to_vec())).unwrap()
    }

    #[test]
    fn sphere_has_k_one_over_r_squared() {
        let r = 2.5;
        let s = revolve(&meridian(r, 1.4));
        for i in 0..=10 {
            for j in 0..=12 {
                let (u, v) = (0.05 + 0.09 * i as f64, j as f64 / 12.0);
                let p = s.point(u, v);
                assert!((p.norm() - r).abs() < 1e-12);
                let c = surface_curvature(&s, u, v).unwrap();
                assert!((c.gaussian - 1.0 / (r * r)).abs() < 1e-10, "{c:?}");
                assert!((c.mean.abs() - 1.0 / r).abs() < 1e-10, "{c:?}");
                // normal is radial
                assert!((c.normal.dot(p / r).abs() - 1.0).abs() < 1e-10);
            }
        }
    }

    #[test]
    fn cylinder_has_zero_gaussian_and_half_inverse_radius_mean() {
        let r = 0.7;
        let line = NurbsCurve::bspline(
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![Vec3::new(r, 0.0, -1.0), Vec3::new(r, 0.0, 2.0)],
        )
        .unwrap();
        let s = revolve(&line);
        for &(u, v) in &[(0.1, 0.1), (0.5, 0.3), (0.9, 0.77), (0.3, 0.5)] {
            let c = surface_curvature(&s, u, v).unwrap();
            assert!(c.gaussian.abs() < 1e-10, "{c:?}");
            assert!((c.mean.abs() - 0.5 / r).abs() < 1e-10, "{c:?}");
        }
    }

    #[test]
    fn pole_gives_no_curvature() {
        let s = revolve(&meridian(1.0, std::f64::consts::FRAC_PI_2));
        assert!(surface_curvature(&s, 0.0, 0.3).is_none());
        assert!(surface_curvature(&s, 0.5, 0.3).is_some());
    }
}
