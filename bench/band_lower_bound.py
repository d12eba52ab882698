"""A global lower bound on F over every curve in the tolerance band of an ellipse arc (numpy/scipy only).

Question (issue 4, docs/f-target-study.md): can ANY curve (any count, degree, rational or not) within tol of
every data point of ``synthetic/quarter_ellipse_200*.csv`` have F <= 0.5 x splprep's F, where
F = L^3 int (dkappa/ds)^2 ds?  A local optimiser found 0.683 x; this script bounds F from BELOW, globally.

Setting
-------
E(sigma) is the exact ellipse (x, y) = (a cos t, b sin t) by arc length sigma (sigma'(t) = g(t) = |E'(t)|),
T its unit tangent, N = left normal (towards the centre), k > 0 its curvature, ' = d/dsigma.  Every data
point is written P_i = E(sigma_i) + d_i N(sigma_i) (foot sigma_i, signed offset d_i; d_i = 0 up to 1e-10 on
the exact file).  A curve C in the band is written as a normal offset of E over the data span
[sigma_0, sigma_N]:  C(sigma) = E(sigma) + w(sigma) N(sigma).

Assumptions (the class of curves bounded; checked a posteriori on real curves, see the docs):
  (A1) C is such a normal graph over [sigma_0, sigma_N] (the ``interior`` span only over [sigma_1, sigma_{N-1}],
       which every curve whose ends are within tol of P_0 and P_N covers), w in H^3;
  (A2) |w| <= W and |w'| <= delta1 there (defaults W = max|d_i| + 2 tol, delta1 = 0.1: the curve's direction
       within 5.7 deg of the ellipse's). |w| <= W holds whenever |w''| <= 8 (W - tau') / h^2 (h the largest
       data spacing: ~200 here), so no real bound on the curvature is assumed. The older pointwise remainder
       (``--delta2``) also assumes |w''| <= delta2.

Exact curvature of C (derived in the docs, checked by finite differences in the test): with a = 1 - k w,
p = w', q = w'', S = sqrt(a^2 + p^2) = |dC/dsigma|, x = p^2 / a^2,
    kappa_C = (a^2 k + a q + p (k' w + 2 k p)) / S^3 = kappa_lin + R,   kappa_lin = k + w'' + k^2 w,
    R = k^3 w^2 / a + (k / a)(f(x) - 1) + q ((1 + x)^-3/2 / a^2 - 1) + p k' w (1 + x)^-3/2 / a^3,
f(x) = (1 + 2x)(1 + x)^-3/2.  The term in q = w'' is an exact sigma-derivative: with
Acal(sigma, w, p) = p (1 / (a S) - 1) (d Acal / dp = (1 + x)^-3/2 / a^2 - 1),
    R = d/dsigma Acal(sigma, w, w') + T(sigma, w, w'),
    T = k^3 w^2 / a + (k / a)((1 - x)(1 + x)^-1/2 - 1) - p k' w (1 + x)^-1/2 / a^3,
so (`integrated_remainder`), with a in [a_lo, a_hi] = [1 - k W, 1 + k W] and x <= x_max = (delta1 / a_lo)^2,
    |Acal| <= delta1 max(1/a_lo^2 - 1, 1 - 1 / (a_hi sqrt(a_hi^2 + delta1^2))),
    |T| <= k^3 W^2 / a_lo + 1.5 k x_max / a_lo + delta1 |k'| W / a_lo^3      (|(1 - x)(1 + x)^-1/2 - 1| <= 1.5 x).
(`remainder_bound`, pointwise, needs |w''| <= delta2:  |R| <= rho := k^3 W^2 / a_lo + k x_max / (2 a_lo)
 + delta2 max(1/a_lo^2 - 1, 1 - (1 + x_max)^-3/2 / a_hi^2) + delta1 |k'| W / a_lo^3.)

Band at the data: dist(P_i, C) <= tol and (A2) give |w(sigma_i) - d_i| <= tau' = tol sqrt(1 + (delta1/a_0)^2),
a_0 = 1 - k_max (max|d| + tol) (the segment from P_i to its nearest curve point, in the flat metric
(1 - k w)^2 dsigma^2 + dw^2 of the normal coordinates, plus the slope bound).

Dual certificate (the lower bound; no discretisation of w at all)
------------------------------------------------------------------
Let phi be continuous with phi' continuous, phi''' + k^2 phi' = 0 between data points, phi'' jumping by J_i at
sigma_i (J_0 = phi''(sigma_0+), J_N = -phi''(sigma_N-)), phi = phi' = 0 at both ends.  Three integrations by
parts give, for every w in H^3,
    int kappa_lin' phi dsigma = int k' phi dsigma - sum_i J_i w(sigma_i),
and with kappa_C' = kappa_lin' + R' (int R' phi = -int R phi' = int Acal phi'' - int T phi', phi' being
continuous and phi'' piecewise continuous):
    int kappa_C' phi >= A(J) := int k' phi - sum J_i d_i - tau' sum |J_i| - int (max|Acal| |phi''| + max|T| |phi'|)
(pointwise variant: - int rho |phi'| instead of the last term).
Cauchy-Schwarz with ds = S dsigma and the length L >= L_sub >= int (1 - k W) dsigma give, for EVERY curve of
the class in the band,
    F >= (L_E,sub - W int k dsigma)^3  max(A(J), 0)^2 / int phi^2 S_max dsigma,   S_max = sqrt((1+kW)^2 + delta1^2).
Any J meeting the three end conditions is a certificate.  phi is built exactly from J: the 3x3 fundamental
matrix Y of (phi, phi', phi'')' = (phi', phi'', -k^2 phi') is integrated once (DOP853, rtol 1e-13), so
phi = e1^T Y(t) sum_{j <= i} Y(t_j)^-1 e3 J_j in interval i, and the end conditions are sum_j Y(t_j)^-1 e3 J_j = 0.
With W = delta1 = 0 and tau' = tol this is the dual of the LINEARISED problem
    min int (k' + (w'' + k^2 w)')^2 dsigma   s.t.  |w(sigma_i) - d_i| <= tol,
a convex QP whose minimum is global; by weak duality every certificate bounds it from below.

Primal (the matching upper bound and the certificate's J)
---------------------------------------------------------
The QP above on clamped quintic B-splines in t with knots at the data parameters, each interval split
``refine`` times (for k = 0 the continuous optimum is a quintic spline with these knots), solved by
bounded least squares in the variables v_i = w(t_i) (the null space of the collocation matrix eliminated
by QR; `box_lsq`: a primal active-set method started from scipy's trf).  Its value is an UPPER bound of the
continuous linearised minimum; its multipliers (J_i = -d(1/2 int f^2)/dv_i) give the certificate, projected onto the three end conditions.
The curve E + w* N of the primal optimum is a real curve in the band (|w*(t_i) - d_i| <= tol, so its distance
to P_i is <= tol); its TRUE (nonlinear) F and deviations are measured with measure.py's own code (a
measure.Curve whose derivatives are the exact ones of E + w N).  So the band's minimum F is pinned between the
certificate's bound and that curve's F.

End gap (docs: "The end gap"): `slope_lemma` proves |w'| < delta1 for every curve with F <= target except
within `lemma_margin` of the span's ends; `Certificate.bound(..., end=(margin, D, L))` uses |w'| <= D there
instead, and `end_slope_needed` finds the largest D for which the bound still exceeds the target;
`nested_end_gap` repeats the lemma at growing thresholds (shorter windows) for a nested profile.

CLI: ``python bench/band_lower_bound.py [--refine 1,2,4] [--delta1 0.1] [--delta2 D] [--grid]`` prints
tables for both quarter-ellipse files (F in the benchmark's units; target = 0.5 x splprep's F, splprep run
through bench/compare.py's own s search and measured by measure.py).
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.integrate import solve_ivp
from scipy.interpolate import BSpline
from scipy.linalg import null_space, qr
from scipy.optimize import lsq_linear

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import measure  # noqa: E402

CURVES = ["synthetic/quarter_ellipse_200.csv", "synthetic/quarter_ellipse_200_noise1e-4.csv"]


# ----------------------------------------------------------------------------- the ellipse


class Ellipse:
    """(a cos t, b sin t): metric g = |E'|, its square G and their t-derivatives, curvature k and k_t."""

    def __init__(self, a=1.0, b=0.5):
        self.a, self.b = float(a), float(b)

    def point(self, t):
        return np.c_[self.a * np.cos(t), self.b * np.sin(t)]

    def G(self, t):
        """G = g^2 and its first three t-derivatives."""
        a2, b2 = self.a**2, self.b**2
        c = 0.5 * (a2 - b2)
        return (0.5 * (a2 + b2) - c * np.cos(2 * t), 2 * c * np.sin(2 * t), 4 * c * np.cos(2 * t),
                -8 * c * np.sin(2 * t))

    def g(self, t):
        return np.sqrt(self.G(t)[0])

    def k(self, t):
        """Curvature k and dk/dt."""
        G, Gt, _, _ = self.G(t)
        ab = self.a * self.b
        return ab * G**-1.5, -1.5 * ab * Gt * G**-2.5

    def normal_raw(self, t, order):
        """n(t) = (-b cos t, -a sin t) (N = n / g) and its t-derivatives up to `order`."""
        out = []
        for m in range(order + 1):
            c = np.cos(t + m * np.pi / 2)
            s = np.sin(t + m * np.pi / 2)
            out.append(np.c_[-self.b * c, -self.a * s])
        return out

    def point_derivs(self, t, order):
        out = []
        for m in range(order + 1):
            out.append(np.c_[self.a * np.cos(t + m * np.pi / 2), self.b * np.sin(t + m * np.pi / 2)])
        return out

    def h_derivs(self, t):
        """h = 1/g = G^-1/2 and its first three t-derivatives."""
        G, G1, G2, G3 = self.G(t)
        h0 = G**-0.5
        h1 = -0.5 * G**-1.5 * G1
        h2 = 0.75 * G**-2.5 * G1**2 - 0.5 * G**-1.5 * G2
        h3 = -1.875 * G**-3.5 * G1**3 + 2.25 * G**-2.5 * G1 * G2 - 0.5 * G**-1.5 * G3
        return [h0, h1, h2, h3]

    def arc(self, t0, t1, n=64):
        """Arc length and total turning int k dsigma between t0 and t1 (Gauss-Legendre, n nodes x 16 cells)."""
        x, w = leggauss(n)
        edges = np.linspace(t0, t1, 17)
        L = K = 0.0
        for c0, c1 in zip(edges[:-1], edges[1:]):
            h = 0.5 * (c1 - c0)
            tt = c0 + h * (x + 1)
            g = self.g(tt)
            L += h * np.sum(w * g)
            K += h * np.sum(w * g * self.k(tt)[0])
        return L, K

    def feet(self, P):
        """Foot parameters t_i and signed offsets d_i along N (Newton on (E(t) - P).E'(t) = 0)."""
        P = np.asarray(P, dtype=float)
        t = np.arctan2(P[:, 1] / self.b, P[:, 0] / self.a)
        for _ in range(50):
            E0, E1, E2 = self.point_derivs(t, 2)
            r = E0 - P
            f = np.sum(r * E1, axis=1)
            fp = np.sum(E1 * E1, axis=1) + np.sum(r * E2, axis=1)
            step = f / fp
            t = t - step
            if np.max(np.abs(step)) < 1e-16:
                break
        n = self.normal_raw(t, 0)[0] / self.g(t)[:, None]
        d = np.sum((P - self.point(t)) * n, axis=1)
        return t, d


