"""A STEP COMPOSITE_CURVE fixture made with OpenCASCADE (OCP), and OpenCASCADE's reading of it.

Usage:
  occ_composite.py write OUT.step   writes the fixture (crates/fairfit/tests/data/occ_composite.step)
  occ_composite.py read FILE.step   prints one JSON line: OpenCASCADE's reading of FILE as a chain

write: three edges, each a Geom_BSplineCurve with known poles, written by STEPControl_Writer as a
compound (three TRIMMED_CURVEs of B-splines in a GEOMETRIC_CURVE_SET); the set's items are then replaced
by one COMPOSITE_CURVE of three segments, by text:
  1. a rational quadratic quarter circle of radius 20 about (0, 20, 0), from (0, 0, 0) to (20, 20, 0),
     trimmed to its parameters [0.2, 1] (the edge starts inside the B-spline): COMPOSITE_CURVE_SEGMENT,
     same_sense .T.;
  2. a cubic from (20, 20, 0) to (40, 10, 5) whose B-spline is stored backwards (from (40, 10, 5)):
     COMPOSITE_CURVE_SEGMENT, same_sense .F.;
  3. a cubic with an interior knot from (40, 10, 5) to (70, 0, 0):
     REPARAMETRISED_COMPOSITE_CURVE_SEGMENT, same_sense .T.
The second joint is a corner (the tangent turns by about 41 degrees), the first is tangent.

read: STEPControl_Reader transfers FILE; every edge of the result, in the order TopExp_Explorer gives
them, is sampled at 41 parameters along its orientation (BRepAdaptor_Curve), and the edges are chained
(an edge is reversed when its end, not its start, meets the chain); prints {"points": [[x, y, z], ...]
per edge, "length": total length (GCPnts_AbscissaPoint)}.
"""

import json
import math
import re
import sys

from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.GCPnts import GCPnts_AbscissaPoint
from OCP.Geom import Geom_BSplineCurve
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Pnt

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


def bspline(poles, knots, mults, degree, weights=None):
    p = arr(TColgp_Array1OfPnt, poles, lambda q: gp_Pnt(*q))
    k = arr(TColStd_Array1OfReal, knots, float)
    m = arr(TColStd_Array1OfInteger, mults, int)
    if weights is None:
        return Geom_BSplineCurve(p, k, m, degree)
    return Geom_BSplineCurve(p, arr(TColStd_Array1OfReal, weights, float), k, m, degree)


def write(out):
    h = math.sqrt(0.5)
    arc = bspline([(0, 0, 0), (20, 0, 0), (20, 20, 0)], [0, 1], [3, 3], 2, [1.0, h, 1.0])
    # stored backwards: from (40, 10, 5) to (20, 20, 0); its start tangent at (20, 20, 0) is +y
    back = bspline([(40, 10, 5), (30, 34, 3), (20, 30, 0), (20, 20, 0)], [0, 1], [4, 4], 3)
    tail = bspline([(40, 10, 5), (52, 4, 5), (58, -6, 2), (64, -3, 0), (70, 0, 0)], [0, 0.6, 1], [4, 1, 4], 3)
    wire = BRepBuilderAPI_MakeWire()
    for e in (BRepBuilderAPI_MakeEdge(arc, 0.2, 1.0), BRepBuilderAPI_MakeEdge(back), BRepBuilderAPI_MakeEdge(tail)):
        wire.Add(e.Edge())
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    w = STEPControl_Writer()
    w.Transfer(wire.Wire(), STEPControl_AsIs)
    tmp = out + ".tmp"
    if w.Write(tmp) != 1:
        raise RuntimeError("cannot write")
    text = open(tmp).read()
    m = re.search(r"GEOMETRIC_CURVE_SET\('',\((#\d+),(#\d+),(#\d+)\)\)", text)
    t1, t2, t3 = m.groups()
    n = max(int(x) for x in re.findall(r"^#(\d+)\s*=", text, re.M))
    s1, s2, s3, cc = (f"#{n + k}" for k in range(1, 5))
    text = text.replace(m.group(0), f"GEOMETRIC_CURVE_SET('',({cc}))")
    extra = (f"{s1} = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,{t1});\n"
             f"{s2} = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.F.,{t2});\n"
             f"{s3} = REPARAMETRISED_COMPOSITE_CURVE_SEGMENT(.DISCONTINUOUS.,.T.,{t3},2.);\n"
             f"{cc} = COMPOSITE_CURVE('chain',({s1},{s2},{s3}),.F.);\n")
    text = text.replace("ENDSEC;\nEND-ISO-10303-21;", extra + "ENDSEC;\nEND-ISO-10303-21;")
    text = re.sub(r"FILE_NAME\('[^']*'", "FILE_NAME('occ_composite.step'", text)
    text = re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'", "'2026-11-26T00:00:00'", text)
    with open(out, "w") as f:
        f.write(text)
    import os
    os.remove(tmp)


def read(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != 1:
        raise RuntimeError("cannot read")
    r.TransferRoots()
    shape = r.OneShape()
    edges = []
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge(ex.Current()) if hasattr(TopoDS, "Edge") else TopoDS.Edge_s(ex.Current())
        c = BRepAdaptor_Curve(e)
        a, b = c.FirstParameter(), c.LastParameter()
        pts = [c.Value(a + (b - a) * k / 40.0) for k in range(41)]
        pts = [[p.X(), p.Y(), p.Z()] for p in pts]
        if e.Orientation() == TopAbs_REVERSED:
            pts.reverse()
        edges.append((pts, GCPnts_AbscissaPoint.Length_s(c, 1e-12)))
        ex.Next()
    chain = [edges[0][0]]
    dist = lambda p, q: math.dist(p, q)
    if len(edges) > 1 and min(dist(chain[0][0], edges[1][0][0]), dist(chain[0][0], edges[1][0][-1])) < 1e-9:
        chain[0].reverse()
    for pts, _ in edges[1:]:
        if dist(pts[-1], chain[-1][-1]) < dist(pts[0], chain[-1][-1]):
            pts.reverse()
        chain.append(pts)
    print(json.dumps({"points": chain, "length": sum(l for _, l in edges)}))


if __name__ == "__main__":
    {"write": write, "read": read}[sys.argv[1]](sys.argv[2])
