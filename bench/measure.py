"""Independent measurer for fitted B-spline / NURBS curves (numpy + scipy only).

This file deliberately shares no code with fairfit: every method's result in the
benchmark (fairfit, scipy splprep, OpenCASCADE, geomdl) is measured here, the same way.

A curve is given as (degree, full knot vector, control points, weights or None).
The homogeneous curve A(u) = sum N_i(u) w_i P_i, w(u) = sum N_i(u) w_i is a plain
`scipy.interpolate.BSpline`; C = A / w and its derivatives follow from the Leibniz
(quotient) rule  C^(k) = (A^(k) - sum_{i=1..k} binom(k,i) w^(i) C^(k-i)) / w.

Measured quantities
-------------------
* ``n_ctrl``       number of independent control points: all of them, except for a periodic curve
  (unclamped knots whose last ``degree`` control points and weights repeat the first ones), where the
  ``degree`` repeated ones are not counted (OpenCASCADE's convention for periodic B-splines).
* ``max_dev``, ``rms_dev``  ORTHOGONAL distance of every data point to the curve: the curve
  is sampled densely in every distinct knot span (``SAMPLES_PER_SPAN``), every sample that can
  be next to the foot point (within the nearest sample's distance plus half an interval's arc
  length) is refined by a safeguarded Newton iteration on
  (C(u) - p) . C'(u) = 0 kept inside the neighbouring sample interval, with a bounded Brent
  minimisation as a fallback whenever Newton does not improve on the sample distance.
* ``F``            scale-free fairness  F = L^3 * int (dkappa/ds)^2 ds,  integrated span by span with
  Gauss-Legendre nodes strictly inside each distinct knot span (third derivatives are never
  evaluated at a knot).  kappa is the signed curvature for planar curves and |C' x C''|/|C'|^3
  in 3D.  L is the arc length (same quadrature).  Jumps of kappa at knots of low continuity
  are not counted (they would be Dirac terms).
* ``extrema``      number of curvature extrema: sign changes of dkappa/ds along a dense sampling
  (``SAMPLES_PER_SPAN`` nodes strictly inside every span, in parameter order).
* ``inflections``  number of sign changes of the signed curvature (planar curves only, else None).

Noise floor (scale-free): both counts work on dimensionless signals, kappa*L and
(dkappa/ds)*L^2, and use hysteresis: a sign change is counted only when the signal goes
from <= -floor to >= +floor (or back), floor = ``NOISE_REL`` * max|signal| + ``NOISE_ABS``.
A wiggle that stays inside the band is noise and is not counted.  Both terms are
dimensionless, so scaling the data changes nothing.

Wall time is measured by the caller, not here.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.interpolate import BSpline
from scipy.optimize import minimize_scalar
from scipy.spatial import cKDTree

SAMPLES_PER_SPAN = 48
GAUSS_NODES = 12
GAUSS_SUBDIVISIONS = 4
NOISE_REL = 1e-6
NOISE_ABS = 1e-9
PLANAR_REL = 1e-12


@dataclass
class Metrics:
    """Everything the measurer reports for one curve and its data points."""

    n_ctrl: int
    max_dev: float
    rms_dev: float
    F: float
    length: float
    extrema: int
    inflections: int | None


def _is_periodic(t, ctrl, w, k):
    """True for a periodic B-spline stored in unclamped form: the first ``k + 1`` knots are not all equal
    and the last ``k`` control points (and weights) repeat the first ``k``."""
    n = ctrl.shape[0]
    if k < 1 or n <= 2 * k or np.all(t[: k + 1] == t[0]):
        return False
    return bool(np.array_equal(ctrl[n - k :], ctrl[:k]) and np.array_equal(w[n - k :], w[:k]))


class Curve:
    """A (rational) B-spline curve evaluated through scipy's BSpline on homogeneous points."""

    def __init__(self, degree, knots, ctrl, weights=None):
        self.k = int(degree)
        self.t = np.asarray(knots, dtype=float)
        ctrl = np.asarray(ctrl, dtype=float)
        if ctrl.ndim != 2:
            raise ValueError("control points must be an (n, dim) array")
        n = ctrl.shape[0]
        if len(self.t) != n + self.k + 1:
            raise ValueError(
                f"knot vector length {len(self.t)} != n + degree + 1 = {n + self.k + 1}"
            )
        if np.any(np.diff(self.t) < 0):
            raise ValueError("knot vector is not non-decreasing")
        w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
        if w.shape != (n,) or np.any(w <= 0):
            raise ValueError("weights must be positive, one per control point")
        self.n = n
        self.dim = ctrl.shape[1]
        self.n_independent = n - self.k if _is_periodic(self.t, ctrl, w, self.k) else n
        self.rational = not np.allclose(w, w[0])
        hom = np.column_stack([ctrl * w[:, None], w])
        self.spline = BSpline(self.t, hom, self.k, extrapolate=False)
        self.lo = self.t[self.k]
        self.hi = self.t[n]
        u = np.unique(self.t[self.k : n + 1])
        self.breaks = u  # distinct knots of the domain

    @property
    def spans(self):
        return list(zip(self.breaks[:-1], self.breaks[1:]))

    def derivs(self, u, order):
        """C and its derivatives up to `order` at parameters u: list of (len(u), dim) arrays."""
        u = np.clip(np.asarray(u, dtype=float), self.lo, self.hi)
        # Derivatives evaluated span-locally by BSpline.__call__(nu=...), which (unlike
        # BSpline.derivative) also works across repeated interior knots.
        hom = [
            self.spline(u, nu) if nu <= self.k else np.zeros((len(u), self.dim + 1))
            for nu in range(order + 1)
        ]
        A = [h[:, : self.dim] for h in hom]
        w = [h[:, self.dim] for h in hom]
        C = []
        for k in range(order + 1):
            acc = A[k].copy()
            for i in range(1, k + 1):
                acc -= comb(k, i) * w[i][:, None] * C[k - i]
            C.append(acc / w[0][:, None])
        return C

    def points(self, u):
        return self.derivs(u, 0)[0]

    def span_samples(self, m, include_ends=False):
        """m parameters strictly inside every distinct span (midpoints of m equal cells)."""
        us = []
        for a, b in self.spans:
            us.append(a + (b - a) * (np.arange(m) + 0.5) / m)
        u = np.concatenate(us)
        if include_ends:
            u = np.concatenate([[self.lo], u, [self.hi]])
        return u


