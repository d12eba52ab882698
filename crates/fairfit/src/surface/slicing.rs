//! Slicing meshes and point clouds into planar sections: `N` planes perpendicular to an axis (or a given
//! normal), evenly spaced strictly inside the data's extent.
//!
//! - Meshes: every triangle crossing a plane gives an exact segment between two crossed mesh edges; the
//!   segments are chained through their shared mesh edges, so chains follow the surface's connectivity.
//!   A chain that ends (at a mesh boundary edge) meets a hole. Per slice the longest chain is kept; other
//!   open pieces are appended end-to-nearest-end when close, and a remaining open end is closed when the
//!   gap is short compared with the chain: every such bridge is reported as a [`Gap`], however short (a
//!   mesh chain only ends at a hole). Loops other than the kept one are reported as dropped.
//! - Point clouds: the points in a thin slab around the plane are projected onto it; with a
//!   tolerance ([`SliceOptions::tolerance`]) they are thinned to one representative per cluster of
//!   radius [`CLUSTER_TOLERANCES`] tolerances (a private module, `slab_cells`: the section's size then
//!   follows the shape and the tolerance, not the point count), and ordered
//!   ([`super::chain::order_points`]); tour edges much longer than the median spacing are gaps. The
//!   points are sorted into their slabs in one pass and the slabs are cut in parallel, collected in
//!   plane order (the same sections on any thread count).

use super::chain::{break_at_gaps, median_spacing, mend_detours, order_points, Gap};
use super::mesh::Mesh;
use super::orient::Section;
use super::pipeline::{MAX_COORDINATE, MIN_SECTION_SIZE};
use super::slab_cells::thin;
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;
use crate::tolerance::Tolerance;
use rayon::prelude::*;
use std::collections::HashMap;

/// The radius of a cloud slab's clusters, in tolerances: a cluster's points lie within half the
/// tolerance of each other in the plane (the size of a tolerance's detail), and two sides of a thin
/// part are merged only where they come that close. Noise across the slab's band can raise it, at
/// most to half the tolerance.
pub const CLUSTER_TOLERANCES: f64 = 0.25;

/// Options of [`slice_mesh`].
#[derive(Clone, Debug)]
pub struct SliceOptions {
    /// Number of planes.
    pub slices: usize,
    /// Plane normal (need not be unit length).
    pub normal: Vec3,
    /// Slab half-thickness for point clouds, as a fraction of the plane spacing.
    pub slab: f64,
    /// A chain edge longer than this many median spacings is a gap.
    pub gap_factor: f64,
    /// Open chains are closed (and the bridge reported) when the gap is below this fraction of their length.
    pub close_fraction: f64,
    /// The fit's tolerance, for point clouds: each slab's points are thinned to clusters of radius
    /// [`CLUSTER_TOLERANCES`] times it. A relative tolerance is a fraction of the largest extent
    /// of a slab's projected points (the largest section's, as the CLI's `--rel-tol`). `None`
    /// (the default): every slab point is a section point. Meshes are not affected.
    pub tolerance: Option<Tolerance>,
}

impl Default for SliceOptions {
    fn default() -> Self {
        SliceOptions {
            slices: 20,
            normal: Vec3::new(0.0, 0.0, 1.0),
            slab: 0.1,
            gap_factor: 5.0,
            close_fraction: 0.25,
            tolerance: None,
        }
    }
}

/// Sections cut from a mesh or cloud, with everything that was not a clean loop reported.
#[derive(Clone, Debug, Default)]
pub struct Slices {
    /// One section per non-empty plane, in plane order.
    pub sections: Vec<Section>,
    /// Signed plane offset along the unit normal, per section.
    pub offsets: Vec<f64>,
    /// Gaps (holes) met, with how they were handled; `section` indexes [`Slices::sections`].
    pub gaps: Vec<Gap>,
    /// Planes that cut nothing usable (offset along the unit normal).
    pub empty_planes: Vec<f64>,
    /// Per section, the number of further chains (other loops or pieces) that were dropped.
    pub dropped_chains: Vec<usize>,
}

