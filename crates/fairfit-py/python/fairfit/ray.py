"""fairfit on a Ray cluster: fleets of curves (and surfaces) fitted as one Ray task each.

``ray`` is an optional dependency (``pip install "fairfit[ray]"``). Start Ray as usual before calling:
``ray.init()`` on one machine, ``ray.init(address="auto")`` (or ``address="ray://head:10001"``) on a
cluster, or submit a script with ``ray job submit``; an uninitialised Ray is started locally by the
first task.

Every task runs one fit with one thread (``threads=1``: the cluster's parallelism is the tasks), and a
fit's result does not depend on where or how it ran: a batch equals the serial loop
``[fairfit.fit_curve(p, **options) for p in inputs]`` byte for byte (:meth:`fairfit.Curve.to_json`).

Surfaces are fitted one task per surface, not one task per section: the compatible section curves share
ONE knot vector, searched over all sections together (the control-point count grows until the worst
section is within tolerance, candidates are ranked by the worst span fairness over all sections), so
the sections' fits are not independent and cannot run as separate tasks before the skinning step.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Union

import ray

import fairfit

#: Extensions of the point files a folder input contributes (as ``fairfit curve`` reads them).
POINT_FILE_EXTENSIONS = (".csv", ".tsv", ".txt", ".dat", ".xyz")


@dataclass
class BatchResult:
    """The outcome of a batch: per input (in input order) its curve or surface (None where it failed)
    and its row of the summary table: ``input``, ``ok``, ``error`` and the report's fields."""

    results: List[Any] = field(default_factory=list)
    rows: List[Dict[str, Any]] = field(default_factory=list)

    @property
    def curves(self) -> List[Optional[fairfit.Curve]]:
        """The fitted objects (None for a failed input)."""
        return self.results

    def table(self):
        """The rows as a ``pandas.DataFrame`` when pandas is installed, else the list of dicts."""
        try:
            import pandas as pd
        except ImportError:
            return self.rows
        return pd.DataFrame(self.rows)

    @property
    def failed(self) -> List[Dict[str, Any]]:
        """The rows of the inputs that failed."""
        return [r for r in self.rows if not r["ok"]]


def _expand(inputs) -> List[Any]:
    """A folder becomes its point files (sorted by name); a list is kept as it is."""
    if isinstance(inputs, (str, os.PathLike)):
        folder = os.fspath(inputs)
        if not os.path.isdir(folder):
            raise fairfit.FairfitError(f"{folder}: not a folder of point files")
        return [
            os.path.join(folder, f)
            for f in sorted(os.listdir(folder))
            if f.lower().endswith(POINT_FILE_EXTENSIONS)
        ]
    return list(inputs)


def _name(item, k: int) -> str:
    return os.fspath(item) if isinstance(item, (str, os.PathLike)) else f"input {k}"


def _fit_curve_task(item, name: str, options: Dict[str, Any]):
    """One input's fit: (True, curve) or (False, message); never raises, so one bad input stops nothing."""
    try:
        points = fairfit.read_points(item) if isinstance(item, (str, os.PathLike)) else item
        return True, fairfit.fit_curve(points, name=name, **options)
    except Exception as e:  # an input's failure is its row, not the batch's
        return False, f"{type(e).__name__}: {e}" if not isinstance(e, fairfit.FairfitError) else str(e)


def _fit_surface_task(sections, name: str, options: Dict[str, Any]):
    try:
        return True, fairfit.fit_surface(sections, **options)
    except Exception as e:
        return False, f"{type(e).__name__}: {e}" if not isinstance(e, fairfit.FairfitError) else str(e)


def _stem(name: str, k: int, used: set) -> str:
    base = os.path.splitext(os.path.basename(name))[0] if os.sep in name or "." in name else name
    base = base.replace(" ", "_") or f"input_{k}"
    stem, i = base, 1
    while stem in used:
        stem, i = f"{base}_{i}", i + 1
    used.add(stem)
    return stem


def _collect(names, outcomes, output: Optional[Union[str, os.PathLike]]) -> BatchResult:
    result = BatchResult()
    used: set = set()
    if output is not None:
        os.makedirs(output, exist_ok=True)
    for k, (name, (ok, value)) in enumerate(zip(names, outcomes)):
        row: Dict[str, Any] = {"input": name, "ok": ok, "error": None if ok else value}
        if ok:
            row.update({k2: v for k2, v in (value.report or {}).items() if k2 != "input"})
        stem = _stem(name, k, used)
        if output is not None and ok:
            path = os.path.join(output, stem + ".json")
            value.save(path)
            with open(os.path.join(output, stem + ".report.json"), "w") as f:
                json.dump(value.report, f, indent=2)
            row["output"] = path
        result.results.append(value if ok else None)
        result.rows.append(row)
    if output is not None:
        with open(os.path.join(output, "summary.jsonl"), "w") as f:
            for row in result.rows:
                f.write(json.dumps(row) + "\n")
    return result


def fit_curves(
    inputs: Union[str, os.PathLike, Sequence[Any]],
    *,
    output: Optional[Union[str, os.PathLike]] = None,
    num_cpus: float = 1,
    **options: Any,
) -> BatchResult:
    """Fits every input as one Ray task (one thread each) and gathers the results in input order.

    inputs: a folder of point files (its .csv/.tsv/.txt/.dat/.xyz files, sorted by name), or a list of
        point files and/or arrays.
    output: a folder to write ``<name>.json`` and ``<name>.report.json`` per fitted input and one
        ``summary.jsonl`` (a row per input, failed ones with their ``error``).
    num_cpus: CPUs Ray reserves per task.
    options: keywords of :func:`fairfit.fit_curve` (``threads`` is set to 1).

    A failed input becomes a row with ``ok`` false and its error message; the others go on.
    """
    items = _expand(inputs)
    names = [_name(x, k) for k, x in enumerate(items)]
    opts = dict(options, threads=1)
    task = ray.remote(num_cpus=num_cpus)(_fit_curve_task)
    refs = [task.remote(x, n, opts) for x, n in zip(items, names)]
    return _collect(names, ray.get(refs), output)


def fit_surfaces(
    surfaces: Sequence[Sequence[Any]],
    *,
    names: Optional[Sequence[str]] = None,
    output: Optional[Union[str, os.PathLike]] = None,
    num_cpus: float = 1,
    **options: Any,
) -> BatchResult:
    """Fits every surface (a list of section arrays) as one Ray task; see the module documentation for
    why a surface's sections are not split into tasks. ``options`` are those of
    :func:`fairfit.fit_surface`; ``output`` and the result are as for :func:`fit_curves`."""
    surfaces = list(surfaces)
    names = list(names) if names is not None else [f"surface {k}" for k in range(len(surfaces))]
    opts = dict(options, threads=1)
    task = ray.remote(num_cpus=num_cpus)(_fit_surface_task)
    refs = [task.remote(s, n, opts) for s, n in zip(surfaces, names)]
    return _collect(names, ray.get(refs), output)
