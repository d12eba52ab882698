//! Curvature, torsion and the arc-length derivative of curvature of curves
//! (method reconstruction §2.2), from the first three derivatives.
//!
//! With `r = C'`, `a = C''`, `b = C'''`, `v = |r|`, `c = r × a`:
//! `κ = |c| / v³`, `τ = (c·b) / |c|²`,
//! `dκ/du = [(c·(r×b)) v² − 3 |c|² (r·a)] / (|c| v⁵)`, `dκ/ds = (dκ/du) / v`.
//! Planar curves (in the xy plane) also get the signed curvature `κ_s = (r_x a_y − r_y a_x)/v³`, which
//! is smooth through inflections. Where `|c| → 0` the unsigned formula uses the one-sided limit
//! `d|c|/du → |r × b|`.

use crate::nurbs::{NurbsCurve, Vec3};

/// `|c|` below this fraction of `v |a|` (and of `v³` times the inverse length scale) counts as zero.
const PARALLEL_EPS: f64 = 1e-12;

/// A speed below this fraction of the curve's reference speed (extent of the control points over the
/// length of the parameter domain) counts as zero: the curve is not regular there. Rounding in the
/// derivative is about `1e-16` of the reference speed, so above the threshold the speed (and with it
/// `κ ∝ 1/v³`) keeps about six correct digits.
pub const REGULAR_SPEED_EPS: f64 = 1e-10;

/// The differential quantities of a curve at one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveDifferentials {
    /// The parameter.
    pub u: f64,
    /// `C(u)`.
    pub point: Vec3,
    /// `C'(u)`.
    pub d1: Vec3,
    /// `C''(u)`.
    pub d2: Vec3,
    /// `C'''(u)`.
    pub d3: Vec3,
    /// Speed `|C'(u)|` (= ds/du).
    pub speed: f64,
    /// Unsigned curvature `|C' × C''| / |C'|³`.
    pub curvature: f64,
    /// Signed curvature of the projection onto the xy plane (positive turning counter-clockwise).
    pub signed_curvature: f64,
    /// Torsion `(c·C''') / |c|²`; 0 where the curvature vanishes.
    pub torsion: f64,
    /// dκ/ds of the unsigned curvature (guarded where κ → 0).
    pub dkappa_ds: f64,
    /// dκ_s/ds of the signed planar curvature.
    pub dkappa_signed_ds: f64,
    /// Whether the curve is regular at `u` (non-zero speed), so that the curvature quantities are
    /// defined. Where it is `false` every curvature quantity above is 0 and means "undefined".
    ///
    /// [`differentials`] decides it scale-free: the speed is compared with
    /// [`REGULAR_SPEED_EPS`] times the curve's extent over its parameter span, on the rescaled copy
    /// it evaluates, so a regular curve 1e-300 long stays regular. [`differentials_from`] has no
    /// reference scale and only flags a speed too small for `v³` (below `√f64::MIN_POSITIVE`) or not
    /// finite.
    pub regular: bool,
}

/// Differential quantities from `[C, C', C'', C''']` at `u`.
///
/// Near-zero speed (below `√f64::MIN_POSITIVE`, where `v³` underflows) gives zeros for every curvature
/// quantity and `regular: false`. Without the curve there is no length or parameter scale to judge a
/// small speed by: prefer [`differentials`], which decides regularity scale-free.
pub fn differentials_from(u: f64, d: &[Vec3; 4]) -> CurveDifferentials {
    let (r, a, b) = (d[1], d[2], d[3]);
    let v2 = r.norm_squared();
    let v = v2.sqrt();
    let mut out = CurveDifferentials {
        u,
        point: d[0],
        d1: r,
        d2: a,
        d3: b,
        speed: v,
        curvature: 0.0,
        signed_curvature: 0.0,
        torsion: 0.0,
        dkappa_ds: 0.0,
        dkappa_signed_ds: 0.0,
        regular: false,
    };
    if !v.is_finite() || v <= f64::MIN_POSITIVE.sqrt() {
        return out;
    }
    out.regular = true;
    let c = r.cross(a);
    let cn = c.norm();
    let v3 = v2 * v;
    let v5 = v3 * v2;
    let ra = r.dot(a);
    let rxb = r.cross(b);
    out.curvature = cn / v3;
    let cz = r.x() * a.y() - r.y() * a.x();
    out.signed_curvature = cz / v3;
    let dks_du = (r.x() * b.y() - r.y() * b.x()) / v3 - 3.0 * cz * ra / v5;
    out.dkappa_signed_ds = dks_du / v;
    let degenerate = cn <= PARALLEL_EPS * v * a.norm() || cn == 0.0;
    if degenerate {
        // one-sided limit of d|c|/du at an isolated zero of c
        let dk_du = (rxb.norm() * v2 - 3.0 * cn * ra) / v5;
        out.dkappa_ds = dk_du / v;
        out.torsion = 0.0;
    } else {
        let dk_du = (c.dot(rxb) * v2 - 3.0 * cn * cn * ra) / (cn * v5);
        out.dkappa_ds = dk_du / v;
        out.torsion = c.dot(b) / (cn * cn);
    }
    out
}

