"""Reads STEP / IGES files written by fairfit with OpenCASCADE (OCP) and checks the geometry read back.

Usage: occ_roundtrip.py FILE SAMPLES.json [FILE SAMPLES.json ...]

SAMPLES.json (written by fairfit beside the CAD file): {"kind": "curve"|"surface",
"params": [[u] | [u, v], ...], "points": [[x, y, z], ...], optional "unit": "mm" | "m"}. OpenCASCADE
converts what it reads to millimetres, so points of a file declared in metres are compared times 1000
(this checks the declared unit too). For every file: read it with
STEPControl_Reader or IGESControl_Reader (by extension), take the one edge (curve) or one face (surface),
require it to be a B-spline, evaluate Geom_BSplineCurve / Geom_BSplineSurface at the sample parameters and
compare with fairfit's points to 1e-9 relative to the geometry's size; a surface must be exactly one face
that BRepCheck_Analyzer reports valid. Prints one JSON line per file; exit 1 on any failure.
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