# ----------------------------------------------------------------------------- the offset curve E + w N


def exact_kappa(ell: Ellipse, t, w_t):
    """Exact signed curvature of C = E + w N and the linearised k + w'' + k^2 w (derivatives in sigma), from
    w and its t-derivatives w_t = [w, w_t, w_tt]: returns (kappa_C, kappa_lin, w', w'')."""
    G, Gt, Gtt, _ = ell.G(t)
    g = np.sqrt(G)
    w0, w1, w2 = w_t
    ws = w1 / g
    wss = w2 / G - w1 * Gt / (2 * G**2)
    k = ell.k(t)[0]
    C = offset_derivs(ell, t, [w0, w1, w2], 2)
    d1, d2 = C[1], C[2]
    kap = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.linalg.norm(d1, axis=1) ** 3
    return kap, k + wss + k**2 * w0, ws, wss


def offset_derivs(ell: Ellipse, t, w_derivs, order):
    """C = E + m n with m = w h (h = 1/g): C and its t-derivatives up to `order` (Leibniz)."""
    from math import comb

    h = ell.h_derivs(t)
    m = []
    for j in range(order + 1):
        m.append(sum(comb(j, i) * w_derivs[i] * h[j - i] for i in range(j + 1)))
    n = ell.normal_raw(t, order)
    E = ell.point_derivs(t, order)
    out = []
    for j in range(order + 1):
        out.append(E[j] + sum(comb(j, i) * m[i][:, None] * n[j - i] for i in range(j + 1)))
    return out


