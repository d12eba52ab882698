"""Tests of bench/constraints.py's bookkeeping (no fairfit binary, no data needed).

Run with `python -m pytest bench/test_constraints.py` or `python bench/test_constraints.py`.
"""

import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import constraints  # noqa: E402
import measure  # noqa: E402


def _quadratic():
    # the Bézier (0,0), (1,0), (1,1): C'(0) = (2,0), C''(0) = (-2,2) -> kappa = 2*2/8 = 0.5 at both ends
    return measure.Curve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 0], [1, 1]])


def test_end_frame_is_the_analytic_tangent_and_signed_curvature():
    c = _quadratic()
    t0, k0 = constraints.end_frame(c, False)
    t1, k1 = constraints.end_frame(c, True)
    assert np.allclose(t0, [1, 0], atol=1e-15) and np.allclose(t1, [0, 1], atol=1e-15)
    assert abs(k0 - 0.5) < 1e-15 and abs(k1 - 0.5) < 1e-15


def test_condition_text_round_trips_the_floats():
    text = constraints.condition(np.array([0.1, -0.3]), np.float64(1 / 3))
    kind, t, k = text.split(":")
    assert kind == "curvature"
    assert [float(x) for x in t.split(",")] == [0.1, -0.3] and float(k) == 1 / 3


def _row(name, ratio, ext=(1, 1), angle=1e-15, k=1e-14, dev=0.5):
    return dict(name=name, ratio=ratio, ext_free=ext[0], ext_g2=ext[1], angle=angle, curvature_rel=k,
                max_dev_g2=dev, tol=1.0)


def test_summary_takes_the_geometric_mean_and_counts_misses():
    s = constraints.summary([_row("a", 2.0), _row("b", 0.5, ext=(1, 3)), {"name": "c", "error": "x"}])
    assert abs(s["geo_mean_F_ratio"] - 1.0) < 1e-15
    assert s["failed"] == 1 and s["extrema_increased"] == 1 and s["curves"] == 3
    assert not constraints.targets_met(s)
    ok = constraints.summary([_row("a", 1.04), _row("b", 1.0)])
    assert math.isclose(ok["geo_mean_F_ratio"], math.sqrt(1.04)) and constraints.targets_met(ok)
    bad = constraints.summary([_row("a", 1.0, angle=2e-9)])
    assert not constraints.targets_met(bad)


if __name__ == "__main__":
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn):
            fn()
            print("ok", name)