/// Differential quantities of `curve` at `u`.
///
/// Far outside unit size (coordinates around 1e±160 and beyond, where `|C'|³` over- or underflows), or
/// with knots far from unit range, the quantities come from an exactly rescaled copy (control points
/// and knots times powers of two, see [`crate::nurbs::scale`]); curvature, torsion and dκ/ds do not
/// depend on the parametrisation.
///
/// [`CurveDifferentials::regular`] is decided on that (rescaled) evaluation against the curve's own
/// reference speed, so it does not depend on the curve's size: where the speed vanishes (e.g. at a
/// clamped end whose first two control points coincide) the curve is not regular and the curvature
/// quantities are 0 with `regular == false`.
///
/// ```
/// use fairfit::diffgeo::differentials;
/// use fairfit::nurbs::{NurbsCurve, Vec3};
///
/// // a cubic whose first two control points coincide: C'(0) = 0
/// let pts = vec![
///     Vec3::new(0.0, 0.0, 0.0),
///     Vec3::new(0.0, 0.0, 0.0),
///     Vec3::new(1.0, 1.0, 0.0),
///     Vec3::new(2.0, 0.0, 0.0),
/// ];
/// let c = NurbsCurve::new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], pts, None).unwrap();
/// assert!(!differentials(&c, 0.0).regular);
/// assert!(differentials(&c, 0.5).regular);
///
/// // an exact circle of radius 1e-300 is regular, with curvature 1e300
/// let tiny = NurbsCurve::circle(Vec3::new(0.0, 0.0, 0.0), 1e-300).unwrap();
/// let d = differentials(&tiny, 0.3);
/// assert!(d.regular);
/// assert!((d.curvature * 1e-300 - 1.0).abs() < 1e-12);
/// ```
pub fn differentials(curve: &NurbsCurve, u: f64) -> CurveDifferentials {
    use crate::nurbs::scale::{normalising_factor, parameter_factor, scaled_curve_and_parameter};
    let f = normalising_factor(curve.control_points());
    // the parameter too: with knots 1e200 apart the speed is about 1e-200 and |C'|³ underflows
    let g = parameter_factor(curve.knots());
    if let Some(s) = (f != 1.0 || g != 1.0)
        .then(|| scaled_curve_and_parameter(curve, f, g).ok())
        .flatten()
    {
        let mut d = [Vec3::ZERO; 4];
        s.derivatives_into(u * g, 3, &mut d);
        let m = differentials_from(u * g, &d);
        let m = with_regularity(m, &s);
        // evaluate C and its derivatives on the curve itself (exact enough, and no 1/f rounding)
        curve.derivatives_into(u, 3, &mut d);
        // the geometric quantities scale with f only; |dC/du| = |dC_s/dt| g / f with t = g u
        return CurveDifferentials {
            u,
            point: d[0],
            d1: d[1],
            d2: d[2],
            d3: d[3],
            speed: m.speed * g / f,
            curvature: m.curvature * f,
            signed_curvature: m.signed_curvature * f,
            torsion: m.torsion * f,
            dkappa_ds: m.dkappa_ds * f * f,
            dkappa_signed_ds: m.dkappa_signed_ds * f * f,
            regular: m.regular,
        };
    }
    let mut d = [Vec3::ZERO; 4];
    curve.derivatives_into(u, 3, &mut d);
    with_regularity(differentials_from(u, &d), curve)
}

/// `m` (evaluated on `curve`) with `regular` decided against `curve`'s reference speed: the largest
/// coordinate range of its control points over the length of its parameter domain. A speed at or below
/// [`REGULAR_SPEED_EPS`] of it makes every curvature quantity 0 and `regular` false.
fn with_regularity(mut m: CurveDifferentials, curve: &NurbsCurve) -> CurveDifferentials {
    let pts = curve.control_points();
    let extent = (0..3)
        .map(|k| {
            let (lo, hi) = pts
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p[k]), h.max(p[k]))
                });
            hi - lo
        })
        .fold(0.0f64, f64::max);
    let (a, b) = curve.domain();
    // compare v·span with eps·extent (no division: the span may be huge or tiny)
    let regular = m.regular && m.speed * (b - a) > REGULAR_SPEED_EPS * extent;
    if !regular {
        m.curvature = 0.0;
        m.signed_curvature = 0.0;
        m.torsion = 0.0;
        m.dkappa_ds = 0.0;
        m.dkappa_signed_ds = 0.0;
        m.regular = false;
    }
    m
}

/// Unsigned curvature of `curve` at `u`.
pub fn curvature(curve: &NurbsCurve, u: f64) -> f64 {
    let mut d = [Vec3::ZERO; 3];
    curve.derivatives_into(u, 2, &mut d);
    let v = d[1].norm();
    if v <= f64::MIN_POSITIVE.sqrt() {
        return 0.0;
    }
    d[1].cross(d[2]).norm() / (v * v * v)
}

