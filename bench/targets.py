"""The issue targets, checked one by one on the rows of a compare.py run, and the blade's fairness
between sections read from the surface benchmark (docs/benchmarks-surface.md).

Rows are (curve name, number of points, tolerance, [Result]) as built by compare.py; `met(result, tol)`
says whether a result meets the tolerance (measured by bench/measure.py). This module only counts and
formats; it measures nothing itself.
"""

from __future__ import annotations

import os
import re
import statistics

SPLPREP = "scipy splprep"
INTEGRATED = "fairfit integrated"
# the 200-point curves once more with fairfit's default threads (all cores): what a user's run costs
ALL_CORES = "fairfit integrated, all cores"
FTF = "fairfit fit-then-fair"
LSQ = "fairfit lsq"
EQUAL = "fairfit integrated, fit-then-fair's ctrl pts"
FTF_NO_CORNERS = "fairfit fit-then-fair, no corners"
EQUAL_NO_CORNERS = "fairfit integrated, no corners, fit-then-fair's ctrl pts"
POINTS_200 = 200
TIME_TARGET_S = 0.2


def _g(x, d=3):
    return "n/a" if x is None or x != x else f"{x:.{d}g}"


def _status(ok):
    return "**met**" if ok else "**not met**"


def _count(all_rows, met, meth, pred):
    """(curves where pred(result, splprep, tol) holds, curves where the method ran): pred is only asked
    when both the method and splprep meet the tolerance, else it counts as a miss."""
    hit = n = 0
    missed = []
    for name, _, tol, results in all_rows:
        by = {r.method: r for r in results}
        r, s = by.get(meth), by.get(SPLPREP)
        if r is None:
            continue
        n += 1
        if met(r, tol) and s is not None and met(s, tol) and pred(r.metrics, s.metrics):
            hit += 1
        else:
            missed.append(name)
    return hit, n, missed


def _met_count(all_rows, met, meth):
    hit = n = 0
    missed = []
    for name, _, tol, results in all_rows:
        r = {x.method: x for x in results}.get(meth)
        if r is None:
            continue
        n += 1
        if met(r, tol):
            hit += 1
        else:
            missed.append(name)
    return hit, n, missed


def _which(missed, limit=6):
    if not missed:
        return ""
    more = f", +{len(missed) - limit} more" if len(missed) > limit else ""
    return " (misses: " + ", ".join(missed[:limit]) + more + ")"


def times_200(all_rows, meth):
    """For the curves of POINTS_200 points: CLI wall times (s), fairfit's own times (s), and the ratios
    of the CLI time to splprep's one call, to splprep's whole s search (incl. the measurer) and to the
    splprep calls of that search alone, in the same run."""
    cli, own, r_one, r_search, r_calls = [], [], [], [], []
    for _, npts, _, results in all_rows:
        if npts != POINTS_200:
            continue
        by = {r.method: r for r in results}
        r, s = by.get(meth), by.get(SPLPREP)
        if r is None or not r.ok:
            continue
        cli.append(r.time_ms / 1e3)
        if r.single_ms == r.single_ms:
            own.append(r.single_ms / 1e3)
        if s is not None and s.ok:
            r_one.append(r.time_ms / s.single_ms)
            r_search.append(r.time_ms / s.time_ms)
            if s.extra.get("calls_ms"):
                r_calls.append(r.time_ms / s.extra["calls_ms"])
    return cli, own, r_one, r_search, r_calls


def _all_cores(all_rows):
    """The 200-point times with fairfit's default threads, when the run measured them, and the max time the
    target is judged on: the issue asks for the time "on this 2-core machine", i.e. what a user's default
    run costs with all of its cores; a run without that row is judged on its single-threaded times (never
    faster). Returns (text, max time or None)."""
    cli = times_200(all_rows, ALL_CORES)[0]
    if not cli:
        return "", None
    return (f"; with fairfit's default threads (all cores, same output bit for bit; the target is judged on "
            f"these): median {_g(_med(cli))} s, max {_g(max(cli))} s", max(cli))


def _med(v):
    return statistics.median(v) if v else float("nan")


def equal_pair(by, equal_name=EQUAL):
    """(integrated at fit-then-fair's count, that fit-then-fair result) of one curve's results by method:
    the pair fitted without corner detection when the bench had to run one (a fixed count cannot be
    shared between corner pieces), else the default pair."""
    if EQUAL_NO_CORNERS in by:
        return by.get(EQUAL_NO_CORNERS), by.get(FTF_NO_CORNERS)
    return by.get(equal_name), by.get(FTF)


