#!/usr/bin/env python3
"""Lowest fairness F reachable inside the tolerance band: an optimiser independent of fairfit.

Question (issue 4): at ``--rel-tol 1e-3`` can ANY curve within the orthogonal tolerance band of the
points have F <= 0.5 x scipy splprep's F, with (a) as many control points as splprep, (b) many
(dense) control points?  F = L^3 * int (dkappa/ds)^2 ds (bench/measure.py's definition).

Formulation (numpy/scipy only, no fairfit code):
  clamped B-spline of degree k on fixed knots t in [0, 1]; variables = control points X (n x 2)
  AND one foot parameter u_i per data point; constraints |C(u_i) - P_i|^2 <= tol_eff^2 (with free
  u_i this is exactly "orthogonal distance <= tol_eff"); u_0 = 0 and u_{m-1} = 1 are fixed, so the
  curve starts and ends within tol of the first and last points (it spans the data, as splprep's
  and fairfit's curves do).  tol_eff = (1 - MARGIN) tol.  Objective F with Gauss-Legendre nodes
  strictly inside every span, analytic gradient; solved by SLSQP from several starts (splprep's
  curve, fairfit's curve, knot-inserted / refitted variants).  Every reported curve is verified by
  bench/measure.py (max orthogonal deviation and F), the benchmark's independent measurer.

Usage (from the repository root):
    python bench/band_optimum.py --only naca23015 [--data DIR] [--fairfit BIN] [--dense 50]
        [--quintic] [--json results.json]
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.interpolate import BSpline
from scipy.optimize import minimize

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import measure  # noqa: E402

REPO = os.path.dirname(HERE)
MARGIN = 1e-4  # the optimiser works with (1 - MARGIN) tol so that the measurer's check has room
GROUPS = ["airfoils", "synthetic", os.path.join("iea15mw", "airfoils")]
QUAD_NODES = 10
QUAD_SUB = 2


# ----------------------------------------------------------------------------- data and baselines


def main_checkout() -> str:
    """The main git checkout (in a worktree, the one holding the common .git), else REPO."""
    try:
        common = subprocess.run(["git", "rev-parse", "--path-format=absolute", "--git-common-dir"], cwd=REPO,
                                capture_output=True, text=True, check=True).stdout.strip()
        return os.path.dirname(common)
    except (OSError, subprocess.CalledProcessError):
        return REPO


def default_data_dir() -> str:
    env = os.environ.get("FAIRFIT_DATA")
    if env:
        return env
    cands = [os.path.join(REPO, "..", "shared", "data"), os.path.join(main_checkout(), "..", "shared", "data")]
    for c in cands:
        if os.path.isdir(os.path.join(c, "airfoils")):
            return os.path.normpath(c)
    return cands[0]


def find_curves(data: str, only: str):
    out = []
    for g in GROUPS:
        d = os.path.join(data, g)
        if not os.path.isdir(d):
            continue
        for name in sorted(os.listdir(d)):
            if name.endswith(".csv") and fnmatch.fnmatch(name[:-4], only):
                out.append(os.path.join(d, name))
    return out


def splprep_curve(P, tol):
    """scipy splprep with bench/compare.py's search on s: the fewest control points meeting tol,
    and among those the largest s. Returns (k, t, ctrl)."""
    from compare import splprep_search

    (k, t, ctrl), _, _ = splprep_search(np.asarray(P, dtype=float), tol)
    return k, np.asarray(t), ctrl


def fairfit_curve(exe, csv, rel_tol, count=None, extra=()):
    """fairfit's integrated curve (k, t, ctrl 2D) or None (extra: more CLI arguments)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "c.json")
        cmd = [exe, "curve", csv, "--rel-tol", repr(rel_tol), "--threads", "1", "-o", out, *extra]
        if count is not None:
            cmd += ["--control-points", str(count)]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            return None
        js = json.load(open(out, encoding="utf-8"))
    w = js.get("weights")
    if w is not None and not np.allclose(w, w[0]):
        return None
    ctrl = np.asarray(js["control_points"], float)[:, :2]
    return int(js["degree"]), np.asarray(js["knots"], float), ctrl


# ----------------------------------------------------------------------------- the band problem


def clamp_knots(interior, k):
    return np.r_[np.zeros(k + 1), np.asarray(interior, float), np.ones(k + 1)]


def basis(t, k, u, nu):
    """Dense (len(u), n) matrix of the nu-th derivatives of the B-spline basis at u."""
    n = len(t) - k - 1
    return BSpline(t, np.eye(n), k, extrapolate=False)(np.clip(u, t[k], t[n]), nu)


