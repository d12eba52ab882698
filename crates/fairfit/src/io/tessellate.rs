//! Tessellation of NURBS surfaces into triangle meshes with vertex normals, and of curves into
//! polylines, with an optional chordal tolerance.
//!
//! The parameter grid starts at `min_per_span` samples per knot span in each direction and is refined
//! interval by interval until the chord height, measured at the quarter points of every grid edge and
//! at every cell centre, is at most the tolerance (or a size limit is hit, which is an error naming the
//! tolerance). Normals are `S_u × S_v`, normalised; at a degenerate point (collapsed edge, pole) the
//! normal is taken a little inside the domain. Geometry far outside unit size (near 1e±300) is
//! tessellated on an exactly rescaled copy (see [`crate::nurbs::scale`]). The grid, the vertices,
//! normals and triangles grow with the square of the intervals per direction and are reserved
//! fallibly: a mesh beyond the memory is a one-line error, never an abort.

use crate::errors::{try_vec, Error, Result};
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::scale::{normalising_factor, scaled_curve, scaled_surface};
use crate::nurbs::{NurbsCurve, NurbsSurface, SurfaceWorkspace, Vec3};

/// Triangles with per-vertex normals, and/or polylines (indices into `vertices`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Unit normals, one per vertex (empty for polylines).
    pub normals: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from the normal side.
    pub triangles: Vec<[u32; 3]>,
    /// Polylines as vertex index lists.
    pub polylines: Vec<Vec<u32>>,
}

/// Options of the tessellation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TessellationOptions {
    /// Maximum chord height (absolute, in model units); `None`: just the initial grid.
    pub chord_tol: Option<f64>,
    /// Initial samples per knot span and direction (at least 1).
    pub min_per_span: usize,
    /// Largest number of intervals per direction before refinement gives up.
    pub max_intervals: usize,
}

impl Default for TessellationOptions {
    fn default() -> Self {
        TessellationOptions {
            chord_tol: None,
            min_per_span: 8,
            max_intervals: 4096,
        }
    }
}

fn initial_params(knots: &[f64], degree: usize, per_span: usize) -> Vec<f64> {
    let bp = distinct_breakpoints(knots, degree);
    let per = per_span.max(1);
    let mut out = Vec::with_capacity((bp.len() - 1) * per + 1);
    for w in bp.windows(2) {
        for k in 0..per {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per as f64);
        }
    }
    if let Some(&last) = bp.last() {
        out.push(last);
    }
    out
}

fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// Most intervals per direction a tessellation may ask for (a surface mesh has its square in vertices).
pub(crate) const MAX_INTERVALS: usize = 1 << 16;

fn check_tol(opts: &TessellationOptions) -> Result<()> {
    if !(1..=MAX_INTERVALS).contains(&opts.max_intervals) || opts.min_per_span > opts.max_intervals
    {
        return Err(Error::InvalidOption(format!(
            "tessellation needs 1 <= samples per span ({}) <= max intervals ({}) <= {MAX_INTERVALS}",
            opts.min_per_span, opts.max_intervals
        )));
    }
    match opts.chord_tol {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(Error::InvalidOption(format!(
            "chord tolerance must be positive and finite, got {t:e}"
        ))),
        _ => Ok(()),
    }
}

/// Runs `tessellate` on a copy scaled by the exact power of two `f` (see [`crate::nurbs::scale`]) with
/// the chord tolerance scaled alike, and scales the vertices back: chord heights, normals and their
/// squares stay in range for geometry near 1e±300. The error names the caller's tolerance.
fn rescaled(
    f: f64,
    opts: &TessellationOptions,
    tessellate: impl FnOnce(&TessellationOptions) -> Result<Mesh>,
) -> Result<Mesh> {
    let scaled_opts = TessellationOptions {
        chord_tol: opts.chord_tol.map(|t| t * f),
        ..*opts
    };
    let mut mesh = tessellate(&scaled_opts).map_err(|e| match e {
        Error::InvalidOption(_) => Error::InvalidOption(format!(
            "chord tolerance {:e} not reached with {} intervals per direction; use a larger tolerance",
            opts.chord_tol.unwrap_or(0.0),
            opts.max_intervals
        )),
        other => other, // out of memory
    })?;
    let g = 1.0 / f;
    for v in &mut mesh.vertices {
        *v = *v * g;
    }
    Ok(mesh)
}

