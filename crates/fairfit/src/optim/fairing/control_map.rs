//! Which control points the final fairing stages ([`super::band`], [`mod@super::polish`]) may
//! move, and how a curve is measured there, for open and for periodic (closed) curves.
//!
//! Both stages work on a clamped B-spline in an [`EvalWorkspace`]. Their variables are the
//! *movable points* `z_v`; every clamped control point is a fixed linear combination of them,
//! `P_j = Σ_v M_jv z_v` (or fixed, when its row is empty):
//!
//! - **open curves** ([`ControlMap::open_ends`] with [`EndCondition::Pinned`]): the interior control points themselves (`M` the
//!   identity on `P_1 … P_{n−2}`); the end points stay where the least-squares fit put them (on the
//!   data's end points), and the data's end points are not measured.
//! - **open curves with free ends** ([`ControlMap::open_ends`] with [`EndCondition::Free`]): every
//!   control point, the end points `P_0`, `P_{n−1}` included. The data's end points are measured
//!   at the curve's end points (`‖P_0 − Q_0‖`, `‖P_{n−1} − Q_{m−1}‖`, the feet held at 0 and 1;
//!   [`ControlMap::end_point`]): that distance bounds their orthogonal distance, so the tolerance
//!   holds, and the curve's ends stay within the tolerance of the data's ends (the curve still
//!   spans the data, as the band optimum of `bench/band_optimum.py` requires).
//! - **periodic curves** ([`ControlMap::periodic`]): the `n_u` distinct control points of the
//!   periodic curve. Its clamped form (same geometry, knots inserted at the seam, as the periodic
//!   measure uses) has `n_u + p` control points, the first and last `p` of which are combinations of
//!   the distinct points near the seam: `M` is that knot-insertion map, built once by clamping unit
//!   vectors. So any move of the variables keeps the curve periodic and `C^(p−1)` at the seam, and
//!   the seam point moves like any other. Every data point is measured, the first one (repeated at
//!   the end of the measure data at parameter 1) by Newton from both sides of the seam.

use crate::errors::{Error, Result};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::search::objective::{
    measure_current, CandidateEval, EvalWorkspace, FitData, MAX_DEGREE,
};
use std::ops::Range;

/// Whether the end points of an open curve move in the final fairing stages (module doc).
///
/// Only open curves have end points; a closed (periodic) curve has none, and the option does not
/// apply to it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EndCondition {
    /// The curve's end points stay on the data's first and last points (the least-squares fit
    /// interpolates them).
    #[default]
    Pinned,
    /// The curve's end points move with the other control points, each within the tolerance of
    /// its data end point, like every other data point (the least-squares start still interpolates
    /// them).
    Free,
}

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
    /// For an open curve with free ends, the number of data points `m`: the data's end points are
    /// measured at the curve's end points.
    ends: Option<usize>,
}

impl ControlMap {
    /// The control points of an open clamped curve with `n_ctrl` control points fitted to
    /// `m_points` data points: with [`EndCondition::Pinned`] the interior ones,
    /// with [`EndCondition::Free`] all of them, every data point constrained (module doc).
    pub fn open_ends(n_ctrl: usize, m_points: usize, ends: EndCondition) -> ControlMap {
        if ends == EndCondition::Free && n_ctrl >= 2 && m_points >= 2 {
            let cols = (0..n_ctrl).map(|j| vec![(j, 1.0)]).collect();
            let rows = (0..n_ctrl).map(|j| vec![(j, 1.0)]).collect();
            return ControlMap {
                cols,
                rows,
                free: 0..m_points,
                seam: None,
                ends: Some(m_points),
            };
        }
        ControlMap::open_fixed(n_ctrl, m_points, 1, 1)
    }

    /// The control points an open curve fitted to `data` may move (`n_ctrl` of them, ends as
    /// `ends`): [`ControlMap::open_ends`], or with the data's end conditions
    /// ([`FitData::ends`]) the points between those the conditions fix (their ends pinned).
    pub fn open_for(n_ctrl: usize, data: &FitData, ends: EndCondition) -> ControlMap {
        let m = data.points.len();
        if data.ends.is_none() {
            return ControlMap::open_ends(n_ctrl, m, ends);
        }
        let (lo, hi) = data.ends.fixed_points();
        ControlMap::open_fixed(n_ctrl, m, lo, hi)
    }

