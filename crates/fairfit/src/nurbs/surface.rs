//! Tensor-product NURBS surfaces: validation, points (NURBS Book A3.5, A4.3) and partial derivatives of
//! any order (A3.6, A4.4), batched without per-point allocation.
//!
//! Written here for the same reasons as [`super::curve`]: fairfit owns its geometry core.

use super::basis::{basis_funs_into, ders_basis_funs_into, Scratch, STACK_DEGREE};
use super::curve::{validate_homogeneous, validate_weights};
use super::knots::{find_span, validate_knots};
use super::vec3::Vec3;
use crate::errors::{Error, Result};

/// A NURBS surface `S(u, v) = Σ_i Σ_j R_ij(u, v) P_ij`; `i` runs along u (rows), `j` along v.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    degree_u: usize,
    degree_v: usize,
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    n_u: usize,
    n_v: usize,
    /// Row-major `n_u x n_v`.
    control_points: Vec<Vec3>,
    weights: Vec<f64>,
    cw: Vec<[f64; 4]>,
    rational: bool,
}

/// Reusable buffers for surface derivative evaluation.
#[derive(Clone, Debug)]
pub struct SurfaceWorkspace {
    pu: usize,
    pv: usize,
    d: usize,
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
    nu: Vec<f64>,
    nv: Vec<f64>,
    temp: Vec<[f64; 4]>,
    aders: Vec<[f64; 4]>,
}

impl SurfaceWorkspace {
    /// Buffers for `surface`, derivatives up to order `d`.
    pub fn new(surface: &NurbsSurface, d: usize) -> Self {
        let (pu, pv) = (surface.degree_u, surface.degree_v);
        let pm = pu.max(pv) + 1;
        SurfaceWorkspace {
            pu,
            pv,
            d,
            left: vec![0.0; pm],
            right: vec![0.0; pm],
            ndu: vec![0.0; pm * pm],
            a: vec![0.0; 2 * pm],
            nu: vec![0.0; (d + 1) * (pu + 1)],
            nv: vec![0.0; (d + 1) * (pv + 1)],
            temp: vec![[0.0; 4]; pv + 1],
            aders: vec![[0.0; 4]; (d + 1) * (d + 1)],
        }
    }
}

