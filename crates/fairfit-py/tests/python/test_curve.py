"""fit_curve and Curve against the CLI of the same build, scipy and finite differences, with numbers."""

import json
import os
import pickle
import concurrent.futures as cf

import numpy as np
import pytest

import fairfit
from conftest import cli_eval, example

# three shared curves of the bundled data: an airfoil, a noisy airfoil, a synthetic ellipse arc
CURVES = ["naca4412.csv", "clarky.csv", "quarter_ellipse_200.csv"]


@pytest.fixture(scope="module")
def naca():
    return fairfit.fit_curve(fairfit.read_points(example("naca4412.csv")), rel_tol=1e-3, seed=0)


@pytest.mark.parametrize("name", CURVES)
def test_fit_curve_gives_the_cli_json_bytes(cli, tmp_path, name):
    path = example(name)
    out = tmp_path / "cli.json"
    cli("curve", path, "--rel-tol", "1e-3", "--seed", "1", "-o", out, "--report", tmp_path / "r.json")
    curve = fairfit.fit_curve(fairfit.read_points(path), rel_tol=1e-3, seed=1, name=path)
    assert curve.to_json() == out.read_text()
    report = json.loads((tmp_path / "r.json").read_text())
    mine = curve.report
    assert set(mine) == set(report)
    for key in ["control_points", "max_deviation", "fairness", "degree", "tolerance", "input"]:
        assert mine[key] == report[key], key


@pytest.mark.parametrize(
    "method, flags, kwargs",
    [
        ("lsq", ["--degree", "3"], {"degree": 3}),
        ("fit-then-fair", [], {}),
        ("integrated", ["--degree", "4", "--control-points", "14"], {"degree": 4, "control_points": 14}),
        ("integrated", ["--tol", "2e-4", "--ends", "free"], {"tol": 2e-4, "ends": "free"}),
    ],
)
def test_other_methods_and_options_match_the_cli(cli, tmp_path, method, flags, kwargs):
    path = example("naca4412.csv")
    out = tmp_path / "cli.json"
    cli("curve", path, "--method", method, *flags, "-o", out)
    curve = fairfit.fit_curve(fairfit.read_points(path), method=method, **kwargs)
    assert curve.to_json() == out.read_text()


def test_pareto_front_is_the_clis_csv_and_curves(cli, tmp_path):
    path = example("naca4412.csv")
    csv, members = tmp_path / "front.csv", tmp_path / "members"
    cli("curve", path, "--seed", "2", "--pareto", csv, "--pareto-curves", members, "-o", tmp_path / "c.json")
    curve, front = fairfit.fit_curve(fairfit.read_points(path), seed=2, pareto=True)
    assert curve.to_json() == (tmp_path / "c.json").read_text()
    rows = csv.read_text().splitlines()[1:]
    assert len(front) == len(rows) == curve.report["pareto_members"] >= 1
    for i, (member, row) in enumerate(zip(front, rows)):
        assert member.to_json() == (members / f"front_{i:03}.json").read_text()
        cols = row.split(",")
        assert member.report["control_points"] == int(cols[1])
        assert member.report["max_deviation"] == pytest.approx(float(cols[2]), rel=1e-5)
        assert member.report["fairness"] == pytest.approx(float(cols[4]), rel=1e-5)
    # by increasing deviation, so decreasing F
    devs = [m.report["max_deviation"] for m in front]
    assert devs == sorted(devs)
    with pytest.raises(fairfit.FairfitError, match="pareto has no effect with method=.lsq.; it needs method=.integrated."):
        fairfit.fit_curve(fairfit.read_points(path), method="lsq", degree=3, pareto=True)


def test_threads_do_not_change_the_result_and_threads_fit_concurrently():
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    one = fairfit.fit_curve(pts, threads=1).to_json()
    assert fairfit.fit_curve(pts, threads=2).to_json() == one
    with cf.ThreadPoolExecutor(2) as ex:
        both = list(ex.map(lambda _: fairfit.fit_curve(pts, threads=1).to_json(), range(2)))
    assert both == [one, one]


