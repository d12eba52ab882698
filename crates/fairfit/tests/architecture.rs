//! Architecture: the modules' imports point one way.
//!
//! The sources of `crates/fairfit/src` and `crates/fairfit-cli/src` are read as text and every
//! dependency of a module on another is collected: the paths of its `use` declarations (groups
//! expanded, `crate::`, `super::`, `self::` and child-module paths resolved) and the `crate::`,
//! `super::` and `self::` paths in its code. Comments, string literals and `#[cfg(test)]` items are
//! skipped: a unit test may read its fixtures through a module its code does not depend on. A path to
//! an item that a module only imports or re-exports (`pub use child::Item`) is followed to the module
//! that defines it, so `super::Item` counts as a dependency on the sibling that holds `Item`.
//!
//! Checks:
//! - the crate's top-level modules respect [`LAYERS`]: a module imports only from a lower rank or
//!   from [`BASE`]; two modules of one rank (optim and surface) do not import each other;
//! - no cycle between the crate's top-level modules;
//! - no cycle among the modules inside `optim`, and none among the CLI's modules (a module and its own
//!   parent are one unit here: the parent declares, re-exports and dispatches to its children);
//! - no file in `optim` over [`OPTIM_MAX_LINES`] lines;
//! - no function over [`MAX_FUNCTION_LINES`] lines in the workspace's sources (`crates/*/src`, unit
//!   tests left out), from its `fn` to its closing brace.
//!
//! The optim and CLI checks hold on today's code through the allowlists below; a cycle passes only when
//! all its modules lie inside one allowlisted cycle, a long file only when it is listed.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The crate's layers, bottom to top: `(top-level module, rank)`. A module may import from a lower
/// rank only; modules of one rank sit side by side.
const LAYERS: &[(&str, usize)] = &[
    ("nurbs", 0),
    ("diffgeo", 1),
    ("fair", 2),
    ("fit", 3),
    ("optim", 4),
    ("surface", 4),
    ("io", 5),
    ("plot", 6),
    ("report", 7),
    // the library's front door: re-exports only, above everything it names
    ("prelude", 8),
];

/// Top-level modules every layer may import (they import no layer themselves).
const BASE: &[&str] = &["errors", "tolerance"];

/// Longest file allowed in `crates/fairfit/src/optim`, in lines.
const OPTIM_MAX_LINES: usize = 600;

/// Cycles allowed among optim's modules (paths below `optim`): none. An entry here is a known
/// violation waiting for its fix, never a permanent exception.
const ALLOWED_OPTIM_CYCLES: &[&[&str]] = &[];

/// Files of optim (paths below `optim`) allowed over [`OPTIM_MAX_LINES`] lines: none, as above.
const ALLOWED_OPTIM_LONG_FILES: &[&str] = &[];

/// Cycles allowed among the CLI's modules: none, as above.
const ALLOWED_CLI_CYCLES: &[&[&str]] = &[];

/// Longest function allowed in the workspace's sources, in lines (signature and body).
const MAX_FUNCTION_LINES: usize = 150;

/// Functions allowed over [`MAX_FUNCTION_LINES`] lines, as `(path below crates, name)`: none. An
/// entry here is a known defect to split, not a licence.
const ALLOWED_LONG_FUNCTIONS: &[(&str, &str)] = &[];

// ---------------------------------------------------------------------------------------------------
// Sources to tokens
// ---------------------------------------------------------------------------------------------------

/// A token of Rust source: an identifier or keyword, or one punctuation character (`::` is one token).
#[derive(Clone, Debug, PartialEq)]
struct Token {
    text: String,
    line: usize,
}

/// The tokens of `src` with comments, string and character literals left out.
fn tokens(src: &str) -> Vec<Token> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize, s: &str| {
        s.chars()
            .enumerate()
            .all(|(k, ch)| c.get(i + k) == Some(&ch))
    };
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if at(i, "//") {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if at(i, "/*") {
            let mut depth = 0;
            while i < c.len() {
                if at(i, "/*") {
                    depth += 1;
                    i += 2;
                } else if at(i, "*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if ch == 'r' && (at(i, "r\"") || at(i, "r#")) && raw_string_end(&c, i).is_some() {
            let end = raw_string_end(&c, i).unwrap_or(c.len());
            line += c[i..end].iter().filter(|&&x| x == '\n').count();
            i = end;
        } else if ch == '"' || (ch == 'b' && at(i, "b\"")) {
            i += if ch == 'b' { 2 } else { 1 };
            while i < c.len() && c[i] != '"' {
                line += usize::from(c[i] == '\n');
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' {
            // a character literal ('a', '\n', '\u{7f}') or a lifetime ('a)
            if c.get(i + 1) == Some(&'\\') {
                i += 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
            }
        } else if ch.is_alphanumeric() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(Token {
                text: c[start..i].iter().collect(),
                line,
            });
        } else if at(i, "::") {
            out.push(Token {
                text: "::".into(),
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                text: ch.to_string(),
                line,
            });
            i += 1;
        }
    }
    out
}