def remainder_bound(k, ks, W, delta1, delta2):
    """rho >= |kappa_C - kappa_lin| for |w| <= W, |w'| <= delta1, |w''| <= delta2 (k, ks = dk/dsigma at the
    point; module doc)."""
    a_lo, a_hi = 1 - k * W, 1 + k * W
    x = (delta1 / a_lo) ** 2
    if np.any(a_lo <= 0) or np.any(x > 0.5):
        raise ValueError("the class (W, delta1) is too wide for the remainder bound")
    return (k**3 * W**2 / a_lo + 0.5 * k * x / a_lo
            + delta2 * np.maximum(1 / a_lo**2 - 1, 1 - (1 + x) ** -1.5 / a_hi**2)
            + delta1 * np.abs(ks) * W / a_lo**3)


def integrated_remainder(ell_k, ks, W, delta1, w=None, p=None):
    """The remainder written as R = d/dsigma Acal(sigma, w, w') + T(sigma, w, w') (module doc), which needs no
    bound on w''. With arrays w, p: returns (Acal, T) pointwise; else (max |Acal|, max |T|) over the class
    |w| <= W, |w'| <= delta1."""
    k = ell_k
    if w is not None:
        a = 1 - k * w
        S = np.sqrt(a**2 + p**2)
        x = (p / a) ** 2
        Acal = p * (1 / (a * S) - 1)
        T = k**3 * w**2 / a + (k / a) * ((1 - x) / np.sqrt(1 + x) - 1) - p * ks * w / (a**3 * np.sqrt(1 + x))
        return Acal, T
    a_lo, a_hi = 1 - k * W, 1 + k * W
    x = (delta1 / a_lo) ** 2
    if np.any(a_lo <= 0) or np.any(x > 0.5):
        raise ValueError("the class (W, delta1) is too wide for the remainder bound")
    Amax = delta1 * np.maximum(1 / a_lo**2 - 1, 1 - 1 / (a_hi * np.sqrt(a_hi**2 + delta1**2)))
    Tmax = k**3 * W**2 / a_lo + 1.5 * k * x / a_lo + delta1 * np.abs(ks) * W / a_lo**3
    return Amax, Tmax


class OffsetCurve(measure.Curve):
    """E + w N, w a scipy BSpline in t, presented to measure.py's fairness() / deviations() with EXACT
    derivatives (spans = w's distinct knot spans)."""

    def __init__(self, ell: Ellipse, w: BSpline):
        self.ell = ell
        self.w = w
        self.k = w.k
        self.t = w.t
        self.n = len(w.t) - w.k - 1
        self.dim = 2
        self.n_independent = self.n
        self.rational = True
        self.lo = w.t[w.k]
        self.hi = w.t[self.n]
        self.breaks = np.unique(w.t[w.k : self.n + 1])

    def derivs(self, u, order):
        u = np.clip(np.asarray(u, dtype=float), self.lo, self.hi)
        wd = [self.w(u, nu) for nu in range(order + 1)]
        return offset_derivs(self.ell, u, wd, order)


# ----------------------------------------------------------------------------- problem data


class Band:
    """The data as feet on the ellipse: t_i, d_i, tol; `interior` drops the two end points."""

    def __init__(self, P, ell: Ellipse, tol=None, interior=False):
        self.ell = ell
        self.P = np.asarray(P, dtype=float)
        self.tol = measure.tolerance(self.P) if tol is None else float(tol)
        t, d = ell.feet(self.P)
        if np.any(np.diff(t) <= 0):
            raise ValueError("data feet are not increasing along the ellipse")
        if interior:
            t, d = t[1:-1], d[1:-1]
        self.ti, self.di = t, d
        self.L_sub, self.K_sub = ell.arc(t[0], t[-1])