def equal_count(all_rows, met, equal_name=EQUAL):
    """Integrated at fit-then-fair's control-point count against fit-then-fair: (wins, compared, F ratios,
    names where integrated does not win)."""
    wins = total = 0
    ratios, lost = [], []
    for name, _, tol, results in all_rows:
        by = {r.method: r for r in results}
        fe, ff = equal_pair(by, equal_name)
        if fe and ff and met(fe, tol) and met(ff, tol) and fe.metrics.n_ctrl == ff.metrics.n_ctrl:
            total += 1
            ratios.append(fe.metrics.F / ff.metrics.F)
            if fe.metrics.F < ff.metrics.F:
                wins += 1
            else:
                lost.append(name)
        elif ff is not None:
            lost.append(name + " (not compared)")
    return wins, total, ratios, lost


def targets_section(all_rows, met, equal_name):
    """Markdown table: every issue-4 target and issue-3's lsq target, with the numbers of this run."""
    n_curves = len(all_rows)
    out = [
        "| target | source | this run | status |",
        "|---|---|---|---|",
    ]
    tm = {m: _met_count(all_rows, met, m) for m in (INTEGRATED, FTF, LSQ)}
    h, n, miss = tm[INTEGRATED]
    others = "; ".join(f"{m.split(' ', 1)[1]} {tm[m][0]}/{tm[m][1]}" for m in (FTF, LSQ))
    out.append(f"| Tolerance met on every curve | issue 4 | integrated {h}/{n}{_which(miss)}; {others} "
               f"| {_status(h == n == n_curves)} |")
    checks = [
        ("Control points <= splprep's on every curve", lambda a, b: a.n_ctrl <= b.n_ctrl),
        ("F <= 0.5 x splprep's on every curve", lambda a, b: a.F <= 0.5 * b.F),
        ("Curvature extrema <= splprep's on every curve", lambda a, b: a.extrema <= b.extrema),
    ]
    for title, pred in checks:
        h, n, miss = _count(all_rows, met, INTEGRATED, pred)
        h2, n2, _ = _count(all_rows, met, FTF, pred)
        out.append(f"| {title} | issue 4 | integrated {h}/{n}{_which(miss)}; fit-then-fair {h2}/{n2} "
                   f"| {_status(h == n == n_curves)} |")
    wins, total, ratios, lost = equal_count(all_rows, met, equal_name)
    gm = _g(statistics.geometric_mean(ratios)) if ratios and min(ratios) > 0 else "n/a"
    worst = _g(max(ratios)) if ratios else "n/a"
    out.append(
        "| Integrated beats fit-then-fair on F at equal tolerance and control points | issue 4 | "
        f"lower F on {wins}/{total} curves compared (of {n_curves}); F ratio integrated / fit-then-fair: "
        f"geometric mean {gm}, worst {worst}{_which(lost)} | {_status(wins == total == n_curves)} |"
    )
    cli, own, r_one, r_search, r_calls = times_200(all_rows, INTEGRATED)
    if cli:
        all_cores_text, all_cores_max = _all_cores(all_rows)
        judged = max(cli) if all_cores_max is None else all_cores_max
        out.append(
            f"| Wall time of a {POINTS_200}-point curve <= {TIME_TARGET_S} s; ratio to splprep | issue 4 | "
            f"integrated, {len(cli)} curves of {POINTS_200} points, whole CLI process: median {_g(_med(cli))} s, "
            f"max {_g(max(cli))} s (fairfit's own time: median {_g(_med(own))} s); median ratio to splprep in the "
            f"same run: {_g(_med(r_search))} x splprep's s search incl. measuring each step, {_g(_med(r_calls))} x "
            f"the splprep calls of that search alone, {_g(_med(r_one))} x one splprep call"
            f"{all_cores_text} | {_status(judged <= TIME_TARGET_S)} |"
        )
    else:
        out.append(f"| Wall time of a {POINTS_200}-point curve <= {TIME_TARGET_S} s | issue 4 | "
                   f"no {POINTS_200}-point curve in this run | n/a |")
    h, n, miss = _count(all_rows, met, LSQ, lambda a, b: a.n_ctrl <= 1.5 * b.n_ctrl)
    out.append(f"| lsq: control points within 1.5 x splprep's | issue 3 | {h}/{n}{_which(miss)} "
               f"| {_status(h == n == n_curves)} |")
    cli, own, r_one, _, _ = times_200(all_rows, LSQ)
    if cli:
        out.append(
            f"| lsq: a fraction of a millisecond per {POINTS_200}-point curve | issue 3 | fairfit's own fit time "
            f"median {_g(1e3 * _med(own))} ms, max {_g(1e3 * max(own)) if own else 'n/a'} ms; whole CLI process "
            f"median {_g(1e3 * _med(cli))} ms ({_g(_med(r_one))} x one splprep call) "
            f"| {_status(bool(own) and max(own) < 1e-3)} |"
        )
    return "\n".join(out)


def _parse_tables(text):
    """Every Markdown table in text as a list of dicts keyed by the header cells."""
    tables, cur, header = [], None, None
    for line in text.splitlines():
        line = line.strip()
        if not line.startswith("|"):
            cur = header = None
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if header is None:
            header, cur = cells, []
            tables.append(cur)
        elif all(set(c) <= set("-: ") for c in cells):
            continue
        else:
            cur.append(dict(zip(header, cells)))
    return tables