class Band:
    """Fairness objective and band constraints for fixed degree k and knots t on [0, 1]."""

    def __init__(self, Q, tol, k, t):
        self.Q, self.tol, self.k, self.t = Q, tol, k, np.asarray(t, float)
        self.n = len(self.t) - k - 1
        self.m = len(Q)
        x, w = leggauss(QUAD_NODES)
        br = np.unique(self.t[k: self.n + 1])
        us, ws = [], []
        for a, b in zip(br[:-1], br[1:]):
            e = np.linspace(a, b, QUAD_SUB + 1)
            for c0, c1 in zip(e[:-1], e[1:]):
                h = 0.5 * (c1 - c0)
                us.append(c0 + h * (x + 1))
                ws.append(h * w)
        self.uq, self.wq = np.concatenate(us), np.concatenate(ws)
        self.s2 = np.ones(self.m)  # per-point band scale squared (pin_ends() shrinks the end points' band)
        self.sign_s = None  # sign targets of dkappa/du at the sign samples (set_signs()); None: no constraint
        self.sign_mode = "fixed"
        self.B1, self.B2, self.B3 = (basis(self.t, k, self.uq, nu) for nu in (1, 2, 3))

    # F and its gradient with respect to the control points (planar, signed curvature)
    def fairness(self, X, grad=True, gn=False):
        a, b, c = self.B1 @ X, self.B2 @ X, self.B3 @ X
        w = self.wq
        v = np.maximum(np.hypot(a[:, 0], a[:, 1]), 1e-300)
        num = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        dnum = a[:, 0] * c[:, 1] - a[:, 1] * c[:, 0]
        dot = np.einsum("ij,ij->i", a, b)
        g = dnum / v**3 - 3 * num * dot / v**5  # dkappa/du
        L = float(np.sum(w * v))
        Iq = float(np.sum(w * g * g / v))
        F = L**3 * Iq
        if not grad:
            return F, L, Iq
        perp = lambda z: np.column_stack([-z[:, 1], z[:, 0]])  # noqa: E731  d(z x y)/dy
        cross_a = lambda z: np.column_stack([z[:, 1], -z[:, 0]])  # noqa: E731  d(y x z)/dy
        dg_dc = perp(a) / v[:, None] ** 3
        dg_db = -3 * (dot[:, None] * perp(a) + num[:, None] * a) / v[:, None] ** 5
        dg_da = (cross_a(c) / v[:, None] ** 3 - 3 * dnum[:, None] * a / v[:, None] ** 5
                 - 3 * (cross_a(b) * dot[:, None] + num[:, None] * b) / v[:, None] ** 5
                 + 15 * (num * dot)[:, None] * a / v[:, None] ** 7)
        s = (w * 2 * g / v)[:, None]
        dI_da = s * dg_da - (w * g * g / v**3)[:, None] * a
        dI_db = s * dg_db
        dI_dc = s * dg_dc
        dL_da = (w / v)[:, None] * a
        coef_L = 3 * L**2 * Iq
        coef_I = L**3
        G = (self.B1.T @ (coef_L * dL_da + coef_I * dI_da) + self.B2.T @ (coef_I * dI_db)
             + self.B3.T @ (coef_I * dI_dc))
        if gn:  # Gauss-Newton: rho_q = L^1.5 sqrt(w_q / v_q) g_q, F = |rho|^2 (L, v held fixed)
            fac = (L**1.5 * np.sqrt(w / v))[:, None]
            Jr = np.empty((len(w), 2 * self.n))
            for d in range(2):
                Jr[:, d::2] = fac * (dg_da[:, [d]] * self.B1 + dg_db[:, [d]] * self.B2 + dg_dc[:, [d]] * self.B3)
            return F, G, Jr
        return F, G

    @staticmethod
    def dkdu(X, B1, B2, B3, jac=False):
        """dkappa/du at the rows of the basis matrices B1..B3 (planar); with jac also its Jacobian
        (rows, 2n) in the interleaved order of X.reshape(-1)."""
        a, b, c = B1 @ X, B2 @ X, B3 @ X
        v = np.maximum(np.hypot(a[:, 0], a[:, 1]), 1e-300)
        num = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        dnum = a[:, 0] * c[:, 1] - a[:, 1] * c[:, 0]
        dot = np.einsum("ij,ij->i", a, b)
        g = dnum / v**3 - 3 * num * dot / v**5
        if not jac:
            return g
        perp = np.column_stack([-a[:, 1], a[:, 0]])
        dg_dc = perp / v[:, None] ** 3
        dg_db = -3 * (dot[:, None] * perp + num[:, None] * a) / v[:, None] ** 5
        dg_da = (np.column_stack([c[:, 1], -c[:, 0]]) / v[:, None] ** 3 - 3 * dnum[:, None] * a / v[:, None] ** 5
                 - 3 * (np.column_stack([b[:, 1], -b[:, 0]]) * dot[:, None] + num[:, None] * b) / v[:, None] ** 5
                 + 15 * (num * dot)[:, None] * a / v[:, None] ** 7)
        J = np.empty((len(g), 2 * B1.shape[1]))
        for d in range(2):
            J[:, d::2] = dg_da[:, [d]] * B1 + dg_db[:, [d]] * B2 + dg_dc[:, [d]] * B3
        return g, J

    def set_signs(self, X, per_span=192, mode="fixed"):
        """Curvature-extrema constraints: s_g dkappa/du(u_g) >= 0 at `per_span` samples strictly inside
        every span (midpoints of equal cells: measure.py's extrema samples at 192), with the sign pattern
        s_g of the curve X (the start). mode "fixed": that pattern for the whole run (the sign changes stay
        between the same two samples, as fairfit's band fairing holds its node targets); "moving": the
        pattern is taken again from the current curve at every restart round, and samples inside the
        hysteresis floor where the sign changes are left free, so a sign change can move along the curve
        (never more changes: a free sample sits between runs of opposite sign)."""
        br = np.unique(self.t[self.k: self.n + 1])
        us = np.concatenate([a + (b - a) * (np.arange(per_span) + 0.5) / per_span for a, b in zip(br[:-1], br[1:])])
        self.SB = tuple(basis(self.t, self.k, us, nu) for nu in (1, 2, 3))
        self.sign_mode = mode
        self.sign_s = sign_pattern(self.dkdu(X, *self.SB), free_transitions=False)
        return self

    def sign_values(self, X, jac=False):
        """s_g dkappa/du(u_g) / scale at the constrained samples (and the Jacobian in X's order)."""
        on = self.sign_s != 0
        s = self.sign_s[on] / self.sign_scale
        if not jac:
            return s * self.dkdu(X, *(B[on] for B in self.SB))
        g, J = self.dkdu(X, *(B[on] for B in self.SB), jac=True)
        return s * g, s[:, None] * J

    def signs_ok(self, X):
        return self.sign_s is None or float(np.min(self.sign_values(X), initial=0.0)) >= -1e-6

    # Band constraints: the foot parameters are eliminated by exact projection.  d_i(X) =
    # min_u |C(u) - P_i|^2 (local Newton from the previous foot; u_0 = 0 and u_{m-1} = 1 fixed);
    # by the envelope theorem grad_X d_i = 2 N(u_i*)^T r_i.  A local foot gives an upper bound on the
    # true distance, so the constraints are conservative.
    def project(self, X, u):
        u = u.copy()
        lo, hi = self.t[self.k], self.t[self.n]
        for _ in range(30):
            N0, N1, N2 = (basis(self.t, self.k, u, nu) for nu in (0, 1, 2))
            r = N0 @ X - self.Q
            c1, c2 = N1 @ X, N2 @ X
            f = np.einsum("ij,ij->i", r, c1)
            fp = np.einsum("ij,ij->i", c1, c1) + np.einsum("ij,ij->i", r, c2)
            step = np.where(fp > 0, -f / np.where(fp > 0, fp, 1.0), -np.sign(f) * 1e-3)
            step = np.clip(step, -0.05, 0.05)
            step[0] = step[-1] = 0.0
            u_new = np.clip(u + step, lo, hi)
            # keep a step only if it does not increase the distance (safeguard)
            r_new = basis(self.t, self.k, u_new, 0) @ X - self.Q
            better = np.einsum("ij,ij->i", r_new, r_new) <= np.einsum("ij,ij->i", r, r)
            u = np.where(better, u_new, u)
            if np.max(np.abs(np.where(better, step, 0))) < 1e-13:
                break
        N0 = basis(self.t, self.k, u, 0)
        return u, N0, N0 @ X - self.Q

    def solve(self, X0, u0, Fref, maxiter=400, rounds=6, ridge=1e-2, precond=True):
        """SLSQP in preconditioned variables: X = Xc + tol * R^-T z, R R^T = Gauss-Newton Hessian of F / Fref
        (in units of tol) plus a small multiple of the data-fit Hessian; restarted (new Xc, new R) for up
        to `rounds` rounds while F still drops. Returns (X, feet, last result, total iterations)."""
        n, tol = self.n, self.tol
        tt = ((1 - MARGIN) * tol) ** 2
        Xc, u_c = X0.copy(), u0.copy()
        total_it, res, F_prev = 0, None, np.inf
        for rnd in range(rounds):
            if self.sign_s is not None:
                if self.sign_mode == "moving" and rnd > 0:
                    self.sign_s = sign_pattern(self.dkdu(Xc, *self.SB), free_transitions=True)
                self.sign_scale = float(np.max(np.abs(self.dkdu(Xc, *self.SB))))
            F0, _, Jr = self.fairness(Xc, gn=True)
            H = 2 * (Jr.T @ Jr) * tol**2 / Fref
            A = basis(self.t, self.k, u_c, 0)
            AtA = np.kron(A.T @ A, np.eye(2)) * tol**2 / tt
            H = H + ridge * np.trace(H) / np.trace(AtA) * AtA + 1e-12 * np.trace(H) / len(H) * np.eye(len(H))
            M = np.linalg.inv(np.linalg.cholesky(H).T) if precond else np.eye(2 * n)  # y = M z
            state = {"u": u_c.copy(), "key": None}

            def xof(z):
                return Xc + tol * (M @ z).reshape(n, 2)

            def proj(z):
                key = z.tobytes()
                if state["key"] != key:
                    u, N0, r = self.project(xof(z), state["u"])
                    state.update(u=u, N0=N0, r=r, key=key)
                return state["N0"], state["r"]

            def f(z):
                F, G = self.fairness(xof(z))
                return F / Fref, (G.reshape(-1) * tol / Fref) @ M

            def cons(z):
                _, r = proj(z)
                return 1.0 - np.einsum("ij,ij->i", r, r) / (tt * self.s2)

            def jac(z):
                N0, r = proj(z)
                J = np.empty((self.m, 2 * n))
                J[:, 0::2] = -2 * tol * r[:, [0]] * N0 / (tt * self.s2[:, None])
                J[:, 1::2] = -2 * tol * r[:, [1]] * N0 / (tt * self.s2[:, None])
                return J @ M

            constraints = [{"type": "ineq", "fun": cons, "jac": jac}]
            if self.sign_s is not None:
                constraints.append({"type": "ineq", "fun": lambda z: self.sign_values(xof(z)),
                                    "jac": lambda z: tol * self.sign_values(xof(z), jac=True)[1] @ M})
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = minimize(f, np.zeros(2 * n), jac=True, method="SLSQP", constraints=constraints,
                               options={"maxiter": maxiter, "ftol": 1e-12})
            total_it += res.nit
            X = xof(res.x)
            u, _, r = self.project(X, state["u"])
            if np.max(np.einsum("ij,ij->i", r, r) / self.s2) > tt * (1 + 1e-9):
                X, u = self.repair(X, u)
            F1 = self.fairness(X, grad=False)[0]
            feasible = self.feasible(X, u)
            if F_prev == np.inf:
                F_prev = self.fairness(Xc, grad=False)[0]
            if not feasible or F1 > F_prev * (1 - 1e-4):
                if feasible and F1 < F_prev:
                    Xc, u_c = X, u
                break
            Xc, u_c, F_prev = X, u, F1
        return Xc, u_c, res, total_it

    def pin_ends(self, rel=1e-3):
        """End points within rel * tol of the first and last data points (fairfit interpolates them)."""
        self.s2[[0, -1]] = rel**2
        return self

    def feasible(self, X, u):
        _, _, r = self.project(X, u)
        return self.signs_ok(X) and bool(np.max(np.einsum("ij,ij->i", r, r) / self.s2) <= ((1 - MARGIN) * self.tol) ** 2 * (1 + 1e-6))

    def repair(self, X1, u1):
        """Nearest control points (least change) that satisfy the band constraints."""
        n, tol = self.n, self.tol
        tt = ((1 - 2 * MARGIN) * tol) ** 2
        state = {"u": u1.copy()}

        def cons(y):
            u, N0, r = self.project(X1 + tol * y.reshape(n, 2), state["u"])
            state["u"] = u
            return 1.0 - np.einsum("ij,ij->i", r, r) / (tt * self.s2)

        def jac(y):
            u, N0, r = self.project(X1 + tol * y.reshape(n, 2), state["u"])
            J = np.empty((self.m, 2 * n))
            J[:, 0::2] = -2 * tol * r[:, [0]] * N0 / (tt * self.s2[:, None])
            J[:, 1::2] = -2 * tol * r[:, [1]] * N0 / (tt * self.s2[:, None])
            return J

        constraints = [{"type": "ineq", "fun": cons, "jac": jac}]
        if self.sign_s is not None:
            constraints.append({"type": "ineq", "fun": lambda y: self.sign_values(X1 + tol * y.reshape(n, 2)),
                                "jac": lambda y: tol * self.sign_values(X1 + tol * y.reshape(n, 2), jac=True)[1]})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = minimize(lambda y: (y @ y, 2 * y), np.zeros(2 * n), jac=True, method="SLSQP",
                           constraints=constraints,
                           options={"maxiter": 200, "ftol": 1e-14})
        X = X1 + tol * res.x.reshape(n, 2)
        return X, self.project(X, state["u"])[0]


