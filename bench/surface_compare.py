#!/usr/bin/env python3
"""Surface benchmark: fairfit surface against OpenCASCADE's BRepOffsetAPI_ThruSections loft and
GeomAPI_PointsToBSplineSurface on the IEA 15 MW blade sections, plus fairfit on the Stanford bunny
sliced into 20 sections.  Every surface is measured by ONE independent measurer written here with
numpy/scipy only (no fairfit or OpenCASCADE evaluation): orthogonal deviation of every section point
and F of iso-curves in both directions, the curve F coming from bench/measure.py.

Usage (from the repository root, release binary built):
    python bench/surface_compare.py [--out docs/benchmarks-surface.md]

Directions.  Every surface here has one parameter ALONG the sections (chordwise, around the airfoil)
and one ACROSS them (spanwise, between the sections):
  * fairfit:                       u along the sections,  v across;
  * ThruSections:                  U along the sections,  V across;
  * PointsToBSplineSurface (here): U across the sections, V along (the point grid is given with one
    row per section, as OCC's Points(i, j) with i = section).
The tables therefore name directions, not letters: "net" is (along x across); "F between sections"
is F of the iso-curves that run across the sections (fixed chordwise parameter).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import measure  # noqa: E402  (curve F: bench/measure.py, owned by the curve benchmark)

REPO = os.path.dirname(HERE)
TOL = 0.0057
ISO_CURVES = 41
SAMPLES_PER_SPAN = 12
MEET_SLACK = 1e-6


# ----------------------------------------------------------------------------------------------
# The measurer: a (rational) tensor-product B-spline surface, evaluated with scipy only.
# ----------------------------------------------------------------------------------------------


class Surface:
    """S(s, t) with s ALONG the sections and t ACROSS them; control net P[i, j] (i along, j across)."""

    def __init__(self, deg_s, knots_s, deg_t, knots_t, ctrl, weights=None):
        self.ps, self.pt = int(deg_s), int(deg_t)
        self.ts, self.tt = np.asarray(knots_s, float), np.asarray(knots_t, float)
        ctrl = np.asarray(ctrl, float)
        self.ns, self.nt = ctrl.shape[:2]
        if len(self.ts) != self.ns + self.ps + 1 or len(self.tt) != self.nt + self.pt + 1:
            raise ValueError("knot vector lengths do not match the control net")
        w = np.ones((self.ns, self.nt)) if weights is None else np.asarray(weights, float)
        self.w = w
        self.ctrl = ctrl
        self.hom = np.concatenate([ctrl * w[..., None], w[..., None]], axis=2)  # (ns, nt, 4)
        self.bs = BSpline(self.ts, np.eye(self.ns), self.ps, extrapolate=False)
        self.bt = BSpline(self.tt, np.eye(self.nt), self.pt, extrapolate=False)
        self.s_lo, self.s_hi = self.ts[self.ps], self.ts[self.ns]
        self.t_lo, self.t_hi = self.tt[self.pt], self.tt[self.nt]

    def _basis(self, spline, u, lo, hi, nu):
        u = np.clip(u, lo, hi)
        return np.nan_to_num(spline(u, nu))

    def derivs(self, s, t):
        """S, S_s, S_t, S_ss, S_st, S_tt at pointwise (s, t) pairs (rational quotient rule)."""
        Ns = [self._basis(self.bs, s, self.s_lo, self.s_hi, k) for k in range(3)]
        Nt = [self._basis(self.bt, t, self.t_lo, self.t_hi, k) for k in range(3)]

        def h(a, b):
            return np.einsum("pi,ijc,pj->pc", Ns[a], self.hom, Nt[b], optimize=True)

        A = {(a, b): h(a, b) for a, b in [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]}
        w = {k: v[:, 3] for k, v in A.items()}
        A = {k: v[:, :3] for k, v in A.items()}
        w0 = w[(0, 0)][:, None]
        S = A[(0, 0)] / w0
        Ss = (A[(1, 0)] - w[(1, 0)][:, None] * S) / w0
        St = (A[(0, 1)] - w[(0, 1)][:, None] * S) / w0
        Sss = (A[(2, 0)] - 2 * w[(1, 0)][:, None] * Ss - w[(2, 0)][:, None] * S) / w0
        Stt = (A[(0, 2)] - 2 * w[(0, 1)][:, None] * St - w[(0, 2)][:, None] * S) / w0
        Sst = (
            A[(1, 1)]
            - w[(1, 0)][:, None] * St
            - w[(0, 1)][:, None] * Ss
            - w[(1, 1)][:, None] * S
        ) / w0
        return S, Ss, St, Sss, Sst, Stt

    def samples(self, knots, deg, n, m):
        br = np.unique(knots[deg : n + 1])
        out = [br[0], br[-1]]
        for a, b in zip(br[:-1], br[1:]):
            out.extend(a + (b - a) * (np.arange(m) + 0.5) / m)
        return np.sort(np.array(out))

    def iso_across(self, s0):
        """The curve of fixed s (along-parameter): it runs across the sections."""
        Ns = self._basis(self.bs, np.array([s0]), self.s_lo, self.s_hi, 0)[0]
        H = np.einsum("i,ijc->jc", Ns, self.hom)
        return measure.Curve(self.pt, self.tt, H[:, :3] / H[:, 3:], H[:, 3])

    def iso_along(self, t0):
        """The curve of fixed t (across-parameter): it runs along the sections."""
        Nt = self._basis(self.bt, np.array([t0]), self.t_lo, self.t_hi, 0)[0]
        H = np.einsum("ijc,j->ic", self.hom, Nt)
        return measure.Curve(self.ps, self.ts, H[:, :3] / H[:, 3:], H[:, 3])


def _per_span_samples(knots, deg, n, total, least=4):
    """Parameters strictly inside every distinct knot span, about `total` in all, in proportion to the
    span lengths (at least `least` per span), plus both ends."""
    br = np.unique(knots[deg : n + 1])
    lens = np.diff(br)
    out = [br[0], br[-1]]
    for a, b, L in zip(br[:-1], br[1:], lens):
        m = max(least, int(np.ceil(total * L / (br[-1] - br[0]))))
        out.extend(a + (b - a) * (np.arange(m) + 0.5) / m)
    return np.sort(np.array(out))


def _newton(S: Surface, Q, s, t, iters=30):
    """Newton on (s, t) for |S(s, t) - q| with step control: a step is taken only if it brings the point
    nearer, otherwise it is shortened; returns (best distance, s, t), never worse than the start."""
    lam = np.ones(len(Q))
    X0, Xs, Xt, Xss, Xst, Xtt = S.derivs(s, t)
    for _ in range(iters):
        r = X0 - Q
        g1, g2 = np.einsum("ij,ij->i", r, Xs), np.einsum("ij,ij->i", r, Xt)
        a11, a12, a22 = (np.einsum("ij,ij->i", Xs, Xs), np.einsum("ij,ij->i", Xs, Xt),
                         np.einsum("ij,ij->i", Xt, Xt))
        h11 = a11 + np.einsum("ij,ij->i", r, Xss)
        h12 = a12 + np.einsum("ij,ij->i", r, Xst)
        h22 = a22 + np.einsum("ij,ij->i", r, Xtt)
        # Gauss-Newton matrix where the full Hessian is not positive definite
        bad = (h11 <= 0) | (h11 * h22 - h12 * h12 <= 0)
        h11, h12, h22 = np.where(bad, a11, h11), np.where(bad, a12, h12), np.where(bad, a22, h22)
        det = h11 * h22 - h12 * h12
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        ds = -(h22 * g1 - h12 * g2) / det
        dt = -(h11 * g2 - h12 * g1) / det
        s_new = np.clip(s + lam * ds, S.s_lo, S.s_hi)
        t_new = np.clip(t + lam * dt, S.t_lo, S.t_hi)
        Y = S.derivs(s_new, t_new)
        ok = np.linalg.norm(Y[0] - Q, axis=1) < np.linalg.norm(r, axis=1)
        s, t = np.where(ok, s_new, s), np.where(ok, t_new, t)
        X0, Xs, Xt, Xss, Xst, Xtt = [np.where(ok[:, None], y, x) for y, x in
                                     zip(Y, (X0, Xs, Xt, Xss, Xst, Xtt))]
        lam = np.where(ok, np.minimum(1.0, 2 * lam), lam / 4)
        if np.all(lam < 1e-12):
            break
    return np.linalg.norm(X0 - Q, axis=1), s, t


def surface_deviation(S: Surface, points, candidates=16):
    """Orthogonal distance of every point, in two stages.  (1) the `candidates` nearest samples of a
    per-span grid, each refined by Newton: this finds the right place ACROSS the sections, but near a thin
    trailing edge it may settle on the wrong side of the profile.  Four candidates were too few on the
    bunny: on a strongly curved section all four nearest samples can lie on one wrong sheet (plane 11:
    0.537 measured, 0.009 true, found by brute force on a 20001 x 401 grid); sixteen agree with brute force.  (2) along the iso-curve through that place, the nearest
    of a dense per-span sampling, refined by Newton again.  The smaller distance of the two counts; both
    are distances to actual surface points, so the result is an upper bound of the true distance that is
    never worse than the nearest sample."""
    P = np.asarray(points, float)
    ss = _per_span_samples(S.ts, S.ps, S.ns, 1000)
    tt = _per_span_samples(S.tt, S.pt, S.nt, 100)
    Ns = S._basis(S.bs, ss, S.s_lo, S.s_hi, 0)
    Nt = S._basis(S.bt, tt, S.t_lo, S.t_hi, 0)
    H = np.einsum("pi,ijc,qj->pqc", Ns, S.hom, Nt, optimize=True).reshape(-1, 4)
    X = H[:, :3] / H[:, 3:]
    gs, gt = np.meshgrid(ss, tt, indexing="ij")
    gs, gt = gs.ravel(), gt.ravel()
    kq = min(candidates, len(X))
    d0, idx = cKDTree(X).query(P, k=kq)
    idx = idx.reshape(len(P), kq)
    Q = np.repeat(P, kq, axis=0)
    d1, s1, t1 = _newton(S, Q, gs[idx.ravel()], gt[idx.ravel()])
    d1 = np.minimum(d1, d0.ravel()).reshape(len(P), kq)
    pick = d1.argmin(axis=1)
    best = d1.min(axis=1)
    t_star = t1.reshape(len(P), kq)[np.arange(len(P)), pick]
    # stage 2: dense samples along the iso-curve t = t* of each point
    sd = _per_span_samples(S.ts, S.ps, S.ns, 4000)
    Nd = S._basis(S.bs, sd, S.s_lo, S.s_hi, 0)
    s2 = np.empty(len(P))
    for a in range(0, len(P), 256):
        b = min(a + 256, len(P))
        Ntp = S._basis(S.bt, t_star[a:b], S.t_lo, S.t_hi, 0)  # (m, nt)
        C = np.einsum("ijc,mj->mic", S.hom, Ntp)  # (m, ns, 4)
        Hc = np.einsum("qi,mic->mqc", Nd, C, optimize=True)  # (m, nsamples, 4)
        Xc = Hc[..., :3] / Hc[..., 3:]
        dist = np.linalg.norm(Xc - P[a:b, None, :], axis=2)
        s2[a:b] = sd[dist.argmin(axis=1)]
    d2, _, _ = _newton(S, P, s2, t_star)
    return np.minimum(best, d2)


def iso_fairness(S: Surface, n=ISO_CURVES):
    """F (bench/measure.py) of n iso-curves per direction, at uniform parameters of each surface."""
    across, along = [], []
    for x in np.linspace(S.s_lo, S.s_hi, n):
        c = S.iso_across(x)
        across.append(measure.fairness(c, planar=False)[0])
    for x in np.linspace(S.t_lo, S.t_hi, n):
        c = S.iso_along(x)
        along.append(measure.fairness(c, planar=False)[0])
    return np.array(across), np.array(along)


def measure_surface(S: Surface, points):
    dev = surface_deviation(S, points)
    fa, fl = iso_fairness(S)
    return {
        "net_along": S.ns,
        "net_across": S.nt,
        "max_dev": float(dev.max()),
        "rms_dev": float(np.sqrt(np.mean(dev**2))),
        "F_across_max": float(fa.max()),
        "F_across_median": float(np.median(fa)),
        "F_along_max": float(fl.max()),
        "F_along_median": float(np.median(fl)),
    }


# ----------------------------------------------------------------------------------------------
# Inputs and the three methods
# ----------------------------------------------------------------------------------------------


def default_data_dir():
    for d in [
        os.environ.get("FAIRFIT_DATA"),
        os.path.join(REPO, "..", "shared", "data"),
        os.path.join(REPO, "..", "..", "shared", "data"),
        "/work/shared/data",
    ]:
        if d and os.path.isdir(os.path.join(d, "iea15mw", "sections")):
            return os.path.abspath(d)
    raise SystemExit("shared data not found: set FAIRFIT_DATA")


def read_sections(folder):
    files = sorted(f for f in os.listdir(folder) if f.endswith(".csv"))
    return [measure.read_points(os.path.join(folder, f)) for f in files]


def fairfit_surface(exe, args, json_out):
    t0 = time.perf_counter()
    p = subprocess.run([exe, "surface", *args, "-o", json_out], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip())
    s = json.load(open(json_out))
    S = Surface(
        s["degree_u"], s["knots_u"], s["degree_v"], s["knots_v"],
        np.array(s["control_points"]), np.array(s["weights"]) if s.get("weights") else None,
    )
    return S, wall


def occ_bspline_surface_to_measurer(bs, along_is_u):
    """Geom_BSplineSurface -> Surface (flat knots, poles, weights), directions named."""
    from OCP.collections import Array1_double

    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    P = np.array([[[bs.Pole(i, j).X(), bs.Pole(i, j).Y(), bs.Pole(i, j).Z()]
                   for j in range(1, nv + 1)] for i in range(1, nu + 1)])
    W = np.array([[bs.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)])

    def flat(n_knots, getter):
        a = Array1_double(1, n_knots)
        getter(a)
        return np.array([a.Value(i) for i in range(1, n_knots + 1)])

    ku = flat(bs.NbUPoles() + bs.UDegree() + 1, bs.UKnotSequence)
    kv = flat(bs.NbVPoles() + bs.VDegree() + 1, bs.VKnotSequence)
    if bs.IsUPeriodic() or bs.IsVPeriodic():
        raise RuntimeError("periodic OCC surface: not handled by this measurer")
    if along_is_u:
        return Surface(bs.UDegree(), ku, bs.VDegree(), kv, P, W)
    return Surface(bs.VDegree(), kv, bs.UDegree(), ku, P.transpose(1, 0, 2), W.T)


def occ_thrusections(sections, tol):
    """Each section approximated by GeomAPI_PointsToBSpline (C2, degree 3..8, Tol3D = tol / 2),
    then lofted by BRepOffsetAPI_ThruSections (smooth, not ruled); the face's B-spline surface."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.BRepOffsetAPI import BRepOffsetAPI_ThruSections
    from OCP.GeomAbs import GeomAbs_C2
    from OCP.GeomAPI import GeomAPI_PointsToBSpline
    from OCP.GeomConvert import GeomConvert
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS
    from OCP.collections import Array1_gp_Pnt
    from OCP.gp import gp_Pnt

    loft = BRepOffsetAPI_ThruSections(False, False, 1e-6)
    for pts in sections:
        arr = Array1_gp_Pnt(1, len(pts))
        for i, p in enumerate(pts):
            arr.SetValue(i + 1, gp_Pnt(*map(float, p)))
        curve = GeomAPI_PointsToBSpline(arr, 3, 8, GeomAbs_C2, tol / 2).Curve()
        edge = BRepBuilderAPI_MakeEdge(curve).Edge()
        loft.AddWire(BRepBuilderAPI_MakeWire(edge).Wire())
    loft.CheckCompatibility(False)
    loft.Build()
    exp = TopExp_Explorer(loft.Shape(), TopAbs_FACE)
    faces = []
    while exp.More():
        faces.append(TopoDS.Face(exp.Current()) if hasattr(TopoDS, "Face") else TopoDS.Face_s(exp.Current()))
        exp.Next()
    if len(faces) != 1:
        raise RuntimeError(f"ThruSections gave {len(faces)} faces")
    surf = BRep_Tool.Surface_s(faces[0])
    return GeomConvert.SurfaceToBSplineSurface_s(surf)