/// The index just past a raw string literal starting at `i` (`r"…"`, `r#"…"#`), if one starts there.
fn raw_string_end(c: &[char], i: usize) -> Option<usize> {
    let mut j = i + 1;
    let mut hashes = 0;
    while c.get(j) == Some(&'#') {
        hashes += 1;
        j += 1;
    }
    if c.get(j) != Some(&'"') {
        return None;
    }
    j += 1;
    while j < c.len() {
        if c[j] == '"' && (1..=hashes).all(|k| c.get(j + k) == Some(&'#')) {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(c.len())
}

/// `tokens` without the items marked `#[cfg(test)]` (a `mod tests { … }`, a `use …;`, a function).
fn without_test_items(t: Vec<Token>) -> Vec<Token> {
    let is = |k: usize, s: &str| t.get(k).is_some_and(|x| x.text == s);
    let mut out = Vec::with_capacity(t.len());
    let mut i = 0;
    while i < t.len() {
        let cfg_test = is(i, "#")
            && is(i + 1, "[")
            && is(i + 2, "cfg")
            && is(i + 3, "(")
            && is(i + 4, "test")
            && is(i + 5, ")")
            && is(i + 6, "]");
        if !cfg_test {
            out.push(t[i].clone());
            i += 1;
            continue;
        }
        // skip the item: up to its `;` or the end of its first brace block
        i += 7;
        let mut depth = 0usize;
        while i < t.len() {
            match t[i].text.as_str() {
                "{" => depth += 1,
                "}" => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        i += 1;
                        break;
                    }
                }
                ";" if depth == 0 => {
                    i += 1;
                    break;
                }
                _ => {}
            }
            i += 1;
        }
    }
    out
}

/// A function of a source file: its name, the line of its `fn`, and its length in lines (from the
/// `fn` to the closing brace of its body).
#[derive(Clone, Debug, PartialEq)]
struct Function {
    name: String,
    line: usize,
    lines: usize,
}

/// Every function with a body in `t` (declarations without a body, as in a trait, are skipped;
/// nested functions are listed on their own and also count in their parent's length).
fn functions(t: &[Token]) -> Vec<Function> {
    let mut out = Vec::new();
    for (i, tok) in t.iter().enumerate() {
        let Some(name) = t
            .get(i + 1)
            .filter(|n| tok.text == "fn" && is_ident(&n.text))
        else {
            continue;
        };
        // the body: the first `{` outside parentheses and brackets, unless a `;` comes first
        let mut j = i + 2;
        let mut depth = 0i32;
        let open = loop {
            match t.get(j).map(|x| x.text.as_str()) {
                None => break None,
                Some("(" | "[") => depth += 1,
                Some(")" | "]") => depth -= 1,
                Some(";") if depth == 0 => break None,
                Some("{") if depth == 0 => break Some(j),
                _ => {}
            }
            j += 1;
        };
        let Some(open) = open else { continue };
        let mut braces = 0usize;
        let mut end = t.len() - 1;
        for (k, x) in t.iter().enumerate().skip(open) {
            match x.text.as_str() {
                "{" => braces += 1,
                "}" => {
                    braces -= 1;
                    if braces == 0 {
                        end = k;
                        break;
                    }
                }
                _ => {}
            }
        }
        out.push(Function {
            name: name.text.clone(),
            line: tok.line,
            lines: t[end].line - tok.line + 1,
        });
    }
    out
}

