//! Which control points the final fairing stages ([`super::band_fairing`], [`super::polish`]) may
//! move, and how a curve is measured there, for open and for periodic (closed) curves.
//!
//! Both stages work on a clamped B-spline in an [`EvalWorkspace`]. Their variables are the
//! *movable points* `z_v`; every clamped control point is a fixed linear combination of them,
//! `P_j = Σ_v M_jv z_v` (or fixed, when its row is empty):
//!
//! - **open curves** ([`ControlMap::open`]): the interior control points themselves (`M` the
//!   identity on `P_1 … P_{n−2}`); the end points stay where the least-squares fit put them (on the
//!   data's end points), and the data's end points are not measured.
//! - **periodic curves** ([`ControlMap::periodic`]): the `n_u` distinct control points of the
//!   periodic curve. Its clamped form (same geometry, knots inserted at the seam, as the periodic
//!   measure uses) has `n_u + p` control points, the first and last `p` of which are combinations of
//!   the distinct points near the seam: `M` is that knot-insertion map, built once by clamping unit
//!   vectors. So any move of the variables keeps the curve periodic and `C^(p−1)` at the seam, and
//!   the seam point moves like any other. Every data point is measured, the first one (repeated at
//!   the end of the measure data at parameter 1) by Newton from both sides of the seam.

use super::objective::{measure_current, CandidateEval, EvalWorkspace, FitData, MAX_DEGREE};
use crate::errors::{Error, Result};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::{NurbsCurve, Vec3};
use std::ops::Range;

/// The movable points of a clamped B-spline and how it is measured (module doc).
#[derive(Clone, Debug)]
pub struct ControlMap {
    /// Per movable point `v`: the clamped control points it moves, `(j, M_jv)`.
    cols: Vec<Vec<(usize, f64)>>,
    /// Per clamped control point `j`: `(v, M_jv)`.
    rows: Vec<Vec<(usize, f64)>>,
    /// The data points whose deviation is constrained (the others are interpolated).
    free: Range<usize>,
    /// For a periodic curve, the number of distinct data points `m` (the measure data repeat the
    /// first point at index `m`).
    seam: Option<usize>,
}

impl ControlMap {
    /// The interior control points of an open clamped curve with `n_ctrl` control points fitted to
    /// `m_points` data points with interpolated ends.
    pub fn open(n_ctrl: usize, m_points: usize) -> ControlMap {
        let inner = 1..n_ctrl.saturating_sub(1).max(1);
        let cols: Vec<Vec<(usize, f64)>> = inner.clone().map(|j| vec![(j, 1.0)]).collect();
        let rows = (0..n_ctrl)
            .map(|j| {
                if inner.contains(&j) {
                    vec![(j - 1, 1.0)]
                } else {
                    Vec::new()
                }
            })
            .collect();
        ControlMap {
            cols,
            rows,
            free: 1..m_points.saturating_sub(1).max(1),
            seam: None,
        }
    }

    /// The `n_u` distinct control points of the periodic curve of degree `degree` with the
    /// unclamped periodic knot vector `knots` (`n_u + p` control points, the last `p` repeating the
    /// first), measured against `m` distinct data points (the measure data have `m + 1`).
    pub fn periodic(degree: usize, knots: &[f64], n_u: usize, m: usize) -> Result<ControlMap> {
        let p = degree;
        let mut cols = Vec::with_capacity(n_u);
        let mut n_clamped = 0;
        for v in 0..n_u {
            let unit: Vec<Vec3> = (0..n_u + p)
                .map(|i| Vec3::new(if i % n_u == v { 1.0 } else { 0.0 }, 0.0, 0.0))
                .collect();
            let clamped = NurbsCurve::bspline(p, knots.to_vec(), unit)?.clamped()?;
            let c = clamped.control_points();
            n_clamped = c.len();
            cols.push(
                c.iter()
                    .enumerate()
                    .filter(|(_, x)| x[0] != 0.0)
                    .map(|(j, x)| (j, x[0]))
                    .collect::<Vec<_>>(),
            );
        }
        if n_clamped != n_u + p {
            return Err(Error::Fit(format!(
                "the clamped periodic curve has {n_clamped} control points, expected {}",
                n_u + p
            )));
        }
        let mut rows = vec![Vec::new(); n_clamped];
        for (v, col) in cols.iter().enumerate() {
            for &(j, c) in col {
                rows[j].push((v, c));
            }
        }
        Ok(ControlMap {
            cols,
            rows,
            free: 0..m,
            seam: Some(m),
        })
    }

