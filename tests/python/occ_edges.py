"""STEP faces whose edges cut their curves at their vertices (EDGE_CURVE over an untrimmed CIRCLE,
ELLIPSE or B-spline inside a SURFACE_CURVE), made with OpenCASCADE (OCP), and OpenCASCADE's reading.

Usage:
  occ_edges.py write OUTDIR   writes the fixtures (crates/fairfit/tests/data/edges/*.step)
  occ_edges.py read FILE      prints one JSON line: OpenCASCADE's reading of FILE's curved edge

write: planar faces, each bounded by one curved edge and the straight line back (STEPControl_Writer
writes every edge as EDGE_CURVE(start, end, SURFACE_CURVE(whole curve, pcurve), .T.)):
  arc.step          the circle of radius 10 about (1, 2, 3) in z = 3, angles 0.5 to 2.0;
  arc_reversed.step arc.step with the EDGE_CURVE's vertices swapped and same_sense .F. (and its
                    ORIENTED_EDGE .F., so the face's loop is unchanged): the same arc;
  arc_long.step     arc.step with same_sense .F. only: the edge runs from angle 0.5 clockwise to 2.0
                    (the 270-degree remainder of the circle, face and all);
  ellipse.step      an ellipse (semi-axes 12 and 5 about (0, 0, 1), tilted) from angle 5.5 to 7.0,
                    across its angle 0;
  bspline.step      the wiggly cubic (7 poles, a double interior knot) flattened to z = 0, parameters
                    0.1 to 0.8 of [0, 1].
read: STEPControl_Reader transfers FILE; the one edge that is no straight line is sampled at 41
parameters along its orientation (BRepAdaptor_Curve); prints {"points": [[x, y, z], ...], "length":
its length (GCPnts_AbscissaPoint)}.
"""

import json
import os
import re
import sys

from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.GCPnts import GCPnts_AbscissaPoint
from OCP.GeomAbs import GeomAbs_Line
from OCP.Geom import Geom_BSplineCurve, Geom_Circle, Geom_Ellipse
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

try:  # OCP 7.7 names
    from OCP.TColgp import TColgp_Array1OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
except ImportError:  # OCP 8 moved the NCollection arrays to OCP.collections
    from OCP.collections import Array1_double as TColStd_Array1OfReal
    from OCP.collections import Array1_gp_Pnt as TColgp_Array1OfPnt
    from OCP.collections import Array1_int as TColStd_Array1OfInteger


def write_step(shape, path):
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    if w.Write(path) != 1:
        raise RuntimeError(f"cannot write {path}")


def face(curve, u0, u1, path):
    w = BRepBuilderAPI_MakeWire()
    w.Add(BRepBuilderAPI_MakeEdge(curve, u0, u1).Edge())
    w.Add(BRepBuilderAPI_MakeEdge(curve.Value(u1), curve.Value(u0)).Edge())
    f = BRepBuilderAPI_MakeFace(w.Wire(), True)
    if not f.IsDone():
        raise RuntimeError(f"no face for {path}")
    write_step(f.Face(), path)


def wiggly_flat():
    pts = [(0, 0), (10, 25), (30, 32), (55, 5), (70, -10), (90, 15), (110, 30)]
    poles = TColgp_Array1OfPnt(1, len(pts))
    for i, (x, y) in enumerate(pts):
        poles.SetValue(i + 1, gp_Pnt(x, y, 0))
    knots, mults = TColStd_Array1OfReal(1, 4), TColStd_Array1OfInteger(1, 4)
    for i, (k, m) in enumerate([(0, 4), (0.2, 1), (0.45, 2), (1, 4)]):
        knots.SetValue(i + 1, k)
        mults.SetValue(i + 1, m)
    return Geom_BSplineCurve(poles, knots, mults, 3)


def edit(src, dst, f):
    with open(src) as fh:
        text = fh.read()
    new = f(text)
    if new == text:
        raise RuntimeError(f"no edit for {dst}")
    with open(dst, "w") as fh:
        fh.write(new)


def write(out):
    os.makedirs(out, exist_ok=True)
    circle = Geom_Circle(gp_Ax2(gp_Pnt(1, 2, 3), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), 10.0)
    arc = os.path.join(out, "arc.step")
    face(circle, 0.5, 2.0, arc)
    # the curved edge is the first EDGE_CURVE, and its ORIENTED_EDGE the first
    ec = re.compile(r"EDGE_CURVE\('',(#\d+),(#\d+),(#\d+),\.T\.\)")
    oe = re.compile(r"(ORIENTED_EDGE\('',\*,\*,#\d+,)\.T\.\)")
    edit(arc, os.path.join(out, "arc_reversed.step"),
         lambda t: oe.sub(r"\1.F.)", ec.sub(r"EDGE_CURVE('',\2,\1,\3,.F.)", t, count=1), count=1))
    edit(arc, os.path.join(out, "arc_long.step"),
         lambda t: ec.sub(r"EDGE_CURVE('',\1,\2,\3,.F.)", t, count=1))
    ellipse = Geom_Ellipse(gp_Ax2(gp_Pnt(0, 0, 1), gp_Dir(0, 0.6, 0.8), gp_Dir(1, 0, 0)), 12.0, 5.0)
    face(ellipse, 5.5, 7.0, os.path.join(out, "ellipse.step"))
    face(wiggly_flat(), 0.1, 0.8, os.path.join(out, "bspline.step"))


def read(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != 1:
        raise RuntimeError(f"cannot read {path}")
    r.TransferRoots()
    shape = r.OneShape()
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge(ex.Current()) if hasattr(TopoDS, "Edge") else TopoDS.Edge_s(ex.Current())
        c = BRepAdaptor_Curve(e)
        if c.GetType() != GeomAbs_Line:
            a, b = c.FirstParameter(), c.LastParameter()
            us = [a + (b - a) * k / 40.0 for k in range(41)]
            if e.Orientation() == TopAbs_REVERSED:
                us.reverse()
            pts = [[c.Value(u).X(), c.Value(u).Y(), c.Value(u).Z()] for u in us]
            length = GCPnts_AbscissaPoint.Length_s(c, 1e-12)
            print(json.dumps({"points": pts, "length": length}))
            return
        ex.Next()
    raise RuntimeError(f"no curved edge in {path}")


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("write", "read"):
        sys.exit(__doc__)
    (write if sys.argv[1] == "write" else read)(sys.argv[2])