def quintic_basis(ti, refine):
    k = 5
    fine = np.concatenate([np.linspace(a, b, refine + 1)[:-1] for a, b in zip(ti[:-1], ti[1:])] + [ti[-1:]])
    knots = np.r_[[fine[0]] * k, fine, [fine[-1]] * k]
    return k, knots, fine


def span_gauss(breaks, n):
    x, w = leggauss(n)
    a, b = breaks[:-1, None], breaks[1:, None]
    h = 0.5 * (b - a)
    return (a + h * (x + 1)).ravel(), (h * w).ravel()


def design(ell: Ellipse, k, knots, tq):
    """Rows: v_sigma(w) = (w'' + k^2 w)' (sigma-derivative) at tq for every basis function, and k_sigma."""
    n = len(knots) - k - 1
    B = [BSpline.design_matrix(tq, knots, k).toarray()]
    for nu in (1, 2, 3):
        B.append(BSpline(knots, np.eye(n), k)(tq, nu))
    G, G1, G2, _ = ell.G(tq)
    g = np.sqrt(G)
    kk, kt = ell.k(tq)
    alpha = 1 / G
    beta = -G1 / (2 * G**2)
    alpha_t = -G1 / G**2
    beta_t = -G2 / (2 * G**2) + G1**2 / G**3
    vt = (alpha[:, None] * B[3] + (alpha_t + beta)[:, None] * B[2] + (beta_t + kk**2)[:, None] * B[1]
          + (2 * kk * kt)[:, None] * B[0])
    return vt / g[:, None], kt / g, g


def box_lsq(R, r, lo, hi, max_iter=2000):
    """min ||R v - r|| s.t. lo <= v <= hi by a primal active-set method (feasible iterates from the box's
    trf start; each step a least-squares solve on the free variables, so R's null space, the operator's three
    null directions, needs no special care). Few constraints are active at the optimum here (6 of 198 on the
    quarter ellipse), so from trf's active set it takes a few solves (from the box's centre ~800), where BVLS
    takes ~500 and trf alone did not converge in 5000 iterations on the interior span.
    Returns (v, description)."""
    # start: a few hundred trf steps (inexact on this ill-conditioned R), its near-active bounds fixed
    v = lsq_linear(R, r, bounds=(lo, hi), method="trf", lsq_solver="exact", tol=1e-12, max_iter=200).x
    v = np.clip(v, lo, hi)
    eps = 1e-6 * (hi - lo)
    fix = np.where(v >= hi - eps, 1, np.where(v <= lo + eps, -1, 0))  # -1 at lo, +1 at hi, 0 free
    v = np.where(fix == 1, hi, np.where(fix == -1, lo, v))
    for it in range(max_iter):
        free = fix == 0
        target = v.copy()
        if free.any():
            rhs = r - R[:, ~free] @ v[~free]
            target[free] = np.linalg.lstsq(R[:, free], rhs, rcond=None)[0]
        p = target - v
        with np.errstate(divide="ignore", invalid="ignore"):
            room = np.where(p > 0, (hi - v) / p, np.where(p < 0, (lo - v) / p, np.inf))
        room[~free] = np.inf
        j = int(np.argmin(room))
        if room[j] < 1.0:
            v = v + room[j] * p
            v[j] = hi[j] if p[j] > 0 else lo[j]
            fix[j] = 1 if p[j] > 0 else -1
            continue
        v = target
        mu = -(R.T @ (R @ v - r))  # > 0 pushes v up
        wrong = np.where(fix == 1, -mu, np.where(fix == -1, mu, 0.0))
        j = int(np.argmax(wrong))
        if wrong[j] <= 1e-12 * (float(np.max(np.abs(mu))) + 1e-300):
            return v, f"active set: {it + 1} solves, {int(np.sum(fix != 0))} active"
        fix[j] = 0
    raise RuntimeError("active-set QP did not converge")


def solve_primal(band: Band, refine=1, tau=None, gauss=6):
    """The linearised QP on quintic B-splines: returns dict(value = int (kappa_lin')^2 dsigma, w BSpline,
    J multipliers (certificate direction), v = w(t_i))."""
    ell = band.ell
    tau = band.tol if tau is None else tau
    k, knots, fine = quintic_basis(band.ti, refine)
    tq, wq = span_gauss(fine, gauss)
    Vs, ks, g = design(ell, k, knots, tq)
    sw = np.sqrt(wq * g)
    M = Vs * sw[:, None]
    rhs = -ks * sw
    A = BSpline.design_matrix(band.ti, knots, k).toarray()
    Ap = np.linalg.pinv(A)
    Zn = null_space(A)
    Mv, My = M @ Ap, M @ Zn
    Q, _ = qr(My, mode="economic")
    Rv = Mv - Q @ (Q.T @ Mv)
    rv = rhs - Q @ (Q.T @ rhs)
    Q2, R2 = qr(np.column_stack([Rv, rv]), mode="economic")
    nv = A.shape[0]
    R, r = R2[:nv, :nv], R2[:nv, nv]
    lo, hi = band.di - tau, band.di + tau
    v, status = box_lsq(R, r, lo, hi)
    y = np.linalg.lstsq(My, rhs - Mv @ v, rcond=None)[0]
    c = Ap @ v + Zn @ y
    f = M @ c - rhs
    grad = R.T @ (R @ v - r)
    return {"value": float(f @ f), "w": BSpline(knots, c, k), "J": -grad, "v": v, "status": status}


# ----------------------------------------------------------------------------- the dual certificate


