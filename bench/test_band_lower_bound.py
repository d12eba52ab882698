"""Tests of the global lower bound on F in the tolerance band (bench/band_lower_bound.py) against
independent truths: finite differences, the duality identity, measure.py, scipy's elliptic integral and
bench/compare.py's own splprep run.

Run with `python -m pytest bench/test_band_lower_bound.py` or `python bench/test_band_lower_bound.py`.
"""

import os
import sys

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline
from scipy.special import ellipe

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import band_lower_bound as blb  # noqa: E402
import compare  # noqa: E402
import measure  # noqa: E402

ELL = blb.Ellipse(1.0, 0.5)
# the repository's own copy (byte-identical to ../shared/data/synthetic/quarter_ellipse_200.csv, see
# examples/data/PROVENANCE.md): CI clones the repository without ../shared/data
QUARTER = os.path.join(compare.REPO, "examples", "data", "quarter_ellipse_200.csv")


def quarter_points(n=200):
    t = np.linspace(0, np.pi / 2, n)
    return ELL.point(t)


def test_offset_curve_derivatives_and_curvature_match_finite_differences():
    # C = E + w N with w = 1e-2 sin(3t) + 5e-3 t^2: the N used here is built independently (rotated,
    # normalised E'); C's t-derivatives by central differences must match offset_derivs, and the curvature
    # from them must match exact_kappa
    def w_of(t):
        return 1e-2 * np.sin(3 * t) + 5e-3 * t**2

    def C_of(t):
        d = np.c_[-np.sin(t), 0.5 * np.cos(t)]
        n = np.c_[-d[:, 1], d[:, 0]] / np.linalg.norm(d, axis=1)[:, None]
        return ELL.point(t) + w_of(t)[:, None] * n

    t = np.linspace(0.1, 1.4, 7)
    wd = [w_of(t), 3e-2 * np.cos(3 * t) + 1e-2 * t, -9e-2 * np.sin(3 * t) + 1e-2, -0.27 * np.cos(3 * t)]
    D = blb.offset_derivs(ELL, t, wd, 3)
    assert np.max(np.abs(D[0] - C_of(t))) < 1e-15
    h = 1e-3
    fd1 = (C_of(t + h) - C_of(t - h)) / (2 * h)
    fd2 = (C_of(t + h) - 2 * C_of(t) + C_of(t - h)) / h**2
    fd3 = (C_of(t + 2 * h) - 2 * C_of(t + h) + 2 * C_of(t - h) - C_of(t - 2 * h)) / (2 * h**3)
    assert np.max(np.abs(D[1] - fd1)) < 1e-6
    assert np.max(np.abs(D[2] - fd2)) < 1e-6
    assert np.max(np.abs(D[3] - fd3)) < 1e-5
    kap, _, _, _ = blb.exact_kappa(ELL, t, wd[:3])
    kap_fd = (fd1[:, 0] * fd2[:, 1] - fd1[:, 1] * fd2[:, 0]) / np.linalg.norm(fd1, axis=1) ** 3
    assert np.max(np.abs(kap - kap_fd)) < 1e-5 * np.max(np.abs(kap))


def test_linearised_curvature_error_is_second_order_and_within_the_remainder_bound():
    # kappa_C - (k + w'' + k^2 w) must shrink 4x when w halves (second order), and stay below rho
    t = np.linspace(0.0, np.pi / 2, 2001)
    errs = []
    for amp in (4e-3, 2e-3, 1e-3):
        wd = [amp * np.cos(5 * t), -5 * amp * np.sin(5 * t), -25 * amp * np.cos(5 * t)]
        kap, klin, ws, wss = blb.exact_kappa(ELL, t, wd)
        err = np.abs(kap - klin)
        errs.append(np.max(err))
        k, kt = ELL.k(t)
        rho = blb.remainder_bound(k, kt / ELL.g(t), np.max(np.abs(wd[0])), np.max(np.abs(ws)), np.max(np.abs(wss)))
        assert np.all(err <= rho)
    assert 3.6 < errs[0] / errs[1] < 4.4 and 3.6 < errs[1] / errs[2] < 4.4


