"""Tests of the dense-section benchmark's data and bookkeeping (bench/dense.py): no fairfit binary needed,
numpy and scipy only, a few seconds.

Run with `python -m pytest bench/test_dense.py` or `python bench/test_dense.py`.
"""

import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import dense  # noqa: E402


def _case(name):
    return next(c for c in dense.build_cases() if c.name == name)


def test_suite_sizes_and_filters():
    names = [c.name for c in dense.build_cases()]
    assert len(names) == len(set(names))
    full = {c.n for c in dense.build_cases() if c.family == "naca4412-0.1"}
    assert full == {1_000, 10_000, 100_000, 1_000_000}
    assert max(c.n for c in dense.build_cases(quick=True)) == dense.QUICK_MAX_POINTS
    only = dense.build_cases(only="naca4412-1e4-*")
    assert {c.name for c in only} == {"naca4412-1e4-clean", "naca4412-1e4-tol100", "naca4412-1e4-tol10",
                                      "naca4412-1e4-tol3", "naca4412-1e4-tol100-bursts",
                                      "naca4412-1e4-tol100-spikes"}
    # exactly one case above tol/10: the one that must warn
    assert [c.name for c in dense.build_cases() if c.noise > 0.1 + 1e-12] == ["naca4412-1e4-tol3"]


def test_data_is_deterministic_and_noise_has_the_stated_sigma():
    c = _case("naca4412-1e4-tol10")
    a, b = dense.make_data(c), dense.make_data(c)
    assert np.array_equal(a.points, b.points)
    assert a.points.shape == (10_000, 2)
    # sigma is tol/10 of the noise-free bounding box; the airfoil's chord is 1
    assert abs(a.tol_gen - 1e-3) < 1e-6 and abs(a.sigma - 1e-4) < 1e-7
    # noise is along the normal: the distance to the generator (a dense polyline) has rms sigma
    d = dense.polyline_distance(a.points, a.poly[1])
    assert abs(math.sqrt(np.mean(d**2)) / a.sigma - 1.0) < 0.05
    # the noise-free points lie on the generator, evenly in arc length
    d0 = dense.polyline_distance(a.clean, a.poly[1])
    assert d0.max() < 1e-8
    steps = np.linalg.norm(np.diff(a.clean, axis=0), axis=1)
    assert steps.max() / steps.min() < 1.01


def test_polyline_distance_against_a_circle():
    # points at known radii from a unit circle; the polyline's chord error is 1/(8 m^2) of the radius
    m = 20_000
    t = np.linspace(0.0, 2 * np.pi, m + 1)
    V = np.column_stack([np.cos(t), np.sin(t)])
    rng = np.random.default_rng(1)
    th = rng.uniform(0, 2 * np.pi, 500)
    r = rng.uniform(0.5, 1.5, 500)
    Q = np.column_stack([r * np.cos(th), r * np.sin(th)])
    d = dense.polyline_distance(Q, V)
    h = 2 * np.pi / m
    assert np.max(np.abs(d - np.abs(r - 1.0))) <= h * h / 8 + 1e-12


def test_spikes_are_isolated_and_of_the_stated_size():
    c = _case("naca4412-1e4-tol100-spikes")
    d = dense.make_data(c)
    assert len(d.spikes) == round(dense.SPIKE_FRACTION * c.n) == 50
    assert np.min(np.diff(d.spikes)) >= 4 and d.spikes[0] >= 5 and d.spikes[-1] < c.n - 5
    # 20 tol along the normal plus the small noise (tol/100)
    off = np.linalg.norm(d.points[d.spikes] - d.clean[d.spikes], axis=1)
    assert np.all(np.abs(off / d.tol_gen - dense.SPIKE_SIZE) < 0.1)
    # as far from the curve (a spike that would land near another part of the curve goes the other way)
    far = dense.polyline_distance(d.points[d.spikes], d.poly[1]) / d.tol_gen
    assert np.all(far > 0.95 * dense.SPIKE_SIZE)
    others = np.setdiff1d(np.arange(c.n), d.spikes)
    assert np.max(dense.polyline_distance(d.points[others], d.poly[1])) < 0.1 * d.tol_gen