def is_planar(points, ctrl):
    """True if the control points (and points) lie in a plane z = const (or are 2D)."""
    pts = np.asarray(points, dtype=float)
    c = np.asarray(ctrl, dtype=float)
    ext = max(float(np.max(np.ptp(pts, axis=0))), 1e-300)
    flat = [a[:, 2] for a in (pts, c) if a.shape[1] >= 3]
    return all(np.ptp(z) <= PLANAR_REL * ext for z in flat)


def deviations(curve: Curve, points, samples_per_span=SAMPLES_PER_SPAN, sub=4):
    """Orthogonal distance of every point to the curve (array, same order as points).

    Candidates: the nearest sample gives an upper bound d0 on a point's distance. The foot point lies
    within half a sample interval (in arc length) of some sample, so that sample is at most
    d0 + half its longer neighbouring interval's arc away; EVERY sample within that radius is refined
    in its neighbour interval (not only the few nearest: on a thin trailing edge the nearest samples
    can all lie on the wrong branch). Arc lengths of the intervals come from `sub` chords each, with
    a safety factor.
    """
    P = np.asarray(points, dtype=float)
    if P.shape[1] != curve.dim:
        if P.shape[1] == 2 and curve.dim == 3:
            P = np.column_stack([P, np.zeros(len(P))])
        elif P.shape[1] == 3 and curve.dim == 2:
            P = P[:, :2]
        else:
            raise ValueError("dimension mismatch between points and curve")
    us = curve.span_samples(samples_per_span, include_ends=True)
    S = curve.points(us)
    fine = us[:-1, None] + np.diff(us)[:, None] * (np.arange(sub + 1) / sub)[None, :]
    Fp = curve.points(fine.reshape(-1)).reshape(len(us) - 1, sub + 1, -1)
    arc = 1.25 * np.sum(np.linalg.norm(np.diff(Fp, axis=1), axis=2), axis=1)
    reach = 0.5 * np.maximum(np.r_[0.0, arc], np.r_[arc, 0.0])  # per sample
    tree = cKDTree(S)
    d0, _ = tree.query(P)
    balls = tree.query_ball_point(P, d0 + reach.max())
    pi, si = [], []
    for j, cand in enumerate(balls):
        cand = np.asarray(cand, dtype=int)
        keep = cand[np.linalg.norm(S[cand] - P[j], axis=1) <= d0[j] + reach[cand]]
        pi.append(np.full(len(keep), j))
        si.append(keep)
    pi, i = np.concatenate(pi), np.concatenate(si)
    # All (point, candidate) pairs are refined together, vectorised.
    Q = P[pi]
    ds = np.linalg.norm(S[i] - Q, axis=1)
    lo = us[np.maximum(i - 1, 0)]
    hi = us[np.minimum(i + 1, len(us) - 1)]
    u = us[i].copy()
    eps = 1e-15 * max(1.0, abs(curve.hi - curve.lo))
    for _ in range(16):
        C0, C1, C2 = curve.derivs(u, 2)
        r = C0 - Q
        f = np.einsum("ij,ij->i", r, C1)
        fp = np.einsum("ij,ij->i", C1, C1) + np.einsum("ij,ij->i", r, C2)
        step = np.where(fp > 0, -f / np.where(fp > 0, fp, 1.0), 0.0)
        u_new = np.clip(u + step, lo, hi)
        moved = np.max(np.abs(u_new - u))
        u = u_new
        if moved <= eps:
            break
    C0, C1 = curve.derivs(u, 1)
    r = C0 - Q
    d_newton = np.linalg.norm(r, axis=1)
    # Fallback: bounded Brent where Newton did not beat the sampled distance or stopped at a
    # non-stationary parameter inside its interval.
    cosang = np.abs(np.einsum("ij,ij->i", r, C1)) / np.maximum(d_newton * np.linalg.norm(C1, axis=1), 1e-300)
    inside = (u > lo + eps) & (u < hi - eps)
    bad = np.nonzero((d_newton > ds * (1 + 1e-12)) | (inside & (cosang > 1e-8) & (d_newton > 0)))[0]
    for b in bad:
        q = Q[b]
        res = minimize_scalar(
            lambda x: float(np.sum((curve.points(np.array([x]))[0] - q) ** 2)),
            bounds=(lo[b], hi[b]),
            method="bounded",
            options={"xatol": eps},
        )
        d_newton[b] = min(d_newton[b], ds[b], float(np.sqrt(res.fun)))
    d = np.minimum(d_newton, ds)
    out = d0.copy()
    np.minimum.at(out, pi, d)
    return out


