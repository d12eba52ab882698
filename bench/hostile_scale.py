#!/usr/bin/env python3
"""Wall time and peak memory of the large hostile inputs of issue 27 ("no answer in 60 s").

Each case is built deterministically in a temporary folder (Python standard library only), run once
with the given `fairfit` binary under a wall-clock cap, and reported as: exit code, wall seconds, peak
resident memory (the child's `ru_maxrss`, read from a small helper process so that this script's own
pages are not counted) and the last line of stderr. The target (issue 27): every case finishes in
seconds or refuses with one line naming its limit, in at most 2 GB.

Cases:
- `surface` on one STEP file of N B-spline sections (N = 250, 500, 1000; 2000 with
  `--max-sections 2000`, and 2000 at the default limit, refused);
- `surface` on one IGES file of 10,000 B-spline sections (type 126 entities; refused by the limit);
- `surface cloud.xyz --slices 6` on a 10^6-point cloud (a wavy cylinder);
- `surface cloud.xyz --slices 50` on 2 x 10^6-point clouds (issue 24): the wavy cylinder, and a
  twisted naca4412 loft with noise sigma = tol/10 (the row adds the report's closed sections and
  largest deviation);
- `curve --method lsq` on 5 x 10^6 points with `--plot` and `--html`;
- `info` on a curve JSON of 10^6 control points (refused by `--max-spans`);
- `curve` with `RAYON_NUM_THREADS=100000`.

Usage:

    python3 bench/hostile_scale.py [--fairfit target/release/fairfit] [--cap 120] [--only NAME]

Prints a Markdown table (the rows of docs/reliability.md, "Large inputs").
"""

from __future__ import annotations