fn unit(n: Vec3) -> Result<Vec3> {
    let l = n.norm();
    if !l.is_finite() || l <= 0.0 {
        return Err(Error::InvalidOption(
            "the slicing normal must be a non-zero vector".into(),
        ));
    }
    Ok(n / l)
}

/// Most slicing planes [`slice_mesh`] accepts (every plane cuts every triangle).
pub(crate) const MAX_SLICES: usize = 10_000;

fn plane_offsets(points: &[Vec3], n: Vec3, count: usize) -> Result<Vec<f64>> {
    if !(2..=MAX_SLICES).contains(&count) {
        return Err(Error::InvalidOption(format!(
            "a surface needs at least 2 slices and at most {MAX_SLICES}, got {count}"
        )));
    }
    let (lo, hi) = points
        .iter()
        .map(|p| p.dot(n))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if hi.is_nan() || hi <= lo {
        return Err(Error::InvalidData(
            "the data has no extent along the slicing direction".into(),
        ));
    }
    Ok((0..count)
        .map(|k| lo + (hi - lo) * (k as f64 + 0.5) / count as f64)
        .collect())
}

/// A direction in the plane used to pick seams and start points (the axis least aligned with `n`).
fn in_plane_dir(n: Vec3) -> Vec3 {
    let a = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    let e = a
        .iter()
        .copied()
        .min_by(|x, y| x.dot(n).abs().total_cmp(&y.dot(n).abs()))
        .unwrap_or(a[0]);
    let d = e - n * e.dot(n);
    d / d.norm().max(f64::MIN_POSITIVE)
}