def test_remainder_bound_holds_over_the_whole_class_and_is_not_loose():
    # random points of the class |w| <= W, |w'| <= delta1, |w''| <= delta2 (as sigma-jets converted to t-jets);
    # the exact curvature comes from the geometric offset_derivs, not from the closed-form remainder
    rng = np.random.default_rng(3)
    W, d1, d2 = 2e-3, 0.1, 2.0
    t = rng.uniform(0, np.pi / 2, 4000)
    w = rng.uniform(-W, W, t.size)
    p = rng.choice([-d1, d1], t.size) * rng.uniform(0.9, 1, t.size)
    q = rng.choice([-d2, d2], t.size) * rng.uniform(0.9, 1, t.size)
    G, Gt, _, _ = ELL.G(t)
    g = np.sqrt(G)
    w_t = p * g
    w_tt = (q + p * Gt / (2 * G**2) * g) * G  # inverse of w'' = w_tt / G - w_t G_t / (2 G^2)
    D = blb.offset_derivs(ELL, t, [w, w_t, w_tt], 2)
    kap = (D[1][:, 0] * D[2][:, 1] - D[1][:, 1] * D[2][:, 0]) / np.linalg.norm(D[1], axis=1) ** 3
    k, kt = ELL.k(t)
    err = np.abs(kap - (k + q + k**2 * w))
    rho = blb.remainder_bound(k, kt / g, W, d1, d2)
    assert np.all(err <= rho)
    assert np.max(err / rho) > 0.5


def test_remainder_is_an_exact_derivative_plus_T_within_the_integrated_bounds():
    # R = kappa_C - kappa_lin = d/dsigma Acal(sigma, w, w') + T(sigma, w, w'): checked by differentiating Acal
    # numerically along the curve, for an offset with a large w'' (curvature change up to 6) that the
    # integrated bounds do not need to know about; |Acal| and |T| stay below their class bounds
    t = np.linspace(0.0, np.pi / 2, 40001)
    amp = 1.5e-3
    wd = [amp * np.cos(60 * t), -60 * amp * np.sin(60 * t), -3600 * amp * np.cos(60 * t)]
    kap, klin, ws, wss = blb.exact_kappa(ELL, t, wd)
    assert np.max(np.abs(wss)) > 4
    k, kt = ELL.k(t)
    ks = kt / ELL.g(t)
    Acal, T = blb.integrated_remainder(k, ks, None, None, w=wd[0], p=ws)
    sig = np.concatenate([[0.0], np.cumsum(0.5 * (ELL.g(t)[1:] + ELL.g(t)[:-1]) * np.diff(t))])
    dA = np.gradient(Acal, sig, edge_order=2)
    R = kap - klin
    inner = slice(10, -10)
    assert np.max(np.abs(R - dA - T)[inner]) < 1e-4 * np.max(np.abs(R))
    Amax, Tmax = blb.integrated_remainder(k, ks, amp, np.max(np.abs(ws)))
    assert np.all(np.abs(Acal) <= Amax) and np.all(np.abs(T) <= Tmax)
    # random points of the class: the bounds hold and are not loose
    rng = np.random.default_rng(4)
    W, d1 = 2e-3, 0.1
    tt = rng.uniform(0, np.pi / 2, 4000)
    w = rng.uniform(-W, W, tt.size)
    p = rng.choice([-d1, d1], tt.size) * rng.uniform(0.9, 1, tt.size)
    k, kt = ELL.k(tt)
    ks = kt / ELL.g(tt)
    Acal, T = blb.integrated_remainder(k, ks, None, None, w=w, p=p)
    Amax, Tmax = blb.integrated_remainder(k, ks, W, d1)
    assert np.all(np.abs(Acal) <= Amax) and np.all(np.abs(T) <= Tmax)
    assert np.max(np.abs(T) / Tmax) > 0.8 and np.max(np.abs(Acal) / Amax) > 0.5


def test_duality_identity_holds_for_any_w_and_closed_jumps():
    # int kappa_lin' phi dsigma = int k' phi dsigma - sum J_i w(sigma_i) for phi built from closed jumps J:
    # the identity the certificate rests on, checked by quadrature for a random quintic w and random J
    P = quarter_points(40)
    band = blb.Band(P, ELL, tol=1e-3)
    cert = blb.Certificate(band)
    rng = np.random.default_rng(1)
    k, knots, _ = blb.quintic_basis(band.ti, 1)
    c = 1e-3 * rng.standard_normal(len(knots) - k - 1)
    w = BSpline(knots, c, k)
    Vs, ks, g = blb.design(ELL, k, knots, cert.tq)
    klin_s = ks + Vs @ c
    J = cert.close(rng.standard_normal(len(band.ti)))
    phi = cert.B0 @ J
    lhs = np.sum(cert.wq * g * klin_s * phi)
    rhs = np.sum(cert.wq * g * ks * phi) - J @ w(band.ti)
    assert abs(lhs - rhs) < 1e-9 * (abs(lhs) + abs(rhs))
    # without the end conditions (J not closed) the boundary terms break the identity
    J2 = rng.standard_normal(len(band.ti))
    phi2 = cert.B0 @ J2
    lhs2 = np.sum(cert.wq * g * klin_s * phi2)
    rhs2 = np.sum(cert.wq * g * ks * phi2) - J2 @ w(band.ti)
    assert abs(lhs2 - rhs2) > 1e-3 * (abs(lhs2) + abs(rhs2))


