#!/usr/bin/env python3
"""Dense-section benchmark (issue 24): scan-like point sequences of 10^3 to 10^6 points, with noise and
spikes, fitted by fairfit (default method) and by scipy splprep, every result measured by bench/measure.py.

Usage (from the repository root):
    python bench/dense.py [--quick] [--only PATTERN] [--out docs/benchmarks-dense.md] [--fairfit PATH]

The suite is deterministic (fixed seeds) and written to a temporary folder:

* real airfoils from ``examples/data``, densified along the curve: an interpolating parametric cubic
  spline through the table (chord-length parameter), sampled evenly in arc length, at 10^3 .. 10^6 points,
  with Gaussian noise along the normal of sigma 0, tol/100 and tol/10, and one case at tol/3 that must get
  the noise warning;
* a 3-D space curve and a closed curve of 10^5 points (noise tol/10);
* curves with true corners (turns of 90 and 45 degrees; one of 30 degrees with ``--corner-angle 20``);
* the airfoil with bursts of density (100:1) and the airfoil with 0.5 % spikes of 20 x tol.

tol = ``REL_TOL`` x the largest side of the bounding box of the noise-free points (the noise sigma is a
fraction of it); the tolerance a fit must meet is the same rule on the input points, as fairfit's
``--rel-tol`` computes it. Every fit is measured with the independent measurer ``bench/measure.py``
(control points, max orthogonal deviation on every input point except the outliers fairfit's report lists,
F, curvature extrema), and against the noise-free generating curve: the fit sampled densely to the
generator, and the generator's points to the fit (both as distances to a dense polyline, whose chord error
is far below the tolerance, see ``polyline_distance``). The report goes to ``docs/benchmarks-dense.md``:
one table per solver and the issue's target checklist (met / not met / not measured).
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from datetime import datetime, timezone

import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import measure  # noqa: E402

REPO = os.path.dirname(HERE)
DATA = os.path.join(REPO, "examples", "data")

REL_TOL = 1e-3
SIZES = (1_000, 10_000, 100_000, 1_000_000)
QUICK_MAX_POINTS = 10_000
# noise sigma as a fraction of tol; the last one must get the noise warning, the others must not
NOISE_LEVELS = (0.0, 0.01, 0.1)
WARN_NOISE = 1.0 / 3.0
SPIKE_FRACTION = 0.005
SPIKE_SIZE = 20.0  # in tol
BURST_RATIO = 100.0
SEED = 20261202
# per-case wall-clock cap of a fairfit run; a run over it is reported as "timeout", never waited for
FAIRFIT_TIMEOUT_S = 120.0
# scipy splprep: its s-search (every step measured) stops at this wall time and is reported as skipped;
# above SPLPREP_MAX_POINTS it is not started (one measured step alone costs ~30 s at 10^6 points)
SPLPREP_TIME_CAP_S = 180.0
SPLPREP_MAX_POINTS = 100_000
# a fit with more control points than this is not measured for F and extrema (it followed the noise)
MEASURE_CTRL_CAP = 5_000
DEV_CHUNK = 50_000  # points per call of the measurer (bounds its memory)
GEN_POLYLINE = 400_000  # vertices of the noise-free generator's polyline
FIT_POLYLINE = 200_000  # samples of a fit for its distance to the generator
MEET_SLACK = 1e-6  # relative round-off slack of "meets the tolerance" (as bench/compare.py)
CORNER_ANGLE_DEFAULT = 60.0  # fairfit's default --corner-angle (degrees)
# a fit's corner is a knot of multiplicity >= degree (C0) whose one-sided tangents turn by more than this
CORNER_MIN_TURN_DEG = 1.0

# fairfit report keys read by this benchmark (missing keys are "n/a", never an error)
OUTLIERS_KEY = "outliers"  # list of {"index": i, "distance": d}, 0-based input rows
CORNERS_KEY = "corners"  # list of 0-based input rows (or of {"index": i})
NOISE_SIGMA_KEYS = ("noise_sigma", ("noise", "sigma"))
# the one-line noise warning on stderr
NOISE_WARNING = re.compile(r"^\s*warning:.*\bnoise\b", re.IGNORECASE)

# target identifiers (the "Targets" list, in order)
T_TOL = "tolerance"
T_FEATURES = "features"
T_SPLPREP = "splprep"
T_CLEAN = "clean"
T_SIGMA = "sigma"
T_TIME_1E6 = "time-1e6"
T_SCALING = "scaling"
T_COUNTS = "counts"
T_SHARED = "shared"


# ----------------------------------------------------------------------------- shapes and cases


@dataclass
class Shape:
    """A noise-free generating curve g(u), u in [0, 1] (vectorised, returns (len(u), dim))."""

    name: str
    g: object
    closed: bool = False
    corner_us: tuple = ()  # parameters of the true corners
    corner_turns: tuple = ()  # their turning angles (degrees)


@dataclass
class Case:
    name: str
    shape: Shape
    n: int
    noise: float  # sigma / tol
    spikes: bool = False
    bursts: bool = False
    extra: tuple = ()  # extra fairfit arguments
    corner_angle: float = CORNER_ANGLE_DEFAULT
    family: str = ""  # cases of one family differ only in the point count

    @property
    def expected_corners(self):
        """Parameters of the true corners fairfit must find: turns of at least the corner angle."""
        return [u for u, a in zip(self.shape.corner_us, self.shape.corner_turns) if a >= self.corner_angle]


def airfoil_shape(name):
    P = measure.read_points(os.path.join(DATA, f"{name}.csv"))
    d = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))]
    spline = make_interp_spline(d / d[-1], P, k=3)
    return Shape(name, lambda u: spline(np.clip(u, 0.0, 1.0)))


def space_shape():
    """A conical helix with a varying pitch: torsion and curvature everywhere, no plane."""

    def g(u):
        th = 3.0 * np.pi * u
        r = 1.0 + 0.3 * u
        return np.column_stack([r * np.cos(th), r * np.sin(th), 0.4 * th / np.pi + 0.1 * np.sin(2 * th)])

    return Shape("helix3d", g)


def closed_shape():
    """A smooth closed blob r(t) = 1 + 0.2 cos 3t + 0.1 sin 5t."""

    def g(u):
        t = 2.0 * np.pi * u
        r = 1.0 + 0.2 * np.cos(3 * t) + 0.1 * np.sin(5 * t)
        return np.column_stack([r * np.cos(t), r * np.sin(t)])

    return Shape("blob-closed", g, closed=True)


def arcs_shape(name, lengths, curvatures, turns):
    """Circular arcs (lengths, signed curvatures) joined by corners that turn the tangent by `turns`
    degrees; u is proportional to arc length."""
    L = float(sum(lengths))
    starts = np.r_[0.0, np.cumsum(lengths)][:-1]
    heading = [0.0]
    origin = [np.zeros(2)]
    for i in range(len(lengths) - 1):
        th, k, ln = heading[-1], curvatures[i], lengths[i]
        origin.append(origin[-1] + _arc(th, k, np.array([ln]))[0])
        heading.append(th + k * ln + math.radians(turns[i]))

    def g(u):
        s = np.clip(np.asarray(u, dtype=float), 0.0, 1.0) * L
        idx = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(lengths) - 1)
        out = np.empty((len(s), 2))
        for i in range(len(lengths)):
            m = idx == i
            out[m] = origin[i] + _arc(heading[i], curvatures[i], s[m] - starts[i])
        return out

    corner_us = tuple(float(x) / L for x in np.cumsum(lengths)[:-1])
    return Shape(name, g, corner_us=corner_us, corner_turns=tuple(abs(t) for t in turns))


def _arc(th, k, s):
    if abs(k) < 1e-12:
        return np.column_stack([s * np.cos(th), s * np.sin(th)])
    return np.column_stack([(np.sin(th + k * s) - np.sin(th)) / k, -(np.cos(th + k * s) - np.cos(th)) / k])


def _noise_name(f):
    if f == 0:
        return "clean"
    return f"tol{round(1.0 / f)}"


def build_cases(quick=False, only=None):
    """The suite, in report order. `quick`: only cases up to QUICK_MAX_POINTS points; `only`: an fnmatch
    pattern on the case name."""
    foil = airfoil_shape("naca4412")
    foil2 = airfoil_shape("fx77w343")
    cases = []
    for n in SIZES:
        for f in NOISE_LEVELS:
            cases.append(Case(f"naca4412-{_n_name(n)}-{_noise_name(f)}", foil, n, f, family=f"naca4412-{f}"))
    cases.append(Case(f"naca4412-{_n_name(10_000)}-{_noise_name(WARN_NOISE)}", foil, 10_000, WARN_NOISE))
    for n in (10_000, 100_000):
        cases.append(Case(f"fx77w343-{_n_name(n)}-tol10", foil2, n, 0.1, family="fx77w343-0.1"))
    cases.append(Case("helix3d-1e5-tol10", space_shape(), 100_000, 0.1))
    cases.append(Case("blob-closed-1e5-tol10", closed_shape(), 100_000, 0.1, extra=("--closed",)))
    two = arcs_shape("corners-90-45", (1.0, 0.8, 1.0), (0.6, -0.8, 0.5), (90.0, -45.0))
    cases.append(Case("corners-90-45-1e4-tol100", two, 10_000, 0.01, extra=("--corner-angle", "30"),
                      corner_angle=30.0))
    one = arcs_shape("corner-30", (1.2, 1.0), (0.5, 0.7), (30.0,))
    cases.append(Case("corner-30-1e4-tol100", one, 10_000, 0.01, extra=("--corner-angle", "20"),
                      corner_angle=20.0))
    cases.append(Case("naca4412-1e4-tol100-bursts", foil, 10_000, 0.01, bursts=True))
    cases.append(Case("naca4412-1e4-tol100-spikes", foil, 10_000, 0.01, spikes=True))
    if quick:
        cases = [c for c in cases if c.n <= QUICK_MAX_POINTS]
    if only:
        cases = [c for c in cases if fnmatch.fnmatch(c.name, only)]
    return cases


def _n_name(n):
    e = round(math.log10(n))
    return f"1e{e}" if 10**e == n else str(n)


# ----------------------------------------------------------------------------- sampling


def generator_polyline(shape, m=GEN_POLYLINE):
    """(u, vertices, cumulative arc length) of a dense polyline of the generator, every corner a vertex."""
    u = np.unique(np.r_[np.linspace(0.0, 1.0, m), np.asarray(shape.corner_us, dtype=float)])
    V = shape.g(u)
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(V, axis=0), axis=1))]
    return u, V, s


def burst_density(x):
    """Relative point density at arc-length fraction x: BURST_RATIO inside three bursts of 2 %."""
    inside = np.zeros_like(x, dtype=bool)
    for c in (0.2, 0.5, 0.8):
        inside |= np.abs(x - c) < 0.01
    return np.where(inside, BURST_RATIO, 1.0)


def sample_params(shape, n, bursts, poly):
    """n parameters evenly spaced in arc length (closed: the last point does not repeat the first), or
    with the density of `burst_density`."""
    u_g, _, s_g = poly
    L = s_g[-1]
    q = np.arange(n) / n if shape.closed else np.linspace(0.0, 1.0, n)
    if bursts:
        x = np.linspace(0.0, 1.0, 200_001)
        rho = burst_density(x)
        cdf = np.r_[0.0, np.cumsum(0.5 * (rho[1:] + rho[:-1]) * np.diff(x))]
        q = np.interp(q, cdf / cdf[-1], x)
    return np.interp(q * L, s_g, u_g)


def unit_normals(shape, u, dim, rng):
    """Unit normals at u: the tangent turned by 90 degrees (planar), or a random unit vector orthogonal to
    the tangent (3-D). Tangents by central differences of g."""
    h = 1e-6
    T = shape.g(np.clip(u + h, 0.0, 1.0)) - shape.g(np.clip(u - h, 0.0, 1.0))
    T /= np.maximum(np.linalg.norm(T, axis=1), 1e-300)[:, None]
    if dim == 2:
        return np.column_stack([-T[:, 1], T[:, 0]])
    R = rng.standard_normal(T.shape)
    R -= np.einsum("ij,ij->i", R, T)[:, None] * T
    return R / np.maximum(np.linalg.norm(R, axis=1), 1e-300)[:, None]


def spike_indices(n, rng):
    """SPIKE_FRACTION of the points, isolated (at least 4 rows apart) and away from the ends."""
    k = max(1, round(SPIKE_FRACTION * n))
    slots = np.arange(5, n - 5, 4)
    return np.sort(rng.choice(slots, size=k, replace=False))


@dataclass
class Data:
    points: np.ndarray
    clean: np.ndarray
    tol_gen: float  # REL_TOL x the noise-free points' bounding box: sigma and spikes are fractions of it
    sigma: float
    spikes: np.ndarray  # rows displaced by a spike
    corners: np.ndarray  # (k, dim) positions of the expected corners
    poly: tuple = field(repr=False, default=None)


def make_data(case):
    rng = np.random.default_rng([SEED, sum(map(ord, case.name))])
    poly = generator_polyline(case.shape)
    u = sample_params(case.shape, case.n, case.bursts, poly)
    clean = case.shape.g(u)
    dim = clean.shape[1]
    tol_gen = measure.tolerance(clean, REL_TOL)
    sigma = case.noise * tol_gen
    N = unit_normals(case.shape, u, dim, rng)
    pts = clean + (sigma * rng.standard_normal(case.n))[:, None] * N
    spikes = np.zeros(0, dtype=int)
    if case.spikes:
        spikes = spike_indices(case.n, rng)
        sign = rng.choice([-1.0, 1.0], size=len(spikes))
        moved = pts[spikes] + (SPIKE_SIZE * tol_gen * sign)[:, None] * N[spikes]
        # a spike is an isolated point far from the curve: where the random side lands near another
        # part of the curve (inside a thin trailing edge or the leading-edge circle), take the other side
        near = polyline_distance(moved, poly[1]) < 0.95 * SPIKE_SIZE * tol_gen
        sign[near] *= -1.0
        pts[spikes] += (SPIKE_SIZE * tol_gen * sign)[:, None] * N[spikes]
    cu = np.asarray(case.expected_corners, dtype=float)
    corners = case.shape.g(cu) if len(cu) else np.zeros((0, dim))
    return Data(pts, clean, tol_gen, sigma, spikes, corners, poly)


def write_csv(path, P):
    header = "x,y,z" if P.shape[1] == 3 else "x,y"
    np.savetxt(path, P, delimiter=",", fmt="%.12g", header=header, comments="")


# ----------------------------------------------------------------------------- distances


def polyline_distance(Q, V, k=4):
    """Distance of every point of Q to the polyline through the vertices V (in order): the segments next
    to each of the k nearest vertices. With vertices h apart along a curve of curvature kappa, the
    polyline is within h^2 kappa / 8 of the curve (1e-9 of the chord for the densities used here)."""
    V = np.asarray(V, dtype=float)
    Q = np.asarray(Q, dtype=float)
    tree = cKDTree(V)
    _, J = tree.query(Q, k=min(k, len(V)))
    J = J.reshape(len(Q), -1)
    best = np.full(len(Q), np.inf)
    for c in range(J.shape[1]):
        for off in (-1, 0):
            a = np.clip(J[:, c] + off, 0, len(V) - 2)
            A, B = V[a], V[a + 1]
            AB = B - A
            t = np.einsum("ij,ij->i", Q - A, AB) / np.maximum(np.einsum("ij,ij->i", AB, AB), 1e-300)
            t = np.clip(t, 0.0, 1.0)
            d = np.linalg.norm(Q - (A + t[:, None] * AB), axis=1)
            best = np.minimum(best, d)
    return best


def curve_polyline(curve, m=FIT_POLYLINE):
    """A fitted curve sampled densely: at least 48 samples per span, about m in all, with both ends."""
    per = max(measure.SAMPLES_PER_SPAN, math.ceil(m / max(1, len(curve.spans))))
    return curve.points(curve.span_samples(per, include_ends=True))


def data_deviations(curve, P):
    """measure.deviations on every point, in chunks."""
    return np.concatenate([measure.deviations(curve, P[i : i + DEV_CHUNK]) for i in range(0, len(P), DEV_CHUNK)])


def clean_distance(curve, data, closed):
    """Max distance between a fit and the noise-free generator, both ways: the fit's dense samples to the
    generator's polyline, and the generator's points (the noise-free data) to the fit's polyline."""
    V = data.poly[1]
    if closed:
        V = np.vstack([V, V[:1]])
    F = curve_polyline(curve)[:, : V.shape[1]]  # a planar fit may come as x, y, 0
    a = float(np.max(polyline_distance(F, V)))
    b = float(np.max(polyline_distance(data.clean, F)))
    return max(a, b)


