"""fit_surface and Surface against the CLI of the same build, with numbers."""

import json
import pickle

import numpy as np
import pytest

import fairfit


def sections():
    """Five open sections (elliptic arcs growing along z), 40 points each."""
    t = np.linspace(0.0, np.pi, 40)
    out = []
    for k in range(5):
        a, b = 1.0 + 0.1 * k, 0.5 + 0.05 * k * k
        out.append(np.c_[a * np.cos(t), b * np.sin(t), np.full_like(t, 0.5 * k)])
    return out


def write_sections(tmp_path):
    paths = []
    for k, s in enumerate(sections()):
        p = tmp_path / f"s{k}.csv"
        p.write_text("".join(f"{float(x)!r},{float(y)!r},{float(z)!r}\n" for x, y, z in s))
        paths.append(p)
    return paths


@pytest.fixture(scope="module")
def surface():
    return fairfit.fit_surface(sections(), rel_tol=1e-3)


def test_fit_surface_gives_the_cli_json_bytes(cli, tmp_path):
    paths = write_sections(tmp_path)
    out = tmp_path / "s.json"
    cli("surface", *paths, "--rel-tol", "1e-3", "-o", out, "--report", tmp_path / "r.json")
    s = fairfit.fit_surface(sections(), rel_tol=1e-3, names=[str(p) for p in paths])
    assert s.to_json() == out.read_text()
    report = json.loads((tmp_path / "r.json").read_text())
    assert set(s.report) == set(report)
    for key in ["tolerance", "within_tolerance", "net", "degree", "knots_u", "v_params", "sections"]:
        assert s.report[key] == report[key], key


