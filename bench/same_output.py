#!/usr/bin/env python3
"""Byte-identity check of two fairfit builds: the same inputs and seeds must write the same JSON.

A refactor that promises "output unchanged" is held to it here.  The set of runs:

- every curve of the shared data (airfoils, synthetic, IEA 15 MW airfoils: 33 curves) at `--rel-tol 1e-3`,
  seeds 0-5, with every method (`integrated`, `lsq`, `fit-then-fair`): the curve JSON and the report
  JSON;
- the IEA 15 MW blade surface (its 10 sections, `--tol 0.0057`) and the Stanford bunny surface (20
  slices along z), surface JSON and report;
- a few CLI contract commands on the written curves (`info`, `eval`, `export --step/--iges`).

Report fields that measure wall time (keys ending in `seconds`) are dropped before comparing, and the time
stamps of STEP/IGES headers are masked; everything else is compared as bytes.

Usage (from the repository root):

    python bench/same_output.py record BIN OUTDIR [--data DIR] [--seeds 0-5] [--jobs N]
    python bench/same_output.py compare OUTDIR_A OUTDIR_B
    python bench/same_output.py BIN_A BIN_B [--data DIR] ...      # record both, then compare

`--data` defaults to the main checkout's sibling `shared/data` (`../shared/data` from the repository
root).  Exit code 0 when every output is identical, 1 otherwise (the differing files are listed).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import filecmp
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
CURVE_GROUPS = ["airfoils", "synthetic", os.path.join("iea15mw", "airfoils")]
METHODS = ["integrated", "lsq", "fit-then-fair"]
BLADE_TOL = "0.0057"


def default_data() -> str:
    """`../shared/data` of the main checkout (a worktree's common git dir names it)."""
    try:
        common = subprocess.run(
            ["git", "rev-parse", "--path-format=absolute", "--git-common-dir"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        root = os.path.dirname(common)
    except (OSError, subprocess.CalledProcessError):
        root = REPO
    return os.path.join(os.path.dirname(root), "shared", "data")


def curves(data: str) -> list[tuple[str, str]]:
    out = []
    for g in CURVE_GROUPS:
        d = os.path.join(data, g)
        for f in sorted(os.listdir(d)):
            if f.endswith(".csv"):
                out.append((os.path.splitext(f)[0], os.path.join(d, f)))
    return out


def parse_seeds(s: str) -> list[int]:
    if "-" in s:
        a, b = s.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(x) for x in s.split(",")]


def strip_times(path: str) -> None:
    """Rewrites a JSON report without its wall-time fields (in place, same formatting)."""
    if not os.path.exists(path):
        return

    def drop(v):
        if isinstance(v, dict):
            return {k: drop(x) for k, x in v.items() if not k.endswith("seconds")}
        if isinstance(v, list):
            return [drop(x) for x in v]
        return v

    with open(path) as f:
        v = json.load(f)
    with open(path, "w") as f:
        json.dump(drop(v), f, indent=1, sort_keys=True)
        f.write("\n")


def run(cmd: list[str], out_prefix: str) -> None:
    """Runs one command; its exit code, stdout and stderr are outputs too."""
    p = subprocess.run(cmd, capture_output=True)
    with open(out_prefix + ".exit", "w") as f:
        f.write(f"{p.returncode}\n")
    with open(out_prefix + ".stdout", "wb") as f:
        f.write(p.stdout)
    # stderr may name temporary paths; the outputs' own bytes are what must match
    with open(out_prefix + ".stderr", "wb") as f:
        f.write(p.stderr)


def jobs_for(binary: str, data: str, out: str, seeds: list[int]) -> list[tuple[list[str], str, list[str]]]:
    """(command, output prefix, reports to strip) of every run."""
    jobs = []
    for name, path in curves(data):
        for method in METHODS:
            for seed in seeds:
                stem = os.path.join(out, f"curve_{name}_{method}_s{seed}")
                cmd = [binary, "curve", path, "--rel-tol", "1e-3", "--method", method, "--seed", str(seed),
                       "-o", stem + ".json", "--report", stem + ".report.json"]
                jobs.append((cmd, stem, [stem + ".report.json"]))
    blade = os.path.join(data, "iea15mw", "sections")
    stem = os.path.join(out, "surface_blade")
    jobs.append(([binary, "surface", blade, "--tol", BLADE_TOL, "-o", stem + ".json", "--report",
                  stem + ".report.json"], stem, [stem + ".report.json"]))
    bunny = os.path.join(data, "scans", "StanfordBunny.ply")
    stem = os.path.join(out, "surface_bunny")
    jobs.append(([binary, "surface", bunny, "--slices", "20", "--axis", "z", "-o", stem + ".json", "--report",
                  stem + ".report.json"], stem, [stem + ".report.json"]))
    return jobs


def contract_jobs(binary: str, out: str) -> list[tuple[list[str], str, list[str]]]:
    """CLI contract commands on curves written by the first pass (run after it)."""
    jobs = []
    for name in ["naca4412", "hq17", "quarter_ellipse_200"]:
        c = os.path.join(out, f"curve_{name}_integrated_s0.json")
        stem = os.path.join(out, f"cli_{name}")
        jobs.append(([binary, "info", c], stem + "_info", []))
        jobs.append(([binary, "eval", c, "--at", "0,0.25,0.5,0.75,1"], stem + "_eval", []))
        jobs.append(([binary, "export", c, "--step", stem + ".step", "--iges", stem + ".igs"], stem + "_export", []))
    s = os.path.join(out, "surface_blade.json")
    jobs.append(([binary, "info", s], os.path.join(out, "cli_blade_info"), []))
    jobs.append(([binary, "eval", s, "--at", "0.5:0.5"], os.path.join(out, "cli_blade_eval"), []))
    return jobs


def record(binary: str, out: str, data: str, seeds: list[int], n_jobs: int) -> None:
    binary = os.path.abspath(binary)
    os.makedirs(out, exist_ok=True)
    for batch in (jobs_for(binary, data, out, seeds), contract_jobs(binary, out)):
        with cf.ThreadPoolExecutor(max_workers=n_jobs) as ex:
            futs = [ex.submit(run, cmd, stem) for cmd, stem, _ in batch]
            for i, f in enumerate(cf.as_completed(futs)):
                f.result()
                if sys.stderr.isatty():
                    print(f"\r{i + 1}/{len(batch)}", end="", file=sys.stderr)
        if sys.stderr.isatty():
            print(file=sys.stderr)
        for _, _, reports in batch:
            for r in reports:
                strip_times(r)


STEP_TIME = re.compile(rb"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'")
IGES_TIME = re.compile(rb"15H\d{8}\.\d{6}")


def masked(text: bytes, folder: str) -> bytes:
    """`text` with the output folder's name and STEP/IGES time stamps replaced by fixed tokens."""
    text = text.replace(folder.encode(), b"OUT")
    return IGES_TIME.sub(b"15HYYYYMMDD.HHNNSS", STEP_TIME.sub(b"'TIME'", text))


def compare(a: str, b: str) -> int:
    fa, fb = set(os.listdir(a)), set(os.listdir(b))
    differ = sorted(f for f in fa & fb if not filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False))
    # stderr may carry the output folder's name, and STEP/IGES headers the time of writing: compare those
    # with the folder name and the time stamps masked
    real = []
    for f in differ:
        ta = masked(open(os.path.join(a, f), "rb").read(), a)
        tb = masked(open(os.path.join(b, f), "rb").read(), b)
        if ta != tb:
            real.append(f)
    only = sorted(fa ^ fb)
    for f in real:
        print(f"differs: {f}")
    for f in only:
        print(f"only in {'A' if f in fa else 'B'}: {f}")
    n = len(fa | fb)
    print(f"{n - len(real) - len(only)}/{n} outputs identical")
    return 0 if not real and not only else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a", help="'record', 'compare', or the first build's fairfit binary")
    ap.add_argument("b", help="the binary (record), the first output folder (compare), or the second binary")
    ap.add_argument("c", nargs="?", help="the output folder (record) or the second output folder (compare)")
    ap.add_argument("--data", default=None, help="the shared data folder (default: ../shared/data)")
    ap.add_argument("--seeds", default="0-5")
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (each uses the default threads)")
    args = ap.parse_args()
    data = args.data or default_data()
    seeds = parse_seeds(args.seeds)
    if args.a == "record":
        record(args.b, args.c, data, seeds, args.jobs)
        return 0
    if args.a == "compare":
        return compare(args.b, args.c)
    with tempfile.TemporaryDirectory() as tmp:
        oa, ob = os.path.join(tmp, "a"), os.path.join(tmp, "b")
        record(args.a, oa, data, seeds, args.jobs)
        record(args.b, ob, data, seeds, args.jobs)
        return compare(oa, ob)


if __name__ == "__main__":
    sys.exit(main())