fn chain_length(c: &[Vec3]) -> f64 {
    c.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Slices a mesh (triangles) or a point cloud (no triangles) into sections.
pub fn slice_mesh(mesh: &Mesh, opts: &SliceOptions) -> Result<Slices> {
    let n = unit(opts.normal)?;
    for (name, v, min) in [
        ("gap factor", opts.gap_factor, f64::MIN_POSITIVE),
        ("slab", opts.slab, f64::MIN_POSITIVE),
        ("close fraction", opts.close_fraction, 0.0),
    ] {
        if !(v.is_finite() && v >= min) {
            return Err(Error::InvalidOption(format!(
                "the slicing {name} must be finite and {}, got {v}",
                if min > 0.0 { "> 0" } else { ">= 0" }
            )));
        }
    }
    // the sections must be fittable (see validate_sections); slicing a mesh beyond these sizes would
    // read every plane as empty or every chain as one point
    let size = crate::surface::orient::extent(&mesh.vertices);
    let reach = mesh
        .vertices
        .iter()
        .flat_map(|p| [p.x().abs(), p.y().abs(), p.z().abs()])
        .fold(0.0, f64::max);
    if size > 0.0 && (size < MIN_SECTION_SIZE || reach > MAX_COORDINATE) {
        return Err(Error::InvalidData(format!(
            "the mesh is {size:.3e} across with coordinates up to {reach:.3e}; meshes must be at least \
             {MIN_SECTION_SIZE:e} across with coordinates up to {MAX_COORDINATE:e}: rescale the \
             points (e.g. change their unit)"
        )));
    }
    let offsets = plane_offsets(&mesh.vertices, n, opts.slices)?;
    let dir = in_plane_dir(n);
    let cuts: Vec<Cut> = if mesh.triangles.is_empty() {
        cloud_cuts(&mesh.vertices, n, &offsets, opts, dir)?
    } else {
        offsets
            .iter()
            .map(|&h| slice_triangles_at(mesh, n, h, opts, dir))
            .collect()
    };
    let mut out = Slices::default();
    for (&h, cut) in offsets.iter().zip(cuts) {
        match cut {
            Some((sec, mut gaps, dropped)) => {
                for g in &mut gaps {
                    g.section = out.sections.len();
                }
                out.sections.push(sec);
                out.offsets.push(h);
                out.gaps.extend(gaps);
                out.dropped_chains.push(dropped);
            }
            None => out.empty_planes.push(h),
        }
    }
    Ok(out)
}

/// A plane's section, its gaps (numbered by [`slice_mesh`]) and how many pieces were dropped;
/// `None` when the plane cuts nothing usable.
type Cut = Option<(Section, Vec<Gap>, usize)>;

/// The cuts of a point cloud by the planes at `offsets` along the unit `n`: its points sorted into
/// the planes' slabs, thinned when a tolerance is given, and ordered; the slabs in parallel,
/// collected in plane order.
fn cloud_cuts(
    pts: &[Vec3],
    n: Vec3,
    offsets: &[f64],
    opts: &SliceOptions,
    dir: Vec3,
) -> Result<Vec<Cut>> {
    let (slabs, half) = slab_points(pts, n, offsets, opts.slab);
    let tol = match opts.tolerance {
        None => None,
        Some(t) => Some(absolute_tolerance(t, &slabs)?),
    };
    let plane = (dir, n.cross(dir));
    Ok(slabs
        .into_par_iter()
        .map(|(near, heights)| {
            let near = match tol {
                Some(tol) if near.len() >= 4 => {
                    thin(&near, &heights, half, CLUSTER_TOLERANCES * tol, plane)
                }
                _ => near,
            };
            cut_slab(near, tol.unwrap_or(0.0), dir, opts)
        })
        .collect())
}

/// The tolerance in the data's units: a relative one times the largest extent of a slab's points.
fn absolute_tolerance(t: Tolerance, slabs: &[Slab]) -> Result<f64> {
    let tol = match t {
        Tolerance::Absolute(t) => t,
        Tolerance::Relative(r) => {
            let largest = slabs
                .iter()
                .map(|s| crate::surface::orient::extent(&s.0))
                .fold(0.0, f64::max);
            r * largest
        }
    };
    // a relative tolerance of slabs that hold nothing (no extent) leaves the points unthinned
    let ok = tol.is_finite() && (tol > 0.0 || matches!(t, Tolerance::Relative(r) if r > 0.0));
    if !ok {
        return Err(Error::InvalidOption(format!(
            "the slicing tolerance must be a positive number, got {t:?}"
        )));
    }
    Ok(tol)
}

/// A slab's points projected onto its plane, and their heights above it.
type Slab = (Vec<Vec3>, Vec<f64>);

/// Each plane's slab (the points within `slab` plane spacings of it, as [`SliceOptions::slab`]),
/// projected onto the plane, with their heights above it, in point order; and the slabs'
/// half-thickness. One pass over the points.
fn slab_points(pts: &[Vec3], n: Vec3, offsets: &[f64], slab: f64) -> (Vec<Slab>, f64) {
    let mut slabs = vec![(Vec::new(), Vec::new()); offsets.len()];
    let (first, last) = (offsets[0], offsets[offsets.len() - 1]);
    let (spacing, half) = if offsets.len() > 1 {
        (
            (last - first) / (offsets.len() - 1) as f64,
            slab * (offsets[1] - offsets[0]),
        )
    } else {
        (1.0, slab)
    };
    let top = (offsets.len() - 1) as f64;
    for &p in pts {
        let d = p.dot(n);
        // the candidate planes, widened by one each side: the exact test below decides
        let a = (((d - half - first) / spacing).floor() - 1.0).clamp(0.0, top) as usize;
        let b = (((d + half - first) / spacing).ceil() + 1.0).clamp(0.0, top) as usize;
        for (k, &h) in offsets.iter().enumerate().take(b + 1).skip(a) {
            if (d - h).abs() <= half {
                slabs[k].0.push(p - n * (d - h));
                slabs[k].1.push(d - h);
            }
        }
    }
    (slabs, half)
}

/// One slab's section from its (thinned) points: ordered by a tour (its detours mended when the
/// slab was thinned, `min_spacing > 0`) opened at its largest gap, gaps judged against a spacing of
/// at least `min_spacing`; `None` below four points.
fn cut_slab(near: Vec<Vec3>, min_spacing: f64, dir: Vec3, opts: &SliceOptions) -> Cut {
    if near.len() < 4 {
        return None;
    }
    let mut tour = order_points(&near, dir);
    if min_spacing > 0.0 {
        // a thinned slab: the tour's detours mended before its gaps are judged
        tour = mend_detours(tour);
    }
    let (chain, closed, gaps) = break_at_gaps(tour, opts.gap_factor, 0, min_spacing);
    let sec = if closed {
        Section::closed_loop(chain)
    } else {
        Section {
            points: chain,
            closed: false,
        }
    };
    Some((sec, gaps, 0))
}

/// The cross-section of a triangle mesh by the plane `x·n = h`: the longest chain of crossed
/// edges, with close open pieces bridged onto it (the section, its gaps, and how many pieces were
/// dropped); `None` when the plane misses the mesh or the chain has fewer than four points.
fn slice_triangles_at(mesh: &Mesh, n: Vec3, h: f64, opts: &SliceOptions, dir: Vec3) -> Cut {
    let segs = crossing_segments(mesh, n, h);
    if segs.is_empty() {
        return None;
    }
    let chains = chain_segments(&segs);
    let mut pieces = chain_points(mesh, n, h, chains);
    if pieces.is_empty() {
        return None;
    }
    // longest piece first
    pieces.sort_by(|a, b| chain_length(&b.0).total_cmp(&chain_length(&a.0)));
    let (mut main, mut closed) = pieces.remove(0);
    let mut gaps = Vec::new();
    let typical = median_spacing(&main, closed).max(f64::MIN_POSITIVE);
    let mut dropped = 0usize;
    if !closed {
        closed = join_open_pieces(&mut main, &mut pieces, &mut gaps, opts, typical);
    }
    dropped += pieces.len();
    if main.len() < 4 {
        return None;
    }
    let sec = if closed {
        // start the loop at its extreme point along `dir`, like point-cloud tours
        let s = (0..main.len())
            .max_by(|&a, &b| main[a].dot(dir).total_cmp(&main[b].dot(dir)))
            .unwrap_or(0);
        main.rotate_left(s);
        Section::closed_loop(main)
    } else {
        Section {
            points: main,
            closed: false,
        }
    };
    Some((sec, gaps, dropped))
}

/// The plane `x·n = h`'s crossing segments, one per triangle with vertices on both sides, each as
/// its two crossed edges (vertex pairs, smaller index first), in triangle order. Signed distances
/// that are exactly zero count as positive, so every crossing is a strict sign change.
fn crossing_segments(mesh: &Mesh, n: Vec3, h: f64) -> Vec<[(usize, usize); 2]> {
    let v = &mesh.vertices;
    let side = |i: usize| v[i].dot(n) - h >= 0.0;
    let key = |a: usize, b: usize| if a < b { (a, b) } else { (b, a) };
    let mut segs: Vec<[(usize, usize); 2]> = Vec::new();
    for t in &mesh.triangles {
        let s = [side(t[0]), side(t[1]), side(t[2])];
        if s[0] == s[1] && s[1] == s[2] {
            continue;
        }
        let mut e = Vec::with_capacity(2);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if s[k] != s[(k + 1) % 3] {
                e.push(key(a, b));
            }
        }
        if e.len() == 2 {
            segs.push([e[0], e[1]]);
        }
    }
    segs
}