def test_properties(naca):
    c = naca
    n = len(c.control_points)
    assert c.control_points.shape == (n, 2)
    assert c.dim == 2
    assert len(c.knots) == n + c.degree + 1
    assert np.all(c.weights == 1.0)
    assert c.domain == (c.knots[0], c.knots[-1])
    assert not c.closed
    assert c.report["control_points"] == n
    assert c.report["max_deviation"] <= c.report["tolerance"]


def test_evaluation_equals_the_cli_eval(cli, naca, tmp_path):
    path = tmp_path / "c.json"
    naca.save(path)
    us = np.linspace(0.0, 1.0, 13)
    rows = cli_eval(cli, path, us)
    pts = naca(us)
    d = naca.derivatives(us, 3)
    kappa = naca.curvature(us)
    assert pts.shape == (13, 2) and d.shape == (13, 4, 2) and kappa.shape == (13,)
    for i, row in enumerate(rows):
        np.testing.assert_allclose(pts[i], row["point"][:2], rtol=1e-12, atol=1e-15)
        for k in range(3):
            np.testing.assert_allclose(d[i, k + 1], row["derivatives"][k][:2], rtol=1e-12, atol=1e-12)
        assert kappa[i] == pytest.approx(row["curvature"], rel=1e-12)


def test_evaluation_equals_scipy(naca):
    us = np.random.default_rng(7).uniform(0.0, 1.0, 5000)
    spl = naca.to_scipy()
    ref = spl(us)
    got = naca(us)
    scale = np.abs(naca.control_points).max()
    assert np.abs(got - ref).max() <= 1e-12 * scale
    for k in (1, 2, 3):
        dk = spl.derivative(k)(us)
        np.testing.assert_allclose(naca.derivatives(us, 3)[:, k], dk, rtol=1e-10, atol=1e-10 * np.abs(dk).max())
    back = fairfit.Curve.from_scipy(spl)
    assert back.to_json() == fairfit.Curve(naca.degree, naca.knots, naca.control_points).to_json()


def test_from_scipy_of_scipys_own_interpolant():
    from scipy.interpolate import make_interp_spline

    t = np.linspace(0.0, 2.0, 30)
    xy = np.c_[np.cos(t), np.sin(2 * t)]
    spl = make_interp_spline(t, xy, k=3)
    c = fairfit.Curve.from_scipy(spl)
    us = np.linspace(0.0, 2.0, 101)
    np.testing.assert_allclose(c(us), spl(us), rtol=0, atol=1e-13)
    np.testing.assert_allclose(c(t), xy, atol=1e-12)


def test_derivatives_against_finite_differences(naca):
    us = np.linspace(0.05, 0.95, 19)
    h = 1e-5
    d = naca.derivatives(us, 2)
    fd1 = (naca(us + h) - naca(us - h)) / (2 * h)
    fd2 = (naca(us + h) - 2 * naca(us) + naca(us - h)) / h**2
    np.testing.assert_allclose(d[:, 1], fd1, rtol=1e-6, atol=1e-6 * np.abs(fd1).max())
    np.testing.assert_allclose(d[:, 2], fd2, rtol=1e-3, atol=1e-3 * np.abs(fd2).max())
    # curvature from the derivatives: |x'y'' - y'x''| / |C'|^3
    x1, y1, x2, y2 = d[:, 1, 0], d[:, 1, 1], d[:, 2, 0], d[:, 2, 1]
    kappa = np.abs(x1 * y2 - y1 * x2) / np.hypot(x1, y1) ** 3
    np.testing.assert_allclose(naca.curvature(us), kappa, rtol=1e-12)


def test_scalar_parameters(naca):
    assert naca(0.25).shape == (2,)
    np.testing.assert_array_equal(naca(0.25), naca(np.array([0.25]))[0])
    assert isinstance(naca.curvature(0.25), float)
    assert naca.derivatives(0.25, 2).shape == (3, 2)