def resample(pts, n):
    """n points at uniform chord length along the section polyline (PointsToBSplineSurface needs a grid)."""
    d = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
    x = np.linspace(0.0, d[-1], n)
    return np.column_stack([np.interp(x, d, pts[:, k]) for k in range(3)])


def occ_points_to_surface(sections, n_pts, tol):
    """GeomAPI_PointsToBSplineSurface (degree 3..8, C2) on a grid: row i = section i, resampled."""
    from OCP.GeomAbs import GeomAbs_C2
    from OCP.GeomAPI import GeomAPI_PointsToBSplineSurface
    from OCP.collections import Array2_gp_Pnt
    from OCP.gp import gp_Pnt

    grid = Array2_gp_Pnt(1, len(sections), 1, n_pts)
    for i, pts in enumerate(sections):
        for j, p in enumerate(resample(pts, n_pts)):
            grid.SetValue(i + 1, j + 1, gp_Pnt(*map(float, p)))
    return GeomAPI_PointsToBSplineSurface(grid, 3, 8, GeomAbs_C2, tol).Surface()


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------


def g(x, d=3):
    return "n/a" if x is None or not np.isfinite(x) else f"{x:.{d}g}"


def row(name, m, tol, secs, note=""):
    meets = "yes" if m["max_dev"] <= tol * (1 + MEET_SLACK) else "**no**"
    return (
        f"| {name} | {m['net_along']} x {m['net_across']} | {m['occ_net']} | {g(m['max_dev'] / tol)} ({meets}) "
        f"| {g(m['rms_dev'] / tol)} | {g(m['F_across_max'])} | {g(m['F_across_median'])} "
        f"| {g(m['F_along_max'])} | {g(m['F_along_median'])} | {secs:.2f} | {note} |"
    )


