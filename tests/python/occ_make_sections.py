"""Writes STEP and IGES files of section curves, a surface and a composite curve with OpenCASCADE (OCP)
for `fairfit surface` from CAD sections and for composite curves.

Usage: occ_make_sections.py OUTDIR

Builds, with known poles and knots:
  sections  five open cubic Geom_BSplineCurves (blade-like cambered sections, 5 to 7 poles, different
            interior knots, twisted and scaled along z), written as one compound of edges in the order
            z = 0, 12, 30, 45, 60 (sections_mm.step / .igs) and once shuffled as z = 30, 0, 60, 12, 45
            (shuffled_mm.step), and once in inches (sections_inch.step: the same poles read as inches);
  face      a non-rational bicubic Geom_BSplineSurface (6 x 5 poles, one interior v knot) as a face
            (face_mm.step);
  wire      a wire of three B-spline edges meeting at two corners (cubic, quadratic, cubic with an
            interior knot; the middle one's parameter range is [0, 2]) (wire_mm.igs: OpenCASCADE writes
            it as one IGES 102 composite curve of three 126 entities).
For every file it prints one JSON line {"file", "kind", "curves": [[[x, y, z], ...], ...] in mm} with
OpenCASCADE's own evaluation (Geom_BSplineCurve.Value, 41 equally spaced parameters per curve, or
Geom_BSplineSurface.Value on a 9 x 9 grid for the face: one entry) in file order; the line of
sections_mm.step also has "dense": every section at 3001 equally spaced parameters.
"""

import json
import math
import os
import sys

from OCP.BRep import BRep_Builder
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface
from OCP.IGESControl import IGESControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.TopoDS import TopoDS_Compound
from OCP.gp import gp_Pnt

try:  # OCP 7.7 names
    from OCP.TColgp import TColgp_Array1OfPnt, TColgp_Array2OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
except ImportError:  # OCP 8 moved the NCollection arrays to OCP.collections
    from OCP.collections import Array1_double as TColStd_Array1OfReal
    from OCP.collections import Array1_gp_Pnt as TColgp_Array1OfPnt
    from OCP.collections import Array1_int as TColStd_Array1OfInteger
    from OCP.collections import Array2_gp_Pnt as TColgp_Array2OfPnt


def arr(cls, xs, f):
    a = cls(1, len(xs))
    for i, x in enumerate(xs):
        a.SetValue(i + 1, f(x))
    return a


def bspline(poles, knots, mults, degree):
    return Geom_BSplineCurve(arr(TColgp_Array1OfPnt, poles, lambda p: gp_Pnt(*p)),
                             arr(TColStd_Array1OfReal, knots, float),
                             arr(TColStd_Array1OfInteger, mults, int), degree)


def section(z, k):
    """A cambered open section at height z: chord 100 - z, twisted by z / 2 degrees."""
    n = 5 + k % 3
    chord, twist = 100.0 - 0.8 * z, math.radians(z / 2.0)
    poles = []
    for i in range(n):
        s = i / (n - 1)
        x = chord * (s - 0.3)
        y = 0.12 * chord * math.sin(math.pi * s) * (1.0 + 0.2 * math.cos(3 * s + k))
        poles.append((x * math.cos(twist) - y * math.sin(twist), x * math.sin(twist) + y * math.cos(twist), z))
    inner = [round(0.2 + 0.6 * (j + 1) / (n - 3) + 0.03 * k, 6) for j in range(n - 4)]
    knots = [0.0] + inner + [1.0]
    mults = [4] + [1] * len(inner) + [4]
    return bspline(poles, knots, mults, 3)