def test_corners_turn_by_the_stated_angles():
    c = _case("corners-90-45-1e4-tol100")
    assert c.expected_corners == list(c.shape.corner_us)  # both turns are over --corner-angle 30
    d = dense.make_data(c)
    assert d.corners.shape == (2, 2)
    for u, want in zip(c.shape.corner_us, (90.0, 45.0)):
        a = c.shape.g(np.array([u - 1e-4, u - 1e-7]))
        b = c.shape.g(np.array([u + 1e-7, u + 1e-4]))
        t1, t2 = a[1] - a[0], b[1] - b[0]
        turn = math.degrees(math.acos(t1 @ t2 / np.linalg.norm(t1) / np.linalg.norm(t2)))
        assert abs(turn - want) < 0.1
    # a turn below the corner angle is not expected as a corner
    low = dense.Case("x", c.shape, 100, 0.0, corner_angle=60.0)
    assert low.expected_corners == [c.shape.corner_us[0]]


def test_bursts_have_the_stated_density_ratio():
    d = dense.make_data(_case("naca4412-1e4-tol100-bursts"))
    steps = np.linalg.norm(np.diff(d.clean, axis=0), axis=1)
    ratio = np.percentile(steps, 99) / np.percentile(steps, 1)
    assert abs(ratio / dense.BURST_RATIO - 1.0) < 0.05


def test_closed_case_does_not_repeat_its_first_point():
    c = _case("blob-closed-1e5-tol10")
    d = dense.make_data(c)
    step = np.linalg.norm(d.clean[1] - d.clean[0])
    assert abs(np.linalg.norm(d.clean[-1] - d.clean[0]) / step - 1.0) < 1e-3


def test_report_keys():
    rep = {"corners": [3, {"index": 9}, True, "x"], "outliers": [{"index": 5, "distance": 0.1}, {"d": 1}]}
    assert dense.report_rows(rep, dense.CORNERS_KEY) == [3, 9]
    assert dense.report_rows(rep, dense.OUTLIERS_KEY) == [5]
    assert dense.report_rows({}, dense.OUTLIERS_KEY) == []
    assert dense.report_sigma({"noise_sigma": 2e-4}) == 2e-4
    assert dense.report_sigma({"noise": {"sigma": 3e-4}}) == 3e-4
    assert dense.report_sigma({"noise": 1.0}) is None and dense.report_sigma({}) is None
    err = "warning: the tolerance 1e-4 is below the measured noise (sigma 2e-4); try --tol 5e-4\n"
    assert dense.noise_warning_lines(err) == 1
    assert dense.noise_warning_lines("warning: dropped 1 duplicate point\nerror: x\n") == 0


def test_run_process_times_out_and_measures_memory():
    rc, wall, peak, _ = dense.run_process([sys.executable, "-c", "import time; time.sleep(30)"], 0.5)
    assert rc is None and wall < 5.0
    rc, _, peak, err = dense.run_process(
        [sys.executable, "-c", "import sys; b = bytearray(120 << 20); b[::4096] = b'x' * len(b[::4096]); "
         "sys.stderr.write('warning: noise\\n'); sys.exit(3)"], 30)
    assert rc == 3 and peak >= 120 and dense.noise_warning_lines(err) == 1


def _row(name, n, noise, tol=1.0, family="", spikes=(), true_corners=(), points=None, **ff):
    case = dense.Case(name, dense.Shape(name, None), n, noise, family=family)
    run = dense.Run("ok", n_ctrl=10, max_dev=0.9 * tol, max_dev_all=0.9 * tol, F=1.0, extrema=2,
                    clean_dist=0.5 * tol, wall_s=1.0, peak_mb=50.0, sigma_est=noise * tol or None)
    for k, v in ff.items():
        setattr(run, k, v)
    pts = np.zeros((n, 2)) if points is None else points
    return dense.Row(case, tol, noise * tol, list(spikes), np.asarray(true_corners, dtype=float).reshape(-1, 2),
                     pts, run, dense.Run("skipped"))


def _status(rows, tid):
    return next(s for t, _, s, _ in dense.targets(rows) if t == tid)


