"""Circle, ellipse and point-trimmed fixtures made with OpenCASCADE (OCP), and OpenCASCADE's reading of them.

Usage:
  occ_conics.py write DIR    writes the fixtures into DIR (crates/fairfit/tests/data/conics) and DIR/occ_truth.json
  occ_conics.py read FILE    prints one JSON line: OpenCASCADE's reading of FILE (see `read`)

Fixtures (every curve is an edge written by STEPControl_Writer / IGESControl_Writer; a few STEP files are
then edited as text, as noted):
  circle.step, circle.igs          full circle, radius 7.5 about (1, 2, 3), axis (0.2, 0.3, 1) (AP214)
  arc_rad.step, arc.igs            arc of that circle from 0.4 to 2.9 rad (AP214; IGES 100 with a 124)
  arc_deg.step                     the same arc written as AP242, the plane-angle unit changed by text to
                                   a CONVERSION_BASED_UNIT 'DEGREE' and the trims to degrees
  arc_points.step                  arc_rad.step with the PARAMETER_VALUE trims removed (points only,
                                   master_representation .CARTESIAN.)
  arc_points_reversed.step         the same arc as TRIMMED_CURVE(basis, (end), (start), .F., .CARTESIAN.)
  ellipse_arc.step, ellipse_arc.igs  ellipse with semi-axes 9 and 4 from 1 to 4 rad (IGES 104 with a 124)
  parabola_arc.igs                 parabola of focal length 2 (same placement) from -3 to 2 (IGES 104)
  hyperbola_arc.igs                hyperbola with semi-axes 6 and 3 (same placement) from -1 to 1.5 (IGES 104)
  parabola_arc.step, hyperbola_arc.step  the same two arcs in STEP (PARABOLA, HYPERBOLA trimmed by
                                   parameters and points); `occ_conics.py write-pq DIR` writes only these
                                   two and adds them to DIR/occ_truth.json
  bspline_points.step              a cubic B-spline edge on [0.15, 0.85] of its [0, 1], its trims
                                   changed by text to points only (.CARTESIAN.)
  section.step, section.igs        an airfoil-like section: an upper cubic B-spline from the trailing
                                   edge (100, 0.5, 0) to (5, 5, 0) arriving level, the half circle of
                                   radius 5 about (5, 0, 0) round the leading edge (0, 0, 0), and a line
                                   from (5, -5, 0) back to (100, -0.5, 0); the STEP set of three
                                   TRIMMED_CURVEs is turned by text into one COMPOSITE_CURVE (as
                                   occ_composite.py does); the IGES wire is OpenCASCADE's 102.
  cone_arcs.step, cone_circles.igs sections of the cone r = 5 + z / 10 at z = 0, 10, 20: arcs from 0 to
                                   270 degrees (STEP), full circles (IGES 100s); not in occ_truth.json

read: the file is transferred by STEPControl_Reader / IGESControl_Reader; every edge, in TopExp_Explorer
order, is sampled at 51 equally spaced parameters along its orientation (BRepAdaptor_Curve) and the
edges chained (an edge is reversed when its end, not its start, meets the chain); prints {"points":
[[[x, y, z], ...] per edge], "length": total length (GCPnts_AbscissaPoint, tolerance 1e-13)}.
occ_truth.json holds that reading for every fixture, by file name.
"""

import json
import math
import os
import re
import sys

from OCP.BRep import BRep_Builder
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.GCPnts import GCPnts_AbscissaPoint
from OCP.Geom import Geom_BSplineCurve, Geom_Circle, Geom_Ellipse, Geom_Hyperbola, Geom_Parabola
from OCP.IGESControl import IGESControl_Reader, IGESControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Compound
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

try:  # OCP 7.7 names
    from OCP.TColgp import TColgp_Array1OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
except ImportError:  # OCP 8 moved the NCollection arrays to OCP.collections
    from OCP.collections import Array1_double as TColStd_Array1OfReal
    from OCP.collections import Array1_gp_Pnt as TColgp_Array1OfPnt
    from OCP.collections import Array1_int as TColStd_Array1OfInteger


def arr(cls, xs, f):
    a = cls(1, len(xs))
    for i, x in enumerate(xs):
        a.SetValue(i + 1, f(x))
    return a


def bspline(poles, knots, mults, degree):
    p = arr(TColgp_Array1OfPnt, poles, lambda q: gp_Pnt(*q))
    return Geom_BSplineCurve(p, arr(TColStd_Array1OfReal, knots, float), arr(TColStd_Array1OfInteger, mults, int), degree)


AX = gp_Ax2(gp_Pnt(1, 2, 3), gp_Dir(0.2, 0.3, 1.0), gp_Dir(1, 0, -0.2))


def write_step(shape, path, schema="AP214IS"):
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    Interface_Static.SetCVal_s("write.step.schema", schema)
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    if w.Write(path) != 1:
        raise RuntimeError("cannot write " + path)
    text = open(path).read()
    text = re.sub(r"FILE_NAME\('[^']*'", f"FILE_NAME('{os.path.basename(path)}'", text)
    text = re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", "'2026-11-27T00:00:00'", text)
    with open(path, "w") as f:
        f.write(text)
    return text