import argparse
import bisect
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def step_sections(path: str, n: int) -> None:
    """`n` open cubic B-spline sections (7 control points each) stacked along z, one STEP file."""
    out = ["ISO-10303-21;", "HEADER;", "FILE_DESCRIPTION(('sections'),'2;1');",
           "FILE_NAME('s','2026-01-01T00:00:00',('a'),('b'),'c','d','e');",
           "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));", "ENDSEC;", "DATA;"]
    eid = 1
    for k in range(n):
        ids = []
        for j in range(7):
            t = j / 6 * math.pi
            y = 0.5 * math.sin(t) * (1 + 0.1 * math.sin(k))
            out.append(f"#{eid} = CARTESIAN_POINT('',({math.cos(t):.6f},{y:.6f},{k * 0.01:.4f}));")
            ids.append(eid)
            eid += 1
        refs = ",".join(f"#{i}" for i in ids)
        out.append(f"#{eid} = B_SPLINE_CURVE_WITH_KNOTS('',3,({refs}),.UNSPECIFIED.,.F.,.F.,"
                   "(4,1,1,1,4),(0.,0.25,0.5,0.75,1.),.UNSPECIFIED.);")
        eid += 1
    out += ["ENDSEC;", "END-ISO-10303-21;"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def iges_sections(path: str, n: int) -> None:
    """`n` cubic B-spline sections as IGES type 126 entities (4 control points, Bezier)."""
    def fixed(text: str, section: str, seq: int) -> str:
        return f"{text:<72}{section}{seq:>7}\n"

    start = [fixed("fairfit hostile_scale sections", "S", 1)]
    glob = ",,4Hsecs,4Hsecs,4Hfair,4Hfair,32,38,6,308,15,4Hsecs,1.,2,2HMM,1,0.01,15H20260101.000000,"
    glob += "1E-07,100.,1Hx,1Hx,11,0;"
    g = [fixed(glob[i:i + 72], "G", k + 1) for k, i in enumerate(range(0, len(glob), 72))]
    d, p = [], []
    for k in range(n):
        z = k * 0.001
        ctrl = [(1.0, 0.0), (0.5, 0.6), (-0.5, 0.6), (-1.0, 0.0)]
        params = ["126", "3", "3", "0", "0", "1", "0", "0", "0", "0", "0", "1", "1", "1", "1"]
        params += ["1", "1", "1", "1"]
        for x, y in ctrl:
            params += [f"{x:.4f}", f"{y * (1 + 0.1 * math.sin(k)):.4f}", f"{z:.4f}"]
        params += ["0", "1", "0", "0", "1"]
        text = ",".join(params) + ";"
        pstart = len(p) + 1
        de = 2 * k + 1
        lines = [text[i:i + 64] for i in range(0, len(text), 64)]
        for line in lines:
            p.append(f"{line:<64}{de:>8}P{len(p) + 1:>7}\n")
        d.append(f"{126:>8}{pstart:>8}{0:>8}{0:>8}{0:>8}{0:>8}{0:>8}{0:>8}{'00000000':>8}D{de:>7}\n")
        d.append(f"{126:>8}{0:>8}{0:>8}{len(lines):>8}{0:>8}{'':>8}{'':>8}{'':>8}{0:>8}D{de + 1:>7}\n")
    t = f"S{1:>7}G{len(g):>7}D{len(d):>7}P{len(p):>7}"
    with open(path, "w") as f:
        f.writelines(start + g + d + p)
        f.write(fixed(t, "T", 1))


def cloud(path: str, n: int) -> None:
    """`n` random points on a wavy cylinder (radius 1 ± 0.1 sin 3t · z, height 1)."""
    rng = random.Random(1)
    with open(path, "w") as f:
        for _ in range(n):
            t, z = rng.random() * 2 * math.pi, rng.random()
            r = 1 + 0.1 * math.sin(3 * t) * z
            f.write(f"{r * math.cos(t):.6f} {r * math.sin(t):.6f} {z:.6f}\n")


def foil_cloud(path: str, n: int, sigma: float = 1e-4) -> None:
    """`n` random points of a naca4412 loft (chord 1, its closed outline from examples/data, the
    blunt trailing edge included), z in [0, 2], twisted by 0.5 rad over the height about the quarter
    chord, with Gaussian noise `sigma` along the outline's normal (tol/10 at --rel-tol 1e-3)."""
    outline = []
    with open(os.path.join(REPO, "examples", "data", "naca4412.csv")) as f:
        for line in f:
            try:
                outline.append(tuple(float(v) for v in line.split(",")))
            except ValueError:
                continue
    outline.append(outline[0])
    cum = [0.0]
    for a, b in zip(outline, outline[1:]):
        cum.append(cum[-1] + math.dist(a, b))
    rng = random.Random(2)
    with open(path, "w") as f:
        for _ in range(n):
            u, z = rng.random() * cum[-1], rng.random() * 2.0
            k = min(max(bisect.bisect_right(cum, u) - 1, 0), len(outline) - 2)
            (x0, y0), (x1, y1) = outline[k], outline[k + 1]
            seg = cum[k + 1] - cum[k]
            t = (u - cum[k]) / seg
            e = rng.gauss(0.0, sigma)
            x = x0 + t * (x1 - x0) + e * (y1 - y0) / seg - 0.25
            y = y0 + t * (y1 - y0) - e * (x1 - x0) / seg
            a = 0.25 * z
            f.write(f"{x * math.cos(a) - y * math.sin(a):.9f} {x * math.sin(a) + y * math.cos(a):.9f} {z:.9f}\n")


def report_note(path: str) -> str:
    """The sections closed and the largest deviation (in tolerances) of a surface report."""
    try:
        r = json.load(open(path))
    except (OSError, ValueError):
        return ""
    closed = sum(1 for s in r["sections"] if s["closed"])
    return (f"{closed} of {len(r['sections'])} sections closed, {len(r['gaps'])} gaps, max deviation "
            f"{r['deviation']['max'] / r['tolerance']:.2f} tol over {r['deviation']['points']} section points; ")


def spiral(path: str, n: int) -> None:
    """`n` points on a planar spiral arc."""
    with open(path, "w") as f:
        for i in range(n):
            t = i / (n - 1) * 3
            f.write(f"{math.cos(t) * (1 + t):.7f},{math.sin(t) * (1 + t):.7f}\n")


def big_curve_json(path: str, n: int) -> None:
    """A cubic B-spline of `n` control points in fairfit's JSON."""
    knots = [0.0] * 4 + [i / (n - 3) for i in range(1, n - 3)] + [1.0] * 4
    ctrl = [[i / n, math.sin(i * 0.01), 0.0] for i in range(n)]
    with open(path, "w") as f:
        json.dump({"kind": "curve", "degree": 3, "knots": knots, "control_points": ctrl}, f)


MEASURE = r"""
import resource, subprocess, sys, time, os
cap = float(sys.argv[1]); env = dict(os.environ); env.update(eval(sys.argv[2]))
t = time.time()
try:
    p = subprocess.run(sys.argv[3:], capture_output=True, text=True, timeout=cap, env=env)
    rc, err = p.returncode, p.stderr
except subprocess.TimeoutExpired as e:
    rc, err = "timeout", (e.stderr or b"").decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
wall = time.time() - t
mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
last = [l for l in err.splitlines() if l.strip()]
print(repr((rc, wall, mb, last[-1] if last else "")))
"""


def run(cmd: list[str], cap: float, env: dict | None = None, cwd: str | None = None):
    out = subprocess.run([sys.executable, "-c", MEASURE, str(cap), repr(env or {})] + cmd,
                         capture_output=True, text=True, cwd=cwd)
    return eval(out.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fairfit", default=os.path.join(REPO, "target", "release", "fairfit"))
    ap.add_argument("--cap", type=float, default=120.0)
    ap.add_argument("--only", default=None)
    args = ap.parse_args()
    ff = os.path.abspath(args.fairfit)
    rows = []
    with tempfile.TemporaryDirectory() as d:
        cases = []
        for n, limit in ((250, None), (500, None), (1000, None), (2000, "2000"), (2000, None)):
            extra = ["--max-sections", limit] if limit else []
            name = f"surface, STEP of {n} sections" + (f" (--max-sections {limit})" if limit else "")
            cases.append((name, lambda n=n: step_sections(f"{d}/s{n}.step", n),
                          [ff, "surface", f"{d}/s{n}.step", "--rel-tol", "1e-3", "-o", f"{d}/s{n}.json"] + extra,
                          None))
        cases.append(("surface, IGES of 10,000 sections", lambda: iges_sections(f"{d}/s.igs", 10_000),
                      [ff, "surface", f"{d}/s.igs", "--rel-tol", "1e-3", "-o", f"{d}/si.json"], None))
        cases.append(("surface --slices 6, cloud of 10^6 points", lambda: cloud(f"{d}/c.xyz", 1_000_000),
                      [ff, "surface", f"{d}/c.xyz", "--slices", "6", "--axis", "z", "--rel-tol", "1e-3",
                       "-o", f"{d}/c.json"], None))
        cases.append(("surface --slices 50, wavy cylinder cloud of 2 x 10^6 points",
                      lambda: cloud(f"{d}/c2.xyz", 2_000_000),
                      [ff, "surface", f"{d}/c2.xyz", "--slices", "50", "--axis", "z", "--rel-tol", "1e-3",
                       "-o", f"{d}/c2.json", "--report", f"{d}/c2.report.json"], None))
        cases.append(("surface --slices 50, twisted naca4412 cloud of 2 x 10^6 points, sigma tol/10",
                      lambda: foil_cloud(f"{d}/f2.xyz", 2_000_000),
                      [ff, "surface", f"{d}/f2.xyz", "--slices", "50", "--axis", "z", "--rel-tol", "1e-3",
                       "-o", f"{d}/f2.json", "--report", f"{d}/f2.report.json"], None))
        cases.append(("curve --method lsq --plot --html, 5 x 10^6 points",
                      lambda: spiral(f"{d}/big.csv", 5_000_000),
                      [ff, "curve", f"{d}/big.csv", "--method", "lsq", "--rel-tol", "1e-3", "-o", f"{d}/b.json",
                       "--plot", f"{d}/b.svg", "--html", f"{d}/b.html"], None))
        cases.append(("info, curve of 10^6 control points", lambda: big_curve_json(f"{d}/big.json", 1_000_000),
                      [ff, "info", f"{d}/big.json"], None))
        cases.append(("curve, RAYON_NUM_THREADS=100000", lambda: spiral(f"{d}/small.csv", 200),
                      [ff, "curve", f"{d}/small.csv", "--rel-tol", "1e-3", "-o", f"{d}/sm.json"],
                      {"RAYON_NUM_THREADS": "100000"}))
        for name, make, cmd, env in cases:
            if args.only and args.only not in name:
                continue
            t = time.time()
            make()
            built = time.time() - t
            rc, wall, mb, last = run(cmd, args.cap, env)
            if "--report" in cmd:
                last = report_note(cmd[cmd.index("--report") + 1]) + last
            rows.append((name, rc, wall, mb, last, built))
            print(f"{name}: rc {rc}, {wall:.1f} s, {mb:.0f} MB", file=sys.stderr)
    print("| case | exit | wall s | peak MB | last stderr line |")
    print("|---|---|---|---|---|")
    for name, rc, wall, mb, last, _ in rows:
        last = last.replace("|", "\\|")
        if len(last) > 110:
            last = last[:107] + "..."
        print(f"| {name} | {rc} | {wall:.1f} | {mb:.0f} | {last} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
