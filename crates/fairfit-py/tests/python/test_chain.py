"""fit_chain against `fairfit curve A B --chain g1|g2` of the same build: the same bytes for the
joined chain and every piece, the same report; the joins' continuity measured here from the returned
curves' own derivatives; and the CLI's refusals as FairfitError."""

import json

import numpy as np
import pytest

import fairfit
from conftest import example


def write_csv(path, pts):
    # repr round-trips every float: the CLI reads the numbers the array holds
    path.write_text("x,y\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in pts))
    return path


def naca4412_halves():
    """NACA 4412 (the bundled Lednicer file) split at its leading edge, the point farthest from the
    trailing edge: upper surface TE -> LE, lower surface LE -> TE, both holding the LE point."""
    pts = fairfit.read_points(example("naca4412.csv"))
    te = (pts[0] + pts[-1]) / 2
    le = int(np.argmax(np.linalg.norm(pts - te, axis=1)))
    assert 0 < le < len(pts) - 1
    return pts[: le + 1], pts[le:]


def ellipse_halves(n=60):
    """The upper half of the ellipse x = 2 cos t, y = sin t split at t = pi/2 (the ends of the minor
    axis), both quarters holding the split point (0, 1), where the curvature is b / a^2 = 1/4."""
    t1 = np.linspace(0.0, np.pi / 2, n)
    t2 = np.linspace(np.pi / 2, np.pi, n)
    return np.c_[2 * np.cos(t1), np.sin(t1)], np.c_[2 * np.cos(t2), np.sin(t2)]


def end_frame(curve, at_end):
    """Point, unit tangent and curvature vector of `curve` at the start or end of its domain, from
    its derivatives through the Python API (C, C', C'' at the exact end parameter)."""
    a, b = curve.domain
    d = curve.derivatives(b if at_end else a, 2)
    p, d1, d2 = (np.r_[v, 0.0] if len(v) == 2 else np.asarray(v) for v in d)
    speed = np.linalg.norm(d1)
    k = np.cross(np.cross(d1, d2), d1) / speed**4
    return p, d1 / speed, k


def join_measures(before, after):
    """(position gap, tangent angle in radians, relative curvature difference) of the join of
    `before`'s end and `after`'s start."""
    p0, t0, k0 = end_frame(before, True)
    p1, t1, k1 = end_frame(after, False)
    angle = np.arctan2(np.linalg.norm(np.cross(t0, t1)), np.dot(t0, t1))
    scale = max(np.linalg.norm(k0), np.linalg.norm(k1))
    rel = np.linalg.norm(k0 - k1) / scale if scale > 0 else 0.0
    return np.linalg.norm(p0 - p1), angle, rel, np.linalg.norm(k0)


def cli_chain(cli, tmp_path, halves, continuity, flags=()):
    """The CLI's chain of `halves` written as CSV files: (joined bytes, [piece bytes], report, the
    paths of the inputs, stderr)."""
    paths = [write_csv(tmp_path / f"p{k + 1}.csv", h) for k, h in enumerate(halves)]
    out, rep = tmp_path / "chain.json", tmp_path / "report.json"
    r = cli("curve", *paths, "--chain", continuity, *flags, "-o", out, "--report", rep)
    pieces = [(tmp_path / f"chain_{k + 1}.json").read_text() for k in range(len(halves))]
    return out.read_text(), pieces, json.loads(rep.read_text()), paths, r.stderr


def same_report(mine, theirs):
    """Equal reports but for wall times and the files the CLI wrote the pieces to."""
    assert set(mine) == set(theirs)
    for k, v in theirs.items():
        if k == "pieces":
            assert len(mine[k]) == len(v)
            for m, t in zip(mine[k], v):
                t = {x: y for x, y in t.items() if x != "output"}
                assert set(m) == set(t)
                for x, y in t.items():
                    if not x.endswith("seconds") and x != "optimizer":
                        assert m[x] == y, (k, x)
        elif not k.endswith("seconds"):
            assert mine[k] == v, k


def arc_then_line():
    """A quarter of the unit circle from (0, -1) to (1, 0), then the straight line on to (1, 1.5)
    that leaves it tangentially: G1 at (1, 0), the curvature jumping from 1 to 0. A G1 chain may
    keep the jump (each piece its own fit); a G2 chain must blend it."""
    t = np.linspace(-np.pi / 2, 0.0, 40)
    return np.c_[np.cos(t), np.sin(t)], np.c_[np.ones(30), np.linspace(0.0, 1.5, 30)]


@pytest.mark.parametrize("continuity", ["g1", "g2"])
@pytest.mark.parametrize("data", ["naca4412", "arc_then_line"])
def test_a_chain_gives_the_cli_bytes_and_report(cli, tmp_path, data, continuity):
    halves = naca4412_halves() if data == "naca4412" else arc_then_line()
    joined_cli, pieces_cli, rep_cli, paths, _ = cli_chain(cli, tmp_path, halves, continuity)
    chain, pieces = fairfit.fit_chain(
        [fairfit.read_points(p) for p in paths], continuity, names=[str(p) for p in paths]
    )
    assert chain.to_json() == joined_cli
    assert [p.to_json() for p in pieces] == pieces_cli
    same_report(chain.report, rep_cli)
    assert chain.report["chain"] == continuity and len(chain.report["joins"]) == 1
    assert [p.report for p in pieces] == chain.report["pieces"]
    assert chain.domain == (0.0, 2.0) and chain.dim == 2
    assert chain.report["tolerance_met"] is True
    assert chain.report["max_deviation"] <= chain.report["tolerance"]
    # relative 1e-3 of the largest side: the chord 1 of the airfoil, the line's 2.5 in y
    side = 1.0 if data == "naca4412" else 2.5
    assert chain.report["tolerance"] == pytest.approx(1e-3 * side, rel=1e-2)


@pytest.mark.parametrize("continuity", ["g1", "g2"])
def test_the_joins_hold_their_continuity_measured_on_the_returned_curves(continuity):
    a, b = arc_then_line()
    chain, (c1, c2) = fairfit.fit_chain([a, b], continuity)
    gap, angle, rel, kappa = join_measures(c1, c2)
    assert gap <= 1e-12
    assert angle <= 1e-9
    tol = chain.report["tolerance"]
    p, t, _ = end_frame(c1, True)
    assert np.linalg.norm(p[:2] - [1.0, 0.0]) <= tol
    # the data's tangent (0, 1) to 0.1 rad: the fairest curve within the tolerance rounds the jump
    assert np.linalg.norm(t[:2] - [0.0, 1.0]) < 0.1
    if continuity == "g2":
        assert rel <= 1e-9
    else:
        # a real G1 join: the arc's piece is its own fit, its curvature its own (about the circle's
        # 1, the line's 0 on the other side), not the G2 blend of the single curve
        assert chain.report["pieces"][0]["from_single_curve"] is False
        assert rel > 1e-3
    # the report's measures are those of the returned curves
    j = chain.report["joins"][0]
    assert j["tangent_angle"] <= 1e-9 and j["position_gap"] <= 1e-12
    assert j["curvature"] == pytest.approx(kappa, rel=1e-9)
    assert j["curvature_relative"] == pytest.approx(rel, rel=1e-6, abs=1e-12)
    # the joined curve is the two pieces, each mapped onto [k, k + 1]
    u = np.linspace(0.0, 1.0, 101)
    for k, c in enumerate((c1, c2)):
        lo, hi = c.domain
        assert np.abs(chain(k + u) - c(lo + u * (hi - lo))).max() <= 1e-12
    # and as continuous there, seen from either side of the knot at 1 (one-sided derivatives)
    d_left, d_right = chain.derivatives(1.0 - 1e-13, 2), chain.derivatives(1.0 + 1e-13, 2)
    t_left, t_right = (d[1] / np.linalg.norm(d[1]) for d in (d_left, d_right))
    cross = t_left[0] * t_right[1] - t_left[1] * t_right[0]
    assert abs(np.arctan2(cross, t_left @ t_right)) <= 1e-9


def test_the_chain_fits_the_ellipse_within_the_tolerance_and_matches_the_cli_with_options(cli, tmp_path):
    halves = ellipse_halves()
    flags = ["--rel-tol", "1e-4", "--degree", "3", "--seed", "3", "--end", "tangent:-0.1,-1"]
    joined_cli, pieces_cli, rep_cli, paths, _ = cli_chain(cli, tmp_path, halves, "g2", flags)
    chain, pieces = fairfit.fit_chain(
        list(halves),
        rel_tol=1e-4,
        degree=3,
        seed=3,
        end="tangent:-0.1,-1",
        names=[str(p) for p in paths],
    )
    assert chain.to_json() == joined_cli
    assert [p.to_json() for p in pieces] == pieces_cli
    same_report(chain.report, rep_cli)
    assert chain.report["max_deviation"] <= chain.report["tolerance"] == pytest.approx(4e-4)
    # G2 at the end of the minor axis, (0, 1), where the curvature is b / a^2 = 1/4
    gap, angle, rel, kappa = join_measures(*pieces)
    assert gap <= 1e-12 and angle <= 1e-9 and rel <= 1e-9
    assert kappa == pytest.approx(0.25, rel=0.02)
    # the chain's own end condition held by the last piece
    _, t, _ = end_frame(pieces[1], True)
    assert np.linalg.norm(t[:2] - np.array([-0.1, -1.0]) / np.hypot(0.1, 1.0)) <= 1e-9


def test_pieces_that_do_not_meet_raise_the_clis_message(cli, tmp_path):
    a, b = ellipse_halves()
    b = b + [0.0, 0.05]  # 0.05 apart: more than twice the tolerance 4e-3
    paths = [write_csv(tmp_path / f"p{k}.csv", h) for k, h in enumerate((a, b))]
    r = cli("curve", *paths, "--chain", "g2", "-o", tmp_path / "c.json", check=False)
    assert r.returncode == 1
    (line,) = [l for l in r.stderr.splitlines() if l.startswith("error: ")]
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_chain([a, b])
    assert str(e.value) == line.removeprefix("error: ")
    assert str(e.value).startswith("invalid input data: chain pieces 1 and 2 do not meet: ")
    assert "5.000e-2" in str(e.value) and "4.000e-3" in str(e.value)


def test_fewer_than_two_pieces_are_refused_as_the_cli_refuses_one_file(cli, tmp_path):
    a, _ = ellipse_halves()
    path = write_csv(tmp_path / "a.csv", a)
    r = cli("curve", path, "--chain", "g2", "-o", tmp_path / "c.json", check=False)
    assert r.returncode == 2
    assert "--chain needs at least two point files (the pieces, in order), got 1" in r.stderr
    for pieces in ([a], []):
        with pytest.raises(fairfit.FairfitError) as e:
            fairfit.fit_chain(pieces)
        assert str(e.value) == (
            f"fit_chain needs at least two point sets (the pieces, in order), got {len(pieces)}"
        )


@pytest.mark.parametrize("bad", ["g3", "G2", "", 2])
def test_a_bad_continuity_is_refused(bad):
    a, b = ellipse_halves()
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_chain([a, b], bad)
    shown = repr(bad) if not isinstance(bad, str) else bad
    assert str(e.value) == f"continuity: expected `g1` or `g2`, got `{shown}`"


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_points_are_refused_with_their_piece_and_row(value):
    a, b = ellipse_halves()
    b = b.copy()
    b[7, 1] = value
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_chain([a, b], "g1")
    shown = "NaN" if np.isnan(value) else "inf"
    assert str(e.value) == f"invalid input data: <piece 2>: point 7: value '{shown}' is not a finite number"
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_chain([a, b], "g1", names=["upper", "lower"])
    assert str(e.value).startswith("invalid input data: lower: point 7: ")


def test_bad_pieces_and_options_raise_fairfit_error_not_a_crash():
    a, b = ellipse_halves()
    cases = [
        ([a, a[:1]], "invalid input data: <piece 2>: at least 2 distinct points are needed, found 1"),
        ([a, np.zeros((5, 4))], "invalid input data: piece 2 must be an (n, 2) or (n, 3) array, got shape (5, 4)"),
        ("ab", "pieces must be a list of (n, 2) or (n, 3) arrays (the point sets, in order), got str"),
    ]
    for pieces, message in cases:
        with pytest.raises(fairfit.FairfitError) as e:
            fairfit.fit_chain(pieces)
        assert str(e.value) == message
    with pytest.raises(fairfit.FairfitError, match=r"^corner_angle must be in \(0, 180\] degrees, got 200$"):
        fairfit.fit_chain([a, b], corner_angle=200)
    with pytest.raises(fairfit.FairfitError, match=r"^degree: expected `auto` or a degree from 1 to 15, got `16`$"):
        fairfit.fit_chain([a, b], degree=16)
    with pytest.raises(fairfit.FairfitError, match=r"^outliers: expected `auto` or `off`, got `no`$"):
        fairfit.fit_chain([a, b], outliers="no")
    with pytest.raises(TypeError):
        fairfit.fit_chain([a, b], method="lsq")  # not a chain's keyword, as the CLI refuses it


def test_duplicates_are_dropped_with_the_clis_warning():
    a, b = ellipse_halves(30)
    a = np.insert(a, 5, a[5], axis=0)
    with pytest.warns(fairfit.FairfitWarning, match=r"^upper: dropped 1 consecutive duplicate point\(s\)$"):
        chain, _ = fairfit.fit_chain([a, b], "g1", degree=3, names=["upper", "lower"])
    assert chain.report["pieces"][0]["points"] == 30