    /// Number of movable points.
    pub fn vars(&self) -> usize {
        self.cols.len()
    }

    /// The clamped control points moved by movable point `v`, with their coefficients.
    pub fn col(&self, v: usize) -> &[(usize, f64)] {
        &self.cols[v]
    }

    /// The movable points clamped control point `j` depends on, with their coefficients.
    pub fn row(&self, j: usize) -> &[(usize, f64)] {
        &self.rows[j]
    }

    /// The data points whose deviation is constrained.
    pub fn free_points(&self) -> Range<usize> {
        self.free.clone()
    }

    /// Measures the curve in `ws` ([`measure_current`], projections from `start`), for a periodic
    /// curve with the first data point measured at the seam ([`ControlMap::with_seam`]).
    pub fn measure(&self, data: &FitData, start: &[f64], ws: &mut EvalWorkspace) -> CandidateEval {
        let e = measure_current(data, start, ws);
        self.with_seam(e, data, ws)
    }

    /// For a periodic curve, `e` (an open measure of the curve in `ws`, which takes the first data
    /// point and its repeat as interpolated) with the first point's distance from the curve near the
    /// seam included; its foot goes to both ends of `ws.foot_params`. Unchanged for an open curve or
    /// when `e` has no deviations.
    pub fn with_seam(
        &self,
        e: CandidateEval,
        data: &FitData,
        ws: &mut EvalWorkspace,
    ) -> CandidateEval {
        let Some(m) = self.seam else {
            return e;
        };
        if !e.solved || !e.max_deviation.is_finite() || ws.foot_params.len() != m + 1 {
            return e;
        }
        let (d0, u0) = seam_foot(data.degree, &ws.knots, &ws.ctrl, data.points[0]);
        ws.foot_params[0] = u0;
        ws.foot_params[m] = u0;
        // the open measure averages over m + 1 points with zeros at both ends
        let sum2 = e.rms_deviation * e.rms_deviation * (m + 1) as f64 + d0 * d0;
        CandidateEval {
            max_deviation: e.max_deviation.max(d0),
            rms_deviation: (sum2 / m as f64).sqrt(),
            ..e
        }
    }

    /// The movable points whose image is `ctrl` (least squares `MᵀM z = Mᵀ P`, exact up to
    /// rounding when `ctrl` is an image), for a periodic map the distinct control points.
    pub fn variables_of(&self, ctrl: &[Vec3]) -> Vec<Vec3> {
        let nv = self.vars();
        let mut a = vec![0.0; nv * nv];
        let mut rhs = vec![Vec3::ZERO; nv];
        for (j, row) in self.rows.iter().enumerate() {
            for &(v, c) in row {
                rhs[v] += ctrl[j] * c;
                for &(w, d) in row {
                    a[v * nv + w] += c * d;
                }
            }
        }
        // Gaussian elimination with partial pivoting (small, dense, symmetric positive definite)
        for col in 0..nv {
            let piv = (col..nv)
                .max_by(|&x, &y| a[x * nv + col].abs().total_cmp(&a[y * nv + col].abs()))
                .unwrap_or(col);
            if piv != col {
                for k in 0..nv {
                    a.swap(col * nv + k, piv * nv + k);
                }
                rhs.swap(col, piv);
            }
            let d = a[col * nv + col];
            if d == 0.0 {
                continue;
            }
            for r in col + 1..nv {
                let f = a[r * nv + col] / d;
                if f == 0.0 {
                    continue;
                }
                for k in col..nv {
                    a[r * nv + k] -= f * a[col * nv + k];
                }
                let sub = rhs[col] * f;
                rhs[r] -= sub;
            }
        }
        let mut z = vec![Vec3::ZERO; nv];
        for r in (0..nv).rev() {
            let mut s = rhs[r];
            for k in r + 1..nv {
                s -= z[k] * a[r * nv + k];
            }
            let d = a[r * nv + r];
            z[r] = if d == 0.0 { Vec3::ZERO } else { s * (1.0 / d) };
        }
        z
    }
}

