"""Writes STEP and IGES files with OpenCASCADE (OCP) for fairfit's CAD readers to read.

Usage: occ_make_cad.py OUTDIR

Builds, with known poles, knots and weights:
  bspline   a non-rational cubic Geom_BSplineCurve (interior knot of multiplicity 2, unequal spans);
  rational  a rational quadratic Geom_BSplineCurve (a half circle of radius 25 lifted in z, plus a tail);
  periodic  a periodic cubic Geom_BSplineCurve (7 poles, closed C2);
  trimmed   the edge of `bspline` between parameters 0.2 and 0.7 (STEP: a TRIMMED_CURVE with parameter
            values; IGES: entity 126 with V(0) = 0.2, V(1) = 0.7);
  surface   a rational bicubic x biquadratic Geom_BSplineSurface;
and writes each as an edge (curves) or a face (surface) with STEPControl_Writer and IGESControl_Writer,
in millimetres (OpenCASCADE's default) and, for `bspline` and `surface`, once more in inches. For every
file it prints one JSON line: {"file", "kind", "unit", "params": [[u] | [u, v], ...], "points": [[x, y, z]
in mm, ...]} with OpenCASCADE's own evaluation (Geom_BSplineCurve.Value / Geom_BSplineSurface.Value) at
parameters inside the geometry's parameter range, which fairfit must reproduce from the files.
"""

import json
import math
import os
import sys

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface
from OCP.IGESControl import IGESControl_Writer
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.gp import gp_Pnt

try:  # OCP 7.7 names
    from OCP.TColgp import TColgp_Array1OfPnt, TColgp_Array2OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal, TColStd_Array2OfReal
except ImportError:  # OCP 8 moved the NCollection arrays to OCP.collections
    from OCP.collections import Array1_double as TColStd_Array1OfReal
    from OCP.collections import Array1_gp_Pnt as TColgp_Array1OfPnt
    from OCP.collections import Array1_int as TColStd_Array1OfInteger
    from OCP.collections import Array2_double as TColStd_Array2OfReal
    from OCP.collections import Array2_gp_Pnt as TColgp_Array2OfPnt


def arr_real(xs):
    a = TColStd_Array1OfReal(1, len(xs))
    for i, x in enumerate(xs):
        a.SetValue(i + 1, float(x))
    return a


def arr_int(xs):
    a = TColStd_Array1OfInteger(1, len(xs))
    for i, x in enumerate(xs):
        a.SetValue(i + 1, int(x))
    return a


def arr_pnt(ps):
    a = TColgp_Array1OfPnt(1, len(ps))
    for i, p in enumerate(ps):
        a.SetValue(i + 1, gp_Pnt(*p))
    return a


def bspline():
    poles = [(0, 0, 0), (10, 25, 2), (30, 32, -4), (55, 5, 3), (70, -10, 0), (90, 15, 6), (110, 30, 1)]
    knots, mults = [0.0, 0.2, 0.45, 1.0], [4, 1, 2, 4]
    return Geom_BSplineCurve(arr_pnt(poles), arr_real(knots), arr_int(mults), 3)


def rational():
    h = math.sqrt(0.5)
    r = 25.0
    poles = [(r, 0, 0), (r, r, 5), (0, r, 10), (-r, r, 15), (-r, 0, 20), (-r, -20, 25)]
    weights = [1.0, h, 1.0, h, 1.0, 1.0]
    knots, mults = [0.0, 1.0, 2.0, 3.0], [3, 2, 1, 3]
    return Geom_BSplineCurve(arr_pnt(poles), arr_real(weights), arr_real(knots), arr_int(mults), 2)


def periodic():
    poles = [(40 * math.cos(t), 18 * math.sin(t) + 3 * math.cos(2 * t), 2 * math.sin(3 * t))
             for t in (2 * math.pi * i / 7 for i in range(7))]
    knots = [0.0, 0.9, 2.0, 3.1, 4.0, 5.2, 6.0, 7.0]
    mults = [1] * len(knots)
    return Geom_BSplineCurve(arr_pnt(poles), arr_real(knots), arr_int(mults), 3, True)


def surface():
    nu, nv = 5, 4
    poles = TColgp_Array2OfPnt(1, nu, 1, nv)
    weights = TColStd_Array2OfReal(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y = 20.0 * i, 15.0 * j
            poles.SetValue(i + 1, j + 1, gp_Pnt(x + 0.2 * y, y, 6 * math.sin(x / 30) * math.cos(y / 25)))
            weights.SetValue(i + 1, j + 1, 1.0 + 0.25 * ((i + 2 * j) % 3))
    uk, um = [0.0, 0.4, 1.0], [4, 1, 4]
    vk, vm = [0.0, 0.5, 1.0], [3, 1, 3]
    return Geom_BSplineSurface(poles, weights, arr_real(uk), arr_real(vk), arr_int(um), arr_int(vm), 3, 2)


def curve_samples(c, a=None, b=None):
    a = c.FirstParameter() if a is None else a
    b = c.LastParameter() if b is None else b
    params = [a + (b - a) * k / 40.0 for k in range(41)]
    pts = []
    for u in params:
        p = c.Value(u)
        pts.append([p.X(), p.Y(), p.Z()])
    return [[u] for u in params], pts


def surface_samples(s):
    u0, u1, v0, v1 = s.Bounds()
    params, pts = [], []
    for i in range(9):
        for j in range(9):
            u, v = u0 + (u1 - u0) * i / 8.0, v0 + (v1 - v0) * j / 8.0
            p = s.Value(u, v)
            params.append([u, v])
            pts.append([p.X(), p.Y(), p.Z()])
    return params, pts


def write_step(shape, path, unit):
    Interface_Static.SetCVal_s("write.step.unit", unit)
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    if w.Write(path) != 1:
        raise RuntimeError(f"cannot write {path}")


def write_iges(shape, path, unit):
    w = IGESControl_Writer(unit, 0)
    w.AddShape(shape)
    w.ComputeModel()
    if not w.Write(path):
        raise RuntimeError(f"cannot write {path}")


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    items = [
        ("bspline", "curve", bspline(), ["MM", "INCH"]),
        ("rational", "curve", rational(), ["MM"]),
        ("periodic", "curve", periodic(), ["MM"]),
        ("trimmed", "curve", bspline(), ["MM"]),
        ("surface", "surface", surface(), ["MM", "INCH"]),
    ]
    for name, kind, geom, units in items:
        if name == "trimmed":
            shape = BRepBuilderAPI_MakeEdge(geom, 0.2, 0.7).Edge()
            params, pts = curve_samples(geom, 0.2, 0.7)
        elif kind == "curve":
            shape = BRepBuilderAPI_MakeEdge(geom).Edge()
            params, pts = curve_samples(geom)
        else:
            shape = BRepBuilderAPI_MakeFace(geom, 1e-7).Face()
            params, pts = surface_samples(geom)
        for unit in units:
            for ext in ("step", "igs"):
                path = os.path.join(out, f"{name}_{unit.lower()}.{ext}")
                if ext == "step":
                    write_step(shape, path, unit)
                else:
                    write_iges(shape, path, "IN" if unit == "INCH" else unit)
                print(json.dumps({"file": path, "kind": kind, "unit": unit.lower(),
                                  "params": params, "points": pts}))


if __name__ == "__main__":
    main()
