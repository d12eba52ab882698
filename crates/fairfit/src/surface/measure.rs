//! Surface measures: orthogonal deviation of input points from a surface (projection: nearest sample of
//! a dense parameter grid, then safeguarded Newton on `(u, v)`, never worse than the best sample), the
//! fairness `F` of iso-curves in both directions, and the control-net size.

use super::fairness_proxy::curve_fairness;
use super::iso::{iso_curve_at_u, iso_curve_at_v};
use crate::errors::Result;
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsSurface, SurfaceWorkspace, Vec3};
use rayon::prelude::*;
use serde::Serialize;

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
            grid,
        }
    }

    /// Closest point of the surface to `q`; `hint` adds a Newton start (e.g. known section parameters).
    pub fn project(
        &self,
        q: Vec3,
        hint: Option<(f64, f64)>,
        ws: &mut SurfaceWorkspace,
    ) -> SurfaceProjection {
        let nv = self.vs.len();
        let (mut bi, mut bd) = (0usize, f64::INFINITY);
        for (i, p) in self.grid.iter().enumerate() {
            let d = (*p - q).norm_squared();
            if d < bd {
                bd = d;
                bi = i;
            }
        }
        let start = (self.us[bi / nv], self.vs[bi % nv]);
        let mut best = self.newton(q, start, ws);
        if let Some(h) = hint {
            let alt = self.newton(q, h, ws);
            if alt.distance < best.distance {
                best = alt;
            }
        }
        best
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

/// Orthogonal deviation of `points` (optional parameter hints, same length) from `surface`.
pub fn surface_deviation(
    surface: &NurbsSurface,
    points: &[Vec3],
    hints: Option<&[(f64, f64)]>,
) -> Deviation {
    let proj = SurfaceProjector::new(surface, 6);
    let d: Vec<f64> = points
        .par_iter()
        .enumerate()
        .map_init(
            || SurfaceWorkspace::new(surface, 2),
            |ws, (i, q)| {
                proj.project(*q, hints.and_then(|h| h.get(i).copied()), ws)
                    .distance
            },
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

/// Fairness `F` of a family of iso-curves.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct IsoFairness {
    /// Number of iso-curves.
    pub curves: usize,
    /// Largest `F` of one iso-curve.
    pub max: f64,
    /// Mean `F`.
    pub mean: f64,
    /// Largest per-span `F_j` over all iso-curves.
    pub max_span: f64,
}

/// Surface fairness summary: iso-curves running along u (fixed v) and along v (fixed u, across sections).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SurfaceFairness {
    /// Curves `u ↦ S(u, v)` at `count` evenly spaced v.
    pub along_u: IsoFairness,
    /// Curves `v ↦ S(u, v)` at `count` evenly spaced u (between the sections).
    pub along_v: IsoFairness,
}

fn summarise(fs: Vec<(f64, f64)>) -> IsoFairness {
    let n = fs.len();
    IsoFairness {
        curves: n,
        max: fs.iter().map(|f| f.0).fold(0.0, f64::max),
        mean: if n > 0 {
            fs.iter().map(|f| f.0).sum::<f64>() / n as f64
        } else {
            0.0
        },
        max_span: fs.iter().map(|f| f.1).fold(0.0, f64::max),
    }
}

/// `F` of `count` iso-curves in each direction, evenly spaced strictly inside the domain.
pub fn iso_fairness(surface: &NurbsSurface, count: usize) -> Result<SurfaceFairness> {
    let count = count.max(1);
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let at = |a: f64, b: f64, i: usize| a + (b - a) * (i as f64 + 0.5) / count as f64;
    let mut fu = Vec::with_capacity(count);
    let mut fv = Vec::with_capacity(count);
    for i in 0..count {
        let c = iso_curve_at_v(surface, at(v0, v1, i))?;
        let f = curve_fairness(&c, 2);
        fu.push((f.total, f.max_span()));
        let c = iso_curve_at_u(surface, at(u0, u1, i))?;
        let f = curve_fairness(&c, 2);
        fv.push((f.total, f.max_span()));
    }
    Ok(SurfaceFairness {
        along_u: summarise(fu),
        along_v: summarise(fv),
    })
}
