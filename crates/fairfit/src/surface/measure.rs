//! Surface measures: orthogonal deviation of input points from a surface (projection: nearest sample of
//! a dense parameter grid, then safeguarded Newton on `(u, v)`, never worse than the best sample). The
//! fairness of iso-curves comes from [`crate::fair::surface_fairness`].
//!
//! Points whose parameters are roughly known (section points: their section curve's parameter and
//! the section's `v`) are projected near them only ([`SurfaceProjector::project_near`],
//! [`surface_deviation_near`]): the samples of the hint's knot span and one span on each side, so the
//! cost per point does not grow with the surface's net (a whole-grid scan per point took minutes
//! for 10^5-10^6 points).
//!
//! Both searches end the same way (`SurfaceProjector::feet`): Newton from the nearest sample and
//! from the hint, the nearer foot kept. On a surface periodic in a direction a start on the seam has
//! a twin on the other side (the same point, the other end of the domain), and Newton runs from both:
//! the parameters are clamped to the domain, so a foot just across the seam is out of reach from
//! the wrong side (from `u = 0` toward `u = 1 − δ`, Newton stops at the domain's end, as far from
//! the point as the seam is).

use super::point_grid::PointGrid;
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};
use rayon::prelude::*;
use serde::Serialize;
use std::sync::OnceLock;

/// The foot point of a surface projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceProjection {
    /// Parameters of the foot point.
    pub u: f64,
    /// Parameters of the foot point.
    pub v: f64,
    /// Distance from the point to `S(u, v)`.
    pub distance: f64,
}

/// Projects points onto one surface; the sample grid is computed once.
#[derive(Clone, Debug)]
pub struct SurfaceProjector<'a> {
    surface: &'a NurbsSurface,
    us: Vec<f64>,
    vs: Vec<f64>,
    grid: Vec<Vec3>,
    /// `grid` on a uniform grid of cells: the nearest sample without a scan of every sample (built
    /// by the first whole-surface projection; the hinted one never needs it).
    index: OnceLock<PointGrid>,
    per_span: usize,
    /// Periodic in u and in v: a start on the seam has a twin across it.
    periodic: (bool, bool),
}

fn sample_params(knots: &[f64], degree: usize, per_span: usize) -> Vec<f64> {
    let b = distinct_breakpoints(knots, degree);
    let mut out = Vec::new();
    for w in b.windows(2) {
        for k in 0..per_span {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
        }
    }
    out.push(*b.last().unwrap_or(&1.0));
    out
}

impl<'a> SurfaceProjector<'a> {
    /// Samples `surface` with `per_span` parameters per knot span in each direction.
    pub fn new(surface: &'a NurbsSurface, per_span: usize) -> Self {
        let per_span = per_span.max(2);
        let us = sample_params(surface.knots_u(), surface.degree_u(), per_span);
        let vs = sample_params(surface.knots_v(), surface.degree_v(), per_span);
        let uv: Vec<(f64, f64)> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .collect();
        let mut grid = vec![Vec3::ZERO; uv.len()];
        surface.points_into(&uv, &mut grid);
        SurfaceProjector {
            surface,
            us,
            vs,
            index: OnceLock::new(),
            grid,
            per_span,
            periodic: (surface.is_periodic_u(), surface.is_periodic_v()),
        }
    }

    /// Closest point of the surface to `q` searched near `hint` (module doc): the nearest grid
    /// sample within one knot span of the hint's samples in each direction, then Newton from it and
    /// from the hint, the better kept.
    pub fn project_near(
        &self,
        q: Vec3,
        hint: (f64, f64),
        ws: &mut SurfaceWorkspace,
    ) -> SurfaceProjection {
        let nv = self.vs.len();
        let window = |ts: &[f64], t: f64| {
            let i = ts.partition_point(|&x| x < t).min(ts.len() - 1);
            (
                i.saturating_sub(self.per_span),
                (i + self.per_span).min(ts.len() - 1),
            )
        };
        let (iu0, iu1) = window(&self.us, hint.0);
        let (iv0, iv1) = window(&self.vs, hint.1);
        let (mut bi, mut bd) = (iu0 * nv + iv0, f64::INFINITY);
        for iu in iu0..=iu1 {
            for iv in iv0..=iv1 {
                let i = iu * nv + iv;
                let d = (self.grid[i] - q).norm_squared();
                if d < bd {
                    bd = d;
                    bi = i;
                }
            }
        }
        self.feet(q, (self.us[bi / nv], self.vs[bi % nv]), Some(hint), ws)
    }

    /// Closest point of the surface to `q`; `hint` adds a Newton start (e.g. known section parameters).
    pub fn project(
        &self,
        q: Vec3,
        hint: Option<(f64, f64)>,
        ws: &mut SurfaceWorkspace,
    ) -> SurfaceProjection {
        let nv = self.vs.len();
        // the nearest sample (the first of equals, as a scan of every sample finds)
        let index = self.index.get_or_init(|| PointGrid::new(&self.grid));
        let bi = index.nearest(&self.grid, q).unwrap_or(0);
        self.feet(q, (self.us[bi / nv], self.vs[bi % nv]), hint, ws)
    }

