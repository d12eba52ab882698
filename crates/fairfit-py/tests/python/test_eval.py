"""curve(u) written into the output array: sorted parameters (spans found incrementally), unsorted
ones, knots hit exactly and the domain's ends, against scipy's independent evaluator, the analytic
circle of a rational curve and the CLI's `fairfit eval`."""

import numpy as np
import pytest

import fairfit
from conftest import cli_eval, example


@pytest.fixture(scope="module")
def naca():
    return fairfit.fit_curve(fairfit.read_points(example("naca4412.csv")), method="lsq", degree=3)


def test_sorted_unsorted_and_scalar_evaluation_agree_bit_for_bit(naca):
    a, b = naca.domain
    knots = np.unique(naca.knots)
    # sorted, with every knot hit exactly, and repeated parameters
    us = np.sort(np.r_[np.linspace(a, b, 100_001), knots, knots[3:6]])
    sorted_pts = naca(us)
    assert sorted_pts.shape == (len(us), 2) and sorted_pts.dtype == np.float64
    perm = np.random.default_rng(3).permutation(len(us))
    shuffled = naca(us[perm])
    assert np.array_equal(shuffled, sorted_pts[perm])
    assert np.array_equal(naca(us[::-1]), sorted_pts[::-1])
    for i in [0, 1, len(us) // 2, len(us) - 1]:
        assert np.array_equal(naca(float(us[i])), sorted_pts[i])
    # a strided view and a list give the same numbers
    assert np.array_equal(naca(us[::7]), sorted_pts[::7])
    assert np.array_equal(naca(list(us[:50])), sorted_pts[:50])
    # the ends are the data's end points (pinned)
    assert np.array_equal(sorted_pts[0], naca.control_points[0])
    assert np.array_equal(sorted_pts[-1], naca.control_points[-1])


def test_evaluation_equals_scipy_to_1e_12(naca):
    a, b = naca.domain
    us = np.r_[np.linspace(a, b, 200_001), np.unique(naca.knots)]
    spl = naca.to_scipy()
    scale = np.abs(naca.control_points).max()
    for u in (np.sort(us), np.random.default_rng(5).permutation(us)):
        assert np.abs(naca(u) - spl(u)).max() <= 1e-12 * scale


def test_a_rational_quarter_circle_lies_on_the_circle():
    w = np.sqrt(0.5)
    c = fairfit.Curve(2, [0, 0, 0, 1, 1, 1], [[1, 0], [1, 1], [0, 1.0]], [1, w, 1])
    us = np.linspace(0, 1, 10_001)
    pts = c(us)
    assert pts.shape == (len(us), 2)
    assert np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 1.0).max() < 1e-15
    # the angle of the rational quadratic's point: tan(theta/2) = w u / (w u + (1 - u)) ... checked
    # at the middle, 45 degrees
    assert np.allclose(c(0.5), [w, w], atol=1e-15)


def test_evaluation_of_a_3d_curve_equals_the_cli_eval(cli, tmp_path):
    t = np.linspace(0, 4 * np.pi, 300)
    c = fairfit.fit_curve(np.c_[np.cos(t), np.sin(t), 0.1 * t], method="lsq", degree=3)
    path = tmp_path / "helix.json"
    c.save(path)
    us = np.linspace(*c.domain, 17)
    rows = cli_eval(cli, path, us)
    got = c(us)
    assert got.shape == (17, 3)
    for g, row in zip(got, rows):
        np.testing.assert_allclose(g, row["point"], rtol=1e-15, atol=1e-15)


def test_parameters_outside_the_domain_or_not_numbers_raise():
    c = fairfit.fit_curve(fairfit.read_points(example("quarter_ellipse_200.csv")), method="lsq", degree=3)
    with pytest.raises(fairfit.FairfitError, match="outside"):
        c(np.array([0.5, 1.5]))
    with pytest.raises(fairfit.FairfitError, match="parameters must be numbers"):
        c(np.array(["a"]))
    with pytest.raises(fairfit.FairfitError):
        c(np.array([0.5, np.nan]))