def blade_section(report_path, fallback_dir=None):
    """Issue 5's blade comparison (F of the iso-curves between sections: fairfit against the OCC loft),
    read from benchmarks-surface.md beside the curve report (else in fallback_dir, the repository's
    docs/ when the report is written elsewhere); a link only when it is missing or has no such table."""
    surf = os.path.join(os.path.dirname(os.path.abspath(report_path)), "benchmarks-surface.md")
    if not os.path.exists(surf) and fallback_dir:
        surf = os.path.join(fallback_dir, "benchmarks-surface.md")
    link = "[benchmarks-surface.md](benchmarks-surface.md)"
    if not os.path.exists(surf):
        return [f"The surface benchmark ({link}, written by `bench/surface_compare.py`) has not been generated yet."]
    with open(surf, encoding="utf-8") as fh:
        text = fh.read()
    key = "F between sections, max"
    rows = next((t for t in _parse_tables(text) if t and key in t[0]), None)
    if not rows:
        return [f"See {link} (written by `bench/surface_compare.py`)."]
    stamp = re.search(r"on (\d{4}-\d\d-\d\d[^,]*UTC), commit (\w+)", text)
    out = [
        f"From {link} (written by `bench/surface_compare.py`"
        + (f" on {stamp.group(1)} at commit `{stamp.group(2)}`" if stamp else "")
        + "; numbers copied, not re-measured here):",
        "",
        "| method | net (along x across) | max dev / tol | F between sections, max | F between sections, median |",
        "|---|---|---|---:|---:|",
    ]
    for r in rows:
        out.append(f"| {r.get('method', '?')} | {r.get('net (along x across)', '?')} | {r.get('max dev / tol', '?')} "
                   f"| {r.get(key, '?')} | {r.get('F between sections, median', '?')} |")

    def f_max(pred):
        for r in rows:
            if pred(r.get("method", "")):
                try:
                    return float(r[key])
                except (KeyError, ValueError):
                    return None
        return None

    ff, loft = f_max(lambda m: m.startswith("fairfit")), f_max(lambda m: "ThruSections" in m)
    if ff is not None and loft is not None:
        verdict = "no worse than" if ff <= loft else "worse than"
        out += ["", f"Issue 5 target (F between sections no worse than the loft's): fairfit's max {_g(ff)} is "
                    f"{verdict} ThruSections' {_g(loft)} ({_g(ff / loft)} x): {_status(ff <= loft)}."]
    return out


def _ellipse_header(path):
    """(a, b) from an analytic quarter-ellipse file's first comment `x=a cos t, y=b sin t, t ... [0, pi/2]`."""
    try:
        with open(path, encoding="utf-8") as fh:
            first = fh.readline()
    except OSError:
        return None
    m = re.search(r"x=\s*([\d.]*)\s*cos t,\s*y=\s*([\d.]*)\s*sin t,.*\[0, pi/2\]", first)
    if not m:
        return None
    return float(m.group(1) or 1.0), float(m.group(2) or 1.0)


def ellipse_fairness(a, b):
    """F = L^3 int (dkappa/ds)^2 ds of the exact quarter ellipse (a cos t, b sin t), t in [0, pi/2],
    by adaptive quadrature (independent of every fitted curve)."""
    import numpy as np
    from scipy.integrate import quad

    sp = lambda t: np.hypot(a * np.sin(t), b * np.cos(t))  # noqa: E731
    dk_dt = lambda t: -3 * a * b * (a * a - b * b) * np.sin(t) * np.cos(t) / sp(t) ** 5  # noqa: E731
    L = quad(sp, 0, np.pi / 2, epsabs=1e-14)[0]
    return L**3 * quad(lambda t: dk_dt(t) ** 2 / sp(t), 0, np.pi / 2, epsabs=1e-14)[0]


def analytic_reference(all_rows, data_dir):
    """A line per analytic curve: the exact curve's F next to splprep's and the integrated method's,
    so the F <= 0.5 x splprep target can be read against the curve the points come from."""
    out = []
    for name, _, _, results in all_rows:
        ab = _ellipse_header(os.path.join(data_dir, "synthetic", name + ".csv"))
        if ab is None:
            continue
        F = ellipse_fairness(*ab)
        by = {r.method: r for r in results}
        got = [f"{m} {_g(by[m].metrics.F)}" for m in (SPLPREP, INTEGRATED) if m in by and by[m].ok]
        out.append(f"- {name}: the exact quarter ellipse x = {ab[0]:g} cos t, y = {ab[1]:g} sin t has F = {_g(F)} "
                   f"(quadrature); " + ", ".join(got) + ".")
    if out:
        out.insert(0, "Reference for the F target: the analytic curve the points were sampled from "
                      "(F <= 0.5 x splprep asks for less than half of splprep's F within the tolerance band):")
    return out