# ----------------------------------------------------------------------------- fairfit


@dataclass
class Run:
    """One solver's result on one case: status "ok", "timeout", "skipped" or "error", and its numbers."""

    status: str
    reason: str = ""
    wall_s: float = float("nan")
    peak_mb: float = float("nan")
    n_ctrl: int | None = None
    max_dev: float = float("nan")  # on every point except the excluded outliers
    max_dev_all: float = float("nan")  # on every point
    F: float = float("nan")
    extrema: int | None = None
    clean_dist: float = float("nan")
    corners: list = field(default_factory=list)  # corner positions measured on the fit (c0_corners)
    report_corners: int | None = None  # how many corners the report lists (None: no such key)
    outliers: list = field(default_factory=list)  # input rows
    sigma_est: float | None = None
    noise_warnings: int = 0
    report: dict = field(default_factory=dict, repr=False)


_SPAWNER = None


def run_process(cmd, timeout):
    """Run cmd with stdout/stderr to files; (returncode or None on timeout, wall s, peak RSS MB, stderr).

    The command is started from a small helper process (a one-worker `forkserver` pool), not from this
    one: Linux counts the resident pages a forked child inherits in its `ru_maxrss`, so a child forked
    from this process, which holds the 10^6-point cases, would report this process's size as its peak.
    The helper's own size (about 80 MB: it imports this module, numpy and scipy) is the floor of what
    it reports.
    """
    global _SPAWNER
    if _SPAWNER is None:
        import multiprocessing

        _SPAWNER = multiprocessing.get_context("forkserver").Pool(1)
    return _SPAWNER.apply(_run_process_here, (cmd, timeout))