/// Joins segments sharing a crossed edge into chains of edges (with whether each closes on
/// itself). Walks from open ends first (edges used once), then loops, in segment order, so the
/// result is deterministic; every segment is used once.
fn chain_segments(segs: &[[(usize, usize); 2]]) -> Vec<(Vec<(usize, usize)>, bool)> {
    let mut by_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (i, s) in segs.iter().enumerate() {
        by_edge.entry(s[0]).or_default().push(i);
        by_edge.entry(s[1]).or_default().push(i);
    }
    let mut used = vec![false; segs.len()];
    let mut chains: Vec<(Vec<(usize, usize)>, bool)> = Vec::new();
    let mut starts: Vec<usize> = (0..segs.len())
        .filter(|&i| {
            segs[i]
                .iter()
                .any(|e| by_edge.get(e).is_some_and(|l| l.len() == 1))
        })
        .collect();
    starts.extend(0..segs.len());
    for s0 in starts {
        if used[s0] {
            continue;
        }
        used[s0] = true;
        let (a, b) = (segs[s0][0], segs[s0][1]);
        // orient so that we walk away from an open end if there is one
        let (first, mut cur) = if by_edge.get(&b).is_some_and(|l| l.len() == 1) {
            (b, a)
        } else {
            (a, b)
        };
        let mut chain = vec![first, cur];
        let mut closed = false;
        loop {
            let next = by_edge
                .get(&cur)
                .and_then(|l| l.iter().copied().find(|&j| !used[j]));
            let Some(j) = next else { break };
            used[j] = true;
            let other = if segs[j][0] == cur {
                segs[j][1]
            } else {
                segs[j][0]
            };
            if other == first {
                closed = true;
                break;
            }
            chain.push(other);
            cur = other;
        }
        chains.push((chain, closed));
    }
    chains
}