HEADER = (
    "| method | net (along x across) | net as OCC counts it (U x V) | max dev / tol | rms dev / tol "
    "| F between sections, max | F between sections, median | F along sections, max "
    "| F along sections, median | time [s] | notes |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|"
)


def machine_line():
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"


def git_rev():
    try:
        return subprocess.run(
            ["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True
        ).stdout.strip()
    except OSError:
        return "?"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=None)
    ap.add_argument("--fairfit", default=os.path.join(REPO, "target", "release", "fairfit"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "benchmarks-surface.md"))
    ap.add_argument("--json", default=None, help="also write the raw numbers here")
    ap.add_argument("--grid", type=int, default=101, help="points per section for PointsToBSplineSurface")
    ap.add_argument("--no-bunny", action="store_true")
    args = ap.parse_args(argv)
    data = args.data or default_data_dir()
    secdir = os.path.join(data, "iea15mw", "sections")
    sections = read_sections(secdir)
    points = np.concatenate(sections)
    tol = TOL
    raw = {"tolerance": tol, "blade": {}, "bunny": None}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        # fairfit
        S, wall = fairfit_surface(args.fairfit, [secdir, "--tol", str(tol)], os.path.join(tmp, "b.json"))
        m = measure_surface(S, points)
        m["occ_net"] = f"{S.nt} x {S.ns} (as PointsToBSplineSurface); fairfit's own: u {S.ns}, v {S.nt}"
        m["time"] = wall
        raw["blade"]["fairfit"] = m
        rows.append(row("fairfit surface", m, tol, wall, "CLI wall time (process, reading, JSON)"))
        print("fairfit", m, file=sys.stderr)

        # ThruSections
        t0 = time.perf_counter()
        bs = occ_thrusections(sections, tol)
        t_loft = time.perf_counter() - t0
        S = occ_bspline_surface_to_measurer(bs, along_is_u=True)
        m = measure_surface(S, points)
        m["occ_net"] = f"{bs.NbUPoles()} x {bs.NbVPoles()}"
        m["time"] = t_loft
        raw["blade"]["thrusections"] = m
        rows.append(row("OCC BRepOffsetAPI_ThruSections", m, tol, t_loft,
                        f"sections by GeomAPI_PointsToBSpline (C2, deg 3..8, Tol3D {tol / 2:g}); in-process"))
        print("thru", m, file=sys.stderr)

        # PointsToBSplineSurface
        t0 = time.perf_counter()
        bs = occ_points_to_surface(sections, args.grid, tol)
        t_p2s = time.perf_counter() - t0
        S = occ_bspline_surface_to_measurer(bs, along_is_u=False)
        m = measure_surface(S, points)
        m["occ_net"] = f"{bs.NbUPoles()} x {bs.NbVPoles()}"
        m["time"] = t_p2s
        raw["blade"]["points_to_surface"] = m
        rows.append(row("OCC GeomAPI_PointsToBSplineSurface", m, tol, t_p2s,
                        f"sections resampled to {args.grid} points each (chord length); deg 3..8, C2, Tol3D {tol:g}; in-process"))
        print("p2s", m, file=sys.stderr)

        bunny_md = ""
        if not args.no_bunny:
            bunny_md, raw["bunny"] = bunny(args.fairfit, data, tmp)

    lines = [
        "# Surface benchmark",
        "",
        f"Generated by `bench/surface_compare.py` on {datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, "
        f"commit {git_rev()}, {machine_line()} (shared machine: times are indicative).",
        "",
        "## IEA 15 MW blade sections",
        "",
        f"10 sections from `iea15mw/sections` ({len(points)} points), tolerance {tol} "
        "(1e-3 of the largest section extent). Every surface is measured by the same independent measurer "
        "(numpy/scipy, in this script; curve F from `bench/measure.py`): orthogonal deviation of every "
        "section point (dense samples per knot span, then Newton on both parameters), and "
        f"F = L^3 int (dkappa/ds)^2 ds of {ISO_CURVES} iso-curves per direction at uniform parameters of each surface.",
        "",
        "Directions: *along* = around the section (chordwise); *across* / *between sections* = spanwise, "
        "from section to section. fairfit's u runs along the sections and v across them; ThruSections' U "
        "runs along and V across; PointsToBSplineSurface (grid rows = sections) has U across and V along. "
        "So the issue's \"10 x 24\" reference net of PointsToBSplineSurface is 10 across x 24 along, and "
        "fairfit's net must be no larger than 24 along x 10 across.",
        "",
        HEADER,
        *rows,
        "",
        "Notes: fairfit's time is the whole CLI process (release build, `fairfit surface DIR --tol 0.0057 -o s.json`); "
        "the OpenCASCADE times are in-process calls (no file I/O). F along the sections is dominated by the "
        "leading edges of the thin airfoils and the blunt trailing-edge corners; F between sections is the "
        "issue's fairness target. The issue quotes ThruSections with a 228 x 12 net missing by 8.6e-3 and "
        "PointsToBSplineSurface with 10 x 24 missing by 1.3e-2; those came from other baseline settings "
        "(section approximation, grid); this table is this run's, with the settings in the notes column.",
        "",
        bunny_md,
        "## Reproduce",
        "",
        "```sh",
        "cargo build --release -p fairfit-cli",
        "python bench/surface_compare.py   # writes docs/benchmarks-surface.md",
        "```",
        "",
    ]
    with open(args.out, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(raw, fh, indent=2)
    print(f"wrote {args.out}", file=sys.stderr)


def seam_cell(report):
    """The report's seam: periodic or clamped, largest tangent angle and curvature jump across it."""
    seam = report.get("seam")
    if not seam:
        return "not closed"
    kind = "periodic (C2)" if report.get("periodic_u") else "clamped (C0)"
    return (f"{kind}: tangent angle {g(seam['max_tangent_angle'])} rad, curvature jump "
            f"{g(seam['max_curvature_jump'])}")


def bunny(exe, data, tmp):
    """fairfit on the Stanford bunny, 20 slices along z; the deviation from our measurer and the CLI's
    gap report.  The measured points are the sliced section points (what the surface was fitted to)."""
    ply = os.path.join(data, "scans", "StanfordBunny.ply")
    out = []
    raw = []
    for extra, label in [([], "defaults: --rel-tol 1e-3, --max-ctrl 120")]:
        rep = os.path.join(tmp, "bunny_report.json")
        js = os.path.join(tmp, "bunny.json")
        S, wall = fairfit_surface(
            exe, [ply, "--slices", "20", "--axis", "z", "--report", rep, *extra], js
        )
        r = json.load(open(rep))
        verts, faces = read_ply(ply)
        hs = np.array([float(sec["name"].split()[-1]) for sec in r["sections"]])
        per_plane = [slice_points(verts, faces, h) for h in hs]
        pts = np.concatenate(per_plane)
        dev = surface_deviation(S, pts)
        m = measure_surface(S, pts[:1])
        m["max_dev"], m["rms_dev"] = float(dev.max()), float(np.sqrt(np.mean(dev**2)))
        m["p99_dev"] = float(np.quantile(dev, 0.99))
        # planes whose slice is one chain: all of their points are data of the surface
        single, k = [], 0
        for sec, pp in zip(r["sections"], per_plane):
            if not sec["dropped_chains"]:
                single.append(dev[k : k + len(pp)])
            k += len(pp)
        single = np.concatenate(single) if single else np.array([np.nan])
        m["max_dev_single_chain"] = float(single.max())
        m["n_points"] = len(pts)
        m["n_single"] = len(single)
        gaps = r["gaps"]
        raw.append({"label": label, "report": {k: r[k] for k in ["net", "deviation", "tolerance",
                    "within_tolerance", "gaps", "empty_planes"]}, "measured": m, "time": wall})
        out += [
            "## Stanford bunny, 20 slices along z",
            "",
            f"`fairfit surface StanfordBunny.ply --slices 20 --axis z` ({label}), tolerance "
            f"{g(r['tolerance'])} (1e-3 of the largest slice extent), {wall:.2f} s wall.",
            "",
            "| quantity | value |",
            "|---|---|",
            f"| net (along x across) | {r['net'][0]} x {r['net'][1]} |",
            f"| sections | {len(r['sections'])} ({sum(s['points'] for s in r['sections'])} points), "
            f"empty planes {len(r['empty_planes'])}, chains dropped (second ear etc.) "
            f"{sum(s['dropped_chains'] or 0 for s in r['sections'])} |",
            f"| max / rms deviation of the section points (fairfit's report) | {g(r['deviation']['max'])} / "
            f"{g(r['deviation']['rms'])} (within tolerance: {r['within_tolerance']}) |",
            f"| max / 99th percentile / rms deviation of ALL plane-mesh crossings ({m['n_points']} points, this "
            f"measurer's own slicing; includes the chains fairfit dropped) | {g(m['max_dev'])} / {g(m['p99_dev'])} / "
            f"{g(m['rms_dev'])} |",
            f"| max deviation of the crossings of the planes cut into ONE chain ({m['n_single']} points) | "
            f"{g(m['max_dev_single_chain'])} |",
            f"| F between sections max / median | {g(m['F_across_max'])} / {g(m['F_across_median'])} |",
            f"| F along sections max / median | {g(m['F_along_max'])} / {g(m['F_along_median'])} |",
            f"| gaps reported | {len(gaps)} |",
            f"| u seam (closed sections) | {seam_cell(r)} |",
            "",
        ]
        if gaps:
            out += ["| section | gap length | typical spacing | handling |", "|---|---|---|---|"]
            out += [f"| {q['section']} | {g(q['length'])} | {g(q['typical_spacing'])} | {q['handling']} |"
                    for q in gaps]
            out.append("")
    return "\n".join(out), raw


def read_ply(path):
    """Vertices and triangles of a binary little-endian PLY (float x, y, z first; faces as
    `list uchar int`), as in the bunny file."""
    with open(path, "rb") as fh:
        header = []
        while True:
            line = fh.readline().decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
        body = fh.read()
    if "format binary_little_endian 1.0" not in header:
        raise RuntimeError(f"{path}: only binary little-endian PLY is read here")
    nv = next(int(h.split()[2]) for h in header if h.startswith("element vertex"))
    nf = next(int(h.split()[2]) for h in header if h.startswith("element face"))
    vprops = []
    for h in header[header.index(next(h for h in header if h.startswith("element vertex"))) + 1 :]:
        if not h.startswith("property"):
            break
        vprops.append(h.split()[-1])
    vdt = np.dtype([(n, "<f4") for n in vprops])
    v = np.frombuffer(body[: nv * vdt.itemsize], dtype=vdt, count=nv)
    verts = np.column_stack([v["x"], v["y"], v["z"]]).astype(float)
    fdt = np.dtype([("n", "u1"), ("i", "<i4", (3,))])
    f = np.frombuffer(body[nv * vdt.itemsize :], dtype=fdt, count=nf)
    if np.any(f["n"] != 3):
        raise RuntimeError(f"{path}: only triangles are read here")
    return verts, f["i"].astype(np.int64)


def slice_points(verts, faces, h):
    """Crossings of the plane z = h with the mesh edges (each edge once)."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    a, b = verts[e[:, 0]], verts[e[:, 1]]
    da, db = a[:, 2] - h, b[:, 2] - h
    cross = da * db < 0
    a, b, da, db = a[cross], b[cross], da[cross], db[cross]
    return a + (b - a) * (da / (da - db))[:, None]


if __name__ == "__main__":
    main()
