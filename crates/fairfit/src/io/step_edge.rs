//! STEP `EDGE_CURVE`s cut their curve at their vertices: the piece of the edge's geometry between its
//! `edge_start` and `edge_end` `VERTEX_POINT`s, as OpenCASCADE reads an edge.
//!
//! CAD systems write the edges of a face or shell as `EDGE_CURVE(name, start, end, geometry,
//! same_sense)` with an untrimmed geometry (a whole `CIRCLE` for an arc, the whole B-spline of a
//! sub-range), often wrapped in a `SURFACE_CURVE` / `SEAM_CURVE` / `INTERSECTION_CURVE` whose
//! `curve_3d` is taken. The edge runs from its start vertex to its end vertex: along the curve when
//! `same_sense` is `.T.`, against it when `.F.` (the piece of the curve from the end vertex to the
//! start vertex, reversed), across the seam of a closed curve when the vertices ask for it. The
//! vertices are taken at their projections onto the curve (CAD vertices carry a tolerance: within
//! 1e-3 of the curve's size, else the file is refused with one line naming the edge; the size of an
//! unbounded parabola or hyperbola is its focal distance or larger semi-axis, or the distance of the
//! farther vertex from its placement's origin if that is larger); a vertex whose
//! distance from an end of the curve is within 1e-7 of the size plus twice its distance from the curve
//! is that end. A
//! B-spline (or a `TRIMMED_CURVE`, read as in [`super::step_read`]) is cut exactly by knot insertion,
//! two pieces joined at the seam ([`super::cad_chain::join_segments`]) for a closed curve; a `CIRCLE`
//! or `ELLIPSE` gives the exact arc between the vertices' angles; an untrimmed `PARABOLA` or `HYPERBOLA`
//! gives the arc between the vertices. An edge that spans its whole curve (both vertices at its ends,
//! or one vertex on a closed curve) leaves the curve as it is read without edges.

use super::p21::{Exchange, Instance, Value};
use super::step_conic::Trim;
use super::step_read::{err, Trimmed};
use crate::diffgeo::CurveProjector;
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, Vec3};
use std::collections::BTreeMap;

/// Largest distance of a vertex from its curve, relative to the curve's size (CAD systems write
/// vertices with their own tolerance, up to about 1e-4 of a part's size).
const ON_CURVE: f64 = 1e-3;

/// The error for a vertex `d` off the curve `#basis`.
fn off_curve(k: usize, d: f64, basis: u64, id: u64, inst: &Instance) -> crate::errors::Error {
    err(
        id,
        inst,
        format!(
            "its {} vertex lies {d:.3e} off its curve #{basis} (more than 1e-3 of the curve's size)",
            if k == 0 { "start" } else { "end" },
        ),
    )
}

/// Distance, relative to the curve's size, within which a vertex is an end of the curve.
const AT_END: f64 = 1e-7;

/// One `EDGE_CURVE` read: the id of the curve it cuts (the `curve_3d` of a surface curve, or the
/// geometry itself), the piece and its kind (`edge` for a B-spline, a conic's kind), and whether the
/// piece is the whole curve (then as it is read without edges).
pub(super) struct Edge {
    pub basis: u64,
    pub curve: NurbsCurve,
    pub kind: &'static str,
    pub whole: bool,
}

/// The 3D curve of an edge's geometry `#g`: the `curve_3d` of a `SURFACE_CURVE`, `SEAM_CURVE` or
/// `INTERSECTION_CURVE`, else `#g` itself.
fn curve_3d(x: &Exchange, g: u64) -> u64 {
    x.data
        .get(&g)
        .and_then(|inst| {
            ["SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"]
                .iter()
                .find_map(|n| inst.part(n))
        })
        .and_then(|p| p.params.get(1))
        .and_then(Value::as_ref_id)
        .unwrap_or(g)
}

