"""fit_curve's screening, end conditions and limits against `fairfit curve` of the same build: the
same JSON bytes and report keys in every method, and the CLI's refusals as FairfitError."""

import json

import numpy as np
import pytest

import fairfit
from conftest import example


def arc(n, spikes=(), sigma=0.0, seed=0):
    """A circle arc of n points (radius 1, 3 rad), points `spikes` pushed out by 5 % (50 tolerances
    at rel_tol 1e-3), Gaussian noise `sigma` along the radius."""
    a = np.linspace(0.0, 3.0, n)
    r = 1.0 + sigma * np.random.default_rng(seed).standard_normal(n)
    r[list(spikes)] += 0.05
    return np.c_[r * np.cos(a), r * np.sin(a)]


def write_csv(path, pts):
    # repr round-trips every float: the CLI reads the numbers the array holds
    path.write_text("x,y\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in pts))
    return path


def both(cli, tmp_path, pts, flags, **kwargs):
    """The CLI's curve bytes, report and stderr, and fit_curve's curve and warnings, on the same points."""
    path = write_csv(tmp_path / "pts.csv", pts)
    out, rep = tmp_path / "c.json", tmp_path / "r.json"
    r = cli("curve", path, *flags, "-o", out, "--report", rep)
    with _Record() as rec:
        curve = fairfit.fit_curve(fairfit.read_points(path), name=str(path), **kwargs)
    return out.read_text(), json.loads(rep.read_text()), r.stderr, curve, rec.messages


class _Record:
    """Records FairfitWarnings (pytest.warns(None) is gone in pytest 8)."""

    def __enter__(self):
        import warnings

        self._cm = warnings.catch_warnings(record=True)
        self._list = self._cm.__enter__()
        warnings.simplefilter("always")
        return self

    def __exit__(self, *exc):
        self._cm.__exit__(*exc)
        self.messages = [str(w.message) for w in self._list if issubclass(w.category, fairfit.FairfitWarning)]
        return False


def same_report(mine, theirs):
    assert set(mine) == set(theirs)
    for k, v in theirs.items():
        if not k.endswith("seconds") and k != "optimizer":
            assert mine[k] == v, k


@pytest.mark.parametrize("method", ["integrated", "lsq", "fit-then-fair"])
def test_spikes_are_excluded_as_the_cli_does(cli, tmp_path, method):
    pts = arc(2000, spikes=(300, 1234))
    flags = ["--method", method] + (["--degree", "3"] if method != "integrated" else [])
    kw = {"method": method} if method == "integrated" else {"method": method, "degree": 3}
    cli_json, cli_rep, _, curve, _ = both(cli, tmp_path, pts, flags, **kw)
    assert curve.to_json() == cli_json
    same_report(curve.report, cli_rep)
    assert [o["index"] for o in curve.report["outliers"]] == [300, 1234]
    assert curve.report["outliers"][0]["distance"] == pytest.approx(0.05, abs=5e-3)
    assert curve.report["points"] == 1998 and curve.report["outliers_mode"] == "auto"


def test_spikes_kept_with_outliers_off_are_named_when_the_tolerance_is_missed(cli, tmp_path):
    pts = arc(400, spikes=(90, 250))
    flags = ["--outliers", "off", "--no-corners", "--control-points", "8"]
    cli_json, cli_rep, err, curve, warned = both(
        cli, tmp_path, pts, flags, outliers="off", corner_angle=None, control_points=8
    )
    assert curve.to_json() == cli_json
    same_report(curve.report, cli_rep)
    assert curve.report["outliers"] == [] and curve.report["outliers_mode"] == "off"
    assert curve.report["max_deviation"] > curve.report["tolerance"]
    (line,) = [l for l in err.splitlines() if "isolated spikes" in l]
    (mine,) = [w for w in warned if "isolated spikes" in w]
    assert "point 90" in mine and "point 250" in mine
    # the CLI's sentence, with the Python keyword for the flag
    assert mine == line.removeprefix("warning: ").replace("--outliers auto", "outliers='auto'")


def test_a_tolerance_below_the_noise_is_raised_in_every_method_as_the_cli_does(cli, tmp_path):
    pts = arc(4000, sigma=6e-4)  # sigma about 0.3 of the tolerance 2e-3
    for method in ["lsq", "fit-then-fair", "integrated"]:
        flags = ["--method", method] + (["--degree", "3"] if method != "integrated" else [])
        kw = {"method": method, "degree": 3 if method != "integrated" else "auto"}
        cli_json, cli_rep, err, curve, warned = both(cli, tmp_path, pts, flags, **kw)
        assert curve.to_json() == cli_json, method
        same_report(curve.report, cli_rep)
        r = curve.report
        assert r["noise_limited"] is True
        assert r["noise_sigma"] == pytest.approx(6e-4, rel=0.25)
        assert r["tolerance_used"] == r["meaningful_tolerance"] == pytest.approx(5 * r["noise_sigma"], rel=1e-12)
        assert r["tolerance"] == pytest.approx(2e-3, rel=1e-2) and r["max_deviation"] <= r["tolerance_used"]
        assert [w for w in warned if "below the noise" in w] == [
            l.removeprefix("warning: ") for l in err.splitlines() if "below the noise" in l
        ]


@pytest.mark.parametrize(
    "method, cond",
    [
        ("integrated", {"start": "tangent:-0.1,1"}),
        ("lsq", {"start": "tangent:-0.1,1", "end": "point:0,0.5"}),
        ("fit-then-fair", {"end": "curvature:-1,0:0.6"}),
        ("integrated", {"start_tangent": (-0.1, 1.0)}),
    ],
)
def test_end_conditions_give_the_cli_bytes_and_report(cli, tmp_path, method, cond):
    # the quarter ellipse x = cos t, y = sin(t) / 2: its own start tangent is (0, 1), its end
    # curvature 0.5
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    flags = ["--method", method] + (["--degree", "3"] if method != "integrated" else [])
    for k, v in cond.items():
        flags += [f"--{k.replace('_', '-')}", v if isinstance(v, str) else ",".join(map(repr, v))]
    kw = dict(cond, method=method, degree=3 if method != "integrated" else "auto")
    cli_json, cli_rep, _, curve, _ = both(cli, tmp_path, pts, flags, **kw)
    assert curve.to_json() == cli_json
    same_report(curve.report, cli_rep)
    ec = curve.report["end_conditions"]
    start = ec["start"] if ("start" in cond or "start_tangent" in cond) else ec["end"]
    assert start["order"] in ("g0", "g1", "g2")
    if start["tangent_angle"] is not None:
        assert start["tangent_angle"] < 1e-9
    assert ec["fairness_cost_ratio"] == pytest.approx(ec["fairness"] / ec["fairness_without_conditions"], rel=1e-12)
    # the tangent is held: the curve's first derivative at the start points along (-0.1, 1)
    if "start" in cond or "start_tangent" in cond:
        d = curve.derivatives(curve.domain[0], 1)[1]
        t = np.array([-0.1, 1.0]) / np.hypot(-0.1, 1.0)
        assert np.dot(d / np.linalg.norm(d), t) == pytest.approx(1.0, abs=1e-12)
    if "end" in cond and cond["end"].startswith("curvature"):
        assert curve.curvature(curve.domain[1]) == pytest.approx(0.6, rel=1e-9)
        assert ec["end"]["curvature_relative"] < 1e-9
    if "end" in cond and cond["end"].startswith("point"):
        assert np.abs(curve(curve.domain[1]) - [0.0, 0.5]).max() < 1e-12


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"knots": "averaging"}, "knots has no effect with method='integrated'; it needs method='lsq' or method='fit-then-fair'"),
        ({"param": "chord"}, "param has no effect with method='integrated'"),
        ({"smoothing": 1e-3}, "smoothing has no effect with method='integrated'"),
        ({"method": "lsq", "degree": 3, "span_fairness": 10.0}, "span_fairness has no effect with method='lsq'; it needs method='integrated'"),
        ({"method": "fit-then-fair", "band_fairing": False}, "band_fairing has no effect with method='fit-then-fair'"),
        ({"start": "tangent:1,0", "start_tangent": (1, 0)}, "start and start_tangent cannot be used together"),
        ({"end": "tangent:1"}, "end: expected X,Y or X,Y,Z, got 1 values, got `tangent:1`"),
        ({"start": "spline:1,0"}, "start: expected point"),
        ({"outliers": "some"}, "outliers: expected `auto` or `off`, got `some`"),
        ({"max_points": 100}, "invalid input data: <array>: 200 points, over the limit of 100 (raise it with max_points=N"),
        ({"max_points": -1}, "max_points must be a whole number >= 0, got -1"),
    ],
)
def test_options_the_cli_refuses_raise_fairfit_error(kwargs, message):
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    assert len(pts) == 200
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_curve(pts, **kwargs)
    assert str(e.value).startswith(message), str(e.value)


