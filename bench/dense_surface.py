#!/usr/bin/env python3
"""Dense-surface benchmark: `fairfit surface CLOUD --slices N` on deterministic point clouds of
10^5 to 2 x 10^6 points sampled from an analytic vase-like surface, with Gaussian noise along the
normal.  It measures, for each case:

- wall time and peak memory of the whole CLI process;
- the net, the deviation of every section point and whether the tolerance is met (fairfit's report,
  verified on every point);
- the noise sigma fairfit measured against the true one;
- the distance of the fitted surface from the NOISE-FREE generating surface on the slicing planes
  (20,000 points of the true section curves, measured by the independent numpy/scipy measurer of
  `bench/surface_compare.py`).

The clouds are generated here (numpy, seed 0) and written to a temporary folder; nothing is read
from the shared data.

Usage (from the repository root, release binary built):
    python bench/dense_surface.py [--exe target/release/fairfit] [--out docs/benchmarks-dense-surface.md]
                                  [--quick] [--threads N]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import surface_compare  # noqa: E402  (the independent surface measurer)
from dense import run_process  # noqa: E402

HEIGHT = 2.0
REL_TOL = 1e-3
TRUE_POINTS = 20_000
# (name, cloud points, slices, noise sigma as a fraction of the tolerance)
CASES = [
    ("vase-1e5", 100_000, 50, 0.1),
    ("vase-1e6", 1_000_000, 50, 0.1),
    ("vase-2e6", 2_000_000, 50, 0.1),
    ("vase-2e6-clean", 2_000_000, 50, 0.0),
]


def radius(theta, z):
    """The vase: r(theta, z) in the plane z = const (a three-lobed section that swells along z)."""
    return (1.0 + 0.08 * np.sin(1.5 * z)) * (1.0 + 0.06 * np.cos(3.0 * theta) + 0.03 * np.sin(2.0 * theta))


def surface_points(theta, z):
    r = radius(theta, z)
    return np.stack([r * np.cos(theta), 0.7 * r * np.sin(theta), z], axis=1)


def normals(theta, z, h=1e-6):
    """Unit normals by central differences of the parameterisation (noise direction)."""
    st = (surface_points(theta + h, z) - surface_points(theta - h, z)) / (2 * h)
    sz = (surface_points(theta, z + h) - surface_points(theta, z - h)) / (2 * h)
    n = np.cross(st, sz)
    return n / np.linalg.norm(n, axis=1)[:, None]


def largest_extent(offsets):
    """The largest bounding-box extent of the true sections at the plane offsets (the tolerance's base)."""
    th = np.linspace(0, 2 * np.pi, 4001)
    ext = 0.0
    for h in offsets:
        P = surface_points(th, np.full_like(th, h))
        ext = max(ext, float((P.max(axis=0) - P.min(axis=0)).max()))
    return ext


def plane_offsets(z, slices):
    """fairfit's slicing planes: evenly spaced strictly inside the data's extent (`slicing.rs`)."""
    lo, hi = float(z.min()), float(z.max())
    return [lo + (hi - lo) * (k + 0.5) / slices for k in range(slices)]


def make_cloud(n, slices, noise_frac, rng):
    theta = rng.uniform(0.0, 2 * np.pi, n)
    z = rng.uniform(0.0, HEIGHT, n)
    P = surface_points(theta, z)
    # the tolerance is known before the noise: rel-tol of the largest true section on the planes
    tol = REL_TOL * largest_extent(plane_offsets(z, slices))
    sigma = noise_frac * tol
    if sigma > 0:
        P = P + normals(theta, z) * rng.normal(0.0, sigma, n)[:, None]
    return P, tol, sigma, plane_offsets(P[:, 2], slices)


def write_xyz(path, P, chunk=200_000):
    """`P` (n x 3) as "x y z" lines with 9 decimals, the same text as `np.savetxt(path, P, fmt="%.9f")`:
    one C-level format of a whole chunk of rows (`savetxt` formats row by row in Python, minutes for
    2 x 10^6 points)."""
    P = np.ascontiguousarray(P, dtype=float)
    with open(path, "w") as f:
        for a in range(0, len(P), chunk):
            rows = P[a:a + chunk]
            f.write(("%.9f %.9f %.9f\n" * len(rows)) % tuple(rows.ravel()))


def true_section_points(offsets, count, rng):
    th = rng.uniform(0.0, 2 * np.pi, count)
    z = np.asarray(offsets)[rng.integers(0, len(offsets), count)]
    return surface_points(th, z)


def read_surface(path):
    s = json.load(open(path))
    return surface_compare.Surface(
        s["degree_u"], s["knots_u"], s["degree_v"], s["knots_v"],
        np.array(s["control_points"]), np.array(s["weights"]) if s.get("weights") else None,
    )


def run_case(exe, name, n, slices, noise_frac, tmp, threads):
    rng = np.random.default_rng(0)
    P, tol, sigma, offsets = make_cloud(n, slices, noise_frac, rng)
    cloud = os.path.join(tmp, f"{name}.xyz")
    t0 = time.perf_counter()
    write_xyz(cloud, P)
    write_s = time.perf_counter() - t0
    out, rep = os.path.join(tmp, f"{name}.json"), os.path.join(tmp, f"{name}.report.json")
    cmd = [exe, "surface", cloud, "--slices", str(slices), "--axis", "z", "--tol", repr(tol),
           "-o", out, "--report", rep, "--threads", str(threads)]
    rc, wall, peak, stderr = run_process(cmd, timeout=1800)
    if rc != 0:
        return {"name": name, "n": n, "slices": slices, "error": stderr.strip()[:200], "wall": wall}
    r = json.load(open(rep))
    S = read_surface(out)
    truth = true_section_points(offsets, TRUE_POINTS, rng)
    t0 = time.perf_counter()
    d_true = surface_compare.surface_deviation(S, truth)
    measure_s = time.perf_counter() - t0
    dense = r.get("dense") or {}
    sigmas = [s["noise_sigma"] for s in dense.get("sections", []) if s["noise_sigma"] > 0]
    return {
        "name": name,
        "n": n,
        "slices": slices,
        "tol": tol,
        "sigma": sigma,
        "wall": wall,
        "peak": peak,
        "net": r["net"],
        "section_points": r["deviation"]["points"],
        "max_dev": r["deviation"]["max"],
        "within": r["within_tolerance"],
        "representatives": sum(s["representatives"] for s in dense.get("sections", [])),
        "sigma_median": float(np.median(sigmas)) if sigmas else 0.0,
        "outliers": sum(len(s["outliers"]) for s in dense.get("sections", [])),
        # a surface twisted between sections (sections starting at different places round the
        # ring) passes through every section point but its iso-curves across the sections wind
        # round: their longest length over the planes' span is about 1 when it is not
        "v_iso_ratio": max(c["length"] for c in r["iso_fairness"]["along_v"]) / (offsets[-1] - offsets[0]),
        "true_max": float(d_true.max()),
        "true_rms": float(np.sqrt(np.mean(d_true**2))),
        "measure_s": measure_s,
        "write_s": write_s,
        "warning": "below the noise" in stderr,
    }


def g(x, d=3):
    return f"{x:.{d}g}"


def table(rows):
    head = ("| case | cloud points | slices | section points | representatives | tol | net (u x v) | "
            "max dev / tol (every section point) | met | sigma true / measured (median) | spikes excluded | "
            "distance to the noise-free surface, max / tol (rms / tol) | longest iso-curve across / plane span | "
            "wall [s] | peak [MB] |")
    lines = [head, "|" + "---|" * 15]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['name']} | {r['n']} | {r['slices']} | failed: {r['error']} |" + " |" * 11)
            continue
        lines.append(
            f"| {r['name']} | {r['n']:,} | {r['slices']} | {r['section_points']:,} | {r['representatives']:,} | "
            f"{g(r['tol'])} | {r['net'][0]} x {r['net'][1]} | {g(r['max_dev'] / r['tol'])} | {r['within']} | "
            f"{g(r['sigma'])} / {g(r['sigma_median'])} | {r['outliers']} | "
            f"{g(r['true_max'] / r['tol'])} ({g(r['true_rms'] / r['tol'])}) | {g(r['v_iso_ratio'])} | "
            f"{r['wall']:.2f} | {r['peak']:.0f} |"
        )
    return "\n".join(lines)