def sign_pattern(g, free_transitions=False):
    """Signs (+1, -1, 0 = free) of the samples g of dkappa/du (parameter order) with measure.py's hysteresis
    floor (1e-6 of the largest magnitude): a sample inside the floor takes the sign of the run around it;
    where the sign changes across floor samples they take the sign of the run before (fixed pattern) or
    are left free (free_transitions). Sign changes of the pattern = the curve's extrema count."""
    g = np.asarray(g, float)
    floor = measure.NOISE_REL * float(np.max(np.abs(g), initial=0.0))
    raw = np.where(g >= floor, 1, np.where(g <= -floor, -1, 0)) if floor > 0 else np.zeros(len(g), int)
    out = raw.copy()
    signed = np.flatnonzero(raw)
    if len(signed) == 0:
        return out
    out[: signed[0]] = raw[signed[0]]
    out[signed[-1] + 1:] = raw[signed[-1]]
    for a, b in zip(signed[:-1], signed[1:]):
        if b > a + 1:
            same = raw[a] == raw[b]
            out[a + 1: b] = raw[a] if same or not free_transitions else 0
    return out


def feet(k, t, X, Q, samples=4000):
    """Orthogonal foot parameters of the points Q on the curve (dense sampling + Newton)."""
    cur = BSpline(t, X, k)
    us = np.linspace(t[k], t[-k - 1], samples)
    S = cur(us)
    i = np.argmin(((Q[:, None, :] - S[None, :, :]) ** 2).sum(-1), axis=1)
    u = us[i]
    d1, d2 = cur.derivative(1), cur.derivative(2)
    for _ in range(20):
        r = cur(u) - Q
        c1, c2 = d1(u), d2(u)
        f = np.einsum("ij,ij->i", r, c1)
        fp = np.einsum("ij,ij->i", c1, c1) + np.einsum("ij,ij->i", r, c2)
        u = np.clip(u - np.where(fp > 0, f / np.where(fp > 0, fp, 1), 0), t[k], t[-k - 1])
    u[0], u[-1] = t[k], t[-k - 1]
    return u