def _run_process_here(cmd, timeout):
    """`run_process` in the calling process."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out, stderr=err)
        rc, ru = None, None
        while True:
            pid, status, ru = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                rc = os.waitstatus_to_exitcode(status)
                break
            if time.perf_counter() - t0 > timeout:
                proc.kill()
                _, _, ru = os.wait4(proc.pid, 0)
                break
            time.sleep(0.02)
        wall = time.perf_counter() - t0
        proc.returncode = rc if rc is not None else -9  # reaped above: keep Popen from waiting again
        err.seek(0)
        stderr = err.read().decode("utf-8", "replace")
    peak = ru.ru_maxrss / 1024.0 if ru is not None else float("nan")  # Linux: kilobytes
    return rc, wall, peak, stderr


def failure_reason(stderr, rc):
    lines = [ln.strip() for ln in (stderr or "").splitlines() if ln.strip()]
    for ln in lines:
        if ln.lower().startswith("error:"):
            return ln[len("error:"):].strip()[:200]
    return lines[0][:200] if lines else f"exit {rc}"


def report_rows(report, key):
    """The 0-based input rows a report lists under `key`: ints, or objects with an "index"."""
    out = []
    for item in report.get(key) or []:
        if isinstance(item, bool):
            continue
        if isinstance(item, int):
            out.append(item)
        elif isinstance(item, dict) and isinstance(item.get("index"), int):
            out.append(item["index"])
    return sorted(out)


def report_sigma(report):
    for key in NOISE_SIGMA_KEYS:
        v = report
        for k in key if isinstance(key, tuple) else (key,):
            v = v.get(k) if isinstance(v, dict) else None
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return float(v)
    return None


def noise_warning_lines(stderr):
    return sum(1 for ln in (stderr or "").splitlines() if NOISE_WARNING.search(ln))


def run_fairfit(exe, csv, case, tmp, timeout):
    out = os.path.join(tmp, f"{case.name}.json")
    rep = os.path.join(tmp, f"{case.name}.report.json")
    cmd = [exe, "curve", csv, "--rel-tol", repr(REL_TOL), "-o", out, "--report", rep, *case.extra]
    rc, wall, peak, stderr = run_process(cmd, timeout)
    if rc is None:
        return Run("timeout", f"over {timeout:.0f} s", wall_s=wall, peak_mb=peak), None
    if rc != 0:
        return Run("error", failure_reason(stderr, rc), wall_s=wall, peak_mb=peak,
                   noise_warnings=noise_warning_lines(stderr)), None
    try:
        with open(out, encoding="utf-8") as fh:
            js = json.load(fh)
        report = {}
        if os.path.exists(rep):
            with open(rep, encoding="utf-8") as fh:
                report = json.load(fh)
        curve = measure.Curve(js["degree"], js["knots"], np.asarray(js["control_points"], dtype=float),
                              js.get("weights"))
    except (OSError, ValueError, KeyError, TypeError) as e:
        return Run("error", f"unreadable output: {e}"[:200], wall_s=wall, peak_mb=peak), None
    run = Run("ok", wall_s=wall, peak_mb=peak, report=report,
              report_corners=len(report_rows(report, CORNERS_KEY)) if CORNERS_KEY in report else None,
              outliers=report_rows(report, OUTLIERS_KEY),
              sigma_est=report_sigma(report), noise_warnings=noise_warning_lines(stderr))
    return run, curve


def c0_corners(curve, closed):
    """The corners of a fitted curve, measured on it: the points at interior knots of multiplicity
    >= degree whose one-sided tangents turn by more than CORNER_MIN_TURN_DEG, and for closed data the
    start of a clamped curve that ends where it starts (a loop cut at a corner)."""
    t, k = curve.t, curve.k
    lo, hi = curve.lo, curve.hi
    eps = 1e-7 * (hi - lo)
    pairs = [(u, u) for u in curve.breaks[1:-1] if np.count_nonzero(t == u) >= k]
    if closed and np.all(t[: k + 1] == lo) and np.all(t[-k - 1 :] == hi):
        ends = curve.points(np.array([lo, hi]))
        ext = float(np.max(np.ptp(curve.points(curve.breaks), axis=0)))
        if np.linalg.norm(ends[0] - ends[1]) <= 1e-9 * max(ext, 1e-300):
            pairs.append((hi, lo))
    out = []
    for before, after in pairs:
        d = curve.derivs(np.array([before - eps, after + eps]), 1)[1]
        a, b = d[0], d[1]
        c = float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-300)
        if math.degrees(math.acos(min(1.0, max(-1.0, c)))) > CORNER_MIN_TURN_DEG:
            out.append(curve.points(np.array([after]))[0])
    return out


def measure_fit(run, curve, case, data):
    """Fill the measured numbers of a successful run (in place)."""
    run.n_ctrl = curve.n_independent
    run.corners = [p[: data.points.shape[1]] for p in c0_corners(curve, case.shape.closed)]
    if run.n_ctrl > MEASURE_CTRL_CAP:
        run.reason = f"{run.n_ctrl} control points: not measured"
        return run
    dev = data_deviations(curve, data.points)
    run.max_dev_all = float(np.max(dev))
    keep = np.ones(len(dev), dtype=bool)
    rows = [i for i in run.outliers if 0 <= i < len(dev)]
    keep[rows] = False
    run.max_dev = float(np.max(dev[keep])) if keep.any() else float("nan")
    planar = measure.is_planar(data.points, data.points)
    run.F, L = measure.fairness(curve, planar)
    run.extrema, _ = measure.shape_counts(curve, planar, L)
    run.clean_dist = clean_distance(curve, data, case.shape.closed)
    return run


# ----------------------------------------------------------------------------- splprep


def splprep_fit(P, s, closed):
    from scipy.interpolate import splprep

    Q = np.vstack([P, P[:1]]) if closed else P
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tck, _ = splprep(list(Q.T), s=s, k=3, per=1 if closed else 0, quiet=2)
    t, c, k = tck
    n = len(t) - k - 1
    return measure.Curve(k, t, np.column_stack([np.asarray(ci)[:n] for ci in c]))


def run_splprep(case, data, tol, cap_s=SPLPREP_TIME_CAP_S, max_points=SPLPREP_MAX_POINTS):
    """s-bisection (log grid, then bisection) for the fewest control points meeting tol on every point,
    as bench/compare.py; stopped at cap_s wall seconds."""
    if case.n > max_points:
        return Run("skipped", f"over {max_points} points (time cap {cap_s:.0f} s)"), None
    P = data.points
    t0 = time.perf_counter()
    evals = {}

    def meets(s):
        if time.perf_counter() - t0 > cap_s:
            raise TimeoutError
        if s not in evals:
            c = splprep_fit(P, s, case.shape.closed)
            evals[s] = (c.n_independent, float(np.max(data_deviations(c, P))), c)
        return evals[s][1] <= tol * (1 + MEET_SLACK)

    base = len(P) * tol * tol
    try:
        _grid_search(meets, np.geomspace(base * 1e-4, base * 10.0, 16), refine=8)
    except TimeoutError:
        return Run("skipped", f"s-search over the time cap of {cap_s:.0f} s"), None
    wall = time.perf_counter() - t0
    ok = [(n, -s, s) for s, (n, d, _) in evals.items() if d <= tol * (1 + MEET_SLACK)]
    if not ok:
        return Run("error", "no smoothing factor met the tolerance", wall_s=wall), None
    curve = evals[min(ok)[2]][2]
    return Run("ok", wall_s=wall), curve


def _grid_search(meets, grid, refine):
    """bench/compare.py's search (the largest grid value that meets, then bisection towards the next),
    with the grid scanned from the coarse end: the same values are found without the fine fits below
    the first one that meets (which at 10^4 noisy points cost minutes)."""
    grid = list(grid)
    i = next((j for j in range(len(grid) - 1, -1, -1) if meets(grid[j])), None)
    if i is None or i + 1 >= len(grid):
        return
    lo, hi = grid[i], grid[i + 1]
    for _ in range(refine):
        mid = float(np.sqrt(lo * hi))
        if meets(mid):
            lo = mid
        else:
            hi = mid


# ----------------------------------------------------------------------------- bookkeeping


@dataclass
class Row:
    case: Case
    tol: float  # the tolerance of the input points (fairfit's --rel-tol rule)
    sigma: float
    true_spikes: list
    true_corners: np.ndarray  # positions
    points: np.ndarray = field(repr=False, default=None)  # input points (corner positions of found rows)
    fairfit: Run = None
    splprep: Run = None


def meets(run, tol):
    return run is not None and run.status == "ok" and run.max_dev <= tol * (1 + MEET_SLACK)


def corner_match(row):
    """(matched true corners, false corners): a corner of the fit matches a true corner when it lies
    within tol of it; each true corner matches at most once."""
    run = row.fairfit
    if run is None or run.status != "ok":
        return 0, 0
    free = list(range(len(row.true_corners)))
    false = 0
    for p in run.corners:
        d = [float(np.linalg.norm(np.asarray(p) - row.true_corners[j])) for j in free]
        if d and min(d) <= row.tol:
            free.pop(int(np.argmin(d)))
        else:
            false += 1
    return len(row.true_corners) - len(free), false


def spike_match(row):
    """(true spikes found, other rows excluded)."""
    run = row.fairfit
    if run is None or run.status != "ok":
        return 0, 0
    found, true = set(run.outliers), set(row.true_spikes)
    return len(found & true), len(found - true)


def _status(ok, measured=True):
    if not measured:
        return "not measured"
    return "met" if ok else "not met"


def targets(rows, quick=False):
    """[(id, target text, status, detail)] for the issue's targets, judged on rows."""
    out = []
    low = [r for r in rows if r.case.noise <= 0.1 + 1e-12]

    miss = [r.case.name for r in low if not meets(r.fairfit, r.tol)]
    out.append((T_TOL, "tolerance met on every input point (noise <= tol/10; only reported spikes excluded)",
                _status(not miss, bool(low)), _misses(miss)))

    bad = []
    for r in rows:
        if r.fairfit is None or r.fairfit.status != "ok":
            bad.append(f"{r.case.name}: {r.fairfit.status if r.fairfit else 'not run'}")
            continue
        got, false = corner_match(r)
        if got < len(r.true_corners) or false:
            bad.append(f"{r.case.name}: corners {got}/{len(r.true_corners)}, {false} false")
        hit, extra = spike_match(r)
        if hit < len(r.true_spikes) or extra:
            bad.append(f"{r.case.name}: spikes {hit}/{len(r.true_spikes)}, {extra} other rows removed")
    has_feat = any(len(r.true_corners) for r in rows) and any(len(r.true_spikes) for r in rows)
    out.append((T_FEATURES, "zero false corners, every true corner and spike found, no other point removed",
                _status(not bad, bool(rows)) + ("" if has_feat or not rows else " (no corner/spike case run)"),
                _misses(bad)))

    cmp, worse = 0, []
    for r in low:
        a, b = r.fairfit, r.splprep
        if b is None or b.status != "ok" or b.n_ctrl is None:
            continue
        cmp += 1
        if a is None or a.status != "ok" or a.n_ctrl is None or a.extrema is None:
            worse.append(f"{r.case.name}: fairfit {_state(a) if a else 'not run'}")
            continue
        why = [w for w, bad_ in (("ctrl", a.n_ctrl > b.n_ctrl), ("F", not a.F <= b.F),
                                  ("extrema", a.extrema > b.extrema)) if bad_]
        if why:
            worse.append(f"{r.case.name}: {', '.join(why)}")
    out.append((T_SPLPREP, "control points, F and curvature extrema <= splprep's (noise <= tol/10, splprep finished)",
                _status(not worse, cmp > 0), f"{cmp} cases compared; " + _misses(worse)))

    far = [f"{r.case.name}: {_ratio(r.fairfit.clean_dist if r.fairfit else None, r.tol)}" for r in low
           if not (r.fairfit and r.fairfit.status == "ok" and r.fairfit.clean_dist <= 1.1 * r.tol)]
    out.append((T_CLEAN, "distance to the noise-free curve <= 1.1 x tol (noise <= tol/10)",
                _status(not far, bool(low)), _misses(far)))

    noisy = [r for r in rows if r.sigma > 0]
    off = []
    for r in noisy:
        est = r.fairfit.sigma_est if r.fairfit else None
        if est is None or not abs(est - r.sigma) <= 0.25 * r.sigma:
            off.append(f"{r.case.name}: {_g(est)} vs {_g(r.sigma)}")
    warn_bad = []
    for r in rows:
        want = r.case.noise > 0.1 + 1e-12
        got = r.fairfit.noise_warnings if r.fairfit else 0
        if (want and got != 1) or (not want and got != 0):
            warn_bad.append(f"{r.case.name}: {got} warning lines")
    warned = any(r.case.noise > 0.1 + 1e-12 for r in rows)
    out.append((T_SIGMA, "noise sigma within +-25 % on every noisy case; the tol/3 case warns in one line, no other",
                _status(not off and not warn_bad and warned, bool(noisy)), _misses(off + warn_bad)))

    big = [r for r in rows if r.case.n >= 1_000_000]
    slow = [f"{r.case.name}: {_g(r.fairfit.wall_s)} s, {_g(r.fairfit.peak_mb)} MB" for r in big
            if not (r.fairfit and r.fairfit.status == "ok" and r.fairfit.wall_s <= 5.0
                    and r.fairfit.peak_mb <= 300.0)]
    out.append((T_TIME_1E6, "a 10^6-point section in <= 5 s (whole CLI process), peak memory <= 300 MB",
                _status(not slow, bool(big)), _misses(slow)))

    ratios, bad_ratio = [], []
    for fam in _families(rows):
        by_n = {r.case.n: r for r in fam}
        a, b = by_n.get(10_000), by_n.get(1_000_000)
        if a and b:
            ta = a.fairfit.wall_s if a.fairfit and a.fairfit.status == "ok" else float("nan")
            tb = b.fairfit.wall_s if b.fairfit and b.fairfit.status == "ok" else float("nan")
            q = tb / ta
            ratios.append(f"{a.case.family}: {_g(q)}")
            if not q <= 20.0:
                bad_ratio.append(a.case.family)
    out.append((T_SCALING, "time(10^6 points) / time(10^4 points) <= 20, same shape",
                _status(not bad_ratio, bool(ratios)), "; ".join(ratios) or "n/a"))

    spread, bad_count = [], []
    for fam in _families(rows):
        ns = [r.fairfit.n_ctrl for r in fam if r.case.n >= 10_000]
        if len(ns) < 2:
            continue
        spread.append(f"{fam[0].case.family}: {ns}")
        if any(n is None for n in ns) or max(ns) - min(ns) > 1:
            bad_count.append(fam[0].case.family)
    out.append((T_COUNTS, "10^4, 10^5, 10^6 points of one shape: control points within +-1 of each other",
                _status(not bad_count, bool(spread)), "; ".join(spread) or "n/a"))

    out.append((T_SHARED, "the 33 shared curves: no target of docs/benchmarks.md worse, 200-point time no slower",
                "not measured", "by bench/compare.py and bench/same_output.py, not this benchmark"))
    return out