    /// An open curve with its first `lo` and last `hi` control points fixed (at least one each),
    /// the data's end points interpolated.
    fn open_fixed(n_ctrl: usize, m_points: usize, lo: usize, hi: usize) -> ControlMap {
        let inner = lo.min(n_ctrl)..n_ctrl.saturating_sub(hi).max(lo.min(n_ctrl));
        let cols: Vec<Vec<(usize, f64)>> = inner.clone().map(|j| vec![(j, 1.0)]).collect();
        let rows = (0..n_ctrl)
            .map(|j| {
                if inner.contains(&j) {
                    vec![(j - inner.start, 1.0)]
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
            ends: None,
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
            ends: None,
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

    /// Whether data point `i` is an end point measured at the curve's end ([`EndCondition::Free`]):
    /// its foot stays at 0 or 1 and its whole distance counts (no sliding along the curve).
    pub fn end_point(&self, i: usize) -> bool {
        self.ends.is_some_and(|m| i == 0 || i + 1 == m)
    }

    /// Measures the curve in `ws` ([`measure_current`], projections from `start`), for a periodic
    /// curve with the first data point measured at the seam, for free ends with the end points
    /// measured ([`ControlMap::with_seam`]).
    pub fn measure(&self, data: &FitData, start: &[f64], ws: &mut EvalWorkspace) -> CandidateEval {
        let e = measure_current(data, start, ws);
        self.with_seam(e, data, ws)
    }

    /// For a periodic curve, `e` (an open measure of the curve in `ws`, which takes the first data
    /// point and its repeat as interpolated) with the first point's distance from the curve near the
    /// seam included; its foot goes to both ends of `ws.foot_params`. For an open curve with free
    /// ends, `e` with the end points' distances from the curve's ends included (`with_ends`).
    /// Unchanged for an open curve with pinned ends or when `e` has no deviations.
    pub fn with_seam(
        &self,
        e: CandidateEval,
        data: &FitData,
        ws: &mut EvalWorkspace,
    ) -> CandidateEval {
        if let Some(m) = self.ends {
            return with_ends(e, data, ws, m);
        }
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

/// `e` (an open measure of the curve in `ws`, which takes the `m` data points' ends as
/// interpolated) with the distances `‖P_0 − Q_0‖` and `‖P_{n−1} − Q_{m−1}‖` of the end points from
/// the curve's end points included; their feet are set to 0 and 1. Unchanged when `e` has no
/// deviations.
fn with_ends(e: CandidateEval, data: &FitData, ws: &mut EvalWorkspace, m: usize) -> CandidateEval {
    if !e.solved
        || !e.max_deviation.is_finite()
        || ws.foot_params.len() != m
        || data.points.len() != m
        || ws.ctrl.is_empty()
    {
        return e;
    }
    let d0 = (ws.ctrl[0] - data.points[0]).norm();
    let d1 = (ws.ctrl[ws.ctrl.len() - 1] - data.points[m - 1]).norm();
    ws.foot_params[0] = 0.0;
    ws.foot_params[m - 1] = 1.0;
    // the open measure averages over the m points with zeros at both ends
    let sum2 = e.rms_deviation * e.rms_deviation * m as f64 + d0 * d0 + d1 * d1;
    CandidateEval {
        max_deviation: e.max_deviation.max(d0).max(d1),
        rms_deviation: (sum2 / m as f64).sqrt(),
        ..e
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
/// the foot parameter in `[0, 1)`: [`crate::optim::search::periodic::seam_foot_by`] on the raw control points.
pub fn seam_foot(p: usize, knots: &[f64], ctrl: &[Vec3], q: Vec3) -> (f64, f64) {
    crate::optim::search::periodic::seam_foot_by(
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

    #[test]
    fn free_ends_move_every_control_point_and_measure_the_data_ends_at_the_curve_ends() {
        // a cubic on 12 points of y = x², its end control points moved off the data's ends by
        // (0, 3e-4) and (−4e-4, 0): the free map must report those distances as the ends'
        // deviations (the interior points' projections are unchanged), the pinned map not
        use crate::optim::search::objective::{evaluate_candidate, set_knots};
        let m = 12;
        let points: Vec<Vec3> = (0..m)
            .map(|i| {
                let x = i as f64 / (m - 1) as f64;
                Vec3::new(x, x * x, 0.0)
            })
            .collect();
        let data = FitData {
            points,
            params: (0..m).map(|i| i as f64 / (m - 1) as f64).collect(),
            degree: 3,
            planar: true,
            corrections: 0,
            ends: Default::default(),
            bands: Default::default(),
        };
        let mut ws = EvalWorkspace::default();
        set_knots(3, &[0.5], &mut ws);
        let e = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
        assert!(e.solved && e.max_deviation < 1e-12, "{}", e.max_deviation);
        let n = ws.ctrl.len();
        ws.ctrl[0] += Vec3::new(0.0, 3e-4, 0.0);
        ws.ctrl[n - 1] += Vec3::new(-4e-4, 0.0, 0.0);
        let start = ws.foot_params.clone();
        let pinned = ControlMap::open_ends(n, m, EndCondition::Pinned);
        let free = ControlMap::open_ends(n, m, EndCondition::Free);
        assert_eq!((pinned.vars(), free.vars()), (n - 2, n));
        assert_eq!(free.free_points(), 0..m);
        assert!(free.end_point(0) && free.end_point(m - 1) && !free.end_point(1));
        assert!(!pinned.end_point(0));
        let ep = pinned.measure(&data, &start, &mut ws);
        let ef = free.measure(&data, &start, &mut ws);
        // moving P_0 up by 3e-4 moves the first interior points by less than that
        assert!(ep.max_deviation < 3e-4, "{}", ep.max_deviation);
        assert!(
            (ef.max_deviation - 4e-4).abs() < 1e-15,
            "{}",
            ef.max_deviation
        );
        let rms2 = (ep.rms_deviation.powi(2) * m as f64 + 9e-8 + 16e-8) / m as f64;
        assert!((ef.rms_deviation - rms2.sqrt()).abs() < 1e-15);
        assert_eq!((ws.foot_params[0], ws.foot_params[m - 1]), (0.0, 1.0));
    }
}
