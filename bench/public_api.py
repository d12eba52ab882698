#!/usr/bin/env python3
"""The public API of the `fairfit` library crate, counted from rustdoc's JSON output.

`bench/layout_metrics.py` counts `pub` lines in the sources; a `pub` item inside a `pub(crate)`
module is not public, and a re-export makes one item public under a second path. This script counts
what a user of the crate can actually name: it asks rustdoc (nightly, `--output-format json`, which
leaves out everything not reachable from the crate root) for the crate's index and walks the public
modules from the root.

Counted per top-level module of the crate: functions, structs, enums, traits, constants, type
aliases, the named fields of public structs and the methods of their inherent impls (trait impls are
not counted: they add no names). A re-export (`pub use`) counts as the item it names, once, under the
first top-level module it is reachable from; a re-export of another crate's item counts as one name.

Usage:

    python3 bench/public_api.py [CHECKOUT ...] [--json]

For every checkout (default: this repository) it runs
`cargo +nightly rustdoc -p fairfit --lib -- -Z unstable-options --output-format json` with a target
directory of its own under the system's temporary folder, and prints one Markdown table (one column
per checkout) or, with `--json`, one JSON object per checkout. Needs the nightly toolchain.
"""

from __future__ import annotations

import argparse
import collections
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def rustdoc_json(checkout: Path) -> dict:
    """The crate's rustdoc JSON, built in a target directory shared by every run of this script."""
    target = Path(tempfile.gettempdir()) / "fairfit-public-api"
    subprocess.run(
        ["cargo", "+nightly", "rustdoc", "-p", "fairfit", "--lib", "--quiet", "--target-dir", str(target),
         "--", "-Z", "unstable-options", "--output-format", "json"],
        cwd=checkout, check=True,
    )
    return json.loads((target / "doc" / "fairfit.json").read_text())


def count(doc: dict) -> dict:
    """Reachable public items per top-level module (`(root)` for the crate root's own items)."""
    index = doc["index"]
    per_module: collections.Counter = collections.Counter()
    per_kind: collections.Counter = collections.Counter()
    seen: set = set()

    def add(top: str, kind: str, n: int = 1) -> None:
        per_module[top] += n
        per_kind[kind] += n

    def walk(item_id, top: str | None) -> None:
        if item_id in seen:
            return
        seen.add(item_id)
        item = index.get(str(item_id))
        if item is None:
            return
        kind, inner = next(iter(item["inner"].items()))
        if kind == "module":
            for child in inner["items"]:
                child_item = index.get(str(child))
                if child_item is not None:
                    walk(child, top or child_item["name"] or "(root)")
            return
        top = top or "(root)"
        if kind == "use":
            # a re-export counts as the item it names (once, wherever it is reachable first); a
            # re-export of another crate's item, or a glob, counts as one name
            target = inner.get("id")
            if target is not None and str(target) in index and not inner.get("is_glob"):
                walk(target, top)
                return
        add(top, kind)
        if kind == "struct" and isinstance(inner["kind"], dict) and "plain" in inner["kind"]:
            add(top, "field", len(inner["kind"]["plain"]["fields"]))
        if kind in ("struct", "enum"):
            for impl_id in inner["impls"]:
                impl = index.get(str(impl_id), {}).get("inner", {}).get("impl")
                if impl and impl.get("trait") is None and not impl.get("is_synthetic") and not impl.get("blanket_impl"):
                    add(top, "method", len(impl["items"]))

    walk(doc["root"], None)
    return {"per_module": dict(sorted(per_module.items())), "per_kind": dict(sorted(per_kind.items())),
            "total": sum(per_module.values())}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("checkouts", nargs="*", type=Path, default=[ROOT])
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    results = {str(c): count(rustdoc_json(c)) for c in args.checkouts}
    if args.json:
        for c, r in results.items():
            print(json.dumps({"checkout": c, **r}))
        return 0
    modules = sorted({m for r in results.values() for m in r["per_module"]})
    print("| public items | " + " | ".join(results) + " |")
    print("|---|" + "---|" * len(results))
    for m in modules:
        print(f"| `{m}` | " + " | ".join(str(r["per_module"].get(m, 0)) for r in results.values()) + " |")
    print("| **total** | " + " | ".join(str(r["total"]) for r in results.values()) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