impl NurbsSurface {
    /// Builds a surface from a row-major net (`control_points[i][j]`, `i` along u), validating all inputs.
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        control_points: Vec<Vec<Vec3>>,
        weights: Option<Vec<Vec<f64>>>,
    ) -> Result<Self> {
        let n_u = control_points.len();
        if n_u == 0 || control_points[0].is_empty() {
            return Err(Error::InvalidControlPoints(
                "a surface needs a non-empty control net".into(),
            ));
        }
        let n_v = control_points[0].len();
        if let Some(i) = control_points.iter().position(|r| r.len() != n_v) {
            return Err(Error::InvalidControlPoints(format!(
                "control net row {i} has {} points, row 0 has {n_v}",
                control_points[i].len()
            )));
        }
        validate_knots(&knots_u, degree_u, n_u, "surface u direction")?;
        validate_knots(&knots_v, degree_v, n_v, "surface v direction")?;
        for (i, row) in control_points.iter().enumerate() {
            if let Some(j) = row.iter().position(|p| !p.is_finite()) {
                return Err(Error::InvalidControlPoints(format!(
                    "control point [{i}][{j}] is not finite: {:?}",
                    row[j].0
                )));
            }
        }
        let flat_w = match weights {
            None => vec![1.0; n_u * n_v],
            Some(w) => {
                if w.len() != n_u {
                    return Err(Error::InvalidWeights(format!(
                        "expected {n_u} rows of weights, got {}",
                        w.len()
                    )));
                }
                for (i, row) in w.iter().enumerate() {
                    if row.len() != n_v {
                        return Err(Error::InvalidWeights(format!(
                            "weight row {i} has {} entries, expected {n_v}",
                            row.len()
                        )));
                    }
                }
                w.into_iter().flatten().collect()
            }
        };
        validate_weights(&flat_w, n_u * n_v)?;
        let flat: Vec<Vec3> = control_points.into_iter().flatten().collect();
        validate_homogeneous(&flat, &flat_w)?;
        Ok(Self::from_flat_unchecked(
            degree_u, degree_v, knots_u, knots_v, n_u, n_v, flat, flat_w,
        ))
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn from_flat_unchecked(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        n_u: usize,
        n_v: usize,
        control_points: Vec<Vec3>,
        weights: Vec<f64>,
    ) -> Self {
        let rational = weights.iter().any(|&w| w != 1.0);
        let cw = control_points
            .iter()
            .zip(&weights)
            .map(|(p, &w)| [p[0] * w, p[1] * w, p[2] * w, w])
            .collect();
        NurbsSurface {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            n_u,
            n_v,
            control_points,
            weights,
            cw,
            rational,
        }
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u
    }
    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v
    }
    /// Knot vector in u.
    pub fn knots_u(&self) -> &[f64] {
        &self.knots_u
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &[f64] {
        &self.knots_v
    }
    /// Net size `(n_u, n_v)`.
    pub fn net_size(&self) -> (usize, usize) {
        (self.n_u, self.n_v)
    }
    /// Control point `P[i][j]`.
    pub fn control_point(&self, i: usize, j: usize) -> Vec3 {
        self.control_points[i * self.n_v + j]
    }
    /// Weight `w[i][j]`.
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.weights[i * self.n_v + j]
    }
    /// The control net, row-major flat (`n_u * n_v`, index `i * n_v + j`).
    pub fn control_points_flat(&self) -> &[Vec3] {
        &self.control_points
    }
    /// The homogeneous control points `(w x, w y, w z, w)`, row-major flat.
    pub fn homogeneous_points(&self) -> &[[f64; 4]] {
        &self.cw
    }
    /// The weights, row-major flat.
    pub fn weights_flat(&self) -> &[f64] {
        &self.weights
    }
    /// The control net as rows (`[i][j]`).
    pub fn control_net(&self) -> Vec<Vec<Vec3>> {
        self.control_points
            .chunks(self.n_v)
            .map(|r| r.to_vec())
            .collect()
    }
    /// The weights as rows (`[i][j]`).
    pub fn weight_net(&self) -> Vec<Vec<f64>> {
        self.weights.chunks(self.n_v).map(|r| r.to_vec()).collect()
    }
    /// True when some weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }
    /// Domain in u.
    pub fn domain_u(&self) -> (f64, f64) {
        (self.knots_u[self.degree_u], self.knots_u[self.n_u])
    }
    /// Domain in v.
    pub fn domain_v(&self) -> (f64, f64) {
        (self.knots_v[self.degree_v], self.knots_v[self.n_v])
    }

    /// Checks that `(u, v)` lies in the domain (relative slack 1e-12).
    pub fn check_parameter(&self, u: f64, v: f64) -> Result<()> {
        for (x, (a, b)) in [(u, self.domain_u()), (v, self.domain_v())] {
            let slack = 1e-12 * (b - a);
            if !x.is_finite() || x < a - slack || x > b + slack {
                return Err(Error::ParameterOutOfDomain {
                    value: x,
                    min: a,
                    max: b,
                });
            }
        }
        Ok(())
    }

    /// The point `S(u, v)`.
    pub fn point(&self, u: f64, v: f64) -> Vec3 {
        let (pu, pv) = (self.degree_u, self.degree_v);
        if pu <= STACK_DEGREE && pv <= STACK_DEGREE {
            let mut s = Scratch::new();
            let mut nu = [0.0; STACK_DEGREE + 1];
            let mut nv = [0.0; STACK_DEGREE + 1];
            self.point_with(u, v, &mut s.left, &mut s.right, &mut nu, &mut nv)
        } else {
            let m = pu.max(pv) + 1;
            let (mut l, mut r, mut nu, mut nv) =
                (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
            self.point_with(u, v, &mut l, &mut r, &mut nu, &mut nv)
        }
    }

    fn point_with(
        &self,
        u: f64,
        v: f64,
        left: &mut [f64],
        right: &mut [f64],
        nu: &mut [f64],
        nv: &mut [f64],
    ) -> Vec3 {
        let (pu, pv) = (self.degree_u, self.degree_v);
        let su = find_span(self.n_u - 1, pu, u, &self.knots_u);
        let sv = find_span(self.n_v - 1, pv, v, &self.knots_v);
        basis_funs_into(su, u, pu, &self.knots_u, left, right, nu);
        basis_funs_into(sv, v, pv, &self.knots_v, left, right, nv);
        let mut s = [0.0; 4];
        for (k, nuk) in nu.iter().take(pu + 1).enumerate() {
            let row = (su - pu + k) * self.n_v + sv - pv;
            let mut t = [0.0; 4];
            for (l, nvl) in nv.iter().take(pv + 1).enumerate() {
                let q = &self.cw[row + l];
                t[0] += nvl * q[0];
                t[1] += nvl * q[1];
                t[2] += nvl * q[2];
                t[3] += nvl * q[3];
            }
            for c in 0..4 {
                s[c] += nuk * t[c];
            }
        }
        Vec3::new(s[0] / s[3], s[1] / s[3], s[2] / s[3])
    }

    /// Points at the parameter pairs `uv` into `out`; no allocation per point.
    ///
    /// # Panics
    /// When `out.len() != uv.len()` (a caller's buffer bug; never input data).
    pub fn points_into(&self, uv: &[(f64, f64)], out: &mut [Vec3]) {
        assert_eq!(uv.len(), out.len(), "points_into: output length must match");
        let m = self.degree_u.max(self.degree_v) + 1;
        let (mut l, mut r, mut nu, mut nv) =
            (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        for (&(u, v), o) in uv.iter().zip(out.iter_mut()) {
            *o = self.point_with(u, v, &mut l, &mut r, &mut nu, &mut nv);
        }
    }

    /// Partial derivatives up to total order `d` using `ws` (sized for at least `d`):
    /// `out[k * (d + 1) + l] = ∂^{k+l} S / ∂u^k ∂v^l` for `k + l <= d` (entries with `k + l > d` are zero).
    ///
    /// # Panics
    /// When `ws` was made for another surface's degrees or a lower order than `d` (a caller's bug;
    /// never input data).
    pub fn derivatives_with(
        &self,
        u: f64,
        v: f64,
        d: usize,
        ws: &mut SurfaceWorkspace,
        out: &mut [Vec3],
    ) {
        assert!(
            ws.d >= d && ws.pu == self.degree_u && ws.pv == self.degree_v,
            "workspace mismatch"
        );
        let (pu, pv) = (self.degree_u, self.degree_v);
        let su = find_span(self.n_u - 1, pu, u, &self.knots_u);
        let sv = find_span(self.n_v - 1, pv, v, &self.knots_v);
        ders_basis_funs_into(
            su,
            u,
            pu,
            d,
            &self.knots_u,
            &mut ws.left,
            &mut ws.right,
            &mut ws.ndu,
            &mut ws.a,
            &mut ws.nu,
        );
        ders_basis_funs_into(
            sv,
            v,
            pv,
            d,
            &self.knots_v,
            &mut ws.left,
            &mut ws.right,
            &mut ws.ndu,
            &mut ws.a,
            &mut ws.nv,
        );
        let d1 = d + 1;
        for x in ws.aders.iter_mut() {
            *x = [0.0; 4];
        }
        for k in 0..=d {
            for s in 0..=pv {
                let mut t = [0.0; 4];
                for r in 0..=pu {
                    let q = &self.cw[(su - pu + r) * self.n_v + sv - pv + s];
                    let b = ws.nu[k * (pu + 1) + r];
                    t[0] += b * q[0];
                    t[1] += b * q[1];
                    t[2] += b * q[2];
                    t[3] += b * q[3];
                }
                ws.temp[s] = t;
            }
            for l in 0..=(d - k) {
                let mut acc = [0.0; 4];
                for s in 0..=pv {
                    let b = ws.nv[l * (pv + 1) + s];
                    for (a, t) in acc.iter_mut().zip(ws.temp[s]) {
                        *a += b * t;
                    }
                }
                ws.aders[k * d1 + l] = acc;
            }
        }
        for x in out.iter_mut().take(d1 * d1) {
            *x = Vec3::ZERO;
        }
        let a = &ws.aders;
        let w = |k: usize, l: usize| a[k * d1 + l][3];
        let w00 = w(0, 0);
        for k in 0..=d {
            for l in 0..=(d - k) {
                let q = a[k * d1 + l];
                let mut val = Vec3::new(q[0], q[1], q[2]);
                for j in 1..=l {
                    val -= out[k * d1 + l - j] * (binom(l, j) * w(0, j));
                }
                for i in 1..=k {
                    val -= out[(k - i) * d1 + l] * (binom(k, i) * w(i, 0));
                    let mut v2 = Vec3::ZERO;
                    for j in 1..=l {
                        v2 += out[(k - i) * d1 + l - j] * (binom(l, j) * w(i, j));
                    }
                    val -= v2 * binom(k, i);
                }
                out[k * d1 + l] = val / w00;
            }
        }
    }

    /// Partial derivatives up to total order `d` as a `(d + 1) x (d + 1)` row-major vector
    /// (`[k * (d + 1) + l]` = `S_{u^k v^l}`).
    pub fn derivatives(&self, u: f64, v: f64, d: usize) -> Vec<Vec3> {
        let mut ws = SurfaceWorkspace::new(self, d);
        let mut out = vec![Vec3::ZERO; (d + 1) * (d + 1)];
        self.derivatives_with(u, v, d, &mut ws, &mut out);
        out
    }
}

/// Binomial coefficient as f64 (small arguments).
#[inline]
pub(crate) fn binom(n: usize, k: usize) -> f64 {
    let mut r = 1.0;
    for i in 1..=k {
        r = r * (n - k + i) as f64 / i as f64;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::uniform_clamped;

    fn sample_surface() -> NurbsSurface {
        let net: Vec<Vec<Vec3>> = (0..5)
            .map(|i| {
                (0..4)
                    .map(|j| Vec3::new(i as f64, j as f64, ((i * 7 + j * 3) % 5) as f64 * 0.3))
                    .collect()
            })
            .collect();
        let w: Vec<Vec<f64>> = (0..5)
            .map(|i| {
                (0..4)
                    .map(|j| 1.0 + 0.1 * ((i + 2 * j) % 3) as f64)
                    .collect()
            })
            .collect();
        NurbsSurface::new(
            3,
            2,
            uniform_clamped(3, 5),
            uniform_clamped(2, 4),
            net,
            Some(w),
        )
        .unwrap()
    }

    #[test]
    fn partials_match_finite_differences() {
        let s = sample_surface();
        let h = 1e-5;
        for &(u, v) in &[(0.2, 0.3), (0.7, 0.6), (0.45, 0.1)] {
            let d = s.derivatives(u, v, 2);
            let du = (s.point(u + h, v) - s.point(u - h, v)) / (2.0 * h);
            let dv = (s.point(u, v + h) - s.point(u, v - h)) / (2.0 * h);
            assert!((du - d[3]).norm() < 1e-6, "{du:?} {:?}", d[3]);
            assert!((dv - d[1]).norm() < 1e-6);
            let dp = s.derivatives(u + h, v, 2);
            let dm = s.derivatives(u - h, v, 2);
            let duu = (dp[3] - dm[3]) / (2.0 * h);
            let duv = (dp[1] - dm[1]) / (2.0 * h);
            assert!((duu - d[6]).norm() < 1e-5);
            assert!((duv - d[4]).norm() < 1e-5);
            assert!((d[0] - s.point(u, v)).norm() < 1e-14);
        }
    }
}