def _kappa_and_dkds(curve: Curve, u, planar):
    """kappa (signed if planar), dkappa/ds and speed |C'| at parameters u."""
    _, d1, d2, d3 = curve.derivs(u, 3)
    speed = np.linalg.norm(d1, axis=1)
    speed = np.maximum(speed, 1e-300)
    dot12 = np.einsum("ij,ij->i", d1, d2)
    if planar:
        if curve.dim == 3:
            d1, d2, d3 = d1[:, :2], d2[:, :2], d3[:, :2]
        num = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        dnum = d1[:, 0] * d3[:, 1] - d1[:, 1] * d3[:, 0]
    else:
        B = np.cross(d1, d2)
        Bp = np.cross(d1, d3)
        num = np.linalg.norm(B, axis=1)
        safe = np.maximum(num, 1e-300)
        dnum = np.einsum("ij,ij->i", B, Bp) / safe
    kappa = num / speed**3
    dk_du = dnum / speed**3 - 3.0 * num * dot12 / speed**5
    return kappa, dk_du / speed, speed


def _gauss_span_nodes(curve: Curve):
    x, w = leggauss(GAUSS_NODES)
    us, ws = [], []
    for a, b in curve.spans:
        edges = np.linspace(a, b, GAUSS_SUBDIVISIONS + 1)
        for c0, c1 in zip(edges[:-1], edges[1:]):
            h = 0.5 * (c1 - c0)
            us.append(c0 + h * (x + 1.0))
            ws.append(h * w)
    return np.concatenate(us), np.concatenate(ws)


