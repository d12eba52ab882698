"""Reads STEP / IGES files written by fairfit with OpenCASCADE (OCP) and checks the geometry read back.

Usage: occ_roundtrip.py FILE SAMPLES.json [FILE SAMPLES.json ...]

SAMPLES.json (written by fairfit beside the CAD file): {"kind": "curve"|"surface",
"params": [[u] | [u, v], ...], "points": [[x, y, z], ...], optional "unit": "mm" | "m"}. OpenCASCADE
converts what it reads to millimetres, so points of a file declared in metres are compared times 1000
(this checks the declared unit too). For every file: read it with
STEPControl_Reader or IGESControl_Reader (by extension), take the one edge (curve) or one face (surface),
require it to be a B-spline, evaluate Geom_BSplineCurve / Geom_BSplineSurface at the sample parameters and
compare with fairfit's points to 1e-9 relative to the geometry's size; a surface must be exactly one face
that BRepCheck_Analyzer reports valid. With `"seam": "u"` in SAMPLES.json the surface must also read back
closed in u (Geom_BSplineSurface.IsUClosed) with a continuous seam: at 21 v the first and second u
derivatives at the two ends of the u range agree to 1e-9 relative (tangent angle and curvature jump are
reported). Prints one JSON line per file; exit 1 on any failure.
"""

import json
import sys

from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.GeomAbs import GeomAbs_BSplineCurve, GeomAbs_BSplineSurface
from OCP.IFSelect import IFSelect_RetDone
from OCP.IGESControl import IGESControl_Reader
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Pnt, gp_Vec

REL_TOL = 1e-9


def read_shape(path):
    reader = STEPControl_Reader() if path.lower().endswith((".step", ".stp")) else IGESControl_Reader()
    if reader.ReadFile(path) != IFSelect_RetDone:
        raise RuntimeError(f"{path}: reader did not accept the file")
    if reader.TransferRoots() < 1:
        raise RuntimeError(f"{path}: nothing transferred")
    return reader.OneShape()


def sub_shapes(shape, kind):
    out = []
    explorer = TopExp_Explorer(shape, kind)
    while explorer.More():
        out.append(explorer.Current())
        explorer.Next()
    return out


def seam_check(geom, scale, result, path):
    """Closed in u with matching first and second u derivatives across the seam."""
    u0, u1, v0, v1 = geom.Bounds()
    result["u_closed"] = bool(geom.IsUClosed())
    result["u_periodic"] = bool(geom.IsUPeriodic())
    if not result["u_closed"]:
        raise RuntimeError(f"{path}: surface not closed in u")
    worst_angle = worst_d1 = worst_d2 = worst_kappa = 0.0
    for k in range(21):
        v = v0 + (v1 - v0) * k / 20
        ends = []
        for u in (u0, u1):
            p, du, dv, duu, dvv, duv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
            geom.D2(u, v, p, du, dv, duu, dvv, duv)
            ends.append((du, duu))
        (a1, a2), (b1, b2) = ends
        worst_angle = max(worst_angle, a1.Angle(b1))
        worst_d1 = max(worst_d1, (a1 - b1).Magnitude() / max(a1.Magnitude(), 1e-300))
        worst_d2 = max(worst_d2, (a2 - b2).Magnitude() / max(a2.Magnitude(), a1.Magnitude(), 1e-300))
        ka = a1.Crossed(a2).Magnitude() / a1.Magnitude() ** 3
        kb = b1.Crossed(b2).Magnitude() / b1.Magnitude() ** 3
        worst_kappa = max(worst_kappa, abs(ka - kb) / max(ka, kb, 1e-300))
    result["seam_tangent_angle"] = worst_angle
    result["seam_curvature_jump"] = worst_kappa
    if max(worst_d1, worst_d2, worst_angle) > REL_TOL:
        raise RuntimeError(
            f"{path}: seam not continuous: angle {worst_angle}, d1 {worst_d1}, d2 {worst_d2}"
        )


def check(path, samples_path):
    with open(samples_path) as f:
        samples = json.load(f)
    shape = read_shape(path)
    factor = {"mm": 1.0, "m": 1000.0}[samples.get("unit", "mm")]
    points = [[c * factor for c in p] for p in samples["points"]]
    scale = max(1.0, max(max(abs(c) for c in p) for p in points))
    result = {"file": path, "kind": samples["kind"], "samples": len(points), "unit_factor": factor}
    if samples["kind"] == "curve":
        edges = sub_shapes(shape, TopAbs_EDGE)
        if len(edges) != 1:
            raise RuntimeError(f"{path}: expected 1 edge, got {len(edges)}")
        adaptor = BRepAdaptor_Curve(TopoDS.Edge(edges[0]))
        if adaptor.GetType() != GeomAbs_BSplineCurve:
            raise RuntimeError(f"{path}: edge is not a B-spline curve")
        geom = adaptor.BSpline()
        evaluate = lambda prm: geom.Value(prm[0])
        result["degree"] = geom.Degree()
        result["poles"] = geom.NbPoles()
    else:
        faces = sub_shapes(shape, TopAbs_FACE)
        if len(faces) != 1:
            raise RuntimeError(f"{path}: expected 1 face, got {len(faces)}")
        if not BRepCheck_Analyzer(shape).IsValid():
            raise RuntimeError(f"{path}: BRepCheck_Analyzer reports the shape invalid")
        adaptor = BRepAdaptor_Surface(TopoDS.Face(faces[0]))
        if adaptor.GetType() != GeomAbs_BSplineSurface:
            raise RuntimeError(f"{path}: face is not a B-spline surface")
        geom = adaptor.BSpline()
        evaluate = lambda prm: geom.Value(prm[0], prm[1])
        result["degrees"] = [geom.UDegree(), geom.VDegree()]
        result["poles"] = [geom.NbUPoles(), geom.NbVPoles()]
        result["valid_faces"] = 1
        if samples.get("seam") == "u":
            seam_check(geom, scale, result, path)
    worst = 0.0
    for prm, want in zip(samples["params"], points):
        got = evaluate(prm)
        err = max(abs(got.X() - want[0]), abs(got.Y() - want[1]), abs(got.Z() - want[2]))
        worst = max(worst, err)
    result["max_error"] = worst
    result["relative_error"] = worst / scale
    if worst > REL_TOL * scale:
        raise RuntimeError(f"{path}: max deviation {worst} > {REL_TOL} * {scale}")
    return result


def main(argv):
    if len(argv) < 2 or len(argv) % 2:
        print(__doc__, file=sys.stderr)
        return 2
    failed = 0
    for path, samples in zip(argv[::2], argv[1::2]):
        try:
            print(json.dumps(check(path, samples)))
        except Exception as e:  # noqa: BLE001 - report every file, then fail
            print(json.dumps({"file": path, "error": str(e)}))
            failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