def write_iges(shape, path):
    w = IGESControl_Writer("MM", 0)
    w.AddShape(shape)
    w.ComputeModel()
    if not w.Write(path):
        raise RuntimeError("cannot write " + path)
    text = open(path).read()
    # the date fields of the Global section vary; OpenCASCADE writes 15H + yyyymmdd.hhmmss
    text = re.sub(r"15H\d{8}\.\d{6}", "15H20261127.000000", text)
    with open(path, "w") as f:
        f.write(text)


TRIM = re.compile(
    r"TRIMMED_CURVE\('',(#\d+),\((#\d+),PARAMETER_VALUE\(([^)]*)\)\),\s*\((#\d+),\s*PARAMETER_VALUE\(([^)]*)\)\),\s*\.T\.,\s*\.PARAMETER\.\)"
)


def edit(path, text):
    with open(path, "w") as f:
        f.write(text)


def write_pq_step(d):
    """parabola_arc.step, hyperbola_arc.step: the IGES fixtures' parabola and hyperbola arcs in STEP."""
    write_step(BRepBuilderAPI_MakeEdge(Geom_Parabola(AX, 2.0), -3.0, 2.0).Edge(), f"{d}/parabola_arc.step")
    write_step(BRepBuilderAPI_MakeEdge(Geom_Hyperbola(AX, 6.0, 3.0), -1.0, 1.5).Edge(), f"{d}/hyperbola_arc.step")


