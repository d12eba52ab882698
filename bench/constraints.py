#!/usr/bin/env python3
"""End-condition benchmark (issue 26 targets): G2 ends taken from the unconstrained fit's own ends.

For every curve of the shared data (airfoils, synthetic, IEA 15 MW airfoils: 33 curves):

1. the unconstrained fit U: `fairfit curve FILE --rel-tol 1e-3 --seed 0` (the default integrated
   method), or its curve JSON from a recorded `bench/same_output.py` folder (`--baseline DIR`,
   `curve_<name>_integrated_s0.json`);
2. U's start and end evaluated here (`measure.Curve`, scipy, no fairfit code): the unit tangent and the
   signed curvature;
3. the constrained fit C: the same command with `--start curvature:TX,TY:K --end curvature:TX,TY:K`;
   closed data (the last point repeats the first) are fitted open (`--open`), both ends held to
   U's frame at the data's first point (leaving it at the start, arriving at the end);
4. both measured by the independent `bench/measure.py`: max deviation, F, curvature extrema, and at C's
   ends the tangent angle to the condition and the relative curvature difference.

Targets: geometric mean of F(C)/F(U) <= 1.05, extrema(C) <= extrema(U) on every curve, every angle
<= 1e-9 rad and every curvature difference <= 1e-9 relative, and C within the tolerance (1e-3 of the
bounding box, with 1e-9 relative slack for rounding). Exit code 0 when all hold, 1 otherwise.

Usage (from the repository root):

    python bench/constraints.py BIN [--data DIR] [--baseline DIR] [--jobs N] [--csv OUT.csv] [--md OUT.md]
    python bench/constraints.py BIN --only NAME[,NAME...]          # a few curves
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import measure  # noqa: E402
from same_output import curves, default_data  # noqa: E402

REL_TOL = 1e-3
F_RISE_MAX = 1.05
ANGLE_MAX = 1e-9
CURVATURE_MAX = 1e-9


def load_curve(path: str) -> measure.Curve:
    with open(path) as f:
        c = json.load(f)
    return measure.Curve(c["degree"], c["knots"], c["control_points"], c.get("weights"))


def end_frame(curve: measure.Curve, at_end: bool):
    """(unit tangent, signed curvature) of a planar curve at its start or end (xy plane)."""
    return frame_at(curve, curve.hi if at_end else curve.lo)


def seam_frames(curve: measure.Curve, point):
    """The frames of closed data's unconstrained fit U where the data start and end (their first
    point, which the last repeats): U's parameter of that point (the nearest of dense samples,
    refined by golden section), U's frame leaving it (the start) and arriving at it (the end), one
    side each, at 1e-13 of the domain from it (U may have a corner there). A periodic U starts at
    the first point; one cut at a corner starts at that corner."""
    lo, hi = curve.lo, curve.hi
    us = np.linspace(lo, hi, 20001)
    q = np.asarray(point, dtype=float)[:2]
    d = np.linalg.norm(curve.points(us)[:, :2] - q, axis=1)
    i = int(np.argmin(d))
    a, b = us[max(i - 1, 0)], us[min(i + 1, len(us) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    dist = lambda u: float(np.linalg.norm(curve.points(np.array([u]))[0, :2] - q))  # noqa: E731
    for _ in range(80):
        c, e = b - g * (b - a), a + g * (b - a)
        if dist(c) < dist(e):
            b = e
        else:
            a = c
    u0 = 0.5 * (a + b)
    eps = 1e-13 * (hi - lo)
    if u0 - lo <= 1e-9 * (hi - lo) or hi - u0 <= 1e-9 * (hi - lo):
        return end_frame(curve, False), end_frame(curve, True)
    return frame_at(curve, u0 + eps), frame_at(curve, u0 - eps)


def frame_at(curve: measure.Curve, u: float):
    """(unit tangent, signed curvature) of a planar curve at `u` (xy plane)."""
    u = np.array([u])
    _, d1, d2 = curve.derivs(u, 2)
    d1, d2 = d1[0][:2], d2[0][:2]
    s = float(np.hypot(d1[0], d1[1]))
    kappa = float(d1[0] * d2[1] - d1[1] * d2[0]) / s**3
    return d1 / s, kappa


def condition(t, kappa) -> str:
    return f"curvature:{float(t[0])!r},{float(t[1])!r}:{float(kappa)!r}"


def fit(binary: str, path: str, out: str, extra: list[str]) -> None:
    cmd = [binary, "curve", path, "--rel-tol", str(REL_TOL), "--seed", "0", "-o", out, *extra]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip() or f"exit {p.returncode}")


def metrics(curve_path: str, points):
    with open(curve_path) as f:
        c = json.load(f)
    return measure.measure(c["degree"], c["knots"], c["control_points"], c.get("weights"), points)


def is_closed(points) -> bool:
    """Whether the last point repeats the first (1e-9 of the bounding box, fairfit's own rule)."""
    p = np.asarray(points, dtype=float)
    extent = float(np.max(p.max(axis=0) - p.min(axis=0)))
    return extent > 0 and float(np.linalg.norm(p[-1] - p[0])) <= 1e-9 * extent


def one(binary: str, name: str, path: str, baseline: str | None, tmp: str) -> dict:
    points = measure.read_points(path)
    base = os.path.join(baseline, f"curve_{name}_integrated_s0.json") if baseline else None
    if not (base and os.path.exists(base)):
        base = os.path.join(tmp, f"{name}_free.json")
        fit(binary, path, base, [])
    u = load_curve(base)
    closed = is_closed(points)
    if closed:
        (t0, k0), (t1, k1) = seam_frames(u, points[0])
    else:
        (t0, k0), (t1, k1) = end_frame(u, False), end_frame(u, True)
    out = os.path.join(tmp, f"{name}_g2.json")
    row = {"name": name}
    row["open"] = "yes" if closed else ""
    extra = ["--open"] if closed else []
    try:
        fit(binary, path, out, ["--start", condition(t0, k0), "--end", condition(t1, k1), *extra])
    except RuntimeError as e:
        row["error"] = str(e).splitlines()[-1][:200]
        return row
    mu, mc = metrics(base, points), metrics(out, points)
    c = load_curve(out)
    worst_angle, worst_k = 0.0, 0.0
    for at_end, (t, k) in [(False, (t0, k0)), (True, (t1, k1))]:
        tc, kc = end_frame(c, at_end)
        cross = tc[0] * t[1] - tc[1] * t[0]
        worst_angle = max(worst_angle, abs(math.atan2(cross, float(tc @ t))))
        worst_k = max(worst_k, abs(kc - k) / max(abs(k), 1e-300))
    tol = measure.tolerance(points, REL_TOL)
    row.update(
        tol=tol,
        n_free=mu.n_ctrl,
        n_g2=mc.n_ctrl,
        F_free=mu.F,
        F_g2=mc.F,
        ratio=mc.F / mu.F,
        ext_free=mu.extrema,
        ext_g2=mc.extrema,
        max_dev_g2=mc.max_dev,
        angle=worst_angle,
        curvature_rel=worst_k,
    )
    return row


def summary(rows: list[dict]) -> dict:
    ok = [r for r in rows if "error" not in r]
    ratios = [r["ratio"] for r in ok]
    gm = math.exp(sum(math.log(x) for x in ratios) / len(ratios)) if ratios else float("nan")
    return {
        "curves": len(rows),
        "failed": len(rows) - len(ok),
        "geo_mean_F_ratio": gm,
        "extrema_increased": sum(r["ext_g2"] > r["ext_free"] for r in ok),
        "max_angle": max((r["angle"] for r in ok), default=float("nan")),
        "max_curvature_rel": max((r["curvature_rel"] for r in ok), default=float("nan")),
        "tolerance_missed": sum(r["max_dev_g2"] > r["tol"] * (1 + 1e-9) for r in ok),
    }


def targets_met(s: dict) -> bool:
    return (
        s["failed"] == 0
        and s["geo_mean_F_ratio"] <= F_RISE_MAX
        and s["extrema_increased"] == 0
        and s["max_angle"] <= ANGLE_MAX
        and s["max_curvature_rel"] <= CURVATURE_MAX
        and s["tolerance_missed"] == 0
    )


COLUMNS = ["name", "open", "n_free", "n_g2", "F_free", "F_g2", "ratio", "ext_free", "ext_g2", "angle",
           "curvature_rel", "max_dev_g2", "tol", "error"]


def fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    return "" if v is None else str(v)


def markdown(rows: list[dict], s: dict) -> str:
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for r in rows:
        lines.append("| " + " | ".join(fmt(r.get(c)) for c in COLUMNS) + " |")
    lines.append("")
    lines.append(
        f"{s['curves']} curves, {s['failed']} failed; geometric mean F ratio {s['geo_mean_F_ratio']:.4f} "
        f"(target <= {F_RISE_MAX}); extrema increased on {s['extrema_increased']}; largest angle "
        f"{s['max_angle']:.3g} rad; largest curvature difference {s['max_curvature_rel']:.3g}; tolerance "
        f"missed on {s['tolerance_missed']}; targets met: {targets_met(s)}"
    )
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("--data", default=None)
    ap.add_argument("--baseline", default=None, help="a bench/same_output.py record folder (seed 0)")
    ap.add_argument("--only", default=None, help="comma-separated curve names")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--csv", default=None)
    ap.add_argument("--md", default=None)
    a = ap.parse_args()
    data = a.data or default_data()
    todo = curves(data)
    if a.only:
        keep = set(a.only.split(","))
        todo = [(n, p) for n, p in todo if n in keep]
    with tempfile.TemporaryDirectory() as tmp:
        with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            rows = list(ex.map(lambda np_: one(a.binary, np_[0], np_[1], a.baseline, tmp), todo))
    s = summary(rows)
    text = markdown(rows, s)
    print(text, end="")
    if a.md:
        with open(a.md, "w") as f:
            f.write(text)
    if a.csv:
        with open(a.csv, "w") as f:
            f.write(",".join(COLUMNS) + "\n")
            for r in rows:
                f.write(",".join(fmt(r.get(c)).replace(",", ";") for c in COLUMNS) + "\n")
    return 0 if targets_met(s) else 1


if __name__ == "__main__":
    sys.exit(main())