/// `[C, C', C'']` of the B-spline (`knots`, `ctrl`, degree `p <= MAX_DEGREE`) at `u`, without
/// allocating.
fn point_ders(knots: &[f64], ctrl: &[Vec3], p: usize, u: f64) -> [Vec3; 3] {
    const P1: usize = MAX_DEGREE + 1;
    let span = find_span(ctrl.len() - 1, p, u, knots);
    let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
    let (mut ndu, mut a) = ([0.0; P1 * P1], [0.0; 2 * P1]);
    let mut ders = [0.0; 3 * P1];
    let nd = 2.min(p);
    ders_basis_funs_into(
        span, u, p, nd, knots, &mut left, &mut right, &mut ndu, &mut a, &mut ders,
    );
    let mut out = [Vec3::ZERO; 3];
    for (k, o) in out.iter_mut().enumerate().take(nd + 1) {
        for j in 0..=p {
            *o += ctrl[span - p + j] * ders[k * (p + 1) + j];
        }
    }
    out
}

/// Distance of `q` from the clamped closed curve (`knots` on `[0, 1]`, `ctrl`) near its seam and
/// the foot parameter in `[0, 1)`: [`super::periodic::seam_foot_by`] on the raw control points.
pub fn seam_foot(p: usize, knots: &[f64], ctrl: &[Vec3], q: Vec3) -> (f64, f64) {
    super::periodic::seam_foot_by(
        (ctrl[0] - q).norm(),
        q,
        |u| point_ders(knots, ctrl, p, u),
        |u| point_ders(knots, ctrl, p, u)[0],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_periodic_map_reproduces_the_clamped_curve_and_inverts() {
        // a periodic cubic with 7 distinct control points on uneven breakpoints: M z must equal
        // the control points of the clamped curve, and variables_of(M z) must give z back
        let p = 3;
        let breaks = [0.0, 0.1, 0.25, 0.4, 0.55, 0.7, 0.9, 1.0];
        let knots = crate::fit::lsq::periodic_knots(&breaks, p);
        let n_u = 7;
        let z: Vec<Vec3> = (0..n_u)
            .map(|i| {
                let t = i as f64 * 0.9;
                Vec3::new(t.cos() + 0.1 * i as f64, (2.0 * t).sin(), 0.0)
            })
            .collect();
        let wrapped: Vec<Vec3> = (0..n_u + p).map(|i| z[i % n_u]).collect();
        let clamped = NurbsCurve::bspline(p, knots.clone(), wrapped)
            .unwrap()
            .clamped()
            .unwrap();
        let map = ControlMap::periodic(p, &knots, n_u, 20).unwrap();
        assert_eq!(map.vars(), n_u);
        for (j, c) in clamped.control_points().iter().enumerate() {
            let mut s = Vec3::ZERO;
            for &(v, a) in map.row(j) {
                s += z[v] * a;
            }
            assert!((s - *c).norm() < 1e-14, "{j}: {s:?} vs {c:?}");
        }
        let back = map.variables_of(clamped.control_points());
        for (a, b) in back.iter().zip(&z) {
            assert!((*a - *b).norm() < 1e-12, "{a:?} vs {b:?}");
        }
        // the seam point: the curve's first clamped control point is C(0)
        let q = clamped.point(0.97) + Vec3::new(0.0, 1e-3, 0.0);
        let (d, u) = seam_foot(p, clamped.knots(), clamped.control_points(), q);
        assert!(d <= 1e-3 + 1e-12 && u > 0.9, "{d} {u}");
    }
}