def write(d):
    os.makedirs(d, exist_ok=True)
    circle = Geom_Circle(AX, 7.5)
    full = BRepBuilderAPI_MakeEdge(circle).Edge()
    arc = BRepBuilderAPI_MakeEdge(circle, 0.4, 2.9).Edge()
    ell = BRepBuilderAPI_MakeEdge(Geom_Ellipse(AX, 9.0, 4.0), 1.0, 4.0).Edge()
    write_step(full, f"{d}/circle.step")
    write_iges(full, f"{d}/circle.igs")
    text = write_step(arc, f"{d}/arc_rad.step")
    write_iges(arc, f"{d}/arc.igs")
    write_step(ell, f"{d}/ellipse_arc.step")
    write_iges(ell, f"{d}/ellipse_arc.igs")
    write_iges(BRepBuilderAPI_MakeEdge(Geom_Parabola(AX, 2.0), -3.0, 2.0).Edge(), f"{d}/parabola_arc.igs")
    write_iges(BRepBuilderAPI_MakeEdge(Geom_Hyperbola(AX, 6.0, 3.0), -1.0, 1.5).Edge(), f"{d}/hyperbola_arc.igs")
    write_pq_step(d)
    # trims by points only, in both senses
    m = TRIM.search(text)
    basis, p1, _, p2, _ = m.groups()
    edit(f"{d}/arc_points.step", text.replace(m.group(0), f"TRIMMED_CURVE('',{basis},({p1}),({p2}),.T.,.CARTESIAN.)"))
    edit(f"{d}/arc_points_reversed.step", text.replace(m.group(0), f"TRIMMED_CURVE('',{basis},({p2}),({p1}),.F.,.CARTESIAN.)"))
    # AP242 in degrees
    text = write_step(arc, f"{d}/arc_deg.step", "AP242DIS")
    m = TRIM.search(text)
    basis, p1, u1, p2, u2 = m.groups()
    deg = lambda u: repr(math.degrees(float(u)))
    text = text.replace(
        m.group(0),
        f"TRIMMED_CURVE('',{basis},({p1},PARAMETER_VALUE({deg(u1)})),({p2},PARAMETER_VALUE({deg(u2)})),.T.,.PARAMETER.)",
    )
    um = re.search(r"(#\d+) = \( NAMED_UNIT\(\*\) PLANE_ANGLE_UNIT\(\) SI_UNIT\(\$,\.RADIAN\.\) \);", text)
    n = max(int(x) for x in re.findall(r"^#(\d+)\s*=", text, re.M))
    rad, mwu, dims = f"#{n + 1}", f"#{n + 2}", f"#{n + 3}"
    text = text.replace(um.group(0), f"{um.group(1)} = ( CONVERSION_BASED_UNIT('DEGREE',{mwu}) NAMED_UNIT({dims}) PLANE_ANGLE_UNIT() );")
    extra = (
        f"{rad} = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );\n"
        f"{mwu} = PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(1.745329251994E-02),{rad});\n"
        f"{dims} = DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.);\n"
    )
    edit(f"{d}/arc_deg.step", text.replace("ENDSEC;\nEND-ISO-10303-21;", extra + "ENDSEC;\nEND-ISO-10303-21;"))
    # a B-spline trimmed by points
    cubic = bspline([(0, 0, 0), (10, 8, 1), (25, -4, 2), (40, 6, 0), (50, 0, -1)], [0, 0.4, 1], [4, 1, 4], 3)
    text = write_step(BRepBuilderAPI_MakeEdge(cubic, 0.15, 0.85).Edge(), f"{d}/bspline_points.step")
    m = TRIM.search(text)
    basis, p1, _, p2, _ = m.groups()
    edit(f"{d}/bspline_points.step", text.replace(m.group(0), f"TRIMMED_CURVE('',{basis},({p1}),({p2}),.T.,.CARTESIAN.)"))
    # the section: B-spline, half circle, line
    upper = bspline([(100, 0.5, 0), (70, 3, 0), (40, 5.5, 0), (20, 5, 0), (5, 5, 0)], [0, 0.5, 1], [4, 1, 4], 3)
    le = Geom_Circle(gp_Ax2(gp_Pnt(5, 0, 0), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 5.0)
    wire = BRepBuilderAPI_MakeWire()
    for e in (
        BRepBuilderAPI_MakeEdge(upper),
        BRepBuilderAPI_MakeEdge(le, math.pi / 2, 3 * math.pi / 2),
        BRepBuilderAPI_MakeEdge(gp_Pnt(5, -5, 0), gp_Pnt(100, -0.5, 0)),
    ):
        wire.Add(e.Edge())
    text = write_step(wire.Wire(), f"{d}/section.step")
    m = re.search(r"GEOMETRIC_CURVE_SET\('',\((#\d+),(#\d+),(#\d+)\)\)", text)
    t1, t2, t3 = m.groups()
    n = max(int(x) for x in re.findall(r"^#(\d+)\s*=", text, re.M))
    s1, s2, s3, cc = (f"#{n + k}" for k in range(1, 5))
    text = text.replace(m.group(0), f"GEOMETRIC_CURVE_SET('',({cc}))")
    extra = (
        f"{s1} = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,{t1});\n"
        f"{s2} = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,{t2});\n"
        f"{s3} = COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,{t3});\n"
        f"{cc} = COMPOSITE_CURVE('section',({s1},{s2},{s3}),.F.);\n"
    )
    edit(f"{d}/section.step", text.replace("ENDSEC;\nEND-ISO-10303-21;", extra + "ENDSEC;\nEND-ISO-10303-21;"))
    write_iges(wire.Wire(), f"{d}/section.igs")
    # sections of the cone r = 5 + z / 10: arcs of 270 degrees, and full circles
    arcs, circles = TopoDS_Compound(), TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(arcs)
    b.MakeCompound(circles)
    for z in (0.0, 10.0, 20.0):
        c = Geom_Circle(gp_Ax2(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 5.0 + z / 10.0)
        b.Add(arcs, BRepBuilderAPI_MakeEdge(c, 0.0, 1.5 * math.pi).Edge())
        b.Add(circles, BRepBuilderAPI_MakeEdge(c).Edge())
    write_step(arcs, f"{d}/cone_arcs.step")
    write_iges(circles, f"{d}/cone_circles.igs")
    truth = {}
    for name in sorted(os.listdir(d)):
        if name.endswith((".step", ".igs")) and not name.startswith("cone_"):
            truth[name] = read_file(f"{d}/{name}")
    with open(f"{d}/occ_truth.json", "w") as f:
        json.dump(truth, f, separators=(",", ":"))
        f.write("\n")


def read_file(path):
    if path.endswith(".igs"):
        r = IGESControl_Reader()
    else:
        r = STEPControl_Reader()
    if r.ReadFile(path) != 1:
        raise RuntimeError("cannot read " + path)
    r.TransferRoots()
    shape = r.OneShape()
    edges = []
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge_s(ex.Current()) if hasattr(TopoDS, "Edge_s") else TopoDS.Edge(ex.Current())
        c = BRepAdaptor_Curve(e)
        a, b = c.FirstParameter(), c.LastParameter()
        pts = [c.Value(a + (b - a) * k / 50.0) for k in range(51)]
        pts = [[p.X(), p.Y(), p.Z()] for p in pts]
        if e.Orientation() == TopAbs_REVERSED:
            pts.reverse()
        edges.append((pts, GCPnts_AbscissaPoint.Length_s(c, 1e-13)))
        ex.Next()
    chain = [edges[0][0]]
    if len(edges) > 1 and min(math.dist(chain[0][0], edges[1][0][0]), math.dist(chain[0][0], edges[1][0][-1])) < 1e-9:
        chain[0].reverse()
    for pts, _ in edges[1:]:
        if math.dist(pts[-1], chain[-1][-1]) < math.dist(pts[0], chain[-1][-1]):
            pts.reverse()
        chain.append(pts)
    return {"points": chain, "length": sum(l for _, l in edges)}


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2])
    elif sys.argv[1] == "write-pq":
        write_pq_step(sys.argv[2])
        with open(f"{sys.argv[2]}/occ_truth.json") as f:
            truth = json.load(f)
        for name in ("parabola_arc.step", "hyperbola_arc.step"):
            truth[name] = read_file(f"{sys.argv[2]}/{name}")
        with open(f"{sys.argv[2]}/occ_truth.json", "w") as f:
            json.dump(dict(sorted(truth.items())), f, separators=(",", ":"))
            f.write("\n")
    else:
        print(json.dumps(read_file(sys.argv[2])))