fn refine(ts: &mut Vec<f64>, split: &[bool], max: usize, tol: f64) -> Result<bool> {
    if !split.iter().any(|&s| s) {
        return Ok(false);
    }
    let mut out = Vec::with_capacity(ts.len() * 2);
    for (k, w) in ts.windows(2).enumerate() {
        out.push(w[0]);
        if split[k] {
            out.push(0.5 * (w[0] + w[1]));
        }
    }
    out.extend(ts.last());
    if out.len() > max + 1 {
        return Err(Error::InvalidOption(format!(
            "chord tolerance {tol:e} not reached with {max} intervals per direction; use a larger tolerance"
        )));
    }
    *ts = out;
    Ok(true)
}

/// A curve as one polyline meeting the chord tolerance.
pub fn tessellate_curve(c: &NurbsCurve, opts: &TessellationOptions) -> Result<Mesh> {
    check_tol(opts)?;
    let f = normalising_factor(c.control_points());
    if let Some(t) = (f != 1.0).then(|| scaled_curve(c, f).ok()).flatten() {
        return rescaled(f, opts, |o| tessellate_curve_as_is(&t, o));
    }
    tessellate_curve_as_is(c, opts)
}

fn tessellate_curve_as_is(c: &NurbsCurve, opts: &TessellationOptions) -> Result<Mesh> {
    let mut ts = initial_params(c.knots(), c.degree(), opts.min_per_span);
    if let Some(tol) = opts.chord_tol {
        loop {
            let split: Vec<bool> = ts
                .windows(2)
                .map(|w| {
                    let (a, b) = (c.point(w[0]), c.point(w[1]));
                    [0.25, 0.5, 0.75]
                        .iter()
                        .any(|&f| segment_distance(c.point(w[0] + f * (w[1] - w[0])), a, b) > tol)
                })
                .collect();
            if !refine(&mut ts, &split, opts.max_intervals, tol)? {
                break;
            }
        }
    }
    let vertices = c.points(&ts);
    Ok(Mesh {
        polylines: vec![(0..vertices.len() as u32).collect()],
        vertices,
        ..Mesh::default()
    })
}

/// Room for a grid of `nu × nv` items of type `T`, reserved fallibly (an error naming `what`, not an
/// abort, when memory runs out; a count beyond `usize` fails alike).
fn grid_vec<T>(nu: usize, nv: usize, what: &str) -> Result<Vec<T>> {
    try_vec(nu.saturating_mul(nv), what)
}

/// Chord errors of the grid: (per u interval, per v interval) flags.
fn surface_splits(
    s: &NurbsSurface,
    us: &[f64],
    vs: &[f64],
    tol: f64,
) -> Result<(Vec<bool>, Vec<bool>)> {
    let mut grid: Vec<Vec3> = grid_vec(us.len(), vs.len(), "the tessellation grid")?;
    grid.extend(
        us.iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .map(|(u, v)| s.point(u, v)),
    );
    let nv = vs.len();
    let at = |i: usize, j: usize| grid[i * nv + j];
    let mut split_u = vec![false; us.len() - 1];
    let mut split_v = vec![false; nv - 1];
    let quarter = [0.25, 0.5, 0.75];
    for i in 0..us.len() - 1 {
        for (j, &v) in vs.iter().enumerate() {
            let (a, b) = (at(i, j), at(i + 1, j));
            let du = us[i + 1] - us[i];
            if quarter
                .iter()
                .any(|&f| segment_distance(s.point(us[i] + f * du, v), a, b) > tol)
            {
                split_u[i] = true;
            }
        }
    }
    for (i, &u) in us.iter().enumerate() {
        for j in 0..nv - 1 {
            let (a, b) = (at(i, j), at(i, j + 1));
            let dv = vs[j + 1] - vs[j];
            if quarter
                .iter()
                .any(|&f| segment_distance(s.point(u, vs[j] + f * dv), a, b) > tol)
            {
                split_v[j] = true;
            }
        }
    }
    for i in 0..us.len() - 1 {
        for j in 0..nv - 1 {
            let centre = s.point(0.5 * (us[i] + us[i + 1]), 0.5 * (vs[j] + vs[j + 1]));
            let avg = (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1)) * 0.25;
            // Edges refine first; a cell whose edges are fine but whose centre is not (twist) splits both ways.
            if !(split_u[i] || split_v[j]) && (centre - avg).norm() > tol {
                split_u[i] = true;
                split_v[j] = true;
            }
        }
    }
    Ok((split_u, split_v))
}