/// True when every control point of `curve` has the same z (a curve in a plane parallel to xy), so the
/// signed planar curvature applies.
pub fn is_xy_planar(curve: &NurbsCurve) -> bool {
    let pts = curve.control_points();
    let z0 = pts[0].z();
    let scale = pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p.max_abs()))
        .max(f64::MIN_POSITIVE);
    pts.iter().all(|p| (p.z() - z0).abs() <= 1e-12 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helix_curvature_and_torsion() {
        // C(t) = (R cos t, R sin t, h t): κ = R/(R²+h²), τ = h/(R²+h²), dκ/ds = 0
        let (rr, h, t) = (2.0f64, 0.5f64, 0.7f64);
        let d = [
            Vec3::new(rr * t.cos(), rr * t.sin(), h * t),
            Vec3::new(-rr * t.sin(), rr * t.cos(), h),
            Vec3::new(-rr * t.cos(), -rr * t.sin(), 0.0),
            Vec3::new(rr * t.sin(), -rr * t.cos(), 0.0),
        ];
        let g = differentials_from(t, &d);
        let den = rr * rr + h * h;
        assert!((g.curvature - rr / den).abs() < 1e-14);
        assert!((g.torsion - h / den).abs() < 1e-14);
        assert!(g.dkappa_ds.abs() < 1e-14);
    }

    #[test]
    fn dkappa_matches_finite_difference_on_analytic_curve() {
        // C(u) = (2 cos u, sin u, 0.3 u²), as in the method note
        let f = |u: f64| {
            [
                Vec3::new(2.0 * u.cos(), u.sin(), 0.3 * u * u),
                Vec3::new(-2.0 * u.sin(), u.cos(), 0.6 * u),
                Vec3::new(-2.0 * u.cos(), -u.sin(), 0.6),
                Vec3::new(2.0 * u.sin(), -u.cos(), 0.0),
            ]
        };
        let (u, h) = (0.8, 1e-6);
        let g = differentials_from(u, &f(u));
        let kp = differentials_from(u + h, &f(u + h)).curvature;
        let km = differentials_from(u - h, &f(u - h)).curvature;
        let fd = (kp - km) / (2.0 * h) / g.speed;
        assert!((fd - g.dkappa_ds).abs() < 1e-8, "{fd} vs {}", g.dkappa_ds);
    }

    /// A cubic Bézier with `P0 = P1` (so `C'(0) = 0`), every coordinate times `s`, on `[0, span]`.
    fn degenerate_start(s: f64, span: f64) -> NurbsCurve {
        let pts = [[0.0, 0.0], [0.0, 0.0], [1.0, 1.0], [2.0, 0.0]]
            .iter()
            .map(|q| Vec3::new(q[0] * s, q[1] * s, 0.0))
            .collect();
        let k = vec![0.0, 0.0, 0.0, 0.0, span, span, span, span];
        NurbsCurve::new(3, k, pts, None).unwrap()
    }

    #[test]
    fn regularity_does_not_depend_on_size_or_parameter_span() {
        // at u = span/2 (by hand, for s = span = 1): C' = (9/4, 3/4), C'' = (3, -3),
        // κ = 9 / (45/8)^(3/2); the curvature scales as 1/s and does not depend on the span
        let kappa_half = 9.0 / (45.0f64 / 8.0).powf(1.5);
        for s in [1.0, 1e-300, 1e-20, 1e20, 1e300] {
            for span in [1.0, 1e-6, 1e6, 1e-250, 1e250] {
                let c = degenerate_start(s, span);
                let d0 = differentials(&c, 0.0);
                assert!(!d0.regular, "s {s:e} span {span:e}");
                assert_eq!(d0.speed, 0.0);
                assert_eq!((d0.curvature, d0.torsion, d0.dkappa_ds), (0.0, 0.0, 0.0));
                let d = differentials(&c, 0.5 * span);
                assert!(d.regular, "s {s:e} span {span:e}");
                assert!((d.curvature * s / kappa_half - 1.0).abs() < 1e-12);
                // just off the end the speed is 6 u (1 - u) √2 s/span: tiny but regular
                let d = differentials(&c, 1e-6 * span);
                assert!(d.regular, "s {s:e} span {span:e}");
            }
        }
    }

    #[test]
    fn differentials_from_flags_only_unrepresentable_speeds() {
        let z = Vec3::ZERO;
        let x = Vec3::new(1.0, 0.0, 0.0);
        let y = Vec3::new(0.0, 1.0, 0.0);
        assert!(!differentials_from(0.0, &[z, z, y, z]).regular);
        assert!(!differentials_from(0.0, &[z, x * 1e-160, y, z]).regular);
        let d = differentials_from(0.0, &[z, x, y, z]);
        assert!(d.regular && d.curvature == 1.0);
    }
}