class Certificate:
    """phi from jumps J (exact ODE propagation) and the bound it certifies."""

    def __init__(self, band: Band, gauss=10):
        ell = band.ell
        self.band = band
        ti = band.ti
        tq, wq = span_gauss(ti, gauss)
        self.tq, self.wq = tq, wq
        self.iq = np.repeat(np.arange(len(ti) - 1), gauss)

        def rhs(t, y):
            Y = y.reshape(3, 3)
            kk = ell.k(t)[0]
            A = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, -kk * kk, 0.0]])
            return (ell.g(t) * (A @ Y)).ravel()

        ts = np.unique(np.r_[ti, tq])
        sol = solve_ivp(rhs, (ti[0], ti[-1]), np.eye(3).ravel(), method="DOP853", t_eval=ts,
                        rtol=1e-13, atol=1e-15)
        Y = sol.y.T.reshape(-1, 3, 3)
        pos = {t: i for i, t in enumerate(ts)}
        Yi = Y[[pos[t] for t in ti]]
        Yq = Y[[pos[t] for t in tq]]
        self.z = np.linalg.solve(Yi, np.broadcast_to(np.array([0.0, 0.0, 1.0]), (len(ti), 3))[..., None])[..., 0]
        # phi, phi' at the nodes: rows of e1^T Y(tq) z_j (j <= interval index), e2^T likewise
        n = len(ti)
        mask = (np.arange(n)[None, :] <= self.iq[:, None]).astype(float)
        self.B0 = (Yq[:, 0, :] @ self.z.T) * mask
        self.B1 = (Yq[:, 1, :] @ self.z.T) * mask
        self.B2 = (Yq[:, 2, :] @ self.z.T) * mask
        G = ell.G(tq)[0]
        self.g = np.sqrt(G)
        self.k, self.kt = ell.k(tq)

    @staticmethod
    def arc_integral(band: Band, n=64):
        """int (dk/dsigma)^2 dsigma of the exact ellipse over the span (w = 0)."""
        x, wg = leggauss(n)
        edges = np.linspace(band.ti[0], band.ti[-1], 33)
        tot = 0.0
        for c0, c1 in zip(edges[:-1], edges[1:]):
            h = 0.5 * (c1 - c0)
            tt = c0 + h * (x + 1)
            kt = band.ell.k(tt)[1]
            tot += h * np.sum(wg * kt**2 / band.ell.g(tt))
        return tot

    def close(self, J):
        """Least change of J meeting the end conditions sum_j z_j J_j = 0."""
        Z = self.z.T
        return J - Z.T @ np.linalg.solve(Z @ Z.T, Z @ J)

    def sigma_nodes(self):
        """Arc length from the span's start at the data feet and at the quadrature nodes (cached)."""
        if not hasattr(self, "_sig"):
            ell, ti = self.band.ell, self.band.ti
            si = np.r_[0.0, np.cumsum([ell.arc(a, b)[0] for a, b in zip(ti[:-1], ti[1:])])]
            sq = np.array([si[i] + ell.arc(ti[i], t, 16)[0] for i, t in zip(self.iq, self.tq)])
            self._sig = (si, sq)
        return self._sig

    def bound(self, J, W=0.0, delta1=0.0, delta2=None, end=None):
        """(F lower bound, details) certified by J (closed first) for the class |w| <= W, |w'| <= delta1; with
        delta2 (|w''| <= delta2) the pointwise remainder bound rho is used instead of the integrated one.
        end = (margin, delta1_end, L): within arc length `margin` of either end of the span the class is
        |w'| <= delta1_end instead (the slope lemma's end gap), and L replaces the length factor's
        L_sub - W K_sub (e.g. the interior span's, which every curve of the class covers). margin and
        delta1_end may be arrays (margins decreasing, slopes increasing: nested windows, the innermost counts)."""
        band = self.band
        J = self.close(np.asarray(J, dtype=float))
        phi = self.B0 @ J
        dphi = self.B1 @ J
        ddphi = self.B2 @ J
        wq, g, k, kt = self.wq, self.g, self.k, self.kt
        ks = kt / g
        kmax = float(np.max(self.band.ell.k(np.linspace(band.ti[0], band.ti[-1], 2001))[0]))
        a0 = 1 - kmax * (np.max(np.abs(band.di)) + band.tol)
        d1_data = delta1
        if end is not None:
            margins, slopes = np.atleast_1d(end[0]), np.atleast_1d(end[1])
            si, sq = self.sigma_nodes()

            def profile(sg):
                r = np.minimum(sg, sg[-1] - sg)  # distance to the nearer end
                out = np.full_like(sg, float(delta1))
                for m, d in zip(margins, slopes):  # margins decreasing, slopes increasing
                    out = np.where(r < m, d, out)
                return out

            d1_data, delta1 = profile(si), profile(sq)
        tau = band.tol * np.sqrt(1 + (d1_data / a0) ** 2)
        if delta2 is None:
            Amax, Tmax = integrated_remainder(k, ks, W, delta1)
        else:
            rho = remainder_bound(k, ks, W, delta1, delta2)
        Smax = np.sqrt((1 + k * W) ** 2 + delta1**2)
        best = None
        for sgn in (1.0, -1.0):
            Js, ph, dph = sgn * J, sgn * phi, sgn * dphi
            lin = float(np.sum(wq * kt * ph))  # int k_sigma phi dsigma = int k_t phi dt
            data = float(Js @ band.di)
            l1 = float(np.sum(tau * np.abs(Js)))
            if delta2 is None:
                rem = float(np.sum(wq * g * (Amax * np.abs(ddphi) + Tmax * np.abs(dph))))
            else:
                rem = float(np.sum(wq * g * rho * np.abs(dph)))
            A = lin - data - l1 - rem
            den = float(np.sum(wq * g * ph**2 * Smax))
            L = band.L_sub - W * band.K_sub if end is None else end[2]
            val = L**3 * A**2 / den if A > 0 and den > 0 else 0.0
            if best is None or val > best[0]:
                best = (val, {"lin": lin, "data": data, "tau": tau, "l1": l1, "rem": rem, "den": den, "L": L})
        return best