/// Each chain's points: where each edge crosses the plane (projected back onto it), consecutive
/// repeats dropped; chains with fewer than two points are left out.
fn chain_points(
    mesh: &Mesh,
    n: Vec3,
    h: f64,
    chains: Vec<(Vec<(usize, usize)>, bool)>,
) -> Vec<(Vec<Vec3>, bool)> {
    let v = &mesh.vertices;
    let point_on = |a: usize, b: usize| {
        let (da, db) = (v[a].dot(n) - h, v[b].dot(n) - h);
        let t = da / (da - db);
        let p = v[a] + (v[b] - v[a]) * t;
        p - n * (p.dot(n) - h)
    };
    chains
        .into_iter()
        .map(|(c, closed)| {
            let mut pts: Vec<Vec3> = Vec::with_capacity(c.len());
            for (a, b) in c {
                let p = point_on(a, b);
                if pts.last().is_none_or(|q: &Vec3| q.distance(p) > 0.0) {
                    pts.push(p);
                }
            }
            (pts, closed)
        })
        .filter(|(p, _)| p.len() >= 2)
        .collect()
}

/// Appends open `pieces` to the open chain `main`, end to nearest end, while they are close
/// compared with the chain (each bridge recorded in `gaps`: a mesh chain only ends at a boundary
/// edge, so every bridge crosses a hole, whatever its size); then records the seam gap and returns
/// whether it is short enough to close the chain. Appended pieces are removed from `pieces`.
fn join_open_pieces(
    main: &mut Vec<Vec3>,
    pieces: &mut Vec<(Vec<Vec3>, bool)>,
    gaps: &mut Vec<Gap>,
    opts: &SliceOptions,
    typical: f64,
) -> bool {
    let mut closed = false;
    loop {
        let len = chain_length(main);
        let end = main[main.len() - 1];
        let best = pieces
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.1)
            .flat_map(|(i, p)| {
                [
                    (i, false, end.distance(p.0[0])),
                    (i, true, end.distance(p.0[p.0.len() - 1])),
                ]
            })
            .min_by(|a, b| a.2.total_cmp(&b.2));
        let Some((i, rev, d)) = best else { break };
        if d > opts.close_fraction * len || d > main[0].distance(end) {
            break;
        }
        let (mut p, _) = pieces.remove(i);
        if rev {
            p.reverse();
        }
        gaps.push(Gap {
            section: 0,
            from: end.0,
            to: p[0].0,
            length: d,
            typical_spacing: typical,
            handling: "bridged".into(),
        });
        main.extend(p);
    }
    let len = chain_length(main);
    let d = main[0].distance(main[main.len() - 1]);
    let handling = if d <= opts.close_fraction * len {
        closed = true;
        "bridged"
    } else {
        "open"
    };
    gaps.push(Gap {
        section: 0,
        from: main[main.len() - 1].0,
        to: main[0].0,
        length: d,
        typical_spacing: typical,
        handling: handling.into(),
    });
    closed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangulated open cylinder of radius `r`, `na` segments around, `nz` rings from z = 0 to 2;
    /// triangles whose centre falls in `hole` (angle range, z range) are left out.
    fn cylinder(r: f64, na: usize, nz: usize, hole: Option<((f64, f64), (f64, f64))>) -> Mesh {
        let mut m = Mesh::default();
        for j in 0..=nz {
            for i in 0..na {
                let t = std::f64::consts::TAU * i as f64 / na as f64;
                m.vertices.push(Vec3::new(
                    r * t.cos(),
                    r * t.sin(),
                    2.0 * j as f64 / nz as f64,
                ));
            }
        }
        for j in 0..nz {
            for i in 0..na {
                let (a, b) = (j * na + i, j * na + (i + 1) % na);
                let (c, d) = (a + na, b + na);
                let tc = std::f64::consts::TAU * (i as f64 + 0.5) / na as f64;
                let zc = 2.0 * (j as f64 + 0.5) / nz as f64;
                if let Some(((t0, t1), (z0, z1))) = hole {
                    if tc > t0 && tc < t1 && zc > z0 && zc < z1 {
                        continue;
                    }
                }
                m.triangles.push([a, b, d]);
                m.triangles.push([a, d, c]);
            }
        }
        m
    }

    #[test]
    fn slicing_a_cylinder_mesh_gives_circles_of_its_radius() {
        let (r, na) = (1.5, 256);
        let m = cylinder(r, na, 7, None);
        let s = slice_mesh(
            &m,
            &SliceOptions {
                slices: 5,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(s.sections.len(), 5);
        assert!(s.gaps.is_empty() && s.empty_planes.is_empty());
        let chord = r * (std::f64::consts::PI / na as f64).cos();
        for (sec, &h) in s.sections.iter().zip(&s.offsets) {
            assert!(sec.closed);
            // one crossing per vertical and per diagonal edge, plus the repeated start
            assert_eq!(sec.points.len(), 2 * na + 1);
            for p in &sec.points {
                let rho = (p.x() * p.x() + p.y() * p.y()).sqrt();
                // crossing points lie on the chords between vertices: chord distance <= rho <= r
                assert!(rho <= r + 1e-12 && rho >= chord - 1e-12, "{rho}");
                assert!((p.z() - h).abs() < 1e-12);
            }
        }
        assert!((s.offsets[0] - 0.2).abs() < 1e-12 && (s.offsets[4] - 1.8).abs() < 1e-12);
    }

    #[test]
    fn slicing_a_cylinder_cloud_gives_exact_circles_and_a_hole_is_reported() {
        let r = 0.75;
        let mut pts = Vec::new();
        for j in 0..=100 {
            for i in 0..90 {
                let t = std::f64::consts::TAU * i as f64 / 90.0 + 0.01 * j as f64;
                pts.push(Vec3::new(r * t.cos(), r * t.sin(), j as f64 / 100.0));
            }
        }
        let cloud = Mesh {
            vertices: pts.clone(),
            triangles: vec![],
        };
        let s = slice_mesh(
            &cloud,
            &SliceOptions {
                slices: 4,
                slab: 0.05,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(s.sections.len(), 4);
        assert!(s.gaps.is_empty(), "{:?}", s.gaps);
        for sec in &s.sections {
            assert!(sec.closed);
            for p in &sec.points {
                assert!(((p.x() * p.x() + p.y() * p.y()).sqrt() - r).abs() < 1e-12);
            }
        }
        // remove a window (angles 1..2 rad, z 0.3..0.7): the slices through it report one gap each
        let holed: Vec<Vec3> = pts
            .into_iter()
            .filter(|p| {
                let t = p.y().atan2(p.x());
                !(t > 1.0 && t < 2.0 && p.z() > 0.3 && p.z() < 0.7)
            })
            .collect();
        let s = slice_mesh(
            &Mesh {
                vertices: holed,
                triangles: vec![],
            },
            &SliceOptions {
                slices: 4,
                slab: 0.05,
                ..Default::default()
            },
        )
        .unwrap();
        // planes at z = 0.125, 0.375, 0.625, 0.875: the middle two cross the hole
        let secs: Vec<usize> = s.gaps.iter().map(|g| g.section).collect();
        assert_eq!(secs, vec![1, 2], "{:?}", s.gaps);
        for g in &s.gaps {
            // the missing arc spans about 1 rad: chord 2 r sin(0.5) plus up to one point spacing
            assert!(
                g.length > 2.0 * r * 0.5f64.sin() * 0.9 && g.length < 2.0 * r * 0.6f64.sin(),
                "{}",
                g.length
            );
            assert_eq!(g.handling, "open");
        }
        assert!(!s.sections[1].closed && s.sections[0].closed);
    }

    #[test]
    fn a_hole_in_a_mesh_is_reported_not_bridged_silently() {
        let m = cylinder(1.0, 128, 20, Some(((0.5, 1.2), (0.8, 1.2))));
        let s = slice_mesh(
            &m,
            &SliceOptions {
                slices: 2,
                normal: Vec3::new(0.0, 0.0, 1.0),
                ..Default::default()
            },
        )
        .unwrap();
        // planes at z = 0.5 (intact) and 1.5 (intact); use a plane through the hole instead
        assert!(s.gaps.is_empty());
        let s = slice_mesh(
            &m,
            &SliceOptions {
                slices: 1 + 1,
                normal: Vec3::new(0.0, 0.0, 1.0),
                ..Default::default()
            },
        );
        assert!(s.is_ok());
        let s = slice_mesh(
            &m,
            &SliceOptions {
                slices: 4,
                ..Default::default()
            },
        )
        .unwrap();
        // planes at 0.25, 0.75, 1.25, 1.75: none inside (0.8, 1.2)
        assert!(s.gaps.is_empty());
        let s = slice_mesh(
            &m,
            &SliceOptions {
                slices: 5,
                ..Default::default()
            },
        )
        .unwrap();
        // plane at z = 1.0 crosses the hole: one gap of about the hole's angular width (0.7 rad)
        assert_eq!(s.gaps.len(), 1, "{:?}", s.gaps);
        let g = &s.gaps[0];
        assert_eq!(g.section, 2);
        let want = 2.0 * (0.35f64).sin();
        assert!((g.length - want).abs() < 0.06, "{} vs {want}", g.length);
        assert!(g.length > 5.0 * g.typical_spacing);
        assert_eq!(g.handling, "bridged");
    }

    #[test]
    fn bad_slicing_options_are_errors() {
        let m = cylinder(1.0, 16, 2, None);
        assert!(slice_mesh(
            &m,
            &SliceOptions {
                slices: 1,
                ..Default::default()
            }
        )
        .is_err());
        assert!(slice_mesh(
            &m,
            &SliceOptions {
                normal: Vec3::ZERO,
                ..Default::default()
            }
        )
        .is_err());
        let flat = Mesh {
            vertices: vec![Vec3::new(0.0, 0.0, 1.0); 5],
            triangles: vec![],
        };
        assert!(slice_mesh(&flat, &SliceOptions::default()).is_err());
    }
}