/// The point of the `VERTEX_POINT` `v`.
fn vertex(x: &Exchange, v: Option<&Value>, id: u64, inst: &Instance) -> Result<Vec3> {
    let vp = v
        .and_then(Value::as_ref_id)
        .and_then(|r| x.data.get(&r))
        .and_then(|vi| vi.part("VERTEX_POINT"))
        .and_then(|p| p.params.get(1));
    match vp {
        Some(p) => super::step_read::point(x, p, id, inst),
        None => Err(err(
            id,
            inst,
            "an edge_start or edge_end is not a VERTEX_POINT with a CARTESIAN_POINT",
        )),
    }
}

/// Every `EDGE_CURVE` whose geometry fairfit reads (a B-spline, a conic, a parabola or hyperbola, or
/// a `TRIMMED_CURVE` of `trims`), by its id; `skip`: ids read as nothing (parameter-space curves).
pub(super) fn edges(
    x: &Exchange,
    trims: &BTreeMap<u64, Trimmed>,
    skip: &std::collections::BTreeSet<u64>,
) -> Result<BTreeMap<u64, Edge>> {
    let mut out = BTreeMap::new();
    for (&id, inst) in &x.data {
        let Some(e) = inst.part("EDGE_CURVE") else {
            continue;
        };
        let Some(g) = e.params.get(3).and_then(Value::as_ref_id) else {
            continue;
        };
        let basis = curve_3d(x, g);
        let Some(b) = x.data.get(&basis) else {
            continue;
        };
        if skip.contains(&basis) {
            continue;
        }
        let sense = !matches!(e.params.get(4), Some(Value::Enum(s)) if s == "F");
        let ends = || -> Result<[Vec3; 2]> {
            Ok([
                vertex(x, e.params.get(1), id, inst)?,
                vertex(x, e.params.get(2), id, inst)?,
            ])
        };
        let by_points = |ends: [Vec3; 2]| {
            ends.map(|p| Trim {
                param: None,
                point: Some(p),
            })
        };
        let whole = |c: &NurbsCurve, kind| (c.clone(), kind, true);
        let (curve, kind, whole) = if let Some(t) = trims.get(&basis) {
            let kind = if t.kind == "trimmed" { "edge" } else { t.kind };
            match cut_bspline(&t.curve, ends()?, sense, basis, id, inst)? {
                Some(c) => (c, kind, false),
                None => whole(&t.curve, kind),
            }
        } else if let Some(c) = super::step_read::curve(x, basis, b)? {
            match cut_bspline(&c, ends()?, sense, basis, id, inst)? {
                Some(p) => (p, "edge", false),
                None => whole(&c, "edge"),
            }
        } else if let Some(c) = super::step_conic::conic(x, basis, b)? {
            // the vertices moved onto the conic (within their tolerance)
            let mut on = ends()?;
            for (k, p) in on.iter_mut().enumerate() {
                let (t, d) = c.angle_of(*p);
                if d.is_nan() || d > ON_CURVE * c.a.max(c.b) {
                    return Err(off_curve(k, d, basis, id, inst));
                }
                *p = c.at(t);
            }
            let (arc, kind) =
                super::step_conic::trimmed_conic(&c, by_points(on), sense, true, 1.0, id, inst)?;
            if kind == c.kind(true) {
                let full = c.full(0.0).map_err(|e| err(id, inst, e))?;
                (full, kind, true)
            } else {
                (arc, kind, false)
            }
        } else if let Some(c) = super::step_conic::open_conic(x, basis, b)? {
            // the vertices moved onto the parabola or hyperbola (within their tolerance, as above)
            let mut on = ends()?;
            let size = c.size_with(&on);
            for (k, p) in on.iter_mut().enumerate() {
                let (t, d) = c.nearest(*p);
                if d.is_nan() || d > ON_CURVE * size {
                    return Err(off_curve(k, d, basis, id, inst));
                }
                *p = c.at(t);
            }
            let trims = by_points(on);
            let (arc, kind) = super::step_conic::trimmed_open_conic(&c, trims, true, id, inst)?;
            (arc, kind, false)
        } else {
            continue;
        };
        out.insert(
            id,
            Edge {
                basis,
                curve,
                kind,
                whole,
            },
        );
    }
    Ok(out)
}