def test_surface_evaluation_equals_the_cli_eval(cli, surface, tmp_path):
    path = tmp_path / "s.json"
    surface.save(path)
    (u0, u1), (v0, v1) = surface.domain
    us = np.linspace(u0, u1, 4)
    vs = np.linspace(v0, v1, 3)
    grid = surface(us, vs)
    assert grid.shape == (4, 3, 3)
    at = ",".join(f"{float(u)!r}:{float(v)!r}" for u in us for v in vs)
    rows = json.loads(cli("eval", path, "--at", at).stdout)
    for n, row in enumerate(rows):
        np.testing.assert_allclose(grid[n // 3, n % 3], row["point"], rtol=1e-12, atol=1e-14)
    pairs = surface(us[:3], vs, grid=False)
    np.testing.assert_array_equal(pairs, np.stack([grid[i, i] for i in range(3)]))


def test_surface_passes_through_its_sections(surface):
    assert surface.report["within_tolerance"]
    assert surface.report["deviation"]["max"] <= surface.report["tolerance"]
    assert surface.degree == (3, 3)
    nu, nv = surface.report["net"]
    assert surface.control_points.shape == (nu, nv, 3)
    assert surface.weights.shape == (nu, nv)
    assert surface.closed == (False, False)


def test_surface_pickle_and_step_round_trip(surface, tmp_path):
    back = pickle.loads(pickle.dumps(surface))
    assert back.to_json() == surface.to_json() and back.report == surface.report
    path = tmp_path / "s.step"
    surface.save(path)
    read = fairfit.read(path)
    assert isinstance(read, fairfit.Surface)
    (u0, u1), (v0, v1) = surface.domain
    us, vs = np.linspace(u0, u1, 9), np.linspace(v0, v1, 7)
    np.testing.assert_allclose(read(us, vs), surface(us, vs), rtol=0, atol=1e-12)


def test_surface_errors():
    with pytest.raises(fairfit.FairfitError, match="a surface needs at least 2 sections, got 1"):
        fairfit.fit_surface(sections()[:1])
    with pytest.raises(fairfit.FairfitError, match="section 1: a section needs at least 3 points, got 2"):
        fairfit.fit_surface([sections()[0], sections()[1][:2]])


def test_a_grid_no_memory_holds_is_refused_with_one_line(surface):
    # before: the (u, v) pairs of a 10^7 x 10^7 grid were collected into a vector, whose growth
    # aborted the interpreter when the allocation failed
    u = np.full(10**7, 0.5)
    with pytest.raises(fairfit.FairfitError, match=r"^invalid input data: surface\(u, v, grid=True\): not enough memory") as e:
        surface(u, u, grid=True)
    assert "\n" not in str(e.value)
    # an ordinary grid is unchanged
    assert surface(np.array([0.0, 0.5]), np.array([0.5]), grid=True).shape == (2, 1, 3)


def test_more_sections_than_max_sections_are_refused_before_any_work(tmp_path):
    assert fairfit.DEFAULT_MAX_SECTIONS == 1000
    with pytest.raises(fairfit.FairfitError) as e:
        fairfit.fit_surface(sections(), max_sections=4)
    assert str(e.value) == "5 sections are above the limit of 4; raise it with max_sections=N"
    # the limit itself is allowed
    assert isinstance(fairfit.fit_surface(sections(), max_sections=5), fairfit.Surface)
    with pytest.raises(fairfit.FairfitError, match="slices 2000 is above the limit of 1000 sections"):
        fairfit.fit_surface_from_mesh(tmp_path / "absent.ply", 2000)
    with pytest.raises(fairfit.FairfitError, match="max_sections must be a whole number >= 0"):
        fairfit.fit_surface(sections(), max_sections=-1)


def test_v_end_tangents_give_the_cli_bytes_and_hold_the_direction(cli, tmp_path):
    paths = write_sections(tmp_path)
    out, rep = tmp_path / "s.json", tmp_path / "r.json"
    d0, d1 = [0.2, 0.0, 1.0], [0.0, 0.3, 1.0]
    cli(
        "surface", *paths, "--rel-tol", "1e-3", "--start-tangent-v", "0.2,0,1",
        "--end-tangent-v", "0,0.3,1", "-o", out, "--report", rep,
    )
    s = fairfit.fit_surface(
        sections(), rel_tol=1e-3, names=[str(p) for p in paths], start_tangent_v=d0,
        end_tangent_v=np.array(d1),
    )
    assert s.to_json() == out.read_text()
    report = json.loads(rep.read_text())
    assert s.report["v_end_tangents"] == report["v_end_tangents"]
    for end, d in [("start", d0), ("end", d1)]:
        assert s.report["v_end_tangents"][end]["max_angle"] <= 1e-9
        np.testing.assert_allclose(s.report["v_end_tangents"][end]["direction"], np.array(d) / np.linalg.norm(d))
    # one more control point across per end; without the keywords no such report key
    assert s.report["net"][1] == 7
    assert "v_end_tangents" not in fairfit.fit_surface(sections(), rel_tol=1e-3).report


def test_v_end_tangent_errors():
    for bad, msg in [
        ([0, 0, 0], "start_tangent_v must be a finite non-zero vector"),
        ([np.nan, 0, 1], "start_tangent_v must be a finite non-zero vector"),
        ([1, 2], "start_tangent_v must be X,Y,Z, got 2 values"),
    ]:
        with pytest.raises(fairfit.FairfitError, match=msg):
            fairfit.fit_surface(sections(), start_tangent_v=bad)
    with pytest.raises(fairfit.FairfitError, match="need degree_v 2 or more"):
        fairfit.fit_surface(sections(), end_tangent_v=[0, 0, 1], degree_v=1)
    with pytest.raises(fairfit.FairfitError, match="at least 4 control points"):
        fairfit.fit_surface(sections(), start_tangent_v=[0, 0, 1], end_tangent_v=[0, 0, 1], approximate_v=3)


def d_sections():
    """Four closed D-shaped sections (a half-ellipse over the top, closed by the straight segment
    along y = 0): a corner at the seam and one inside (as the CLI test of held corners)."""
    out = []
    for z in [0.0, 1.0, 2.5, 3.0]:
        a, b = 2.0 + 0.3 * z, 1.0 + 0.1 * z * z
        t = np.pi * np.arange(61) / 60.0
        top = np.column_stack([a * np.cos(t), b * np.sin(t), np.full(61, z)])
        x = -a + 2.0 * a * np.arange(1, 21) / 20.0
        base = np.column_stack([x, np.zeros(20), np.full(20, z)])
        out.append(np.vstack([top, base]))
    return out


def test_corner_angle_holds_inner_corners_as_the_cli_does(cli, tmp_path):
    paths = []
    for k, s in enumerate(d_sections()):
        p = tmp_path / f"sec_{k}.csv"
        np.savetxt(p, s, delimiter=",", fmt="%.17g")
        paths.append(p)
    names = [str(p) for p in paths]
    for flags, kw, held, found in [
        ([], {}, True, 1),
        (["--no-corners"], {"corner_angle": None}, False, 1),
        (["--corner-angle", "100"], {"corner_angle": 100}, False, 0),
    ]:
        out, rep = tmp_path / "s.json", tmp_path / "r.json"
        cli("surface", *paths, "--tol", "1e-3", *flags, "-o", out, "--report", rep)
        s = fairfit.fit_surface(d_sections(), tol=1e-3, names=names, **kw)
        assert s.to_json() == out.read_text(), flags
        c = s.report["corners"]
        assert c == json.loads(rep.read_text())["corners"]
        assert c["held"] is held and c["per_section"] == [found] * 4, (flags, c)
    with pytest.raises(fairfit.FairfitError, match=r"corner_angle must be in \(0, 180\] degrees"):
        fairfit.fit_surface(d_sections(), corner_angle=0)


def naca_sections():
    """Three open NACA 00tt sections (thickness 12 %, 15 %, 18 %), chord shrinking and twisted
    along z: upper trailing edge round the nose (x = 0, the leading edge) to the lower one."""
    out = []
    for k, t in enumerate([0.12, 0.15, 0.18]):
        x = 0.5 * (1.0 + np.cos(np.pi * np.arange(81) / 80.0))
        yt = 5 * t * (0.2969 * np.sqrt(x) - 0.126 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1015 * x**4)
        xs = np.r_[x, x[::-1][1:]]
        ys = np.r_[yt, -yt[::-1][1:]]
        c, tw = 1.0 - 0.1 * k, np.radians(5.0 * k)
        px, py = (xs - 0.25) * c, ys * c
        out.append(np.column_stack([np.cos(tw) * px - np.sin(tw) * py, np.sin(tw) * px + np.cos(tw) * py, np.full(len(xs), 0.8 * k)]))
    return out


def save_csvs(tmp_path, arrays, stem):
    """Each array as `stem_K.csv` (17 significant digits: the CLI reads the numbers the array holds)."""
    paths = []
    for k, a in enumerate(arrays):
        p = tmp_path / f"{stem}_{k}.csv"
        np.savetxt(p, a, delimiter=",", fmt="%.17g")
        paths.append(p)
    return paths


def test_split_at_le_pins_the_noses_as_the_cli_does(cli, tmp_path):
    paths = save_csvs(tmp_path, naca_sections(), "sec")
    out, rep = tmp_path / "s.json", tmp_path / "r.json"
    cli("surface", *paths, "--tol", "1e-4", "--split-at-le", "-o", out, "--report", rep)
    s = fairfit.fit_surface(naca_sections(), tol=1e-4, names=[str(p) for p in paths], split_at_le=True)
    assert s.to_json() == out.read_text()
    le = s.report["split_at_le"]
    assert le == json.loads(rep.read_text())["split_at_le"]
    assert le["parameter"] == 0.5 and s.report["within_tolerance"]
    for k, (row, sec) in enumerate(zip(le["sections"], naca_sections())):
        nose = sec[80]  # the point at chord position 0: farthest from the trailing edge
        np.testing.assert_array_equal(row["point"], nose)
        on = s(np.array([0.5]), np.array([s.report["v_params"][k]]))[0, 0]
        assert np.linalg.norm(on - nose) <= 1e-9, k
    assert "split_at_le" not in fairfit.fit_surface(naca_sections(), tol=1e-4).report
    # elliptic arcs: the farthest points from the midpoint of the ends are the ends
    with pytest.raises(fairfit.FairfitError, match="section 0: no leading edge"):
        fairfit.fit_surface(sections(), split_at_le=True)


def rings():
    """Three wavy rings (ellipses 1 x (0.6 + 0.1 k) at z = k), 200 points at equal steps of a 200-step
    turn: each stops one step short of closing."""
    t = 2.0 * np.pi * np.arange(200) / 200.0
    r = 1.0 + 0.05 * np.cos(3.0 * t)
    return [np.c_[r * np.cos(t), (0.6 + 0.1 * k) * r * np.sin(t), np.full_like(t, float(k))] for k in range(3)]


def test_rings_one_step_short_are_closed_as_the_cli_does(cli, tmp_path):
    paths = save_csvs(tmp_path, rings(), "ring")
    out, rep = tmp_path / "s.json", tmp_path / "r.json"
    cli("surface", *paths, "--tol", "0.04", "-o", out, "--report", rep)
    s = fairfit.fit_surface(rings(), tol=0.04, names=[str(p) for p in paths])
    assert s.to_json() == out.read_text()
    assert s.report["sections"] == json.loads(rep.read_text())["sections"]
    assert s.report["periodic_u"]
    for row, ring in zip(s.report["sections"], rings()):
        assert row["closed"] and row["points"] == 201
        assert row["closed_by_gap"] == pytest.approx(np.linalg.norm(ring[0] - ring[-1]), rel=1e-12)
    kept = fairfit.fit_surface(rings(), tol=0.04, open_sections=True)
    assert not kept.report["periodic_u"]
    assert all(not row["closed"] and "closed_by_gap" not in row for row in kept.report["sections"])