def test_certificate_is_below_the_primal_and_every_feasible_curve():
    # weak duality: the certificate is <= the QP's value and <= the linearised F of random feasible curves
    P = quarter_points(60)
    band = blb.Band(P, ELL, tol=1e-3)
    cert = blb.Certificate(band)
    pr = blb.solve_primal(band, 1)
    L3 = band.L_sub**3
    lo = cert.bound(pr["J"])[0]
    assert lo <= L3 * pr["value"] * (1 + 1e-9) and lo >= L3 * pr["value"] * (1 - 1e-5)
    rng = np.random.default_rng(2)
    k, knots, fine = blb.quintic_basis(band.ti, 2)
    tq, wq = blb.span_gauss(fine, 6)
    Vs, ks, g = blb.design(ELL, k, knots, tq)
    A = BSpline.design_matrix(band.ti, knots, k).toarray()
    for _ in range(5):
        c = rng.standard_normal(len(knots) - k - 1)
        c *= 0.999 * band.tol / np.max(np.abs(A @ c))
        f = ks + Vs @ c
        assert L3 * np.sum(wq * g * f**2) >= lo


def test_tol_to_zero_gives_the_exact_arcs_F():
    # with tol -> 0 the band's minimum tends to the exact arc's F: L from scipy's complete elliptic integral,
    # F from measure.py on a dense quintic interpolant of the arc (independent of this module's formulas)
    L = ellipe(0.75)  # quarter perimeter of a = 1, b = 0.5: a E(1 - b^2/a^2)
    t = np.linspace(0, np.pi / 2, 2001)
    s = make_interp_spline(t, ELL.point(t), k=5)
    F_arc = measure.measure(5, s.t, s.c, None, ELL.point(t)).F
    band = blb.Band(quarter_points(200), ELL, tol=1e-9)
    assert abs(band.L_sub / L - 1) < 1e-12
    assert abs(band.L_sub**3 * blb.Certificate.arc_integral(band) / F_arc - 1) < 1e-6
    assert abs(F_arc - 40.76) < 0.01
    pr = blb.solve_primal(band, 1)
    lo = blb.Certificate(band).bound(pr["J"])[0]
    up = band.L_sub**3 * pr["value"]
    assert lo <= up <= F_arc and lo > 0.999 * F_arc


def test_circle_arc_bound_is_zero():
    # constant curvature: k' = 0, w = 0 is optimal, the bound and the QP's value are 0 (to rounding)
    circ = blb.Ellipse(1.0, 1.0)
    t = np.linspace(0, 1.2, 50)
    band = blb.Band(circ.point(t), circ, tol=1e-3)
    pr = blb.solve_primal(band, 1)
    assert pr["value"] < 1e-18
    assert blb.Certificate(band).bound(pr["J"])[0] < 1e-18


def test_built_curve_is_within_tol_and_its_true_F_is_close_to_the_linearised_optimum():
    # E + w* N (the QP's optimum) measured by measure.py: max orthogonal deviation <= tol, true F within
    # 1 % of the linearised value (the linearisation error is O(k tol) ~ 0.4 %)
    P = measure.read_points(QUARTER)
    band = blb.Band(P, ELL)
    pr = blb.solve_primal(band, 1)
    F, L, dev = blb.verify(band, pr["w"], P)
    assert dev <= 1 + 1e-9
    assert abs(F / (band.L_sub**3 * pr["value"]) - 1) < 0.01
    st = blb.class_stats(band, pr["w"])
    assert st["W"] < 2 * band.tol and st["d1"] < 0.1 and st["d2"] < 2.0  # inside the classes used