    /// The nearest of the feet Newton finds from `start`, from the twins of `start` across a
    /// periodic seam, from `hint` and from its twins (module doc); ties keep the earlier.
    fn feet(
        &self,
        q: Vec3,
        start: (f64, f64),
        hint: Option<(f64, f64)>,
        ws: &mut SurfaceWorkspace,
    ) -> SurfaceProjection {
        let mut best = self.newton(q, start, ws);
        let hinted = hint
            .into_iter()
            .flat_map(|h| std::iter::once(h).chain(self.twins(h)));
        for t in self.twins(start).into_iter().chain(hinted) {
            let alt = self.newton(q, t, ws);
            if alt.distance < best.distance {
                best = alt;
            }
        }
        best
    }

    /// The twins of `(u, v)` across the seams of its periodic directions: the same surface point at
    /// the other end of the domain (none where `(u, v)` is on no periodic seam).
    fn twins(&self, (u, v): (f64, f64)) -> Vec<(f64, f64)> {
        let s = self.surface;
        let across = |t: f64, (a, b): (f64, f64), periodic: bool| {
            if !periodic {
                None
            } else if t <= a {
                Some(b)
            } else if t >= b {
                Some(a)
            } else {
                None
            }
        };
        let tu = across(u, s.domain_u(), self.periodic.0);
        let tv = across(v, s.domain_v(), self.periodic.1);
        [tu.map(|x| (x, v)), tv.map(|y| (u, y)), tu.zip(tv)]
            .into_iter()
            .flatten()
            .collect()
    }

    fn newton(&self, q: Vec3, start: (f64, f64), ws: &mut SurfaceWorkspace) -> SurfaceProjection {
        let s = self.surface;
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let (mut u, mut v) = (start.0.clamp(u0, u1), start.1.clamp(v0, v1));
        let mut d = [Vec3::ZERO; 9];
        s.derivatives_with(u, v, 2, ws, &mut d);
        let mut best = SurfaceProjection {
            u,
            v,
            distance: (d[0] - q).norm(),
        };
        for _ in 0..30 {
            let r = d[0] - q;
            let (su, sv) = (d[3], d[1]);
            let (suu, suv, svv) = (d[6], d[4], d[2]);
            let f = su.dot(r);
            let g = sv.dot(r);
            let a11 = su.dot(su) + suu.dot(r);
            let a12 = su.dot(sv) + suv.dot(r);
            let a22 = sv.dot(sv) + svv.dot(r);
            let det = a11 * a22 - a12 * a12;
            let (du, dv) = if det.abs() > 1e-300 && a11 > 0.0 && det > 0.0 {
                ((-f * a22 + g * a12) / det, (-g * a11 + f * a12) / det)
            } else {
                // gradient step scaled by the metric diagonal
                let (m1, m2) = (su.dot(su).max(1e-300), sv.dot(sv).max(1e-300));
                (-f / m1, -g / m2)
            };
            let mut step = 1.0;
            let mut improved = false;
            for _ in 0..8 {
                let nu = (u + step * du).clamp(u0, u1);
                let nv = (v + step * dv).clamp(v0, v1);
                let p = s.point(nu, nv);
                let dist = (p - q).norm();
                if dist < best.distance {
                    best = SurfaceProjection {
                        u: nu,
                        v: nv,
                        distance: dist,
                    };
                    u = nu;
                    v = nv;
                    improved = true;
                    break;
                }
                step *= 0.5;
            }
            if !improved || (du.abs() < 1e-15 && dv.abs() < 1e-15) {
                break;
            }
            s.derivatives_with(u, v, 2, ws, &mut d);
        }
        best
    }
}

/// Deviation statistics of points from a surface.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Deviation {
    /// Largest orthogonal distance.
    pub max: f64,
    /// Root mean square of the orthogonal distances.
    pub rms: f64,
    /// Number of points measured.
    pub points: usize,
}

/// Orthogonal deviation of `points` from `surface`, each projected near its parameters `hints`
/// (same length; [`SurfaceProjector::project_near`]).
pub fn surface_deviation_near(
    surface: &NurbsSurface,
    points: &[Vec3],
    hints: &[(f64, f64)],
) -> Deviation {
    deviation(surface, points, |proj, i, q, ws| {
        proj.project_near(q, hints[i], ws)
    })
}

/// Orthogonal deviation of `points` (optional parameter hints, same length) from `surface`.
pub fn surface_deviation(
    surface: &NurbsSurface,
    points: &[Vec3],
    hints: Option<&[(f64, f64)]>,
) -> Deviation {
    deviation(surface, points, |proj, i, q, ws| {
        proj.project(q, hints.and_then(|h| h.get(i).copied()), ws)
    })
}

/// The deviation statistics of `points` from `surface`, point `i` projected by `project` (one
/// projector sampling 6 parameters per span, one workspace per worker).
fn deviation(
    surface: &NurbsSurface,
    points: &[Vec3],
    project: impl Fn(&SurfaceProjector, usize, Vec3, &mut SurfaceWorkspace) -> SurfaceProjection + Sync,
) -> Deviation {
    let proj = SurfaceProjector::new(surface, 6);
    let d: Vec<f64> = points
        .par_iter()
        .enumerate()
        .map_init(
            || SurfaceWorkspace::new(surface, 2),
            |ws, (i, &q)| project(&proj, i, q, ws).distance,
        )
        .collect();
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = if d.is_empty() {
        0.0
    } else {
        (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
    };
    Deviation {
        max,
        rms,
        points: d.len(),
    }
}