/// The piece of the B-spline `c` (`#basis`) from the vertex `ends[0]` to `ends[1]` (see the module
/// documentation), `None` when that is the whole curve.
fn cut_bspline(
    c: &NurbsCurve,
    ends: [Vec3; 2],
    sense: bool,
    basis: u64,
    id: u64,
    inst: &Instance,
) -> Result<Option<NurbsCurve>> {
    let size = crate::fit::sampling::control_extent(c.control_points());
    let (a, b) = c.domain();
    let (ca, cb) = (c.point(a), c.point(b));
    let closed = (ca - cb).norm() <= AT_END * size;
    let proj = CurveProjector::new(c, 16);
    let mut u = [(0.0, 0.0); 2];
    for (k, &p) in ends.iter().enumerate() {
        let pr = proj.project(p);
        if pr.distance.is_nan() || pr.distance > ON_CURVE * size {
            return Err(off_curve(k, pr.distance, basis, id, inst));
        }
        u[k] = (pr.u, pr.distance);
    }
    // the piece runs forward along the curve from lo to hi
    let (lo_p, hi_p, [(mut lo, lo_d), (mut hi, hi_d)]) = if sense {
        (ends[0], ends[1], u)
    } else {
        (ends[1], ends[0], [u[1], u[0]])
    };
    let near = |p: Vec3, q: Vec3, d: f64| (p - q).norm() <= AT_END * size + 2.0 * d;
    if near(lo_p, ca, lo_d) {
        lo = a;
    } else if near(lo_p, cb, lo_d) {
        lo = b;
    }
    if near(hi_p, cb, hi_d) {
        hi = b;
    } else if near(hi_p, ca, hi_d) {
        hi = a;
    }
    if closed && lo == b {
        lo = a;
    }
    if closed && hi == a {
        hi = b;
    }
    if lo == a && hi == b || (closed && lo == hi) {
        return Ok(None);
    }
    let piece = if lo < hi {
        super::cad_read::trimmed(c.clone(), lo, hi).map_err(|e| err(id, inst, e))?
    } else if closed {
        // across the seam: [lo, b] then [a, hi]
        let first = super::cad_read::trimmed(c.clone(), lo, b).map_err(|e| err(id, inst, e))?;
        let second = super::cad_read::trimmed(c.clone(), a, hi).map_err(|e| err(id, inst, e))?;
        super::cad_chain::join_segments(&[first, second]).map_err(|e| err(id, inst, e))?
    } else {
        return Err(err(
            id,
            inst,
            format!(
                "its vertices run against its open curve #{basis} (same_sense {}): no piece of \
                 the curve lies between them",
                if sense { ".T." } else { ".F." }
            ),
        ));
    };
    Ok(Some(if sense { piece } else { piece.reversed() }))
}

#[cfg(test)]
mod tests {
    use super::super::p21::parse;
    use super::super::step_read::contents;
    use super::*;

    fn wrap(data: &str) -> String {
        format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n")
    }

    /// A unit square as a closed degree-1 B-spline #6 (u = 0 at the origin, counter-clockwise, one
    /// unit of u per side) and an edge #9 from (0.5, 1) to (0.5, 0) with `sense`.
    fn square(sense: &str) -> String {
        format!(
            "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,0.,0.));\
             #3=CARTESIAN_POINT('',(1.,1.,0.));#4=CARTESIAN_POINT('',(0.,1.,0.));\
             #6=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2,#3,#4,#1),.UNSPECIFIED.,.T.,.F.,(2,1,1,1,2),\
             (0.,1.,2.,3.,4.),.UNSPECIFIED.);\
             #7=CARTESIAN_POINT('',(0.5,1.,0.));#8=CARTESIAN_POINT('',(0.5,0.,0.));\
             #10=VERTEX_POINT('',#7);#11=VERTEX_POINT('',#8);\
             #9=EDGE_CURVE('',#10,#11,#6,{sense});"
        )
    }

    fn length(c: &NurbsCurve) -> f64 {
        crate::diffgeo::arc_length(c)
    }