fn normal_at(s: &NurbsSurface, u: f64, v: f64, ws: &mut SurfaceWorkspace) -> Vec3 {
    let mut d = [Vec3::ZERO; 4];
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let (uc, vc) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
    for shift in [0.0, 1e-6, 1e-4, 1e-2] {
        let (uu, vv) = (u + (uc - u) * shift, v + (vc - v) * shift);
        s.derivatives_with(uu, vv, 1, ws, &mut d);
        let n = d[2].cross(d[1]);
        let len = n.norm();
        if len > 1e-14 * (d[2].norm() * d[1].norm()).max(f64::MIN_POSITIVE) {
            return n / len;
        }
    }
    Vec3::ZERO
}

/// A surface as a triangle mesh with vertex normals meeting the chord tolerance.
pub fn tessellate_surface(s: &NurbsSurface, opts: &TessellationOptions) -> Result<Mesh> {
    check_tol(opts)?;
    let f = normalising_factor(s.control_points_flat());
    if let Some(t) = (f != 1.0).then(|| scaled_surface(s, f).ok()).flatten() {
        return rescaled(f, opts, |o| tessellate_surface_as_is(&t, o));
    }
    tessellate_surface_as_is(s, opts)
}

fn tessellate_surface_as_is(s: &NurbsSurface, opts: &TessellationOptions) -> Result<Mesh> {
    let mut us = initial_params(s.knots_u(), s.degree_u(), opts.min_per_span);
    let mut vs = initial_params(s.knots_v(), s.degree_v(), opts.min_per_span);
    if let Some(tol) = opts.chord_tol {
        loop {
            let (su, sv) = surface_splits(s, &us, &vs, tol)?;
            let a = refine(&mut us, &su, opts.max_intervals, tol)?;
            let b = refine(&mut vs, &sv, opts.max_intervals, tol)?;
            if !(a || b) {
                break;
            }
        }
    }
    let nv = vs.len();
    let cells = (us.len() - 1).saturating_mul(2);
    let mut mesh = Mesh {
        vertices: grid_vec(us.len(), nv, "the mesh vertices")?,
        normals: grid_vec(us.len(), nv, "the mesh normals")?,
        triangles: grid_vec(cells, nv - 1, "the mesh triangles")?,
        polylines: Vec::new(),
    };
    let mut ws = SurfaceWorkspace::new(s, 1);
    for &u in &us {
        for &v in &vs {
            mesh.vertices.push(s.point(u, v));
            mesh.normals.push(normal_at(s, u, v, &mut ws));
        }
    }
    let idx = |i: usize, j: usize| (i * nv + j) as u32;
    for i in 0..us.len() - 1 {
        for j in 0..nv - 1 {
            for t in [
                [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)],
                [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)],
            ] {
                let [a, b, c] = t.map(|k| mesh.vertices[k as usize]);
                if (b - a).cross(c - a).norm() > 0.0 {
                    mesh.triangles.push(t);
                }
            }
        }
    }
    Ok(mesh)
}