# ----------------------------------------------------------------------------- the study


def target_of(P, tol):
    """0.5 x splprep's F: bench/compare.py's own s search, measured by measure.py."""
    import compare

    curve, _, _ = compare.splprep_search(np.asarray(P, dtype=float), tol)
    k, t, ctrl = curve
    m = measure.measure(k, t, ctrl, None, P)
    return m.F, m.n_ctrl


def verify(band: Band, w: BSpline, P):
    """TRUE F (measure.py's fairness on the exact E + w N) and max orthogonal deviation / tol."""
    c = OffsetCurve(band.ell, w)
    F, L = measure.fairness(c, True)
    dev = measure.deviations(c, P)
    return F, L, float(np.max(dev)) / band.tol


def class_stats(band: Band, w: BSpline, n=20001):
    """max |w|, |w'|, |w''| (sigma-derivatives) and max |kappa_C - kappa_lin| of E + w N over the span."""
    tt = np.linspace(band.ti[0], band.ti[-1], n)
    kap, klin, ws, wss = exact_kappa(band.ell, tt, [w(tt), w(tt, 1), w(tt, 2)])
    return {"W": float(np.max(np.abs(w(tt)))), "d1": float(np.max(np.abs(ws))), "d2": float(np.max(np.abs(wss))),
            "R": float(np.max(np.abs(kap - klin)))}


def slope_lemma(band: Band, W, delta1, F_target):
    """A priori check of the slope class away from the span's ends (docs: "The slope bound").

    Let psi0 > 0 be a local maximum of the angle between C's and E's tangents (tan psi = w' / a), |w'| >= delta1
    there, and [sa, sb] the component of {psi >= psi0 / 2} around it, assumed inside the span (its maximum
    psi_m >= psi0 has a half-level component inside it, so every psi >= psi0 is checked: the minimum counts).
    w increases there by <= 2 W, so its length in C's arc length is l <= 2 W / sin(psi0 / 2). C turns by
    +psi0/2 + int k dsigma on the left part and -psi0/2 + int k dsigma on the right, so C's mean curvatures on
    the two parts differ by >= jump = 2 psi0 / l - (variation of k / S over the window), and Cauchy-Schwarz
    gives int kappa'^2 ds >= 3 jump^2 / l (the variation of k / S capped at k_max / a_lo). F <= F_target
    needs int kappa'^2 ds <= F_target / L_min^3 with
    L_min = |P_last - P_first| - 2 tol. Returns (3 jump^2 / l, F_target / L_min^3, l): the slope delta1 is
    impossible inside the span (farther than l / a_lo from its ends) when the first exceeds the second."""
    ell = band.ell
    tt = np.linspace(band.ti[0], band.ti[-1], 20001)
    k, kt = ell.k(tt)
    kmax = float(np.max(k))
    ks_max = float(np.max(np.abs(kt / ell.g(tt))))
    a_lo, a_hi = 1 - kmax * W, 1 + kmax * W
    # every angle from atan(delta1 / a_hi) up to ~pi/2 (a local maximum psi1 >= psi0 leads to the maximum
    # psi_m >= psi1 of its component, whose own half-level component lies inside it): the worst case counts
    psi = np.arctan(delta1 / a_hi) + (np.pi / 2 - 1e-3 - np.arctan(delta1 / a_hi)) * np.linspace(0, 1, 2001) ** 3
    ell_ss = 2 * W / np.sin(psi / 2)
    var = np.minimum(ks_max * ell_ss / a_lo + kmax * (1 / (np.cos(psi) * a_lo) - 1 / a_hi), kmax / a_lo)
    jumps = 2 * psi / ell_ss - var
    energy = 3 * np.maximum(jumps, 0.0) ** 2 / ell_ss
    i = int(np.argmin(energy))
    ell_s, jump = float(ell_ss[0]), float(jumps[i])
    P = band.ell.point(band.ti[[0, -1]]) + band.di[[0, -1], None] * (
        ell.normal_raw(band.ti[[0, -1]], 0)[0] / ell.g(band.ti[[0, -1]])[:, None])
    L_min = float(np.linalg.norm(P[1] - P[0])) - 2 * band.tol
    return float(energy[i]), F_target / L_min**3, ell_s


def lemma_margin(band: Band, W, delta1):
    """Arc length m (in sigma) from the span's ends beyond which the slope lemma proves |w'| < delta1: the
    component K of {psi >= psi0/2} (psi0 = atan(delta1 / a_hi)) through a point with |w'| >= delta1 lies inside
    the span when that point is farther than K's sigma-length from the ends. Two bounds on it, the smaller
    counts: (i) w rises by <= 2 W on K, so its length is <= 2 W / (a_lo sin(psi0/2)); (ii) the data: each P_i
    has a curve point within tol, a "witness" at sigma'_i with |sigma'_i - sigma_i| <= tol / a_1 and
    |w(sigma'_i) - d_i| <= tol (flat metric (1 - k w)^2 dsigma^2 + dw^2, a_1 = 1 - k_max (max|d| + tol)); w
    rises by <= max d - min d + 2 tol between the first and last witness in K, and K extends past them by less
    than one witness gap (<= h_max + 2 tol / a_1) on each side. Returns (m, bound (i), bound (ii))."""
    ell = band.ell
    kmax = float(np.max(ell.k(np.linspace(band.ti[0], band.ti[-1], 2001))[0]))
    a_lo, a_hi = 1 - kmax * W, 1 + kmax * W
    a1 = 1 - kmax * (float(np.max(np.abs(band.di))) + band.tol)
    s = np.sin(0.5 * np.arctan(delta1 / a_hi))
    h = max(ell.arc(a, b)[0] for a, b in zip(band.ti[:-1], band.ti[1:]))
    m1 = 2 * W / (a_lo * s)
    m2 = (float(np.ptp(band.di)) + 2 * band.tol) / (a_lo * s) + 2 * (h + 2 * band.tol / a1)
    return min(m1, m2), m1, m2


