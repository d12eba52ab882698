#!/usr/bin/env python3
"""The Python package's targets (issue 25), measured, not asserted: run it by hand on a quiet machine.

- overhead: `fairfit.fit_curve` on a 200-point curve against the library's own time for the same fit
  and report (the report's `wall_seconds`, measured inside the extension), target <= 5 %;
- evaluation: `curve(u)` for 10^6 parameters on one core, random and sorted, target >= 5 M points/s,
  and equal to the Rust evaluator's numbers (`fairfit eval` at a sample of them);
- the GIL: two Python threads fitting at once against the serial time, target <= 0.6x on 2 cores;
- Ray: the batch of the shared curves on a local 2-CPU Ray against the serial loop, byte for byte, both
  wall times (needs `ray`; `--data` is the shared data folder, default `../shared/data`).

Usage: python bench/python_targets.py [--data DIR] [--bin target/release/fairfit] [--skip-ray] [--only-eval]
(with the package installed: `pip install ./crates/fairfit-py`).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import glob
import json
import os
import subprocess
import tempfile
import time

import numpy as np

import fairfit

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
GROUPS = ["airfoils", "synthetic", os.path.join("iea15mw", "airfoils")]


def default_data() -> str:
    """The nearest `shared/data` beside the checkout or one of its parents (a worktree sits deeper)."""
    d = REPO
    while True:
        cand = os.path.join(os.path.dirname(d), "shared", "data")
        if os.path.isdir(cand) or os.path.dirname(d) == d:
            return cand
        d = os.path.dirname(d)


def shared_curves(data: str) -> list[str]:
    files = []
    for g in GROUPS:
        files += sorted(glob.glob(os.path.join(data, g, "*.csv")))
    return files


def overhead() -> dict:
    pts = fairfit.read_points(os.path.join(REPO, "examples", "data", "quarter_ellipse_200.csv"))
    fairfit.fit_curve(pts, threads=1)  # warm up
    rows = []
    for _ in range(5):
        t0 = time.perf_counter()
        c = fairfit.fit_curve(pts, threads=1)
        wall = time.perf_counter() - t0
        # the library's own time: the extension's whole call (fit and report, `wall_seconds`); the
        # search alone (`optimizer.seconds`) leaves out the report, which the CLI makes too
        rows.append((wall, c.report["wall_seconds"], c.report["optimizer"]["seconds"]))
    wall, lib, search = map(np.median, zip(*rows))
    return {
        "points": len(pts),
        "python_wall_s": wall,
        "library_s": lib,
        "library_search_s": search,
        "overhead": wall / lib - 1,
    }


def evaluation(binary: str | None) -> dict:
    """`curve(u)` for 10^6 random parameters and for 10^6 sorted ones (the spans found incrementally),
    the median and best wall time and the median CPU time of 7 calls each (one core: the evaluation is
    serial), and the numbers against `fairfit eval`."""
    pts = fairfit.read_points(os.path.join(REPO, "examples", "data", "naca4412.csv"))
    c = fairfit.fit_curve(pts)
    us = np.random.default_rng(0).uniform(0, 1, 1_000_000)
    c(us[:1000])
    row = {"parameters": len(us)}
    for label, u in (("random", us), ("sorted", np.linspace(0.0, 1.0, len(us)))):
        times, cpu = [], []
        for _ in range(7):
            t0, c0 = time.perf_counter(), time.process_time()
            out = c(u)
            times.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        # the CPU time of the (serial) call: what one core of its own would take; the wall time
        # also holds the waits for a core on a loaded machine
        row[label] = {
            "median_s": float(np.median(times)),
            "best_s": min(times),
            "points_per_s_median": len(u) / float(np.median(times)),
            "points_per_s_best": len(u) / min(times),
            "cpu_s_median": float(np.median(cpu)),
            "points_per_cpu_s": len(u) / float(np.median(cpu)),
        }
    out = c(us)
    if binary:
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "c.json")
            c.save(path)
            sample = us[:: len(us) // 100]
            at = ",".join(repr(float(u)) for u in sample)
            rows = json.loads(subprocess.run([binary, "eval", path, "--at", at], check=True,
                                             capture_output=True, text=True).stdout)
            ref = np.array([r["point"][:2] for r in rows])
            row["max_abs_difference_to_cli_eval"] = float(np.abs(out[:: len(us) // 100][: len(ref)] - ref).max())
    return row


def gil() -> dict:
    pts = fairfit.read_points(os.path.join(REPO, "examples", "data", "naca4412.csv"))
    fit = lambda _: fairfit.fit_curve(pts, threads=1).to_json()  # noqa: E731
    fit(0)
    t0 = time.perf_counter()
    serial = [fit(0), fit(1)]
    t_serial = time.perf_counter() - t0
    with cf.ThreadPoolExecutor(2) as ex:
        t0 = time.perf_counter()
        both = list(ex.map(fit, range(2)))
        t_threads = time.perf_counter() - t0
    assert both == serial
    return {"serial_s": t_serial, "two_threads_s": t_threads, "ratio": t_threads / t_serial}


def ray_batch(data: str) -> dict:
    import ray

    import fairfit.ray as fray

    files = shared_curves(data)
    t0 = time.perf_counter()
    serial = [fairfit.fit_curve(fairfit.read_points(f), threads=1, name=f).to_json() for f in files]
    t_serial = time.perf_counter() - t0
    ray.init(num_cpus=2, include_dashboard=False)
    try:
        fray.fit_curves(files[:2])  # workers started
        t0 = time.perf_counter()
        batch = fray.fit_curves(files)
        t_ray = time.perf_counter() - t0
    finally:
        ray.shutdown()
    same = [c.to_json() for c in batch.curves] == serial
    return {"curves": len(files), "serial_s": t_serial, "ray_s": t_ray, "identical": same}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=default_data(), help="the shared data folder")
    ap.add_argument("--bin", default=os.path.join(REPO, "target", "release", "fairfit"))
    ap.add_argument("--skip-ray", action="store_true")
    ap.add_argument("--only-eval", action="store_true", help="measure the evaluation alone")
    a = ap.parse_args()
    binary = a.bin if os.path.exists(a.bin) else None
    # a loaded machine slows the threads and the evaluation: the load is part of the result
    result = {"load_average_before": os.getloadavg()[0], "cpus": os.cpu_count()}
    if a.only_eval:
        result["evaluation"] = evaluation(binary)
        result["load_average_after"] = os.getloadavg()[0]
        print(json.dumps(result, indent=2))
        return
    result.update({"overhead": overhead(), "evaluation": evaluation(binary), "gil": gil()})
    if not a.skip_ray:
        result["ray"] = ray_batch(a.data)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
