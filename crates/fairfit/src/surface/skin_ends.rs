//! End tangents across the sections: a direction asked for `∂S/∂v` along the whole first (`v = 0`) or
//! last (`v = 1`) section of a skinned surface.
//!
//! Why a direction holds exactly for every `u`: at a clamped end `v = 0` of a degree-`q` skin, each
//! homogeneous control column `C_i^w(v)` has the end derivative `(q / v_{q+1}) (P_{i,1}^w − P_{i,0}^w)`.
//! [`super::skin`] gives every column the homogeneous end derivative `(m w_{i,0} d, 0)`: direction `d`
//! (unit) in the point part, scaled by the column's end weight `w_{i,0}`, and a weight derivative of 0.
//! With `A(u, v) = Σ N_i(u) C_i^w(v)` (point part) and `W` its weight part, `S = A / W` and
//! `S_v = (A_v − S W_v) / W`; at `v = 0`, `W_v = 0` and `A_v = m d Σ N_i(u) w_{i,0} = m d W`, so
//! `S_v(u, 0) = m d` for every `u`, whatever the sections' weights (sections with all weights 1, the
//! pipeline's case, keep weights 1 and a non-rational surface). The same holds at `v = 1`.
//!
//! The magnitude `m` is the method's, not the caller's: the mean over the control columns of their
//! polygon lengths (the speed of a chord-length parameterisation on `[0, 1]`, the choice the NURBS
//! Book suggests for the end derivatives of §9.2.2). It changes the shape near the end, never the
//! direction.
//!
//! Interpolation gains one control point per asked end (NURBS Book §9.2.2, eq. 9.21): the knots are
//! the averaging knots (eq. 9.8) of the parameters with each constrained end parameter doubled, which
//! is eq. 9.22 when both ends are asked. Approximation with `n` control points holds the first two
//! (last two) control points of every column instead, so it needs `n >= 2 +` the ends asked.

use crate::errors::{Error, Result};
use crate::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};
use serde::Serialize;

/// u samples (intervals: one fewer) at which [`max_v_tangent_angle`] is measured by the pipeline.
pub const V_TANGENT_SAMPLES: usize = 1001;

/// The unit vector of an asked end direction; `what` names it in the error.
pub(crate) fn unit_direction(d: Vec3, what: &str) -> Result<Vec3> {
    let n = d.norm();
    if !(d.is_finite() && n.is_finite() && n > 0.0) {
        return Err(Error::InvalidOption(format!(
            "{what} must be a finite non-zero vector, got ({}, {}, {})",
            d.x(),
            d.y(),
            d.z()
        )));
    }
    Ok(d / n)
}

/// The parameters with the first (`start`) and last (`end`) doubled: averaging knots (eq. 9.8) of this
/// list are the knots of interpolation with end derivatives (eq. 9.22 when both are doubled).
pub(crate) fn doubled_ends(params: &[f64], start: bool, end: bool) -> Vec<f64> {
    let mut t = Vec::with_capacity(params.len() + 2);
    if start {
        t.push(params[0]);
    }
    t.extend_from_slice(params);
    if end {
        t.push(params[params.len() - 1]);
    }
    t
}

/// The derivative magnitude `m` (module documentation): the mean Euclidean polygon length of the
/// homogeneous control columns `cols[i][k]`.
pub(crate) fn column_speed(cols: &[Vec<[f64; 4]>]) -> Result<f64> {
    let euclid = |c: &[f64; 4]| Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3]);
    let total: f64 = cols
        .iter()
        .map(|col| {
            col.windows(2)
                .map(|w| euclid(&w[0]).distance(euclid(&w[1])))
                .sum::<f64>()
        })
        .sum();
    let m = total / cols.len() as f64;
    if !(m.is_finite() && m > 0.0) {
        return Err(Error::InvalidData(format!(
            "the sections' control columns have no length ({m}): no v end tangent can be scaled"
        )));
    }
    Ok(m)
}

/// The homogeneous end derivative of a column whose end control point is `end` (module
/// documentation): `(m w d, 0)`.
pub(crate) fn homogeneous_derivative(end: &[f64; 4], speed: f64, dir: Vec3) -> [f64; 4] {
    let s = speed * end[3];
    [s * dir.x(), s * dir.y(), s * dir.z(), 0.0]
}

/// `P_1 − P_0 = (v_{q+1} / q) D` at the start and `P_n − P_{n−1} = ((1 − v_{n}) / q) D` at the end of a
/// clamped degree-`q` knot vector `kv` on `[0, 1]`: the factor multiplying `D`.
pub(crate) fn leg_factor(kv: &[f64], q: usize, at_start: bool) -> f64 {
    if at_start {
        (kv[q + 1] - kv[0]) / q as f64
    } else {
        (kv[kv.len() - 1] - kv[kv.len() - q - 2]) / q as f64
    }
}

/// The largest angle (radians) between `∂S/∂v (u, v)` and `dir` over `samples` equally spaced `u`
/// (ends included); a vanishing derivative counts as π (no direction).
pub fn max_v_tangent_angle(surface: &NurbsSurface, v: f64, dir: Vec3, samples: usize) -> f64 {
    let (u0, u1) = surface.domain_u();
    let mut ws = SurfaceWorkspace::new(surface, 1);
    let mut out = [Vec3::ZERO; 4];
    let n = samples.max(2) - 1;
    let mut worst = 0.0f64;
    for i in 0..=n {
        let u = u0 + (u1 - u0) * i as f64 / n as f64;
        surface.derivatives_with(u, v, 1, &mut ws, &mut out);
        // out[k * 2 + l] = S_{u^k v^l}: S_v is out[1]
        let sv = out[1];
        let angle = if sv.norm() > 0.0 {
            sv.cross(dir).norm().atan2(sv.dot(dir))
        } else {
            std::f64::consts::PI
        };
        worst = worst.max(if angle.is_nan() {
            std::f64::consts::PI
        } else {
            angle
        });
    }
    worst
}

/// One asked v end tangent and how closely the surface follows it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VTangentCheck {
    /// The asked direction (unit).
    pub direction: [f64; 3],
    /// The largest angle (radians) between `∂S/∂v` and the direction over
    /// [`VEndTangents::u_samples`] equally spaced `u`.
    pub max_angle: f64,
}

/// The asked v end tangents of a skinned surface, measured ([`max_v_tangent_angle`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VEndTangents {
    /// At the first section (`v = 0`), when asked.
    pub start: Option<VTangentCheck>,
    /// At the last section (`v = 1`), when asked.
    pub end: Option<VTangentCheck>,
    /// The derivative magnitude used (the mean polygon length of the control columns).
    pub speed: f64,
    /// The number of u samples measured.
    pub u_samples: usize,
}

impl VEndTangents {
    /// Measures `surface` against the asked directions (`None` when neither end was asked).
    pub fn measure(
        surface: &NurbsSurface,
        start: Option<Vec3>,
        end: Option<Vec3>,
        speed: f64,
    ) -> Option<VEndTangents> {
        if start.is_none() && end.is_none() {
            return None;
        }
        let (v0, v1) = surface.domain_v();
        let check = |d: Vec3, v: f64| {
            let u = d / d.norm();
            VTangentCheck {
                direction: [u.x(), u.y(), u.z()],
                max_angle: max_v_tangent_angle(surface, v, u, V_TANGENT_SAMPLES),
            }
        };
        Some(VEndTangents {
            start: start.map(|d| check(d, v0)),
            end: end.map(|d| check(d, v1)),
            speed,
            u_samples: V_TANGENT_SAMPLES,
        })
    }
}