def test_quarter_ellipse_bound_exceeds_half_splprep():
    # the certified bound over the interior span (no end assumption) for the default class exceeds
    # 0.5 x splprep's F, splprep run through bench/compare.py's own s search and measured by measure.py
    P = measure.read_points(QUARTER)
    Fs, n = blb.target_of(P, measure.tolerance(P))
    assert n == 6 and 30 < Fs < 40
    val, _, W, _, cert, pr = blb.certified(P, ELL, 0.1, None, 2.0, spans=("interior",))["interior"]
    val2 = cert.bound(pr["J"], W=W, delta1=0.1, delta2=2.0)[0]
    # integrated remainder (no bound on w''), and the pointwise one with |w''| <= 2
    for v in (val, val2):
        assert 0.5 * Fs * 1.05 < v < 0.7 * Fs  # and below the best curve found (0.683 x, docs/f-target-study.md)
    # the slope class away from the ends: |w'| >= 0.1 would need int kappa'^2 ds far above what F <= target
    # allows (a wider band, 10 tol, does not exclude it)
    band = blb.Band(P, ELL, interior=True)
    e, allowed, _ = blb.slope_lemma(band, W, 0.1, 0.5 * Fs)
    assert e > 5 * allowed and 10 < allowed < 15
    assert blb.slope_lemma(band, 10 * band.tol, 0.1, 0.5 * Fs)[0] < allowed


def test_end_gap_slope_profile():
    # the slope lemma proves |w'| < 0.1 except within its window of the interior span's ends; with |w'| <= D
    # allowed there the certified bound stays above the target up to D ~ 0.225 (end_slope_needed), and:
    # D = 0.1 gives the uniform-class bound, the bound decreases with D, the node arc lengths add up to L_sub
    P = measure.read_points(QUARTER)
    target = 0.5 * blb.target_of(P, measure.tolerance(P))[0]
    val, _, W, band, cert, pr = blb.certified(P, ELL, 0.1, None, 2.0, spans=("interior",))["interior"]
    si, sq = cert.sigma_nodes()
    assert abs(si[-1] / band.L_sub - 1) < 1e-12 and np.all(np.diff(sq) > 0)
    e, allowed, l = blb.slope_lemma(band, W, 0.1, target)
    assert e > allowed
    margin, m1, m2 = blb.lemma_margin(band, W, 0.1)
    assert abs(m1 / (l / (1 - 4.0 * W)) - 1) < 1e-4  # k_max ~ 4 near the vertex (1, 0); the lemma's window
    # the data witnesses: 2 tol / (a_lo sin(psi0 / 2)) + 2 (h_max + 2 tol / a_1) with h_max = 0.00789
    assert margin == m2 and 0.059 < m2 < 0.062
    L = band.L_sub - W * band.K_sub
    vals = [cert.bound(pr["J"], W=W, delta1=0.1, end=(margin, D, L))[0] for D in (0.1, 0.15, 0.2, 0.3)]
    assert abs(vals[0] / val - 1) < 1e-12
    assert all(a > b for a, b in zip(vals, vals[1:]))
    D = blb.end_slope_needed(cert, pr["J"], W, 0.1, margin, target)
    assert 0.215 < D < 0.235
    assert 0.18 < blb.end_slope_needed(cert, pr["J"], W, 0.1, m1, target) < 0.2  # the wider gap
    assert cert.bound(pr["J"], W=W, delta1=0.1, end=(margin, D, L))[0] > target
    assert cert.bound(pr["J"], W=W, delta1=0.1, end=(margin, D + 1e-3, L))[0] < target
    # nested: the lemma at thresholds 0.1, 0.125, ..., 0.25 (windows shrinking to 0.0333) and |w'| <= D in
    # the innermost window keep the bound above the target up to D ~ 0.271 > 0.25 (consistent)
    ms, ds, Dn = blb.nested_end_gap(cert, pr["J"], W, 0.1, target)
    assert ds[0] == 0.1 and abs(ms[0] - margin) < 1e-15 and np.all(np.diff(ms) < 0)
    assert ds[-1] == 0.25 and 0.032 < ms[-1] < 0.035 and ds[-1] < Dn < 0.29
    for d in ds:  # every threshold is excluded by the lemma's energy away from its window
        e, allowed, _ = blb.slope_lemma(band, W, d, target)
        assert e > allowed
    prof = (np.array(ms), np.array(ds[1:] + [Dn]), L)
    assert target < cert.bound(pr["J"], W=W, delta1=0.1, end=prof)[0] < 1.01 * target


if __name__ == "__main__":
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn):
            fn()
            print("ok", name)