    #[test]
    fn edges_of_a_closed_bspline_run_either_way_round() {
        // .T.: from (0.5, 1) on along the square, across its seam at the origin, to (0.5, 0); .F.:
        // the other way round through (1, 0.5); both 2 long
        for (sense, through, not) in [
            (".T.", Vec3::new(0.0, 0.5, 0.0), Vec3::new(1.0, 0.5, 0.0)),
            (".F.", Vec3::new(1.0, 0.5, 0.0), Vec3::new(0.0, 0.5, 0.0)),
        ] {
            let c = contents(&parse(&wrap(&square(sense))).unwrap()).unwrap();
            assert_eq!(c.curves.len(), 1);
            assert_eq!(c.curves[0].0, "#9 (edge of #6)");
            let e = &c.curves[0].1;
            let (a, b) = e.domain();
            assert!(
                (e.point(a) - Vec3::new(0.5, 1.0, 0.0)).norm() < 1e-15,
                "{sense}"
            );
            assert!(
                (e.point(b) - Vec3::new(0.5, 0.0, 0.0)).norm() < 1e-15,
                "{sense}"
            );
            assert!((length(e) - 2.0).abs() < 1e-12, "{sense}: {}", length(e));
            let proj = CurveProjector::new(e, 16);
            assert!(proj.project(through).distance < 1e-15, "{sense}");
            assert!(proj.project(not).distance > 0.4, "{sense}");
        }
    }