def fairness(curve: Curve, planar):
    """(F, L): F = L^3 int (dkappa/ds)^2 ds, Gauss-Legendre strictly inside each span."""
    u, w = _gauss_span_nodes(curve)
    _, dkds, speed = _kappa_and_dkds(curve, u, planar)
    L = float(np.sum(w * speed))
    integral = float(np.sum(w * dkds**2 * speed))
    return L**3 * integral, L


def _hysteresis_sign_changes(sig):
    sig = np.asarray(sig, dtype=float)
    sig = sig[np.isfinite(sig)]
    if sig.size == 0:
        return 0
    floor = NOISE_REL * float(np.max(np.abs(sig))) + NOISE_ABS
    state = 0
    changes = 0
    for v in sig:
        s = 1 if v >= floor else (-1 if v <= -floor else 0)
        if s == 0:
            continue
        if state != 0 and s != state:
            changes += 1
        state = s
    return changes


def shape_counts(curve: Curve, planar, L, samples_per_span=4 * SAMPLES_PER_SPAN):
    """(curvature extrema, inflections or None) on a dense per-span sampling."""
    u = curve.span_samples(samples_per_span)
    kappa, dkds, _ = _kappa_and_dkds(curve, u, planar)
    extrema = _hysteresis_sign_changes(dkds * L**2)
    infl = _hysteresis_sign_changes(kappa * L) if planar else None
    return extrema, infl


def measure(degree, knots, ctrl, weights, points, deviation_only=False) -> Metrics:
    """Measure one curve against its data points (see module doc)."""
    ctrl = np.asarray(ctrl, dtype=float)
    points = np.asarray(points, dtype=float)
    curve = Curve(degree, knots, ctrl, weights)
    dev = deviations(curve, points)
    max_dev = float(np.max(dev))
    rms_dev = float(np.sqrt(np.mean(dev**2)))
    if deviation_only:
        return Metrics(curve.n_independent, max_dev, rms_dev, float("nan"), float("nan"), -1, None)
    planar = is_planar(points, ctrl)
    F, L = fairness(curve, planar)
    extrema, infl = shape_counts(curve, planar, L)
    return Metrics(curve.n_independent, max_dev, rms_dev, F, L, extrema, infl)


def tolerance(points, rel_tol=1e-3):
    """rel_tol times the largest extent of the points' bounding box."""
    P = np.asarray(points, dtype=float)
    return rel_tol * float(np.max(np.ptp(P, axis=0)))


def read_points(path):
    """Read an x,y[,z] CSV with '#' comment lines and an optional header line."""
    rows = []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            parts = [p for p in s.replace(";", ",").replace("\t", ",").split(",") if p.strip()]
            if len(parts) == 1:
                parts = s.split()
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                continue  # header line
    if not rows:
        raise ValueError(f"{path}: no numeric rows")
    width = len(rows[0])
    if width not in (2, 3) or any(len(r) != width for r in rows):
        raise ValueError(f"{path}: not a 2- or 3-column point table")
    return np.asarray(rows, dtype=float)