def end_slope_needed(cert: Certificate, J, W, delta1, margin, target, hi=0.6, iters=30):
    """The smallest end slope bound D (|w'| <= delta1 on the span but <= D within arc length `margin` of its
    ends) at which the certified bound drops to `target` (bisection; the bound decreases with D). So every
    curve of the class |w| <= W, normal graph, with F <= target has |w'| > D somewhere in the end regions."""
    L = cert.band.L_sub - W * cert.band.K_sub
    lo = delta1
    if cert.bound(J, W=W, delta1=delta1, end=(margin, lo, L))[0] <= target:
        return lo
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        if cert.bound(J, W=W, delta1=delta1, end=(margin, mid, L))[0] > target:
            lo = mid
        else:
            hi = mid
    return lo


def nested_end_gap(cert: Certificate, J, W, delta1, target,
                   levels=(0.125, 0.15, 0.175, 0.2, 0.225, 0.25, 0.275, 0.3)):
    """The slope lemma at growing thresholds d_0 = delta1 < d_1 < ...: |w'| < d_j is proved farther than
    lemma_margin(d_j) from the ends (each d_j checked against the target's energy). With that nested profile
    (|w'| <= d_j between the windows of d_j and d_(j+1)) and |w'| <= D in the innermost window, the largest D
    keeping the certified bound above the target is found by bisection. Levels are added while D stays above
    the last one, so the statement is consistent: every curve of the class with F <= target has |w'| > D
    within margins[-1] of an end. Returns (margins, thresholds, D) (D None: not even d_0 holds)."""
    band = cert.band
    L = band.L_sub - W * band.K_sub

    def largest_D(ms, ds):
        def val(D):
            return cert.bound(J, W=W, delta1=delta1, end=(np.array(ms), np.array(ds[1:] + [D]), L))[0]

        lo, hi = ds[-1], 0.6
        if val(lo) <= target:
            return None
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if val(mid) > target else (lo, mid)
        return lo

    best = None
    ds, ms = [], []
    for d in (delta1,) + tuple(levels):
        e, ebar, _ = slope_lemma(band, W, d, target)
        if e <= ebar:
            break
        D = largest_D(ms + [lemma_margin(band, W, d)[0]], ds + [d])
        if D is None:
            break
        ds.append(d)
        ms.append(lemma_margin(band, W, d)[0])
        best = (list(ms), list(ds), D)
    return best if best is not None else ([], [], None)


def certified(P, ell, delta1, delta2, W_tols, refine=1, spans=("full", "interior")):
    """delta2 None: the integrated remainder (no bound on w'' needed); else the pointwise one."""
    """Certified bounds for the class (A2): over the full data span (times the end-extension factor, see the
    docs) and over the interior span (points 1..N-1, no end assumption). Returns a dict."""
    out = {}
    for name in spans:
        interior = name == "interior"
        band = Band(P, ell, interior=interior)
        W = float(np.max(np.abs(band.di))) + W_tols * band.tol
        cert = Certificate(band)
        pr = solve_primal(band, refine=refine)
        val, det = cert.bound(pr["J"], W=W, delta1=delta1, delta2=delta2)
        if not interior:
            # a curve ending short of the end normals, extended by circular arcs (kappa' = 0) of length <= e
            kmax = float(np.max(ell.k(np.linspace(band.ti[0], band.ti[-1], 2001))[0]))
            a_lo = 1 - kmax * W
            e = band.tol * np.sqrt((1 + kmax * W) ** 2 + delta1**2) / a_lo
            Lmin = det["L"] - 2 * band.tol / a_lo
            fac = (Lmin / (Lmin + 2 * e)) ** 3
            val *= fac
            det["extension_factor"] = fac
        out[name] = (val, det, W, band, cert, pr)
    return out