def face_surface():
    nu, nv = 6, 5
    poles = TColgp_Array2OfPnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y = 20.0 * i, 18.0 * j
            poles.SetValue(i + 1, j + 1, gp_Pnt(x, y + 0.1 * x, 8 * math.sin(x / 35) * math.cos(y / 30)))
    uk, um = [0.0, 0.3, 0.6, 1.0], [4, 1, 1, 4]
    vk, vm = [0.0, 0.45, 1.0], [4, 1, 4]
    return Geom_BSplineSurface(poles, arr(TColStd_Array1OfReal, uk, float), arr(TColStd_Array1OfReal, vk, float),
                               arr(TColStd_Array1OfInteger, um, int), arr(TColStd_Array1OfInteger, vm, int), 3, 3)


def wire_curves():
    c1 = bspline([(0, 0, 0), (10, 8, 0), (20, 8, 1), (30, 0, 0)], [0, 1], [4, 4], 3)
    c2 = bspline([(30, 0, 0), (38, -6, 0), (40, -15, 3)], [0, 2], [3, 3], 2)
    c3 = bspline([(40, -15, 3), (48, -10, 3), (55, 0, 0), (62, 6, -1), (70, 0, 0)], [0, 0.4, 1], [4, 1, 4], 3)
    return [c1, c2, c3]


def samples(c, n=40):
    a, b = c.FirstParameter(), c.LastParameter()
    pts = [c.Value(a + (b - a) * k / n) for k in range(n + 1)]
    return [[p.X(), p.Y(), p.Z()] for p in pts]


def compound(curves):
    b, comp = BRep_Builder(), TopoDS_Compound()
    b.MakeCompound(comp)
    for c in curves:
        b.Add(comp, BRepBuilderAPI_MakeEdge(c).Edge())
    return comp


def write_step(shape, path, unit="MM"):
    Interface_Static.SetCVal_s("write.step.unit", unit)
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    if w.Write(path) != 1:
        raise RuntimeError(f"cannot write {path}")


def write_iges(shape, path):
    w = IGESControl_Writer("MM", 0)
    w.AddShape(shape)
    w.ComputeModel()
    if not w.Write(path):
        raise RuntimeError(f"cannot write {path}")


def emit(path, kind, curves, dense=None):
    line = {"file": path, "kind": kind, "curves": curves}
    if dense is not None:
        line["dense"] = dense
    print(json.dumps(line))


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    heights = [0.0, 12.0, 30.0, 45.0, 60.0]
    secs = [section(z, k) for k, z in enumerate(heights)]
    for ext in ("step", "igs"):
        path = os.path.join(out, f"sections_mm.{ext}")
        (write_step if ext == "step" else write_iges)(compound(secs), path)
        dense = [samples(c, 3000) for c in secs] if ext == "step" else None
        emit(path, "sections", [samples(c) for c in secs], dense)
    order = [2, 0, 4, 1, 3]
    path = os.path.join(out, "shuffled_mm.step")
    write_step(compound([secs[i] for i in order]), path)
    emit(path, "sections", [samples(secs[i]) for i in order])
    path = os.path.join(out, "sections_inch.step")
    # the same numbers, declared in inches: OpenCASCADE scales mm geometry to the file unit, so the
    # shape is built 25.4 times larger to write the same numbers
    big = [section(z, k) for k, z in enumerate(heights)]
    for c in big:
        c.Scale(gp_Pnt(0, 0, 0), 25.4)
    write_step(compound(big), path, "INCH")
    emit(path, "sections", [samples(c) for c in big])
    s = face_surface()
    path = os.path.join(out, "face_mm.step")
    write_step(BRepBuilderAPI_MakeFace(s, 1e-7).Face(), path)
    grid = []
    for i in range(9):
        for j in range(9):
            p = s.Value(i / 8.0, j / 8.0)
            grid.append([p.X(), p.Y(), p.Z()])
    emit(path, "surface", [grid])
    w = BRepBuilderAPI_MakeWire()
    wc = wire_curves()
    for c in wc:
        w.Add(BRepBuilderAPI_MakeEdge(c).Edge())
    path = os.path.join(out, "wire_mm.igs")
    write_iges(w.Wire(), path)
    emit(path, "composite", [samples(c) for c in wc])


if __name__ == "__main__":
    main()