def test_the_cli_refuses_the_same_options(cli):
    path = example("quarter_ellipse_200.csv")
    r = cli("curve", path, "--knots", "averaging", check=False)
    assert r.returncode == 2 and "--knots has no effect with --method integrated" in r.stderr
    r = cli("--max-points", "100", "curve", path, check=False)
    assert r.returncode == 1 and "than the limit of 100 (raise it with --max-points N" in r.stderr
    # at the limit, fitted
    c = fairfit.fit_curve(fairfit.read_points(path), max_points=200, method="lsq", degree=3)
    assert c.report["points"] == 200


@pytest.mark.parametrize("method", ["integrated", "lsq", "fit-then-fair"])
def test_weights_and_points_to_interpolate_give_the_cli_bytes_and_report(cli, tmp_path, method):
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    w = np.ones(len(pts))
    w[50], w[120] = 2.0, 0.0
    wfile = tmp_path / "w.txt"
    wfile.write_text("".join(f"{float(x)!r}\n" for x in w))
    flags = ["--method", method, "--weights", wfile, "--interpolate", "10,100"]
    flags += ["--degree", "3"] if method != "integrated" else []
    kw = dict(method=method, degree=3 if method != "integrated" else "auto", weights=w, interpolate=[100, 10])
    cli_json, cli_rep, _, curve, _ = both(cli, tmp_path, pts, flags, **kw)
    assert curve.to_json() == cli_json
    same_report(curve.report, cli_rep)
    rep = curve.report
    assert [p["index"] for p in rep["point_constraints"]] == [10, 100]
    assert max(p["distance"] for p in rep["point_constraints"]) <= 1e-9 * 1.0
    assert rep["point_constraint_fit"]["ignored"] == [120]
    assert rep["point_constraint_fit"]["weighted_ratio"] <= 1.0


def test_a_weight_0_row_is_the_row_deleted():
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    w = np.ones(len(pts))
    w[77] = 0.0
    a = fairfit.fit_curve(pts, method="lsq", degree=3, weights=w)
    b = fairfit.fit_curve(np.delete(pts, 77, axis=0), method="lsq", degree=3)
    assert np.array_equal(a.control_points, b.control_points)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"weights": [1.0, 2.0]}, "weights: 2 weights for 200 points"),
        ({"weights": [-1.0] + [1.0] * 199}, "weights:"),
        ({"interpolate": [500]}, "interpolate:"),
        ({"interpolate": [-1]}, "interpolate: expected row indices >= 0"),
    ],
)
def test_bad_weights_and_indices_raise_fairfit_error(kwargs, message):
    pts = fairfit.read_points(example("quarter_ellipse_200.csv"))
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_curve(pts, **kwargs)
    assert str(e.value).startswith(message), str(e.value)
    assert "\n" not in str(e.value)