def test_fairness_matches_cli_info(cli, naca, tmp_path):
    path = tmp_path / "c.json"
    naca.save(path)
    info = json.loads(cli("info", path).stdout)
    f = naca.fairness()
    for key in ["length", "energy", "fairness", "max_span_fairness", "bending_energy",
                "curvature_extrema", "inflections", "curvature_extrema_exact", "inflections_exact"]:
        assert f[key] == info[key], key
    np.testing.assert_array_equal(f["span_fairness"], info["span_fairness"])
    assert f["fairness"] == pytest.approx(f["span_fairness"].sum(), rel=1e-12)


def test_pickle_round_trip(naca):
    back = pickle.loads(pickle.dumps(naca))
    assert back.to_json() == naca.to_json()
    assert back.report == naca.report
    assert back.dim == 2
    us = np.linspace(0, 1, 50)
    np.testing.assert_array_equal(back(us), naca(us))


@pytest.mark.parametrize("ext", ["step", "iges"])
def test_cad_file_written_and_read_back_gives_the_same_geometry(naca, tmp_path, ext):
    path = tmp_path / f"c.{ext}"
    naca.save(path)
    back = fairfit.read(path)
    assert isinstance(back, fairfit.Curve)
    assert back.degree == naca.degree
    np.testing.assert_allclose(back.knots, naca.knots, rtol=0, atol=1e-12)
    np.testing.assert_allclose(back.control_points, naca.control_points, rtol=0, atol=1e-12)
    us = np.linspace(0, 1, 200)
    np.testing.assert_allclose(back(us), naca(us), rtol=0, atol=1e-12)


def test_other_outputs_are_written(naca, tmp_path):
    pts = fairfit.read_points(example("naca4412.csv"))
    for ext in ["obj", "ply", "svg", "png", "html"]:
        path = tmp_path / f"c.{ext}"
        naca.save(path, points=pts)
        assert path.stat().st_size > 100, ext
    assert (tmp_path / "c.svg").read_text().startswith("<svg") or "<svg" in (tmp_path / "c.svg").read_text()[:200]
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(fairfit.FairfitError, match="unknown format"):
        naca.save(tmp_path / "c.xyz")
    with pytest.raises(fairfit.FairfitError, match="STL holds triangles only: write a curve as .obj or .ply"):
        naca.save(tmp_path / "c.stl")


