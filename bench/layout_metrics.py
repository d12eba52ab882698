#!/usr/bin/env python3
"""Layout metrics of a fairfit checkout: the before/after table of a restructuring.

For every checkout given (default: this repository) it counts, from the sources alone:

- files and lines in `crates/*/src`, and in `crates/fairfit/src/optim`;
- the largest file, and the largest function (line span of a `fn` body, found by brace matching;
  comments and string literals are skipped);
- import cycles: strongly connected components of more than one module, between the library's
  top-level modules, among the modules inside `optim`, and among the CLI's modules. Dependencies are
  the paths of `use` declarations and the `crate::`/`super::`/`self::` paths in code, outside
  `#[cfg(test)]` items; a name a module only re-exports is followed to the module that defines it, and
  a module and its own ancestors count as one unit (as `crates/fairfit/tests/architecture.rs` does);
- `pub` items: lines starting with `pub fn/struct/enum/const/trait/type/mod/static/use` (not
  `pub(crate)`), in `crates/*/src`;
- named constants: `const` and `static` items (not `const fn`), in `crates/*/src`;
- test binaries: `tests/*.rs` and `tests/*/main.rs` of every crate (its `[[test]]` targets when the
  manifest says `autotests = false`);
- `#[path]` attributes in `crates/` (tests and benches).

Usage:

    python3 bench/layout_metrics.py [CHECKOUT ...] [--json]

One column per checkout (a Markdown table), or a JSON object per checkout with `--json`.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

# ------------------------------------------------------------------------------------------------
# Tokens
# ------------------------------------------------------------------------------------------------


def tokens(src: str) -> list[tuple[str, int]]:
    """(text, line) of every identifier and punctuation character (`::` one token); comments and
    string and character literals left out."""
    out: list[tuple[str, int]] = []
    i, line, n = 0, 1, len(src)
    while i < n:
        ch = src[i]
        if ch == "\n":
            line += 1
            i += 1
        elif ch.isspace():
            i += 1
        elif src.startswith("//", i):
            while i < n and src[i] != "\n":
                i += 1
        elif src.startswith("/*", i):
            depth = 0
            while i < n:
                if src.startswith("/*", i):
                    depth += 1
                    i += 2
                elif src.startswith("*/", i):
                    depth -= 1
                    i += 2
                    if depth == 0:
                        break
                else:
                    line += src[i] == "\n"
                    i += 1
        elif ch == "r" and (m := re.match(r'r(#*)"', src[i:])):
            end = src.find('"' + m.group(1), i + len(m.group(0)))
            end = n if end < 0 else end + 1 + len(m.group(1))
            line += src.count("\n", i, end)
            i = end
        elif ch == '"' or src.startswith('b"', i):
            i += 2 if ch == "b" else 1
            while i < n and src[i] != '"':
                line += src[i] == "\n"
                i += 2 if src[i] == "\\" else 1
            i += 1
        elif ch == "'":
            if src.startswith("\\", i + 1):
                i += 3
                while i < n and src[i] != "'":
                    i += 1
                i += 1
            elif i + 2 < n and src[i + 2] == "'":
                i += 3
            else:
                i += 1
        elif ch.isalnum() or ch == "_":
            start = i
            while i < n and (src[i].isalnum() or src[i] == "_"):
                i += 1
            out.append((src[start:i], line))
        elif src.startswith("::", i):
            out.append(("::", line))
            i += 2
        else:
            out.append((ch, line))
            i += 1
    return out


CFG_TEST = ["#", "[", "cfg", "(", "test", ")", "]"]


def without_test_items(t: list[tuple[str, int]]) -> list[tuple[str, int]]:
    out = []
    i = 0
    while i < len(t):
        if [x[0] for x in t[i : i + 7]] != CFG_TEST:
            out.append(t[i])
            i += 1
            continue
        i += 7
        depth = 0
        while i < len(t):
            s = t[i][0]
            if s == "{":
                depth += 1
            elif s == "}":
                depth = max(depth - 1, 0)
                if depth == 0:
                    i += 1
                    break
            elif s == ";" and depth == 0:
                i += 1
                break
            i += 1
    return out


def is_ident(s: str) -> bool:
    return bool(s) and (s[0].isalpha() or s[0] == "_")


def references(t: list[tuple[str, int]]) -> list[tuple[list[str], str | None]]:
    """(path as written, name bound or None) of every use-tree leaf and anchored path in code."""
    out: list[tuple[list[str], str | None]] = []
    i = 0

    def use_tree(i: int, prefix: list[str]) -> int:
        path = list(prefix)
        if i < len(t) and t[i][0] == "::":
            i += 1
        while i < len(t):
            s = t[i][0]
            if s == "{":
                i += 1
                while i < len(t) and t[i][0] != "}":
                    i = use_tree(i, path)
                    if i < len(t) and t[i][0] == ",":
                        i += 1
                return i + 1
            if s == "*":
                out.append((path, None))
                return i + 1
            if is_ident(s):
                path.append(s)
                i += 1
                if i < len(t) and t[i][0] == "::":
                    i += 1
                    continue
                binds = path[-1]
                if i < len(t) and t[i][0] == "as":
                    binds = t[i + 1][0] if i + 1 < len(t) else None
                    i += 2
                if binds == "self":
                    path.pop()
                    binds = path[-1] if path else None
                out.append((path, binds))
                return i
            return i
        return i

    while i < len(t):
        s = t[i][0]
        if s == "use":
            i = use_tree(i + 1, [])
            while i < len(t) and t[i][0] != ";":
                i += 1
        elif (
            s in ("crate", "super", "self")
            and i + 1 < len(t)
            and t[i + 1][0] == "::"
            and (i == 0 or t[i - 1][0] != "::")
        ):
            path = [s]
            i += 1
            while i + 1 < len(t) and t[i][0] == "::" and is_ident(t[i + 1][0]):
                path.append(t[i + 1][0])
                i += 2
            out.append((path, None))
            continue
        i += 1
    return out


# ------------------------------------------------------------------------------------------------
# Module graph
# ------------------------------------------------------------------------------------------------


def module_of_file(rel: str) -> tuple[str, ...]:
    segs = rel[: -len(".rs")].split("/")
    if segs[-1] in ("mod", "lib", "main"):
        segs.pop()
    return tuple(segs)


class Crate:
    def __init__(self, src: Path):
        self.files = []
        for p in sorted(src.rglob("*.rs")):
            rel = p.relative_to(src).as_posix()
            refs = references(without_test_items(tokens(p.read_text(encoding="utf-8"))))
            self.files.append((module_of_file(rel), refs))
        self.modules = {m for m, _ in self.files}
        self.bindings: dict[tuple[str, ...], dict[str, tuple[str, ...]]] = {}
        for m, refs in self.files:
            for path, binds in refs:
                a = self.absolute(m, path)
                if binds is not None and a is not None:
                    self.bindings.setdefault(m, {})[binds] = a

    def absolute(self, m, path):
        if not path:
            return None
        first = path[0]
        if first == "crate":
            return tuple(path[1:])
        if first == "self":
            return m + tuple(path[1:])
        if first == "super":
            ups = 0
            while ups < len(path) and path[ups] == "super":
                ups += 1
            if ups > len(m):
                return None
            return m[: len(m) - ups] + tuple(path[ups:])
        if m + (first,) in self.modules:
            return m + tuple(path)
        return None

    def target(self, path):
        for _ in range(8):
            k = max(k for k in range(len(path) + 1) if k == 0 or path[:k] in self.modules)
            module = path[:k]
            nxt = path[k] if k < len(path) else None
            abs_ = self.bindings.get(module, {}).get(nxt) if nxt is not None else None
            if abs_ is not None and abs_ != path:
                path = abs_ + path[k + 1 :]
            else:
                return module
        return path

    def edges(self):
        out = set()
        for m, refs in self.files:
            for path, _ in refs:
                a = self.absolute(m, path)
                if a is None:
                    continue
                to = self.target(a)
                if to != m:
                    out.add((m, to))
        return out


def sccs(edges) -> list[list[str]]:
    """Strongly connected components of more than one node (Tarjan, iterative)."""
    graph: dict[str, set[str]] = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    x = stack.pop()
                    on.discard(x)
                    comp.append(x)
                    if x == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return sorted(out)


def is_prefix(a, b):
    return len(a) <= len(b) and b[: len(a)] == a


def crate_cycles(krate: Crate):
    edges = {(a[0], b[0]) for a, b in krate.edges() if a and b and a[0] != b[0]}
    return sccs(edges)


def cycles_below(krate: Crate, scope: tuple[str, ...]):
    edges = {
        ("::".join(a[len(scope) :]), "::".join(b[len(scope) :]))
        for a, b in krate.edges()
        if is_prefix(scope, a) and is_prefix(scope, b) and not is_prefix(a, b) and not is_prefix(b, a)
    }
    return sccs(edges)


# ------------------------------------------------------------------------------------------------
# Counts
# ------------------------------------------------------------------------------------------------

PUB_ITEM = re.compile(r"^\s*pub\s+(?:unsafe\s+|async\s+|const\s+(?=fn))?(fn|struct|enum|const|trait|type|mod|static|use)\b")
CONST_ITEM = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?(?:const|static)\s+(?!fn\b)(?:mut\s+)?[A-Za-z_]\w*\s*:")


def largest_function(path: Path) -> tuple[int, str]:
    """(line span, name) of the longest `fn` body of a file."""
    t = tokens(path.read_text(encoding="utf-8"))
    best = (0, "")
    for i, (s, line) in enumerate(t):
        if s != "fn" or i + 1 >= len(t) or not is_ident(t[i + 1][0]):
            continue
        # the body: the first `{` at bracket depth 0 before a `;` (a declaration has no body)
        j, depth = i + 2, 0
        while j < len(t):
            x = t[j][0]
            if x in "([<" and len(x) == 1:
                depth += x != "<"
            elif x in ")]":
                depth -= 1
            elif x == ";" and depth == 0:
                j = -1
                break
            elif x == "{" and depth == 0:
                break
            j += 1
        if j < 0 or j >= len(t):
            continue
        k, braces = j, 0
        while k < len(t):
            if t[k][0] == "{":
                braces += 1
            elif t[k][0] == "}":
                braces -= 1
                if braces == 0:
                    break
            k += 1
        span = t[min(k, len(t) - 1)][1] - line + 1
        if span > best[0]:
            best = (span, t[i + 1][0])
    return best


def metrics(root: Path) -> dict:
    crates = root / "crates"
    src_files = sorted(p for d in sorted(crates.glob("*/src")) for p in d.rglob("*.rs"))
    optim_dir = crates / "fairfit" / "src" / "optim"
    optim_files = [p for p in src_files if is_prefix(optim_dir.parts, p.parts)]
    lines = {p: len(p.read_text(encoding="utf-8").splitlines()) for p in src_files}
    rel = lambda p: p.relative_to(crates).as_posix()  # noqa: E731
    big = max(src_files, key=lambda p: lines[p])
    fn_best = (0, "", None)
    for p in src_files:
        span, name = largest_function(p)
        if span > fn_best[0]:
            fn_best = (span, name, p)
    pub_items = consts = optim_consts = 0
    for p in src_files:
        for ln in p.read_text(encoding="utf-8").splitlines():
            pub_items += bool(PUB_ITEM.match(ln))
            consts += bool(CONST_ITEM.match(ln))
            optim_consts += bool(CONST_ITEM.match(ln)) and p in optim_files
    binaries = {}
    for c in sorted(crates.iterdir()):
        tests = c / "tests"
        if tests.is_dir():
            manifest = (c / "Cargo.toml").read_text(encoding="utf-8")
            if re.search(r"^autotests\s*=\s*false", manifest, re.M):
                # only the declared targets are built
                n = len(re.findall(r"^\[\[test\]\]", manifest, re.M))
            else:
                n = len(list(tests.glob("*.rs"))) + len(list(tests.glob("*/main.rs")))
            binaries[c.name] = n
    path_includes: dict[str, int] = {}
    for p in sorted(crates.rglob("*.rs")):
        n = len(re.findall(r"(?m)^\s*#\[path\s*=", p.read_text(encoding="utf-8")))
        if n:
            where = p.relative_to(crates).parts[1]
            path_includes[where] = path_includes.get(where, 0) + n
    lib = Crate(crates / "fairfit" / "src")
    cli = Crate(crates / "fairfit-cli" / "src")
    lib_cycles = crate_cycles(lib)
    optim_cycles = cycles_below(lib, ("optim",))
    cli_cycles = cycles_below(cli, ())
    return {
        "checkout": str(root),
        "src_files": len(src_files),
        "src_lines": sum(lines.values()),
        "optim_files": len(optim_files),
        "optim_lines": sum(lines[p] for p in optim_files),
        "largest_file": {"path": rel(big), "lines": lines[big]},
        "largest_function": {"name": fn_best[1], "path": rel(fn_best[2]), "lines": fn_best[0]},
        "crate_cycles": lib_cycles,
        "optim_cycles": optim_cycles,
        "cli_cycles": cli_cycles,
        "pub_items": pub_items,
        "named_constants": consts,
        "optim_named_constants": optim_consts,
        "test_binaries": binaries,
        "path_includes": path_includes,
    }


def cycles_cell(cs) -> str:
    if not cs:
        return "0"
    return f"{len(cs)} (" + "; ".join(f"{len(c)} modules" if len(c) > 3 else " ↔ ".join(c) for c in cs) + ")"


def table(ms: list[dict]) -> str:
    rows = [
        ("files in crates/*/src", lambda m: str(m["src_files"])),
        ("lines in crates/*/src", lambda m: str(m["src_lines"])),
        ("files in optim/", lambda m: str(m["optim_files"])),
        ("lines in optim/", lambda m: str(m["optim_lines"])),
        ("largest file", lambda m: f"{m['largest_file']['path']} ({m['largest_file']['lines']})"),
        (
            "largest function",
            lambda m: f"`{m['largest_function']['name']}` in {m['largest_function']['path']} ({m['largest_function']['lines']})",
        ),
        ("import cycles, crate modules", lambda m: cycles_cell(m["crate_cycles"])),
        ("import cycles, inside optim", lambda m: cycles_cell(m["optim_cycles"])),
        ("import cycles, CLI modules", lambda m: cycles_cell(m["cli_cycles"])),
        ("`pub` items", lambda m: str(m["pub_items"])),
        ("named constants (in optim/)", lambda m: f"{m['named_constants']} ({m['optim_named_constants']})"),
        (
            "test binaries",
            lambda m: f"{sum(m['test_binaries'].values())} ("
            + ", ".join(f"{k} {v}" for k, v in m["test_binaries"].items())
            + ")",
        ),
        (
            "`#[path]` includes",
            lambda m: f"{sum(m['path_includes'].values())} ("
            + ", ".join(f"{k} {v}" for k, v in m["path_includes"].items())
            + ")",
        ),
    ]
    head = "| metric | " + " | ".join(m["checkout"] for m in ms) + " |"
    sep = "|---|" + "---|" * len(ms)
    body = ["| " + name + " | " + " | ".join(f(m) for m in ms) + " |" for name, f in rows]
    return "\n".join([head, sep, *body])


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checkouts", nargs="*", type=Path, help="checkout roots (default: this repository)")
    ap.add_argument("--json", action="store_true", help="JSON instead of a Markdown table")
    args = ap.parse_args(argv)
    roots = args.checkouts or [Path(__file__).resolve().parent.parent]
    ms = [metrics(r.resolve()) for r in roots]
    print(json.dumps(ms if len(ms) > 1 else ms[0], indent=2) if args.json else table(ms))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
