"""Tests of the independent measurer on analytic cases.

Run with `python -m pytest bench/test_measure.py` or `python bench/test_measure.py`.
"""

import os
import sys

import numpy as np
from scipy.integrate import quad

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import measure  # noqa: E402

S2 = np.sqrt(0.5)


def full_circle(r=1.0, cx=0.0, cy=0.0):
    """Exact circle: 9-point rational quadratic (4 quarter arcs)."""
    ctrl = np.array(
        [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float
    )
    ctrl = ctrl * r + [cx, cy]
    w = np.array([1, S2, 1, S2, 1, S2, 1, S2, 1])
    knots = [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1]
    return 2, knots, ctrl, w


def cubic_bezier(f, a, b):
    """Cubic Bezier control points reproducing the cubic polynomial curve (t, f(t)), t in [a, b]."""
    s = np.linspace(0, 1, 4)
    t = a + (b - a) * s
    B = np.array([[[1, 3, 3, 1][i] * si**i * (1 - si) ** (3 - i) for i in range(4)] for si in s])
    cx = np.linalg.solve(B, t)
    cy = np.linalg.solve(B, f(t))
    return 3, [0, 0, 0, 0, 1, 1, 1, 1], np.column_stack([cx, cy]), None


def test_circle_curvature_and_fairness():
    r = 2.5
    deg, knots, ctrl, w = full_circle(r, 1.0, -3.0)
    c = measure.Curve(deg, knots, ctrl, w)
    u = c.span_samples(20)
    pts = c.points(u)
    assert np.allclose(np.linalg.norm(pts - [1.0, -3.0], axis=1), r, atol=1e-12)
    kappa, dkds, speed = measure._kappa_and_dkds(c, u, planar=True)
    assert np.allclose(kappa, 1.0 / r, rtol=1e-10), kappa[:4]
    assert np.max(np.abs(dkds)) < 1e-9
    F, L = measure.fairness(c, planar=True)
    assert abs(L - 2 * np.pi * r) < 1e-10 * r, L
    assert F < 1e-16, F


def test_circle_orthogonal_deviation_exact():
    r = 1.0
    deg, knots, ctrl, w = full_circle(r)
    rng = np.random.default_rng(7)
    ang = rng.uniform(0, 2 * np.pi, 300)
    off = rng.uniform(-0.01, 0.01, 300)
    pts = np.column_stack([(r + off) * np.cos(ang), (r + off) * np.sin(ang)])
    m = measure.measure(deg, knots, ctrl, w, pts)
    assert abs(m.max_dev - np.max(np.abs(off))) < 1e-12, (m.max_dev, np.max(np.abs(off)))
    assert abs(m.rms_dev - np.sqrt(np.mean(off**2))) < 1e-12
    assert m.n_ctrl == 9
    assert m.extrema == 0 and m.inflections == 0
    assert m.F < 1e-14


def test_tilted_circle_in_3d_unsigned_curvature():
    deg, knots, ctrl2, w = full_circle(3.0)
    R = np.array([[1, 0, 0], [0, np.cos(0.7), -np.sin(0.7)], [0, np.sin(0.7), np.cos(0.7)]])
    ctrl = np.column_stack([ctrl2, np.zeros(9)]) @ R.T
    c = measure.Curve(deg, knots, ctrl, w)
    kappa, dkds, _ = measure._kappa_and_dkds(c, c.span_samples(10), planar=False)
    assert np.allclose(kappa, 1 / 3.0, rtol=1e-10)
    F, L = measure.fairness(c, planar=False)
    assert F < 1e-14 and abs(L - 6 * np.pi) < 1e-9


def test_cubic_graph_fairness_against_quad():
    # (t, t^3), t in [-1, 1]: signed kappa = 6t / (1 + 9t^4)^(3/2).
    deg, knots, ctrl, w = cubic_bezier(lambda t: t**3, -1.0, 1.0)
    c = measure.Curve(deg, knots, ctrl, w)
    t = np.linspace(-1, 1, 11)
    assert np.allclose(c.points((t + 1) / 2), np.column_stack([t, t**3]), atol=1e-13)

    def kappa(t):
        return 6 * t / (1 + 9 * t**4) ** 1.5

    def dk_dt(t, h=1e-5):
        return (kappa(t + h) - kappa(t - h)) / (2 * h)

    def speed(t):
        return np.sqrt(1 + 9 * t**4)

    L = quad(speed, -1, 1, epsabs=1e-13)[0]
    integ = quad(lambda t: dk_dt(t) ** 2 / speed(t), -1, 1, epsabs=1e-12, limit=200)[0]
    F_true = L**3 * integ
    F, Lm = measure.fairness(c, planar=True)
    assert abs(Lm - L) < 1e-10, (Lm, L)
    assert abs(F - F_true) < 1e-6 * F_true, (F, F_true)
    # Signed curvature: one inflection (t = 0) and two extrema (t = +-(1/45)^(1/4)).
    pts = c.points(np.linspace(0, 1, 50))
    m = measure.measure(deg, knots, ctrl, w, pts)
    assert m.inflections == 1, m
    assert m.extrema == 2, m
    assert m.max_dev < 1e-12


def test_parabola_one_extremum_no_inflection_scale_free():
    deg, knots, ctrl, w = cubic_bezier(lambda t: t**2, -1.0, 1.0)
    pts = measure.Curve(deg, knots, ctrl, w).points(np.linspace(0, 1, 40))
    m1 = measure.measure(deg, knots, ctrl, w, pts)
    m2 = measure.measure(deg, knots, ctrl * 1000.0, w, pts * 1000.0)
    assert m1.extrema == 1 and m1.inflections == 0, m1
    assert (m2.extrema, m2.inflections) == (m1.extrema, m1.inflections)
    assert abs(m2.F - m1.F) < 1e-9 * m1.F
    # F of (t, t^2): independent quadrature.
    k = lambda t: 2 / (1 + 4 * t * t) ** 1.5  # noqa: E731
    dk = lambda t: -24 * t / (1 + 4 * t * t) ** 2.5  # noqa: E731
    sp = lambda t: np.sqrt(1 + 4 * t * t)  # noqa: E731
    L = quad(sp, -1, 1)[0]
    F_true = L**3 * quad(lambda t: dk(t) ** 2 / sp(t), -1, 1, epsabs=1e-13)[0]
    assert abs(m1.F - F_true) < 1e-8 * F_true, (m1.F, F_true)
    assert k(0) == 2.0


def test_tolerance_is_relative_to_bounding_box_and_exact_circle_fits():
    deg, knots, ctrl, w = full_circle(1.0)
    pts = np.array([[np.cos(a), np.sin(a)] for a in np.linspace(0, 2 * np.pi, 101)])
    assert abs(measure.tolerance(pts) - 2e-3) < 1e-12
    m = measure.measure(deg, knots, ctrl, w, pts)
    assert m.max_dev < 1e-13


def test_deviation_matches_brute_force_on_random_rational_spline():
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(3)
    n, k = 12, 3
    knots = np.r_[[0.0] * 4, np.sort(rng.uniform(0, 1, n - k - 1)), [1.0] * 4]
    ctrl = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    w = rng.uniform(0.5, 2.0, n)
    c = measure.Curve(k, knots, ctrl, w)
    pts = c.points(rng.uniform(0, 1, 80)) + rng.normal(scale=0.05, size=(80, 2))
    dense = c.points(np.linspace(0, 1, 400_001))
    brute, _ = cKDTree(dense).query(pts)
    d = measure.deviations(c, pts)
    # the measurer is never worse than brute force and within its sampling error
    assert np.all(d <= brute + 1e-12)
    spacing = np.max(np.linalg.norm(np.diff(dense, axis=0), axis=1))
    assert np.max(brute - d) <= spacing, (np.max(brute - d), spacing)


def test_deviation_on_thin_hairpin_finds_the_far_sampled_branch():
    """A thin hairpin (like a sharp trailing edge): the upper branch is ONE long knot span, the lower
    branch many short ones, 0.004 apart at the open end. Near the end, the nearest samples of a
    point beside the upper branch all lie on the lower branch; the measurer must still find the
    upper branch's foot point (an earlier version reported up to 0.054 too much here)."""
    from scipy.spatial import cKDTree

    up = np.array([[1.0, 0.002], [0.6, 0.03], [0.2, 0.03], [0.0, 0.0]])
    s = np.linspace(0, 1, 12)[1:]
    low = np.column_stack([s, -0.002 - 0.03 * np.sin(np.pi * s)])
    ctrl = np.vstack([up, low])
    knots = np.r_[[0.0] * 4, np.linspace(0.9, 1.0, len(ctrl) - 3)[:-1], [1.0] * 4]
    c = measure.Curve(3, knots, ctrl)
    pts = c.points(np.linspace(0, 0.9, 200))
    tang = np.gradient(pts, axis=0)
    nrm = np.column_stack([-tang[:, 1], tang[:, 0]]) / np.linalg.norm(tang, axis=1)[:, None]
    pts = pts + 1e-3 * nrm * np.where(np.arange(200) % 2, 1.0, -1.0)[:, None]
    dense = c.points(np.linspace(0, 1, 2_000_001))
    brute, _ = cKDTree(dense).query(pts)
    d = measure.deviations(c, pts, samples_per_span=8)
    assert np.all(d <= brute + 1e-12), np.max(d - brute)
    assert np.max(brute - d) < 1e-8, np.max(brute - d)
    assert abs(np.max(d) - 1e-3) < 1e-4, np.max(d)  # the offset, where the branches do not interfere


def test_read_points_skips_comments_and_header(tmp_path=None):
    import tempfile

    d = tmp_path or tempfile.mkdtemp()
    p = os.path.join(str(d), "pts.csv")
    with open(p, "w") as fh:
        fh.write("# comment\nx,y\n1,0\n0.5,0.25\n0,0\n")
    P = measure.read_points(p)
    assert P.shape == (3, 2) and P[1, 1] == 0.25


def test_periodic_curve_counts_its_distinct_control_points():
    # a uniform periodic cubic over 8 distinct points of a circle, stored unclamped as 8 + 3 points
    k, m = 3, 8
    P = np.array([[np.cos(2 * np.pi * i / m), np.sin(2 * np.pi * i / m)] for i in range(m)])
    C = np.vstack([P, P[:k]])
    t = np.arange(len(C) + k + 1, dtype=float)
    c = measure.Curve(k, t, C)
    assert (c.n, c.n_independent) == (11, 8)
    # it closes: the ends of its domain [t_k, t_n] meet
    a = c.spline(c.lo)
    b = c.spline(c.hi)
    assert np.allclose(a, b, atol=1e-12)
    # the same 11 points on a clamped knot vector are an open curve: all 11 count
    t2 = np.r_[[0.0] * 4, np.linspace(0, 1, len(C) - 2)[1:-1], [1.0] * 4]
    assert measure.Curve(k, t2, C).n_independent == 11
    # unclamped but not wrapped (last points differ): all count
    C3 = C.copy()
    C3[-1] += 0.1
    assert measure.Curve(k, t, C3).n_independent == 11


if __name__ == "__main__":
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn):
            fn()
            print("ok", name)
