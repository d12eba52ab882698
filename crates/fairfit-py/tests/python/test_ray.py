"""fairfit.ray on a local Ray instance (2 CPUs): the batch equals the serial loop byte for byte."""

import json
import os
import shutil

import pytest

ray = pytest.importorskip("ray", reason="ray is not installed (optional dependency)")

import fairfit  # noqa: E402
import fairfit.ray as fray  # noqa: E402
from conftest import example  # noqa: E402

FILES = ["naca4412.csv", "clarky.csv", "quarter_ellipse_200.csv"]


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()


def test_fit_curves_equals_the_serial_loop_and_writes_a_summary(local_ray, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    for f in FILES:
        shutil.copy(example(f), folder / f)
    (folder / "broken.csv").write_text("0,0\n")
    out = tmp_path / "out"
    batch = fray.fit_curves(str(folder), output=str(out), rel_tol=1e-3, seed=0)
    names = sorted(FILES + ["broken.csv"])
    assert [r["input"] for r in batch.rows] == [str(folder / n) for n in names]
    for name, curve, row in zip(names, batch.curves, batch.rows):
        if name == "broken.csv":
            assert curve is None and not row["ok"]
            assert "at least 2 distinct points are needed, found 1" in row["error"]
            continue
        serial = fairfit.fit_curve(fairfit.read_points(folder / name), rel_tol=1e-3, seed=0)
        assert curve.to_json() == serial.to_json()
        assert (out / (os.path.splitext(name)[0] + ".json")).read_text() == serial.to_json()
        assert row["ok"] and row["control_points"] == serial.report["control_points"]
    lines = (out / "summary.jsonl").read_text().splitlines()
    assert len(lines) == 4
    assert [json.loads(l)["ok"] for l in lines] == [n != "broken.csv" for n in names]


def test_fit_curves_of_arrays_and_surfaces(local_ray):
    pts = [fairfit.read_points(example(f)) for f in FILES[:2]]
    batch = fray.fit_curves(pts, method="lsq")
    assert [c.to_json() for c in batch.curves] == [fairfit.fit_curve(p, method="lsq").to_json() for p in pts]
    from test_surface import sections

    s = fray.fit_surfaces([sections(), sections()[:3]])
    assert [x.to_json() for x in s.results] == [
        fairfit.fit_surface(sections()).to_json(),
        fairfit.fit_surface(sections()[:3]).to_json(),
    ]
