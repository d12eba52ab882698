"""Shared fixtures: the CLI binary of the same build ($FAIRFIT_BIN) and the bundled example data."""

import json
import os
import subprocess

import pytest

EXAMPLES = os.environ.get(
    "FAIRFIT_EXAMPLES",
    os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "examples", "data"),
)


@pytest.fixture(scope="session")
def cli():
    """Runs the `fairfit` CLI: cli(*args) -> CompletedProcess (text)."""
    binary = os.environ.get("FAIRFIT_BIN")
    if not binary:
        pytest.skip("FAIRFIT_BIN (the fairfit CLI binary) is not set")

    def run(*args, check=True):
        r = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"fairfit {' '.join(map(str, args))} failed: {r.stderr}")
        return r

    return run


@pytest.fixture(scope="session")
def examples():
    return EXAMPLES


def example(name: str) -> str:
    return os.path.join(EXAMPLES, name)


def cli_eval(cli, curve_json_path, us):
    """`fairfit eval FILE --at ...` as parsed JSON."""
    at = ",".join(repr(float(u)) for u in us)
    return json.loads(cli("eval", curve_json_path, "--at", at).stdout)