def git_rev():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(REPO, "target", "release", "fairfit"))
    ap.add_argument("--out", default=None, help="write the markdown table here")
    ap.add_argument("--quick", action="store_true", help="the 10^5-point case only")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--only", default=None, help="run only the case of this name")
    a = ap.parse_args(argv)
    cases = CASES[:1] if a.quick else CASES
    if a.only:
        cases = [c for c in CASES if c[0] == a.only]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for c in cases:
            r = run_case(a.exe, *c, tmp, a.threads)
            print(json.dumps(r), flush=True)
            rows.append(r)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    text = (
        "# Dense surface benchmark\n\n"
        f"Generated by `bench/dense_surface.py` on {stamp}, commit {git_rev()}, {platform.machine()}, "
        f"{os.cpu_count()} cores, threads {a.threads or 'default'} (shared machine: times are indicative).\n\n"
        "Clouds sampled uniformly (numpy seed 0) from the vase r(theta, z) = (1 + 0.08 sin 1.5z)(1 + 0.06 cos 3theta "
        "+ 0.03 sin 2theta), x = r cos theta, y = 0.7 r sin theta, z in [0, 2], with Gaussian noise along the normal; "
        "`fairfit surface CLOUD.xyz --slices N --axis z --tol T` with T = 1e-3 of the largest true section. "
        "The section points are the cloud points of each plane's slab projected onto it (fairfit's slicing). "
        "The distance to the noise-free surface is measured by the independent measurer of "
        "`bench/surface_compare.py` at 20,000 points of the true section curves on the slicing planes.\n\n"
        + table(rows) + "\n"
    )
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        print(text)


if __name__ == "__main__":
    main()