def test_rational_curve_refuses_scipy_and_evaluates_a_circle_exactly():
    h = np.sqrt(0.5)
    c = fairfit.Curve(2, [0, 0, 0, 1, 1, 1], [[1, 0], [1, 1], [0, 1]], [1, h, 1])
    assert c.rational
    us = np.linspace(0, 1, 101)
    np.testing.assert_allclose(np.hypot(*c(us).T), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(c.curvature(us), 1.0, rtol=1e-12)
    with pytest.raises(fairfit.FairfitError, match="rational"):
        c.to_scipy()


# --- errors: FairfitError (a ValueError) with the CLI's one-line message ---------------------------


def test_error_class():
    assert issubclass(fairfit.FairfitError, ValueError)
    assert fairfit.FairfitError.__module__ == "fairfit"
    e = pickle.loads(pickle.dumps(fairfit.FairfitError("a message")))
    assert type(e) is fairfit.FairfitError and str(e) == "a message"


def test_nan_points():
    pts = np.array([[0.0, 0.0], [1.0, np.nan], [2.0, 1.0], [3.0, 0.0]])
    with pytest.raises(fairfit.FairfitError, match=r"^invalid input data: <array>: point 1: value 'NaN' is not a finite number$"):
        fairfit.fit_curve(pts)


def test_too_few_points_gives_the_cli_message(cli, tmp_path):
    f = tmp_path / "one.csv"
    f.write_text("0,0\n0,0\n")
    r = cli("curve", f, "-o", tmp_path / "o.json", check=False)
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_curve([[0.0, 0.0], [0.0, 0.0]], name=str(f))
    assert r.stderr.strip() == f"error: {e.value}"


def test_two_points_give_the_cli_result_or_message(cli, tmp_path):
    f = tmp_path / "two.csv"
    f.write_text("0,0\n1,1\n")
    r = cli("curve", f, "-o", tmp_path / "o.json", check=False)
    if r.returncode == 0:
        assert fairfit.fit_curve([[0.0, 0.0], [1.0, 1.0]]).to_json() == (tmp_path / "o.json").read_text()
    else:
        with pytest.raises(fairfit.FairfitError) as e:
            fairfit.fit_curve([[0.0, 0.0], [1.0, 1.0]], name=str(f))
        assert r.stderr.strip().startswith(f"error: {e.value}")


def test_negative_tolerance_gives_the_cli_message(cli, tmp_path):
    path = example("naca4412.csv")
    r = cli("curve", path, "--tol=-1", "-o", tmp_path / "o.json", check=False)
    assert r.returncode == 2
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_curve(fairfit.read_points(path), tol=-1)
    # the library names its setting, the CLI the flag it came from; the reason is the same line
    reason = "the tolerance must be positive, got -1"
    assert str(e.value) == f"invalid option tolerance: {reason}"
    assert r.stderr.startswith(f"error: invalid option --tol: {reason}")


def test_ragged_array():
    with pytest.raises(fairfit.FairfitError, match="rows differ in length"):
        fairfit.fit_curve([[0.0, 0.0], [1.0, 1.0, 1.0], [2.0]])


def test_wrong_dtype():
    with pytest.raises(fairfit.FairfitError, match="must be numbers, got an array of dtype <U"):
        fairfit.fit_curve(np.array([["a", "b"], ["c", "d"], ["e", "f"]]))
    with pytest.raises(fairfit.FairfitError, match=r"must be an \(n, 2\) or \(n, 3\) array, got shape \(5, 4\)"):
        fairfit.fit_curve(np.zeros((5, 4)))


def test_option_errors():
    pts = fairfit.read_points(example("naca4412.csv"))
    with pytest.raises(fairfit.FairfitError, match="^control_points needs method='integrated'$"):
        fairfit.fit_curve(pts, method="lsq", control_points=10)
    with pytest.raises(fairfit.FairfitError, match=r"corner_angle must be in \(0, 180\] degrees, got 200"):
        fairfit.fit_curve(pts, corner_angle=200)
    with pytest.raises(fairfit.FairfitError, match="degree: expected `auto` or a degree from 1 to 15, got `16`"):
        fairfit.fit_curve(pts, degree=16)
    with pytest.raises(fairfit.FairfitError, match="^control_points 1000 exceeds the .* distinct input points$"):
        fairfit.fit_curve(pts, control_points=1000)


def test_parameter_outside_the_domain(naca):
    with pytest.raises(fairfit.FairfitError, match=r"parameter 2 is outside the domain \[0, 1\]"):
        naca(np.array([0.5, 2.0]))


def test_derivatives_of_an_order_no_memory_holds_are_refused_with_one_line(naca):
    # before: a k this large reached `vec![..; m * (k + 1)]`: an allocation failure aborted the
    # interpreter, or the product wrapped around
    for k in (10**15, 2**64 - 1):
        with pytest.raises(fairfit.FairfitError, match=r"^invalid input data: derivatives of order \d+ at 2 parameter\(s\): not enough memory") as e:
            naca.derivatives(np.array([0.1, 0.5]), k)
        assert "\n" not in str(e.value)
    # an ordinary order is unchanged
    assert naca.derivatives(0.5, 3).shape == (4, 2)


def test_a_rust_panic_becomes_a_fairfit_error():
    from fairfit import _fairfit

    with pytest.raises(fairfit.FairfitError, match=r"^internal error \(a test panic\); please report it"):
        _fairfit._panic_for_tests()


def test_duplicates_are_dropped_with_a_warning():
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    doubled = np.insert(pts, 5, pts[5], axis=0)
    with pytest.warns(fairfit.FairfitWarning, match="dropped 1 consecutive duplicate point"):
        c = fairfit.fit_curve(doubled)
    assert c.to_json() == fairfit.fit_curve(pts).to_json()


def test_help_is_useful():
    doc = fairfit.fit_curve.__doc__
    assert "rel_tol" in doc and "--rel-tol" in doc and "byte-identical" in doc