def study(path, refines=(1, 2, 4), delta1=0.1, delta2=None, W_tols=2.0, splprep=True, grid=None, out=print):
    """The CLI's table for one data file; returns a dict of the numbers."""
    P = measure.read_points(path)
    ell = Ellipse()
    band = Band(P, ell)
    cert = Certificate(band)
    res = {"name": os.path.basename(path), "tol": band.tol}
    if splprep:
        Fs, ns = target_of(P, band.tol)
        res.update(splprep_F=Fs, splprep_n=ns, target=0.5 * Fs)
        out(f"{res['name']}: tol {band.tol:.6g}, splprep F {Fs:.6g} ({ns} ctrl pts), target 0.5x = {0.5 * Fs:.6g}")
    out(f"  full span: {len(band.ti)} points, t in [{band.ti[0]:.6f}, {band.ti[-1]:.6f}], L_E {band.L_sub:.6f}, "
        f"F of the exact arc {band.L_sub**3 * Certificate.arc_integral(band):.4f}")
    out("| refine | quintic coeffs | primal (linearised, upper) | certificate (linearised, lower) | rel. gap | "
        "true F of E + w* N | its dev/tol | max abs w/tol, w', w'' | max abs kappa - kappa_lin |")
    out("|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    rows = []
    for r in refines:
        pr = solve_primal(band, refine=r)
        up = band.L_sub**3 * pr["value"]
        lo, _ = cert.bound(pr["J"])
        Ft, _, dev = verify(band, pr["w"], P)
        st = class_stats(band, pr["w"])
        rows.append({"refine": r, "upper": up, "lower": lo, "F_true": Ft, "dev": dev, **st})
        out(f"| {r} | {len(pr['w'].c)} | {up:.6f} | {lo:.6f} | {(up - lo) / up:.1e} | {Ft:.5f} | {dev:.7f} | "
            f"{st['W'] / band.tol:.4f}, {st['d1']:.4f}, {st['d2']:.3f} | {st['R']:.4f} |")
    res["rows"] = rows
    cb = certified(P, ell, delta1, delta2, W_tols)
    for name in ("full", "interior"):
        val, det, W, bnd, _, _ = cb[name]
        res[name] = val
        extra = f", end-extension factor {det['extension_factor']:.5f}" if "extension_factor" in det else ""
        ratio = f" = {val / res['splprep_F']:.4f} x splprep's F" if splprep else ""
        cls = f"|w''| <= {delta2}" if delta2 is not None else "no bound on w'' (integrated remainder)"
        if name == "interior":
            hmax = float(np.max(np.diff([ell.arc(bnd.ti[0], t)[0] for t in bnd.ti])))
            room = W - float(np.max(np.abs(bnd.di))) - det["tau"]
            out(f"  (|w| <= {W:.3g} holds for every curve with |w''| <= 8 (W - max|d| - tau') / h^2 = "
                f"{8 * room / hmax**2:.0f} between the data, h = {hmax:.5f} the largest spacing)")
        out(f"  certified, {name} span, class |w| <= {W:.3g}, |w'| <= {delta1}, {cls}: "
            f"F >= {val:.4f}{ratio}{extra}")
    if splprep:
        bi, Wi = cb["interior"][3], cb["interior"][2]
        for d1 in (delta1, 0.137):
            e, ebar, l = slope_lemma(bi, Wi, d1, res["target"])
            out(f"  slope lemma: |w'| >= {d1:g} inside the span (window {l:.4f}) needs int kappa'^2 ds >= {e:.1f}; "
                f"F <= target allows {ebar:.2f}: {'impossible' if e > ebar else 'not excluded'}")
        _, _, Wi, bi, ci, pi = cb["interior"]
        e, ebar, l = slope_lemma(bi, Wi, delta1, res["target"])
        if e > ebar:
            margin, m1, m2 = lemma_margin(bi, Wi, delta1)
            D = end_slope_needed(ci, pi["J"], Wi, delta1, margin, res["target"])
            D1 = end_slope_needed(ci, pi["J"], Wi, delta1, m1, res["target"])
            res["end_margin"], res["end_slope"] = margin, D
            out(f"  end gap: |w'| <= {delta1:g} is proved except within {margin:.4f} (arc length; {m1:.4f} from "
                f"|w| <= W alone) of the interior span's ends; the bound stays above the target for end slopes "
                f"up to {D:.4f} there ({D1:.4f} with the wider gap)")
            ms, ds, Dn = nested_end_gap(ci, pi["J"], Wi, delta1, res["target"])
            res["nested_margin"], res["nested_slope"] = ms[-1], Dn
            out(f"  nested end gap (lemma at |w'| thresholds {', '.join(f'{d:g}' for d in ds)}: windows "
                f"{', '.join(f'{m:.4f}' for m in ms)}): F <= target needs |w'| > {Dn:.4f} within {ms[-1]:.4f} "
                f"of an end")
    if grid:
        d1s, d2s = grid
        _, _, Wi, _, ci, pi = cb["interior"]
        out("  certified bound (interior span) by class: rows |w'| <= delta1; columns: integrated remainder (no "
            "bound on w''), pointwise remainder with |w''| <= delta2")
        out("| delta1 | integrated | " + " | ".join(f"delta2 = {d:g}" for d in d2s) + " |")
        out("|---:|---:|" + "---:|" * len(d2s))
        for d1 in d1s:
            out(f"| {d1:g} | {ci.bound(pi['J'], W=Wi, delta1=d1)[0]:.3f} | "
                + " | ".join(f"{ci.bound(pi['J'], W=Wi, delta1=d1, delta2=d2)[0]:.3f}" for d2 in d2s) + " |")
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=None, help="data directory (default: bench/compare.py's ../shared/data)")
    ap.add_argument("--refine", default="1,2,4")
    ap.add_argument("--delta1", type=float, default=0.1, help="class bound on |w'| (slope against the ellipse)")
    ap.add_argument("--delta2", type=float, default=None,
                    help="class bound on |w''| (pointwise remainder); default: none (integrated remainder)")
    ap.add_argument("--W-tols", type=float, default=2.0, help="class bound |w| <= max|d_i| + this x tol")
    ap.add_argument("--grid", action="store_true", help="also print the bound over a (delta1, delta2) grid")
    a = ap.parse_args(argv)
    refines = [int(x) for x in a.refine.split(",")]
    if a.data is None:
        import compare

        a.data = compare.default_data_dir()
    grid = ((0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3), (1.0, 2.0, 4.0)) if a.grid else None
    for c in CURVES:
        res = study(os.path.join(a.data, c), refines, a.delta1, a.delta2, a.W_tols, grid=grid)
        lo = min(res["full"], res["interior"])
        verdict = "EXCLUDED (bound > target)" if lo > res["target"] else "not excluded"
        print(f"  => every curve of the class in the band has F >= {lo:.4f} = {lo / res['splprep_F']:.4f} x "
              f"splprep's F; target {res['target']:.4f}: {verdict}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