    #[test]
    fn whole_edges_leave_the_curve_and_bad_vertices_are_refused() {
        let parabola = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));\
                        #3=CARTESIAN_POINT('',(2.,0.,0.));\
                        #4=B_SPLINE_CURVE_WITH_KNOTS('',2,(#1,#2,#3),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);\
                        #10=VERTEX_POINT('',#1);#11=VERTEX_POINT('',#3);\
                        #5=CARTESIAN_POINT('',(0.5,0.375,0.));#6=CARTESIAN_POINT('',(1.6,0.32,0.));\
                        #12=VERTEX_POINT('',#5);#13=VERTEX_POINT('',#6);";
        let read = |edge: &str| contents(&parse(&wrap(&format!("{parabola}{edge}"))).unwrap());
        // the whole curve: read as it is, under its own id
        let c = read("#9=EDGE_CURVE('',#10,#11,#4,.T.);").unwrap();
        assert_eq!(c.curves.len(), 1);
        assert_eq!(c.curves[0].0, "#4");
        // against the curve from u = 0.8 back to u = 0.25 (C(u) = (2u, 2u(1-u)))
        let c = read("#9=EDGE_CURVE('',#13,#12,#4,.F.);").unwrap();
        assert_eq!(c.curves[0].0, "#9 (edge of #4)");
        let e = &c.curves[0].1;
        let (a, b) = e.domain();
        assert!((e.point(a) - Vec3::new(1.6, 0.32, 0.0)).norm() < 1e-15);
        assert!((e.point(b) - Vec3::new(0.5, 0.375, 0.0)).norm() < 1e-15);
        // along the open curve from u = 0.8 to u = 0.25: no piece
        let e = read("#9=EDGE_CURVE('',#13,#12,#4,.T.);")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("#9") && e.contains("run against its open curve #4"),
            "{e}"
        );
        assert_eq!(e.lines().count(), 1);
        // a vertex off the curve
        let e = read(
            "#20=CARTESIAN_POINT('',(1.,2.,0.));#21=VERTEX_POINT('',#20);\
                      #9=EDGE_CURVE('',#21,#11,#4,.T.);",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("start vertex lies") && e.contains("off its curve #4"),
            "{e}"
        );
        // a vertex 1e-5 off the curve's start (a CAD vertex tolerance) is that end: the whole curve
        let c = read(
            "#20=CARTESIAN_POINT('',(0.,0.00001,0.));#21=VERTEX_POINT('',#20);\
                      #9=EDGE_CURVE('',#21,#11,#4,.T.);",
        )
        .unwrap();
        assert_eq!(c.curves[0].0, "#4");
        // a vertex that is no VERTEX_POINT
        let e = read("#9=EDGE_CURVE('',#1,#11,#4,.T.);")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a VERTEX_POINT"), "{e}");
    }

    /// An edge of the parabola `(t², 2t)` (f = 1) or the hyperbola `(2 cosh t, sinh t)` from `t = -1`
    /// (`t = 0` on the hyperbola) to `t1`, its end vertex `off` along the conic's normal there.
    fn open_conic_edge(
        parabola: bool,
        t1: f64,
        off: f64,
    ) -> Result<super::super::cad_read::CadContents> {
        type Planar = fn(f64) -> (f64, f64);
        let (c, dc): (Planar, Planar) = if parabola {
            (|t| (t * t, 2.0 * t), |t| (2.0 * t, 2.0))
        } else {
            (
                |t| (2.0 * t.cosh(), t.sinh()),
                |t| (2.0 * t.sinh(), t.cosh()),
            )
        };
        let (shape, t0) = if parabola {
            ("PARABOLA('',#4,1.)", -1.0)
        } else {
            ("HYPERBOLA('',#4,2.,1.)", 0.0)
        };
        let (p0, (x, y), (dx, dy)) = (c(t0), c(t1), dc(t1));
        let n = dx.hypot(dy);
        let (x, y) = (x + off * dy / n, y - off * dx / n);
        contents(&parse(&wrap(&format!(
            "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));\
             #3=DIRECTION('',(1.,0.,0.));#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5={shape};\
             #6=CARTESIAN_POINT('',({:?},{:?},0.));#7=CARTESIAN_POINT('',({x:?},{y:?},0.));\
             #10=VERTEX_POINT('',#6);#11=VERTEX_POINT('',#7);#9=EDGE_CURVE('',#10,#11,#5,.T.);",
            p0.0, p0.1
        )))?)
    }

    #[test]
    fn parabola_and_hyperbola_edges_take_vertices_within_1e_3_of_the_size() {
        // sizes: the farther vertex from the origin, |(4, 4)| = 5.657 and |(2 cosh 1, sinh 1)| = 3.272
        for (parabola, t1, size, on) in [
            (
                true,
                2.0,
                32f64.sqrt(),
                (|x: f64, y: f64| y * y - 4.0 * x) as fn(f64, f64) -> f64,
            ),
            (
                false,
                1.0,
                (4.0 * 1f64.cosh().powi(2) + 1f64.sinh().powi(2)).sqrt(),
                |x, y| x * x / 4.0 - y * y - 1.0,
            ),
        ] {
            let end = if parabola {
                Vec3::new(4.0, 4.0, 0.0)
            } else {
                Vec3::new(2.0 * 1f64.cosh(), 1f64.sinh(), 0.0)
            };
            let start = if parabola {
                Vec3::new(1.0, -2.0, 0.0)
            } else {
                Vec3::new(2.0, 0.0, 0.0)
            };
            // 0.35e-3 of the size off (was refused beyond 1e-6): the end vertex moves onto the conic
            let c = open_conic_edge(parabola, t1, 0.35e-3 * size).unwrap();
            assert_eq!(c.curves.len(), 1, "{parabola}");
            let kind = if parabola { "parabolic" } else { "hyperbolic" };
            assert_eq!(c.curves[0].0, format!("#9 ({kind} arc, edge of #5)"));
            let e = &c.curves[0].1;
            let (a, b) = e.domain();
            assert!(
                (e.point(a) - start).norm() < 1e-14,
                "{parabola}: {:?}",
                e.point(a)
            );
            assert!(
                (e.point(b) - end).norm() < 1e-13,
                "{parabola}: {:?}",
                e.point(b)
            );
            for i in 0..=20 {
                let p = e.point(a + (b - a) * i as f64 / 20.0);
                assert!(on(p.x(), p.y()).abs() < 1e-12, "{parabola}: {i}");
            }
            // 2e-3 of the size off: one line with the distance from the conic (not along y)
            let m = open_conic_edge(parabola, t1, 2e-3 * size)
                .unwrap_err()
                .to_string();
            let want = format!(
                "its end vertex lies {:.3e} off its curve #5 (more than 1e-3 of the curve's size)",
                2e-3 * size
            );
            assert!(m.contains("#9") && m.contains(&want), "{m}");
            assert_eq!(m.lines().count(), 1);
        }
    }
}