def test_corner_and_spike_matching():
    r = _row("c", 100, 0.0, tol=0.01, true_corners=[[1.005, 0.0], [0.0, 1.0]],
             corners=[np.array([1.0, 0.0]), np.array([0.3, 0.3])], outliers=[3, 4])
    r.true_spikes = [3, 5]
    assert dense.corner_match(r) == (1, 1)  # (1, 0) matches within tol, (0.3, 0.3) is false, (0, 1) missed
    assert dense.spike_match(r) == (1, 1)  # 3 found, 5 missed, 4 removed wrongly
    assert _status([r], dense.T_FEATURES) == "not met"
    r.fairfit.corners = [np.array([0.0, 1.0]), np.array([1.0, 0.0])]
    r.fairfit.outliers, r.true_spikes = [3, 5], [5, 3]
    assert dense.corner_match(r) == (2, 0) and dense.spike_match(r) == (2, 0)
    assert _status([r], dense.T_FEATURES) == "met"
    # two fit corners at one true corner: the second is false
    r.fairfit.corners = [np.array([0.0, 1.0]), np.array([1.0, 0.0]), np.array([1.002, 0.0])]
    assert dense.corner_match(r) == (2, 1)


def test_corners_are_measured_on_the_fit():
    # a cubic with a triple knot at 0.5 through (1, 0): a 90-degree corner there
    knots = [0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1]
    ctrl = np.array([[0, 0], [0.3, 0], [0.6, 0], [1, 0], [1, 0.3], [1, 0.6], [1, 1]], dtype=float)
    c = dense.measure.Curve(3, knots, ctrl)
    got = dense.c0_corners(c, closed=False)
    assert len(got) == 1 and np.allclose(got[0], [1.0, 0.0])
    # the same knots on a straight line: a C0 knot without a turn is no corner
    straight = dense.measure.Curve(3, knots, np.column_stack([np.arange(7.0), np.zeros(7)]))
    assert dense.c0_corners(straight, closed=False) == []
    # a clamped loop around a square-ish path: its start, where it turns by 90 degrees, is a corner
    loop = np.array([[0, 0], [0.5, 0], [1, 0], [1, 0.5], [1, 1], [0.5, 1], [0, 1], [0, 0.5], [0, 0]], dtype=float)
    lk = [0, 0, 0, 0, 0.2, 0.4, 0.6, 0.8, 0.9, 1, 1, 1, 1]
    lc = dense.measure.Curve(3, lk, loop)
    got = dense.c0_corners(lc, closed=True)
    assert len(got) == 1 and np.allclose(got[0], [0.0, 0.0])
    assert dense.c0_corners(lc, closed=False) == []


def test_targets_tolerance_clean_distance_and_splprep():
    rows = [_row("a", 1000, 0.1), _row("b", 1000, 0.0), _row("w", 1000, 1 / 3, noise_warnings=1)]
    assert _status(rows, dense.T_TOL) == "met"
    assert _status(rows, dense.T_CLEAN) == "met"
    assert _status(rows, dense.T_SPLPREP) == "not measured"
    assert _status(rows, dense.T_SIGMA) == "met"
    rows[0].fairfit.max_dev = 1.01
    rows[1].fairfit.clean_dist = 1.2
    assert _status(rows, dense.T_TOL) == "not met"
    assert _status(rows, dense.T_CLEAN) == "not met"
    # the tol/3 case is not judged on the tolerance nor the clean distance
    rows[0].fairfit.max_dev, rows[1].fairfit.clean_dist = 0.9, 0.5
    rows[2].fairfit.max_dev, rows[2].fairfit.clean_dist = 5.0, 5.0
    assert _status(rows, dense.T_TOL) == "met" and _status(rows, dense.T_CLEAN) == "met"
    # splprep comparison: count, F and extrema each
    rows[0].splprep = dense.Run("ok", n_ctrl=10, F=1.0, extrema=2)
    assert _status(rows, dense.T_SPLPREP) == "met"
    rows[0].splprep.F = 0.99
    assert _status(rows, dense.T_SPLPREP) == "not met"
    rows[0].splprep = dense.Run("ok", n_ctrl=9, F=2.0, extrema=2)
    assert _status(rows, dense.T_SPLPREP) == "not met"
    # a timeout is a miss
    rows[1].fairfit = dense.Run("timeout", "over 120 s")
    assert _status(rows, dense.T_TOL) == "not met"