def _families(rows):
    fams = {}
    for r in rows:
        if r.case.family and r.fairfit is not None:
            fams.setdefault(r.case.family, []).append(r)
    return [sorted(v, key=lambda r: r.case.n) for v in fams.values() if len(v) > 1]


def _misses(items):
    if not items:
        return ""
    shown = "; ".join(items[:6])
    return shown + (f"; and {len(items) - 6} more" if len(items) > 6 else "")


def _g(x, d=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    return f"{x:.{d}g}"


def _ratio(x, tol):
    return "n/a" if x is None or not math.isfinite(x) else f"{x / tol:.3g}"


# ----------------------------------------------------------------------------- report


def fairfit_table(rows):
    head = ("| case | points | sigma/tol | status | ctrl | max dev/tol | all pts/tol | F | extrema | "
            "dist to clean/tol | corners (true) | false corners | report corners | spikes found (true) | "
            "other removed | "
            "sigma est/true | noise warnings | wall s | peak MB |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        a = r.fairfit
        got, false = corner_match(r)
        hit, extra = spike_match(r)
        est = a.sigma_est if a else None
        lines.append("| " + " | ".join([
            r.case.name, str(r.case.n), _g(r.case.noise), _state(a), _g(a.n_ctrl),
            _ratio(a.max_dev, r.tol), _ratio(a.max_dev_all, r.tol), _g(a.F), _g(a.extrema),
            _ratio(a.clean_dist, r.tol), f"{got} ({len(r.true_corners)})", str(false),
            _g(a.report_corners), f"{hit} ({len(r.true_spikes)})", str(extra),
            "n/a" if est is None or r.sigma == 0 else f"{est / r.sigma:.3g}", str(a.noise_warnings),
            _g(a.wall_s), _g(a.peak_mb),
        ]) + " |")
    return "\n".join(lines)


def splprep_table(rows):
    head = "| case | points | status | ctrl | max dev/tol | F | extrema | dist to clean/tol | search s |"
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        b = r.splprep
        lines.append("| " + " | ".join([
            r.case.name, str(r.case.n), _state(b), _g(b.n_ctrl), _ratio(b.max_dev, r.tol), _g(b.F),
            _g(b.extrema), _ratio(b.clean_dist, r.tol), _g(b.wall_s),
        ]) + " |")
    return "\n".join(lines)


def _state(run):
    if run.status == "ok":
        return "ok" + (f" ({run.reason})" if run.reason else "")
    return f"{run.status}: {run.reason}" if run.reason else run.status


def targets_table(rows, quick=False):
    lines = ["| target | status | detail |", "|---|---|---|"]
    for _, text, status, detail in targets(rows, quick):
        lines.append(f"| {text} | {status} | {detail.replace('|', '/')} |")
    return "\n".join(lines)


def write_report(path, rows, args, seconds):
    now = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    try:
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True,
                             text=True).stdout.strip()
    except OSError:
        rev = "?"
    text = f"""# Dense-section benchmark

Written by `bench/dense.py` (see `bench/README.md`) on {now}, commit `{rev or '?'}`, {platform.machine()},
{os.cpu_count()} cores; run time {seconds:.0f} s{', `--quick` (up to 10^4 points)' if args.quick else ''}.
fairfit: `fairfit curve FILE --rel-tol {REL_TOL:g} --report R` (default method, default threads), each run
capped at {args.timeout:.0f} s. scipy splprep: s-search to the same max deviation, capped at
{SPLPREP_TIME_CAP_S:.0f} s and not started above {SPLPREP_MAX_POINTS} points.
Every number is measured by `bench/measure.py`; tol = {REL_TOL:g} x the largest side of the input's bounding
box; "max dev" excludes the rows fairfit reports as outliers (`{OUTLIERS_KEY}`), "all pts" does not.
"dist to clean" is the largest distance between the fit and the noise-free generating curve, both ways.
A corner of a fit is a C0 knot (multiplicity >= degree) whose tangents turn by more than
{CORNER_MIN_TURN_DEG:g} degree, measured on the curve; it matches a true corner within tol.
"report corners" counts the report's `{CORNERS_KEY}` list.

## Targets (issue 24)

{targets_table(rows, args.quick)}

## fairfit

{fairfit_table(rows)}

## scipy splprep

{splprep_table(rows)}
"""
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


# ----------------------------------------------------------------------------- main


def run_case(case, exe, tmp, timeout, with_splprep=True):
    data = make_data(case)
    csv = os.path.join(tmp, f"{case.name}.csv")
    write_csv(csv, data.points)
    tol = measure.tolerance(data.points, REL_TOL)
    row = Row(case, tol, data.sigma, [int(i) for i in data.spikes], data.corners, data.points)
    run, curve = run_fairfit(exe, csv, case, tmp, timeout)
    if curve is not None:
        measure_fit(run, curve, case, data)
    row.fairfit = run
    if with_splprep:
        sp, c = run_splprep(case, data, tol)
        if c is not None:
            measure_fit(sp, c, case, data)
        row.splprep = sp
    else:
        row.splprep = Run("skipped", "--no-splprep")
    os.remove(csv)
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help=f"only cases up to {QUICK_MAX_POINTS} points")
    ap.add_argument("--only", help="fnmatch pattern on case names, e.g. 'naca4412-1e4-*'")
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "benchmarks-dense.md"))
    ap.add_argument("--fairfit", default=os.path.join(REPO, "target", "release", "fairfit"))
    ap.add_argument("--timeout", type=float, default=FAIRFIT_TIMEOUT_S, help="seconds per fairfit run")
    ap.add_argument("--no-splprep", action="store_true", help="fairfit only")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    args = ap.parse_args(argv)
    cases = build_cases(args.quick, args.only)
    if args.list:
        for c in cases:
            print(c.name)
        return 0
    if not cases:
        print("no case matches", file=sys.stderr)
        return 2
    if not os.path.exists(args.fairfit):
        print(f"fairfit binary not found: {args.fairfit} (cargo build --release -p fairfit-cli)",
              file=sys.stderr)
        return 1
    tmp = tempfile.mkdtemp(prefix="fairfit-dense-")
    t0 = time.perf_counter()
    rows = []
    try:
        for c in cases:
            t1 = time.perf_counter()
            row = run_case(c, args.fairfit, tmp, args.timeout, not args.no_splprep)
            a = row.fairfit
            print(f"{c.name}: fairfit {_state(a)}, ctrl {_g(a.n_ctrl)}, {_g(a.wall_s)} s; "
                  f"splprep {_state(row.splprep)}, ctrl {_g(row.splprep.n_ctrl)} "
                  f"[{time.perf_counter() - t1:.0f} s]", file=sys.stderr)
            rows.append(row)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    write_report(args.out, rows, args, time.perf_counter() - t0)
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