/// The functions of `sources` (`(path, text)`) over `max` lines, unit tests left out (`#[cfg(test)]`
/// items and files named `tests.rs`), except `allowed` `(path, name)`: `path:line name (n lines)`.
fn long_functions(
    sources: &[(String, String)],
    max: usize,
    allowed: &[(&str, &str)],
) -> Vec<String> {
    let mut out = Vec::new();
    for (path, text) in sources {
        if path == "tests.rs" || path.ends_with("/tests.rs") {
            continue;
        }
        for f in functions(&without_test_items(tokens(text))) {
            if f.lines > max && !allowed.contains(&(path.as_str(), f.name.as_str())) {
                out.push(format!("{path}:{} {} ({} lines)", f.line, f.name, f.lines));
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------------
// Tokens to references
// ---------------------------------------------------------------------------------------------------

/// A path a module names: its segments as written, the name it binds (a `use` declaration's last
/// segment or alias; `None` for a path in code or a glob), and its line.
#[derive(Clone, Debug, PartialEq)]
struct Reference {
    path: Vec<String>,
    binds: Option<String>,
    line: usize,
}

/// The `use` trees and the `crate::`/`super::`/`self::` paths of a file's tokens.
fn references(t: &[Token]) -> Vec<Reference> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < t.len() {
        if t[i].text == "use" {
            let line = t[i].line;
            i += 1;
            use_tree(t, &mut i, &[], line, &mut out);
            while i < t.len() && t[i].text != ";" {
                i += 1;
            }
        } else if matches!(t[i].text.as_str(), "crate" | "super" | "self")
            && t.get(i + 1).is_some_and(|x| x.text == "::")
            && (i == 0 || t[i - 1].text != "::")
        {
            let line = t[i].line;
            let mut path = vec![t[i].text.clone()];
            i += 1;
            while t.get(i).is_some_and(|x| x.text == "::")
                && t.get(i + 1).is_some_and(|x| is_ident(&x.text))
            {
                path.push(t[i + 1].text.clone());
                i += 2;
            }
            out.push(Reference {
                path,
                binds: None,
                line,
            });
            continue;
        }
        i += 1;
    }
    out
}

fn is_ident(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// Parses one use tree at `t[*i]` below `prefix`, pushing every leaf path.
fn use_tree(t: &[Token], i: &mut usize, prefix: &[String], line: usize, out: &mut Vec<Reference>) {
    let mut path = prefix.to_vec();
    if t.get(*i).is_some_and(|x| x.text == "::") {
        *i += 1; // a leading `::` (`use ::std::…`)
    }
    loop {
        let Some(tok) = t.get(*i) else { return };
        match tok.text.as_str() {
            "{" => {
                *i += 1;
                while t.get(*i).is_some_and(|x| x.text != "}") {
                    use_tree(t, i, &path, line, out);
                    if t.get(*i).is_some_and(|x| x.text == ",") {
                        *i += 1;
                    }
                }
                *i += 1;
                return;
            }
            "*" => {
                *i += 1;
                out.push(Reference {
                    path,
                    binds: None,
                    line,
                });
                return;
            }
            s if is_ident(s) => {
                path.push(s.to_string());
                *i += 1;
                if t.get(*i).is_some_and(|x| x.text == "::") {
                    *i += 1;
                    continue;
                }
                let mut binds = path.last().cloned();
                if t.get(*i).is_some_and(|x| x.text == "as") {
                    binds = t.get(*i + 1).map(|x| x.text.clone());
                    *i += 2;
                }
                if binds.as_deref() == Some("self") {
                    path.pop();
                    binds = path.last().cloned();
                }
                out.push(Reference { path, binds, line });
                return;
            }
            _ => return,
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// References to a module graph
// ---------------------------------------------------------------------------------------------------

/// A module path below its crate's root (`[]` is the root, `["io", "cad_read"]` is `io::cad_read`).
type Module = Vec<String>;

/// The module a source file is, from its path below `src` (`io/mod.rs` is `io`, `lib.rs` the root).
fn module_of_file(rel: &str) -> Module {
    let rel = rel.trim_end_matches(".rs");
    let mut segs: Vec<String> = rel.split('/').map(str::to_string).collect();
    if matches!(
        segs.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        segs.pop();
    }
    segs
}

fn name(m: &[String]) -> String {
    m.join("::")
}

/// One dependency: `from` names something of `to` at `file:line` (`text` is the path as written).
#[derive(Clone, Debug)]
struct Edge {
    from: Module,
    to: Module,
    file: String,
    line: usize,
    text: String,
}

/// A crate's sources: `(path below src, text)`.
struct Crate {
    files: Vec<(String, Module, Vec<Reference>)>,
    modules: BTreeSet<Module>,
    /// Per module, the names its `use` declarations bind and the absolute paths they bind.
    bindings: BTreeMap<Module, BTreeMap<String, Vec<String>>>,
}

impl Crate {
    fn new(sources: &[(String, String)]) -> Crate {
        let mut files = Vec::new();
        for (rel, text) in sources {
            let refs = references(&without_test_items(tokens(text)));
            files.push((rel.clone(), module_of_file(rel), refs));
        }
        let modules: BTreeSet<Module> = files.iter().map(|f| f.1.clone()).collect();
        let mut krate = Crate {
            files,
            modules,
            bindings: BTreeMap::new(),
        };
        let mut bindings: BTreeMap<Module, BTreeMap<String, Vec<String>>> = BTreeMap::new();
        for (_, m, refs) in &krate.files {
            for r in refs {
                if let (Some(b), Some(abs)) = (&r.binds, krate.absolute(m, &r.path)) {
                    bindings
                        .entry(m.clone())
                        .or_default()
                        .insert(b.clone(), abs);
                }
            }
        }
        krate.bindings = bindings;
        krate
    }

    /// `path` as named in module `m`, made absolute; `None` for a path outside the crate.
    fn absolute(&self, m: &[String], path: &[String]) -> Option<Vec<String>> {
        let first = path.first()?;
        match first.as_str() {
            "crate" => Some(path[1..].to_vec()),
            "self" => Some([m, &path[1..]].concat()),
            "super" => {
                let ups = path.iter().take_while(|s| *s == "super").count();
                let base = m.get(..m.len().checked_sub(ups)?)?;
                Some([base, &path[ups..]].concat())
            }
            _ => {
                let child: Module = [m, &path[..1]].concat();
                self.modules.contains(&child).then(|| [m, path].concat())
            }
        }
    }

    /// The module that defines what the absolute `path` names: its longest module prefix, and through
    /// the `use` bindings of that module when the next segment is a name it imports.
    fn target(&self, path: &[String]) -> Module {
        let mut path = path.to_vec();
        for _ in 0..8 {
            let k = (0..=path.len())
                .rev()
                .find(|&k| self.modules.contains(&path[..k]))
                .unwrap_or(0);
            let module = path[..k].to_vec();
            let next = path.get(k);
            match next.and_then(|n| self.bindings.get(&module)?.get(n)) {
                Some(abs) if abs.as_slice() != path.as_slice() => {
                    path = [abs.as_slice(), &path[k + 1..]].concat();
                }
                _ => return module,
            }
        }
        path
    }

    /// Every dependency between two different modules.
    fn edges(&self) -> Vec<Edge> {
        let mut out = Vec::new();
        for (file, m, refs) in &self.files {
            for r in refs {
                let Some(abs) = self.absolute(m, &r.path) else {
                    continue;
                };
                let to = self.target(&abs);
                if &to != m {
                    out.push(Edge {
                        from: m.clone(),
                        to,
                        file: file.clone(),
                        line: r.line,
                        text: r.path.join("::"),
                    });
                }
            }
        }
        out
    }
}

/// The strongly connected components of more than one node (Tarjan), each sorted, in sorted order.
fn cycles(edges: &[(String, String)]) -> Vec<Vec<String>> {
    let mut nodes: BTreeSet<&str> = BTreeSet::new();
    let mut next: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for (a, b) in edges {
        nodes.insert(a);
        nodes.insert(b);
        next.entry(a).or_default().insert(b);
    }
    struct State<'a> {
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(v: &'a str, next: &BTreeMap<&'a str, BTreeSet<&'a str>>, s: &mut State<'a>) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        for &w in next.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(w, next, s);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in nodes {
        if !s.index.contains_key(v) {
            visit(v, &next, &mut s);
        }
    }
    s.out.sort();
    s.out
}

// ---------------------------------------------------------------------------------------------------
// The checks
// ---------------------------------------------------------------------------------------------------

fn rank(top: &str) -> Option<usize> {
    LAYERS.iter().find(|(m, _)| *m == top).map(|&(_, r)| r)
}

/// The imports of the library that break [`LAYERS`], one line each naming the file.
fn layer_violations(krate: &Crate) -> Vec<String> {
    let mut out = BTreeSet::new();
    for e in krate.edges() {
        let (Some(from), Some(to)) = (e.from.first(), e.to.first()) else {
            continue; // the crate root declares and re-exports every module
        };
        if from == to || BASE.contains(&to.as_str()) {
            continue;
        }
        let at = format!("{}:{} uses {}", e.file, e.line, e.text);
        match (rank(from), rank(to)) {
            _ if BASE.contains(&from.as_str()) => {
                out.insert(format!(
                    "{at}: `{from}` is a base module and imports no layer"
                ));
            }
            (Some(rf), Some(rt)) if rt > rf => {
                out.insert(format!("{at}: `{from}` imports upward from `{to}`"));
            }
            (Some(rf), Some(rt)) if rt == rf => {
                out.insert(format!("{at}: `{from}` and `{to}` sit side by side"));
            }
            (None, _) | (_, None) => {
                out.insert(format!(
                    "{at}: place `{from}` and `{to}` in LAYERS or BASE of tests/architecture.rs"
                ));
            }
            _ => {}
        }
    }
    out.into_iter().collect()
}

/// The cycles between the library's top-level modules.
fn crate_cycles(krate: &Crate) -> Vec<Vec<String>> {
    let edges: Vec<(String, String)> = krate
        .edges()
        .into_iter()
        .filter_map(|e| Some((e.from.first()?.clone(), e.to.first()?.clone())))
        .filter(|(a, b)| a != b)
        .collect();
    cycles(&edges)
}

fn is_prefix(a: &[String], b: &[String]) -> bool {
    a.len() <= b.len() && b[..a.len()] == *a
}

/// The cycles among the modules below `scope` (named relative to it), a module and its ancestors
/// counted as one unit.
fn cycles_below(krate: &Crate, scope: &[String]) -> Vec<Vec<String>> {
    let edges: Vec<(String, String)> = krate
        .edges()
        .into_iter()
        .filter(|e| is_prefix(scope, &e.from) && is_prefix(scope, &e.to))
        .filter(|e| !is_prefix(&e.from, &e.to) && !is_prefix(&e.to, &e.from))
        .map(|e| (name(&e.from[scope.len()..]), name(&e.to[scope.len()..])))
        .collect();
    cycles(&edges)
}

/// The cycles of `found` that do not lie inside one of `allowed`, each with the edges that close it.
fn new_cycles(found: &[Vec<String>], allowed: &[&[&str]]) -> Vec<Vec<String>> {
    found
        .iter()
        .filter(|c| {
            !allowed
                .iter()
                .any(|a| c.iter().all(|m| a.contains(&m.as_str())))
        })
        .cloned()
        .collect()
}

/// The edges inside one cycle, for a failure message.
fn cycle_evidence(krate: &Crate, scope: &[String], cycle: &[String]) -> String {
    let inside = |m: &Module| {
        is_prefix(scope, m) && {
            let n = name(&m[scope.len()..]);
            cycle
                .iter()
                .any(|c| n == *c || n.starts_with(&format!("{c}::")))
        }
    };
    let mut lines: BTreeSet<String> = BTreeSet::new();
    for e in krate.edges() {
        if inside(&e.from)
            && inside(&e.to)
            && !is_prefix(&e.from, &e.to)
            && !is_prefix(&e.to, &e.from)
        {
            lines.insert(format!("    {}:{} uses {}", e.file, e.line, e.text));
        }
    }
    lines.into_iter().collect::<Vec<_>>().join("\n")
}

/// Every `.rs` file below `dir`: `(path below dir with '/', text)`, sorted.
fn read_sources(dir: &Path) -> Vec<(String, String)> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.push((rel, std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out
}

fn library() -> Vec<(String, String)> {
    read_sources(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"))
}

fn cli() -> Vec<(String, String)> {
    read_sources(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../fairfit-cli/src"))
}

/// The sources of every crate of the workspace (`crates/*/src`), paths below `crates`.
fn workspace_sources() -> Vec<(String, String)> {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut names: Vec<String> = std::fs::read_dir(&crates)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| crates.join(n).join("src").is_dir())
        .collect();
    names.sort();
    let mut out = Vec::new();
    for n in names {
        for (rel, text) in read_sources(&crates.join(&n).join("src")) {
            out.push((format!("{n}/src/{rel}"), text));
        }
    }
    out
}

fn optim() -> Module {
    vec!["optim".to_string()]
}

#[test]
fn the_library_imports_only_from_lower_layers() {
    let v = layer_violations(&Crate::new(&library()));
    assert!(v.is_empty(), "imports across the layers:\n{}", v.join("\n"));
}

#[test]
fn no_cycle_between_the_librarys_modules() {
    let krate = Crate::new(&library());
    let shown: Vec<String> = crate_cycles(&krate)
        .iter()
        .map(|c| format!("{c:?}\n{}", cycle_evidence(&krate, &[], c)))
        .collect();
    assert!(
        shown.is_empty(),
        "cycles between the crate's modules:\n{}",
        shown.join("\n")
    );
}

#[test]
fn no_new_cycle_inside_optim() {
    let krate = Crate::new(&library());
    let new = new_cycles(&cycles_below(&krate, &optim()), ALLOWED_OPTIM_CYCLES);
    let shown: Vec<String> = new
        .iter()
        .map(|c| format!("{c:?}\n{}", cycle_evidence(&krate, &optim(), c)))
        .collect();
    assert!(new.is_empty(), "cycles inside optim:\n{}", shown.join("\n"));
}

#[test]
fn no_new_long_file_in_optim() {
    let long: Vec<String> = library()
        .into_iter()
        .filter_map(|(rel, text)| {
            let below = rel.strip_prefix("optim/")?.to_string();
            let n = text.lines().count();
            (n > OPTIM_MAX_LINES && !ALLOWED_OPTIM_LONG_FILES.contains(&below.as_str()))
                .then(|| format!("src/{rel}: {n} lines"))
        })
        .collect();
    assert!(
        long.is_empty(),
        "files in optim over {OPTIM_MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn no_new_long_function() {
    let sources = workspace_sources();
    assert!(sources.len() > 100, "{} source files", sources.len());
    let long = long_functions(&sources, MAX_FUNCTION_LINES, ALLOWED_LONG_FUNCTIONS);
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines:\n{}",
        long.join("\n")
    );
    // an allowed entry that no longer names a long function is stale: remove it
    let stale: Vec<&(&str, &str)> = ALLOWED_LONG_FUNCTIONS
        .iter()
        .filter(|a| {
            long_functions(&sources, MAX_FUNCTION_LINES, &[])
                .iter()
                .all(|l| {
                    !(l.starts_with(&format!("{}:", a.0)) && l.contains(&format!(" {} (", a.1)))
                })
        })
        .collect();
    assert!(stale.is_empty(), "stale allowed long functions: {stale:?}");
}

#[test]
fn no_new_cycle_between_the_clis_modules() {
    let krate = Crate::new(&cli());
    let new = new_cycles(&cycles_below(&krate, &[]), ALLOWED_CLI_CYCLES);
    let shown: Vec<String> = new
        .iter()
        .map(|c| format!("{c:?}\n{}", cycle_evidence(&krate, &[], c)))
        .collect();
    assert!(new.is_empty(), "cycles in the CLI:\n{}", shown.join("\n"));
}

// ---------------------------------------------------------------------------------------------------
// The checks can fail: synthetic crates
// ---------------------------------------------------------------------------------------------------

fn synthetic(files: &[(&str, &str)]) -> Crate {
    let owned: Vec<(String, String)> = files
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    Crate::new(&owned)
}

fn s(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

#[test]
fn a_two_cycle_between_modules_is_found() {
    let k = synthetic(&[
        ("lib.rs", "pub mod fit;\npub mod io;\n"),
        ("fit/mod.rs", "pub mod shape;\n"),
        ("fit/shape.rs", "use crate::io::points::extent;\n"),
        ("io/mod.rs", "pub mod points;\n"),
        ("io/points.rs", "pub fn f() { crate::fit::shape::g(); }\n"),
    ]);
    assert_eq!(crate_cycles(&k), vec![s(&["fit", "io"])]);
    let v = layer_violations(&k);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(
        v[0].starts_with("fit/shape.rs:1 uses crate::io::points::extent"),
        "{v:?}"
    );
    assert!(v[0].contains("imports upward"), "{v:?}");
}

#[test]
fn an_upward_import_in_a_group_is_found_and_comments_strings_and_tests_are_not() {
    let k = synthetic(&[
        (
            "nurbs/knots.rs",
            "use crate::{errors::Error, nurbs::{curve::C, Vec3}};\n\
             /// [`crate::fit::lsq`] builds them\n\
             const S: &str = \"crate::plot::x\";\n\
             #[cfg(test)]\nmod tests { use crate::io::read_points; }\n\
             fn f() { let _ = crate::fit::lsq::periodic_knots; }\n",
        ),
        ("nurbs/curve.rs", ""),
        ("fit/lsq.rs", ""),
        ("io/mod.rs", ""),
        ("plot/mod.rs", ""),
        ("errors.rs", ""),
    ]);
    let v = layer_violations(&k);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(v[0].starts_with("nurbs/knots.rs:6 uses crate::fit::lsq::periodic_knots"));
}

#[test]
fn side_by_side_and_unplaced_modules_are_found() {
    let k = synthetic(&[
        ("surface/a.rs", "use crate::optim::x::Y;\n"),
        ("optim/x.rs", ""),
        ("extras.rs", "pub use crate::fit::F;\n"),
        ("fit/mod.rs", ""),
    ]);
    let v = layer_violations(&k);
    assert_eq!(v.len(), 2, "{v:?}");
    assert!(v.iter().any(|l| l.contains("side by side")), "{v:?}");
    assert!(v.iter().any(|l| l.contains("place `extras`")), "{v:?}");
}

#[test]
fn super_paths_and_reexports_resolve_to_the_defining_sibling() {
    // `b` uses `super::Thing`, which `optim/mod.rs` re-exports from `a`; `a` uses `b` back
    let k = synthetic(&[
        ("optim/mod.rs", "mod a;\nmod b;\npub use a::Thing;\n"),
        ("optim/a.rs", "use super::b::helper;\npub struct Thing;\n"),
        ("optim/b.rs", "use super::Thing;\npub fn helper() {}\n"),
        ("optim/c.rs", "use super::super::optim::a;\n"),
    ]);
    assert_eq!(cycles_below(&k, &optim()), vec![s(&["a", "b"])]);
    assert!(new_cycles(&cycles_below(&k, &optim()), &[&["a", "b", "z"]]).is_empty());
    assert_eq!(
        new_cycles(&cycles_below(&k, &optim()), &[&["a", "z"]]),
        vec![s(&["a", "b"])]
    );
    assert!(crate_cycles(&k).is_empty());
}

#[test]
fn a_parent_and_its_children_are_one_unit() {
    // the CLI's `commands/mod.rs` dispatches to its children, which use its error type
    let k = synthetic(&[
        ("main.rs", "mod commands;\nfn main() { commands::run(); }\n"),
        (
            "commands/mod.rs",
            "pub mod curve;\npub struct CliError;\npub fn run() { curve::run(); }\n",
        ),
        (
            "commands/curve.rs",
            "use super::CliError;\npub fn run() {}\n",
        ),
    ]);
    assert!(cycles_below(&k, &[]).is_empty());
}

#[test]
fn a_long_function_is_found_and_tests_declarations_and_strings_are_not() {
    let body = |n: usize| "    let x = 1;\n".repeat(n);
    let src = format!(
        "trait T {{\n    fn declared(&self) -> [u8; 3];\n}}\n\
         fn short() {{\n{}}}\n\
         pub(crate) fn long<A: Fn() -> ()>(a: [u8; 2]) -> Result<(), ()> {{\n    let s = \"}}\";\n{}}}\n\
         #[cfg(test)]\nmod tests {{\n    fn long_test() {{\n{}    }}\n}}\n",
        body(8),
        body(10),
        body(20)
    );
    let sources = vec![
        ("a/src/lib.rs".to_string(), src.clone()),
        ("a/src/tests.rs".to_string(), src),
    ];
    let f = functions(&without_test_items(tokens(&sources[0].1)));
    let named: Vec<(&str, usize, usize)> = f
        .iter()
        .map(|f| (f.name.as_str(), f.line, f.lines))
        .collect();
    // `short` spans its `fn` line, 8 body lines and the brace; `long` its `fn` line, the string
    // holding a brace, 10 body lines and the brace
    assert_eq!(named, vec![("short", 4, 10), ("long", 14, 13)]);
    assert_eq!(
        long_functions(&sources, 12, &[]),
        vec!["a/src/lib.rs:14 long (13 lines)".to_string()]
    );
    assert!(long_functions(&sources, 13, &[]).is_empty());
    assert!(long_functions(&sources, 12, &[("a/src/lib.rs", "long")]).is_empty());
}

#[test]
fn the_tokenizer_skips_raw_strings_chars_and_nested_comments() {
    let t =
        tokens("let a = r#\"use crate::x;\"#; /* a /* b */ crate::y */ let c = '\"'; crate::z::w");
    let r = references(&t);
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(r[0].path, s(&["crate", "z", "w"]));
    let r = references(&tokens(
        "use std::{io, fmt::Write as _};\nuse self::a::{self, B};\n",
    ));
    let paths: Vec<Vec<String>> = r.iter().map(|x| x.path.clone()).collect();
    assert_eq!(
        paths,
        vec![
            s(&["std", "io"]),
            s(&["std", "fmt", "Write"]),
            s(&["self", "a"]),
            s(&["self", "a", "B"])
        ]
    );
    assert_eq!(r[1].binds.as_deref(), Some("_"));
}

// ---------------------------------------------------------------------------------------------------
// No bare unwrap outside tests
// ---------------------------------------------------------------------------------------------------

/// Files of `sources` that are test modules of their own: declared `#[cfg(test)] mod name;` by their
/// parent (`name.rs`, `name/mod.rs`, and everything below `name/`).
fn test_module_files(sources: &[(String, String)]) -> BTreeSet<String> {
    let mut prefixes = Vec::new();
    for (rel, text) in sources {
        let t = tokens(text);
        let is = |k: usize, s: &str| t.get(k).is_some_and(|x| x.text == s);
        // the folder of the file's child modules: `a/b.rs` -> `a/b/`, `a/mod.rs` -> `a/`
        let dir = match rel.rsplit_once('/') {
            Some((d, f)) if ["mod.rs", "lib.rs", "main.rs"].contains(&f) => format!("{d}/"),
            None if ["mod.rs", "lib.rs", "main.rs"].contains(&rel.as_str()) => String::new(),
            _ => format!("{}/", rel.trim_end_matches(".rs")),
        };
        for i in 0..t.len() {
            let cfg_test = ["#", "[", "cfg", "(", "test", ")", "]"]
                .iter()
                .enumerate()
                .all(|(k, s)| is(i + k, s));
            let j = if is(i + 7, "pub") { i + 8 } else { i + 7 };
            if cfg_test && is(j, "mod") && is(j + 2, ";") {
                prefixes.push(format!("{dir}{}", t[j + 1].text));
            }
        }
    }
    sources
        .iter()
        .map(|(rel, _)| rel.clone())
        .filter(|rel| {
            prefixes
                .iter()
                .any(|p| *rel == format!("{p}.rs") || rel.starts_with(&format!("{p}/")))
        })
        .collect()
}

/// Every `.unwrap()` call in the non-test code of `sources`, as `path:line`: comments, strings,
/// `#[cfg(test)]` items and test-module files left out. `unwrap_or`, `unwrap_or_else` and the like
/// are other tokens and pass.
fn bare_unwraps(sources: &[(String, String)]) -> Vec<String> {
    let tests = test_module_files(sources);
    let mut found = Vec::new();
    for (rel, text) in sources {
        if tests.contains(rel) {
            continue;
        }
        let t = without_test_items(tokens(text));
        for w in t.windows(4) {
            let texts: Vec<&str> = w.iter().map(|x| x.text.as_str()).collect();
            if texts == [".", "unwrap", "(", ")"] {
                found.push(format!("{rel}:{}", w[1].line));
            }
        }
    }
    found
}

/// A bare `unwrap()` is a panic with no message: in the library and the CLI, every unwrap that
/// cannot fail is an `expect` naming the invariant that makes it infallible, and every one that input
/// can reach is a typed error (docs/reliability.md, "Panics audit").
#[test]
fn no_bare_unwrap_in_the_library_or_the_cli() {
    for (name, sources) in [
        ("crates/fairfit/src", library()),
        ("crates/fairfit-cli/src", cli()),
    ] {
        assert!(sources.len() > 10, "{name}: {} source files", sources.len());
        let found = bare_unwraps(&sources);
        assert!(
            found.is_empty(),
            "bare .unwrap() in {name} (use an error, or expect(\"the invariant\")):\n{}",
            found.join("\n")
        );
    }
}

#[test]
fn a_planted_unwrap_is_found_and_comments_strings_and_tests_are_not() {
    let lib = "//! `x.unwrap()` in a doc comment\n\
               /// let c = f().unwrap();\n\
               pub fn f(x: Option<u8>) -> u8 {\n\
               \x20   let s = \"x.unwrap()\"; let r = r#\"y.unwrap()\"#; /* z.unwrap() */\n\
               \x20   let c = '.'; let _ = x.unwrap_or(0);\n\
               \x20   x.unwrap()\n\
               }\n\
               #[cfg(test)]\nmod tests {\n    fn t() { Some(1).unwrap(); }\n}\n\
               #[cfg(test)]\nmod more;\n";
    let sources = vec![
        ("a/mod.rs".to_string(), lib.to_string()),
        (
            "a/more.rs".to_string(),
            "fn g() { Some(1).unwrap(); }\n".to_string(),
        ),
        (
            "a/more/deep.rs".to_string(),
            "fn h() { Some(1).unwrap(); }\n".to_string(),
        ),
        (
            "b.rs".to_string(),
            "fn k() -> u8 { Some(1)\n    .unwrap() }\n".to_string(),
        ),
    ];
    assert_eq!(
        test_module_files(&sources).into_iter().collect::<Vec<_>>(),
        vec!["a/more.rs".to_string(), "a/more/deep.rs".to_string()]
    );
    assert_eq!(bare_unwraps(&sources), vec!["a/mod.rs:6", "b.rs:2"]);
}