def test_targets_sigma_and_warning():
    rows = [_row("a", 1000, 0.1), _row("w", 1000, 1 / 3, noise_warnings=1)]
    rows[0].fairfit.sigma_est = 0.1 * 1.24
    assert _status(rows, dense.T_SIGMA) == "met"
    rows[0].fairfit.sigma_est = 0.1 * 1.26
    assert _status(rows, dense.T_SIGMA) == "not met"
    rows[0].fairfit.sigma_est = None  # no report key: not met
    assert _status(rows, dense.T_SIGMA) == "not met"
    rows[0].fairfit.sigma_est = 0.1
    rows[0].fairfit.noise_warnings = 1  # a warning where there is no reason for one
    assert _status(rows, dense.T_SIGMA) == "not met"
    rows[0].fairfit.noise_warnings, rows[1].fairfit.noise_warnings = 0, 2  # not one line
    assert _status(rows, dense.T_SIGMA) == "not met"


def test_targets_time_scaling_and_counts():
    fam = [_row(f"f{n}", n, 0.1, family="f") for n in (1_000, 10_000, 100_000, 1_000_000)]
    for r, w, c in zip(fam, (0.5, 1.0, 3.0, 4.0), (15, 11, 12, 12)):
        r.fairfit.wall_s, r.fairfit.n_ctrl = w, c
    assert _status(fam, dense.T_TIME_1E6) == "met"
    assert _status(fam, dense.T_SCALING) == "met"
    assert _status(fam, dense.T_COUNTS) == "met"  # 10^3 points not judged; 11, 12, 12 differ by 1 at most
    fam[3].fairfit.n_ctrl = 10
    assert _status(fam, dense.T_COUNTS) == "not met"
    fam[3].fairfit.wall_s = 21.0
    assert _status(fam, dense.T_SCALING) == "not met" and _status(fam, dense.T_TIME_1E6) == "not met"
    fam[3].fairfit.wall_s, fam[3].fairfit.peak_mb = 4.0, 301.0
    assert _status(fam, dense.T_TIME_1E6) == "not met"
    # a quick run has no 10^6 case: not measured, not met
    assert _status(fam[:2], dense.T_TIME_1E6) == "not measured"
    assert _status(fam[:2], dense.T_SCALING) == "not measured"


def test_report_tables_render_every_row():
    rows = [_row("a", 1000, 0.1), _row("b", 1000, 0.0)]
    rows[1].fairfit = dense.Run("timeout", "over 120 s")
    ff, sp, tg = dense.fairfit_table(rows), dense.splprep_table(rows), dense.targets_table(rows)
    assert len(ff.splitlines()) == 4 and "timeout: over 120 s" in ff
    assert ff.splitlines()[0].count("|") == ff.splitlines()[2].count("|")
    assert len(sp.splitlines()) == 4
    assert len(tg.splitlines()) == 2 + 9


def test_splprep_search_is_coarse_first_and_capped():
    calls = []

    def meets(s):
        calls.append(s)
        return s <= 5.3

    dense._grid_search(meets, [1.0, 2.0, 4.0, 8.0, 16.0], refine=6)
    # the largest grid value meeting is 4; nothing finer than it is fitted; bisection towards 8
    assert calls[:3] == [16.0, 8.0, 4.0] and min(calls) == 4.0
    assert max(c for c in calls if c <= 5.3) > 5.0
    c = _case("naca4412-1e3-tol10")
    d = dense.make_data(c)
    tol = dense.measure.tolerance(d.points)
    run, curve = dense.run_splprep(c, d, tol, cap_s=0.0)
    assert run.status == "skipped" and "time cap" in run.reason and curve is None
    run, curve = dense.run_splprep(c, d, tol, max_points=999)
    assert run.status == "skipped" and "999 points" in run.reason and curve is None


if __name__ == "__main__":
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn):
            fn()
            print("ok", name)