def normalise_param(k, t, X):
    """Same curve on the parameter domain [0, 1]."""
    a, b = t[k], t[len(t) - k - 1]
    return (t - a) / (b - a)


def refit(k, t_new, k_src, t_src, X_src, params=None, samples=3000):
    """Least-squares B-spline on knots t_new of samples of the source curve (exact when the source's
    space is contained in the new one, same parameter). params: 'arc' re-parametrises by arc length."""
    src = BSpline(t_src, X_src, k_src)
    s = np.linspace(0, 1, samples)
    pts = src(s)
    if params == "arc":
        seg = np.r_[0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
        s = seg / seg[-1]
    A = basis(t_new, k, s, 0)
    X, *_ = np.linalg.lstsq(A, pts, rcond=None)
    return X


def insert_to_count(t, k, n_target):
    """Knots with midpoints of the longest spans inserted until n control points = n_target."""
    t = list(t)
    while len(t) - k - 1 < n_target:
        br = np.unique(t)
        j = int(np.argmax(np.diff(br)))
        t.append(0.5 * (br[j] + br[j + 1]))
        t.sort()
    return np.asarray(t)


# ----------------------------------------------------------------------------- study of one curve


class Frame:
    """Normalisation P -> Q = (P - c) / S so that the largest bounding-box side is 1."""

    def __init__(self, P):
        self.c = P.min(axis=0)
        self.S = float(np.max(np.ptp(P, axis=0)))

    def to(self, A):
        return (A - self.c) / self.S

    def back(self, A):
        return A * self.S + self.c


def verify(k, t, Xn, frame, P):
    m = measure.measure(k, t, frame.back(Xn), None, P)
    return m


def arc_profile(k, t, X, bins=10):
    """Share of int (dkappa/ds)^2 ds per arc-length decile (list of fractions) and curvature peak."""
    band = Band(np.zeros((2, 2)), 1.0, k, t)
    a, b, c = band.B1 @ X, band.B2 @ X, band.B3 @ X
    v = np.hypot(a[:, 0], a[:, 1])
    num = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dnum = a[:, 0] * c[:, 1] - a[:, 1] * c[:, 0]
    dot = np.einsum("ij,ij->i", a, b)
    g = dnum / v**3 - 3 * num * dot / v**5
    contrib = band.wq * g * g / v
    order = np.argsort(band.uq)
    s = np.cumsum((band.wq * v)[order])
    s /= s[-1]
    idx = np.minimum((s * bins).astype(int), bins - 1)
    share = np.bincount(idx, weights=contrib[order], minlength=bins)
    return list(share / share.sum()), float(np.max(np.abs(num / v**3)))


def run_curve(csv, args):
    name = os.path.basename(csv)[:-4]
    P = measure.read_points(csv)[:, :2]
    tol = measure.tolerance(P, args.rel_tol)
    frame = Frame(P)
    Q = frame.to(P)
    tq = args.rel_tol  # tolerance in the normalised frame
    out = {"name": name, "points": len(P)}
    t0 = time.time()

    if args.own:
        return run_own(csv, args, name, P, tol, frame, Q, tq, out, t0)
    k, t, C = splprep_curve(P, tol)
    n_sp = len(C)
    ms = measure.measure(k, t, C, None, P)
    out["splprep"] = {"n": n_sp, "F": ms.F, "dev": ms.max_dev / tol, "extrema": ms.extrema}
    Fref = ms.F
    tn_sp = normalise_param(k, t, C)
    starts_a = [("splprep", 3, tn_sp, frame.to(C))]
    ff = fairfit_curve(args.fairfit, csv, args.rel_tol)
    if ff is not None:
        kf, tf, Cf = ff
        mf = measure.measure(kf, tf, Cf, None, P)
        out["fairfit"] = {"n": len(Cf), "F": mf.F, "dev": mf.max_dev / tol}
        tf = normalise_param(kf, tf, Cf)
        out["fairfit_profile"] = arc_profile(kf, tf, frame.to(Cf))
        if kf == 3:
            ti = insert_to_count(tf, 3, n_sp)
            starts_a.append(("fairfit+ins", 3, ti, refit(3, ti, 3, tf, frame.to(Cf))))
    ffn = fairfit_curve(args.fairfit, csv, args.rel_tol, count=n_sp)
    if ffn is not None and ffn[0] == 3:
        tfn = normalise_param(3, ffn[1], ffn[2])
        mfn = measure.measure(*ffn, None, P)
        out["fairfit_at_n"] = {"n": len(ffn[2]), "F": mfn.F, "dev": mfn.max_dev / tol, "extrema": mfn.extrema}
        starts_a.append(("fairfit@n", 3, tfn, frame.to(ffn[2])))
    print(f"{name}: tol {tol:.3g}, splprep n={n_sp} F={Fref:.4g}; fairfit "
          f"{out.get('fairfit', {}).get('n')} F={out.get('fairfit', {}).get('F', float('nan')):.4g}", flush=True)

    def optimise(label, k, t, X0, maxiter):
        band = Band(Q, tq, k, t)
        if args.pin_ends:
            band.pin_ends()
        u0 = feet(k, t, X0, Q)
        ts = time.time()
        X, u, res, nit = band.solve(X0, u0, Fref, maxiter=maxiter)
        m = verify(k, t, X, frame, P)
        rec = {"start": label, "k": k, "n": band.n, "F": m.F, "ratio": m.F / Fref, "dev": m.max_dev / tol,
               "ok": bool(m.max_dev <= tol * (1 + 1e-6)), "iters": int(nit), "status": res.message,
               "seconds": round(time.time() - ts, 1), "extrema": m.extrema, "inflections": m.inflections,
               "knots": list(t), "ctrl": X.tolist()}
        print(f"  [{label}] k={k} n={band.n}: F={m.F:.4g} ratio {m.F / Fref:.3f} dev/tol {m.max_dev / tol:.5f} "
              f"it={nit} {rec['seconds']}s ({res.message})", flush=True)
        return rec

    def best_of(recs):
        ok = [r for r in recs if r["ok"]]
        return min(ok, key=lambda r: r["F"]) if ok else None

    out["pinned"] = bool(args.pin_ends)
    # (a) at splprep's count (or the best (a) curve of an earlier run, --dense-from)
    prev = previous_best_at_n(args.dense_from, name) if args.dense_from else None
    if prev is not None:
        recs_a = []
        ba = prev
    else:
        recs_a = [optimise(lab, kk, tt, X0, args.maxiter) for lab, kk, tt, X0 in starts_a]
        if "fairfit_at_n" in out and not args.pin_ends:  # fairfit's own curve at n is a candidate too
            recs_a.append(as_is_record("fairfit@n as is", mfn, Fref, tol, tfn, frame.to(ffn[2])))
        ba = best_of(recs_a)
    # (b) dense: adapted knots (superset of the best (a) curve's knots: exact start) and uniform knots
    recs_b = []
    if ba is not None and args.dense > 0:
        tb = np.asarray(ba["knots"])
        Xb = np.asarray(ba["ctrl"])
        td = insert_to_count(tb, 3, args.dense)
        recs_b.append(optimise("dense adapted", 3, td, refit(3, td, 3, tb, Xb), args.maxiter))
        if args.dense_knots == "both":
            tu = clamp_knots(np.linspace(0, 1, args.dense - 3 + 1)[1:-1], 3)
            recs_b.append(optimise("dense uniform(arc)", 3, tu, refit(3, tu, 3, tb, Xb, params="arc"), args.maxiter))
        if args.quintic:
            b3 = best_of(recs_b) or ba
            t3, X3 = np.asarray(b3["knots"]), np.asarray(b3["ctrl"])
            br = np.unique(t3)[1:-1]
            t5 = np.r_[np.zeros(6), np.repeat(br, 1), np.ones(6)]  # C4 quintic on the same breaks
            recs_b.append(optimise("dense quintic", 5, t5, refit(5, t5, 3, t3, X3), args.maxiter))
    bb = best_of(recs_b)
    out["at_n"] = recs_a
    out["dense"] = recs_b
    for key, b in (("best_at_n", ba), ("best_dense", bb)):
        if b is not None:
            out[key] = {kk: b[kk] for kk in ("start", "k", "n", "F", "ratio", "dev", "extrema", "inflections")}
            out[key + "_profile"] = arc_profile(b["k"], np.asarray(b["knots"]), np.asarray(b["ctrl"]))
    out["seconds"] = round(time.time() - t0, 1)
    return out


def run_own(csv, args, name, P, tol, frame, Q, tq, out, t0):
    """--own: the band optimum at the start curve's OWN knots and count, from that curve, for every --signs
    mode (off: tolerance only; fixed / moving: curvature-extrema constraints from the start curve's sign
    pattern, Band.set_signs), end points pinned with --pin-ends. The start curve is fairfit's default curve
    (--own-start fairfit) or splprep's own curve (--own-start splprep: splprep's count and knots, and with
    --signs fixed splprep's sign pattern, so the optimum has no more curvature extrema than splprep's curve).
    Records in out["own"]; out["fairfit"] describes the start curve (key kept for --own-table)."""
    k, t, C = splprep_curve(P, tol)
    ms = measure.measure(k, t, C, None, P)
    out["splprep"] = {"n": len(C), "F": ms.F, "dev": ms.max_dev / tol, "extrema": ms.extrema}
    Fref = ms.F
    out["pinned"] = bool(args.pin_ends)
    out["own_start"] = args.own_start
    out["own"] = []
    ff = (k, t, C) if args.own_start == "splprep" else \
        fairfit_curve(args.fairfit, csv, args.rel_tol, extra=args.fairfit_args.split())
    if ff is None:
        return out
    kf, tf, Cf = ff
    mf = measure.measure(kf, tf, Cf, None, P)
    out["fairfit"] = {"n": len(Cf), "k": kf, "F": mf.F, "ratio": mf.F / Fref, "dev": mf.max_dev / tol,
                      "extrema": mf.extrema}
    tn, X0 = normalise_param(kf, tf, Cf), frame.to(Cf)
    print(f"{name}: splprep n={len(C)} F={Fref:.4g} extrema {ms.extrema}; start ({args.own_start}) n={len(Cf)} "
          f"k={kf} ratio {mf.F / Fref:.4f} extrema {mf.extrema}", flush=True)
    for mode in args.signs.split(","):
        band = Band(Q, tq, kf, tn)
        if args.pin_ends:
            band.pin_ends()
        if mode != "off":
            band.set_signs(X0, args.sign_samples, mode)
        ts = time.time()
        X, u, res, nit = band.solve(X0, feet(kf, tn, X0, Q), Fref, maxiter=args.maxiter)
        m = verify(kf, tn, X, frame, P)
        rec = {"start": f"{args.own_start} own signs={mode}", "signs": mode, "k": kf, "n": band.n, "F": m.F,
               "ratio": m.F / Fref, "gain": 1 - m.F / mf.F, "dev": m.max_dev / tol,
               "ok": bool(m.max_dev <= tol * (1 + 1e-6)), "iters": int(nit), "status": res.message,
               "seconds": round(time.time() - ts, 1), "extrema": m.extrema, "inflections": m.inflections,
               "knots": list(tn), "ctrl": X.tolist()}
        print(f"  [own signs={mode}] F={m.F:.4g} ratio {m.F / Fref:.4f} (start {mf.F / Fref:.4f}, gain "
              f"{100 * rec['gain']:.2f} %) dev/tol {m.max_dev / tol:.5f} extrema {m.extrema} it={nit} "
              f"{rec['seconds']}s ({res.message})", flush=True)
        out["own"].append(rec)
    out["seconds"] = round(time.time() - t0, 1)
    return out


def own_table(jsonls):
    """Markdown table of --own runs: per curve (and start curve, --own-start) the start's ratio and extrema
    (fairfit's default curve, or splprep's: "(from splprep)") and each signs mode's best verified ratio
    (extrema), from --json files."""
    rows, modes = {}, []
    for path in jsonls:
        with open(path, encoding="utf-8") as fh:
            for line in fh:
                if not line.strip():
                    continue
                r = json.loads(line)
                if "own" not in r or "fairfit" not in r:
                    continue
                start = r.get("own_start", "fairfit")
                label = r["name"] + ("" if start == "fairfit" else f" (from {start})")
                row = rows.setdefault(label, {"r": r, "runs": {}})
                for x in r["own"]:
                    modes += [x["signs"]] if x["signs"] not in modes else []
                    y = row["runs"].get(x["signs"])
                    if x["ok"] and (y is None or x["F"] < y["F"]):
                        row["runs"][x["signs"]] = x
    out = ["| curve | splprep extrema | fairfit n (k) | fairfit ratio (extrema) | "
           + " | ".join(f"band optimum signs={md} (extrema, gain vs fairfit)" for md in modes) + " |",
           "|---|---:|---:|---:|" + "---:|" * len(modes)]
    for name, row in rows.items():
        r, ff = row["r"], row["r"]["fairfit"]
        cells = []
        for md in modes:
            x = row["runs"].get(md)
            cells.append(f"{x['ratio']:.4f} ({x['extrema']}, {100 * x['gain']:.1f} %)" if x else "-")
        out.append(f"| {name} | {r['splprep']['extrema']} | {ff['n']} ({ff['k']}) | {ff['ratio']:.4f} "
                   f"({ff['extrema']}) | " + " | ".join(cells) + " |")
    return "\n".join(out)


def as_is_record(label, m, Fref, tol, t, X):
    """A run record of an unoptimised curve (measure.py's result m)."""
    return {"start": label, "k": 3, "n": len(X), "F": m.F, "ratio": m.F / Fref, "dev": m.max_dev / tol,
            "ok": bool(m.max_dev <= tol * (1 + 1e-6)), "iters": 0, "status": "as is", "seconds": 0.0,
            "extrema": m.extrema, "inflections": m.inflections, "knots": list(t), "ctrl": np.asarray(X).tolist()}


def previous_best_at_n(jsonl, name):
    """The best verified run at splprep's count of curve `name` (last record, ends not pinned) in a --json file."""
    best = None
    with open(jsonl, encoding="utf-8") as fh:
        for line in fh:
            if line.strip():
                r = json.loads(line)
                if r["name"] == name and not r.get("pinned") and r.get("at_n"):
                    ok = [x for x in r["at_n"] if x["ok"]]
                    best = min(ok, key=lambda x: x["F"]) if ok else best
    return best


def merged(jsonls):
    """Per curve, from one or more --json files: splprep, fairfit, the best run at splprep's n (ends free), the
    best dense run and the best pinned-ends run at n (each the lowest verified F over all records)."""
    out = {}
    for path in jsonls:
        with open(path, encoding="utf-8") as fh:
            for line in fh:
                if not line.strip():
                    continue
                r = json.loads(line)
                m = out.setdefault(r["name"], {"name": r["name"]})
                m["splprep"] = {**m.get("splprep", {}), **r["splprep"]}
                for key in ("fairfit", "fairfit_at_n"):
                    if key in r:
                        m[key] = r[key]
                if not r.get("pinned"):
                    for x in r.get("at_n", []) + r.get("dense", []):
                        y = m.setdefault("runs", {}).get(x["start"])
                        if y is None or (x["ok"], -x["F"]) > (y["ok"], -y["F"]):
                            m["runs"][x["start"]] = x
                m.setdefault("runs", {})
                slots = (("best_pinned", r.get("at_n", [])),) if r.get("pinned") else \
                    (("best_at_n", r.get("at_n", [])), ("best_dense", r.get("dense", [])))
                ext = m["splprep"].get("extrema")
                if ext is not None and not r.get("pinned"):  # issue 4 also asks extrema <= splprep's
                    slots += (("best_at_n_ext", [x for x in r.get("at_n", []) if x["extrema"] <= ext]),)
                for slot, runs in slots:
                    for x in runs:
                        if x["ok"] and (slot not in m or x["F"] < m[slot]["F"]):
                            m[slot] = {kk: x[kk] for kk in ("start", "k", "n", "F", "ratio", "dev", "extrema")}
    return out


def results_csv(jsonls, path):
    """bench/band_optimum_results.csv: per curve the lowest verified ratios F / splprep's F."""
    fmt = lambda b: f"{b['ratio']:.4f}" if b else ""  # noqa: E731
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("curve,splprep_n,splprep_F,best_ratio_at_n,best_ratio_dense,pinned_ends,splprep_extrema,"
                 "best_ratio_at_n_extrema_ok\n")
        for name, m in merged(jsonls).items():
            sp = m["splprep"]
            fh.write(f"{name},{sp['n']},{sp['F']:.6g},{fmt(m.get('best_at_n'))},{fmt(m.get('best_dense'))},"
                     f"{fmt(m.get('best_pinned'))},{sp.get('extrema', '')},{fmt(m.get('best_at_n_ext'))}\n")


def table(jsonls):
    """Markdown tables (one row per curve, best verified runs over all records) from --json results files:
    the summary and the ratio of every start."""
    m_all = merged(jsonls)
    rows = ["| curve | splprep n | splprep F | fairfit n | fairfit F (ratio) | best F at splprep's n (ratio, dev/tol, "
            "start, extrema) | best F dense (n, ratio, dev/tol, knots) | pinned ends at n (ratio) | best ratio at n with "
            "extrema <= splprep's (splprep's extrema) | lowest ratio found |",
            "|---|---:|---:|---:|---:|---|---|---:|---:|---:|"]
    for name, m in m_all.items():
        sp, ff = m["splprep"], m.get("fairfit", {})
        a, b, p = m.get("best_at_n"), m.get("best_dense"), m.get("best_pinned")
        fa = f"{a['F']:.4g} ({a['ratio']:.3f}, {a['dev']:.4f}, {a['start']}, {a.get('extrema', '?')})" if a else "-"
        e = m.get("best_at_n_ext")
        fe = (f"{e['ratio']:.3f}" if e else "none") + f" ({sp.get('extrema', '?')})" if "extrema" in sp else "-"
        fb = f"{b['F']:.4g} ({b['n']}, {b['ratio']:.3f}, {b['dev']:.4f}, {b['start']})" if b else "-"
        fp = f"{p['ratio']:.3f}" if p else "-"
        low = min([x["ratio"] for x in (a, b, p) if x] + [ff.get("F", np.inf) / sp["F"]])
        rows.append(f"| {name} | {sp['n']} | {sp['F']:.4g} | {ff.get('n', '-')} | "
                    f"{ff.get('F', float('nan')):.4g} ({ff.get('F', float('nan')) / sp['F']:.3f}) | {fa} | {fb} | "
                    f"{fp} | {fe} | {low:.3f} |")
    starts = ["splprep", "fairfit+ins", "fairfit@n", "dense adapted", "dense uniform(arc)"]
    rows += ["", "| curve | " + " | ".join(starts) + " | fairfit's own F at n |", "|---|" + "---:|" * (len(starts) + 1)]
    for name, m in m_all.items():
        cells = []
        for st in starts:
            x = m["runs"].get(st)
            cells.append("-" if x is None else (f"{x['ratio']:.3f}" + (" conv." if "success" in x["status"] else "")
                                                if x["ok"] else "infeasible"))
        fn = m.get("fairfit_at_n")
        cells.append(f"{fn['F'] / m['splprep']['F']:.3f}" if fn else "-")
        rows.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", default="*", help="curve name glob (file name without .csv)")
    ap.add_argument("--data", default=None, help="data directory (default ../shared/data from the repo root)")
    ap.add_argument("--fairfit", default=None, help="fairfit binary (default target/release/fairfit of this "
                    "checkout, else of the main checkout)")
    ap.add_argument("--rel-tol", type=float, default=1e-3)
    ap.add_argument("--dense", type=int, default=50, help="control points of the dense study")
    ap.add_argument("--dense-knots", choices=["both", "adapted"], default="both",
                    help="dense knots: adapted (the best n-curve's knots + midpoints) and uniform in arc length, "
                    "or adapted only")
    ap.add_argument("--quintic", action="store_true", help="also a quintic dense curve")
    ap.add_argument("--maxiter", type=int, default=150)
    ap.add_argument("--json", default=None, help="append one JSON line per curve to this file")
    ap.add_argument("--table", default=None, help="only print the Markdown tables of the comma-separated --json results files")
    ap.add_argument("--pin-ends", action="store_true", help="end points within 1e-3 tol of the first and last "
                    "data points (as a curve closed at a sharp trailing edge needs)")
    ap.add_argument("--dense-from", default=None, help="skip the runs at splprep's count: start the dense runs "
                    "from the best such run of the same curve in this --json file")
    ap.add_argument("--results-csv", nargs=2, metavar=("OUT", "JSONS"), default=None,
                    help="only write the per-curve best ratios of the comma-separated --json files to OUT")
    ap.add_argument("--own", action="store_true", help="only the band optimum at fairfit's own knots and count, "
                    "from fairfit's default curve (one run per --signs mode)")
    ap.add_argument("--own-start", choices=["fairfit", "splprep"], default="fairfit", help="with --own: the start "
                    "curve (its knots, count and sign pattern): fairfit's default curve or splprep's own curve")
    ap.add_argument("--signs", default="off,fixed", help="with --own: comma-separated modes of the curvature-extrema "
                    "constraints: off, fixed (fairfit's sign pattern of dkappa/ds), moving (its sign changes may move)")
    ap.add_argument("--sign-samples", type=int, default=192, help="samples per span of the sign constraints "
                    "(measure.py counts extrema at 192)")
    ap.add_argument("--fairfit-args", default="", help="with --own: more arguments of fairfit's curve command "
                    "(e.g. '--degree auto', the benchmark's setting)")
    ap.add_argument("--own-table", default=None, help="only print the table of the comma-separated --own --json files")
    args = ap.parse_args(argv)
    if args.own_table:
        print(own_table(args.own_table.split(",")))
        return 0
    if args.table:
        print(table(args.table.split(",")))
        return 0
    if args.results_csv:
        results_csv(args.results_csv[1].split(","), args.results_csv[0])
        return 0
    data = args.data or default_data_dir()
    if args.fairfit is None:
        args.fairfit = os.path.join(REPO, "target", "release", "fairfit")
        if not os.path.exists(args.fairfit):
            args.fairfit = os.path.join(main_checkout(), "target", "release", "fairfit")
    files = find_curves(data, args.only)
    if not files:
        print(f"no curve matches {args.only!r} under {data}", file=sys.stderr)
        return 1
    for csv in files:
        res = run_curve(csv, args)
        summary = {k: v for k, v in res.items() if k not in ("at_n", "dense")}
        summary = {k: v for k, v in summary.items() if k != "own"}
        summary["runs"] = [{kk: r[kk] for kk in r if kk not in ("knots", "ctrl")}
                           for r in res.get("at_n", []) + res.get("dense", []) + res.get("own", [])]
        print(json.dumps({k: v for k, v in summary.items() if not k.endswith("profile")}, default=str))
        if args.json:
            with open(args.json, "a", encoding="utf-8") as fh:
                fh.write(json.dumps(res, default=str) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
