#!/usr/bin/env python3
"""Data flows one way in src/: no import circle between its top-level modules,
nor between the files of one.

Reads every `.rs` file under src/ (src/main.rs aside: it is another crate,
which uses the library by name), finds the paths that reach another module —
`crate::X…`, `use crate::{X…, Y…}`, and `super::` chains — and fails when
those references make a cycle between top-level modules (api, service,
store, jobs, dynamics, …), or between the files of one top-level module
(src/jobs/spec.rs and src/jobs/kind.rs, say; a folder below one, like
src/kinds/forensic/, counts as one file). A name that a module's mod.rs
re-exports (`pub use registry::Job`) counts as a use of the file it comes
from.

Comments and string literals are skipped, and so are items under
`#[cfg(test)]`: a test may use any module to check another (they are listed
apart, for information). The edges of SET_ASIDE (circles left on purpose,
each with its reason) are listed and left out; a circle without them fails
the check.

    python3 tests/import_graph.py          # the check; exit status 1 on a cycle
    python3 tests/import_graph.py --dot    # the graph in Graphviz form
"""

from __future__ import annotations

import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"

# Edges of circles that run through modules being reworked elsewhere, each
# with why it exists: set aside, so that the check fails on any other circle.
# A line whose edge is gone is reported, to be removed.
SET_ASIDE: dict[tuple[str, str], str] = {}

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
RAW = re.compile(r'r(#*)"')
CHAR = re.compile(r"'(\\(u\{[0-9a-fA-F]+\}|x[0-9a-fA-F]{2}|.)|[^\\'])'")


def tokens(text: str) -> list[str]:
    """Rust tokens enough for paths: identifiers, `::`, punctuation; comments,
    strings and character literals dropped (lifetimes kept as `'a`)."""
    out: list[str] = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c.isspace():
            i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j + 1
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif c == "r" and RAW.match(text, i):
            m = RAW.match(text, i)
            assert m
            close = '"' + m.group(1)
            j = text.find(close, i + len(m.group(0)))
            i = n if j < 0 else j + len(close)
            out.append('""')
        elif c == "b" and text.startswith(('b"', "br\"", "br#", "b'"), i):
            i += 1  # a byte string or byte: read on as a string or character
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'":
            # A character literal ('a', '\n', '\u{..}') or a lifetime ('a).
            m = CHAR.match(text, i)
            if m:
                i += len(m.group(0))
                out.append("''")
            else:
                m = IDENT.match(text, i + 1)
                if m:
                    out.append("'" + m.group(0))
                    i = m.end()
                else:
                    out.append("'")
                    i += 1
        elif text.startswith("::", i):
            out.append("::")
            i += 2
        else:
            m = IDENT.match(text, i)
            if m:
                out.append(m.group(0))
                i = m.end()
            else:
                out.append(c)
                i += 1
    return out


def module_path(file: Path, src: Path = SRC) -> list[str]:
    """The module path of a file: src/api/jobs.rs → [api, jobs]."""
    parts = list(file.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return parts


def group_heads(toks: list[str], i: int) -> list[int]:
    """Indices of the first tokens of each path of the `{…}` group at `i`."""
    heads, depth, j = [i + 1], 0, i
    while j < len(toks):
        t = toks[j]
        if t == "{":
            depth += 1
        elif t == "}":
            depth -= 1
            if depth == 0:
                break
        elif t == "," and depth == 1:
            heads.append(j + 1)
        j += 1
    return [h for h in heads if h < len(toks) and IDENT.fullmatch(toks[h])]


def two_levels(toks: list[str], h: int, prefix: list[str]) -> list[tuple[str, ...]]:
    """The paths that start at token `h` under `prefix`, cut to their first two
    names (`jobs::{spec::X, kind}` → (jobs, spec), (jobs, kind))."""
    path = prefix + [toks[h]]
    if len(path) >= 2:
        return [tuple(path[:2])]
    if toks[h + 1 : h + 2] == ["::"] and h + 2 < len(toks):
        if toks[h + 2] == "{":
            return [tuple(path + [toks[k]]) for k in group_heads(toks, h + 2)]
        if IDENT.fullmatch(toks[h + 2]):
            return [tuple(path + [toks[h + 2]])]
    return [tuple(path)]


def references(
    text: str, base: list[str], top: set[str]
) -> tuple[list[tuple[tuple[str, ...], bool]], list[list[str]]]:
    """(module path cut to two names, under #[cfg(test)]) of each reference
    that names a top-level module in `text`, the source of module `base`
    (`crate::jobs::spec::X` → (jobs, spec)); and the module paths of the
    files it declares under #[cfg(test)] (`mod tests;`)."""
    toks = tokens(text)
    found: list[tuple[tuple[str, ...], bool]] = []
    test_files: list[list[str]] = []
    # Inline modules: (name, brace depth inside it, under cfg(test)).
    stack: list[tuple[str, int, bool]] = []
    depth = 0
    test_until: int | None = None  # brace depth at which a cfg(test) item ends
    pending_test = False
    i = 0
    while i < len(toks):
        t = toks[i]
        in_test = pending_test or test_until is not None or any(s[2] for s in stack)
        if t == "#" and toks[i + 1 : i + 7] == ["[", "cfg", "(", "test", ")", "]"]:
            pending_test = True
            i += 7
            continue
        if t == "mod" and i + 2 < len(toks) and IDENT.fullmatch(toks[i + 1]) and toks[i + 2] == "{":
            depth += 1
            stack.append((toks[i + 1], depth, pending_test))
            pending_test = False
            i += 3
            continue
        if t == "mod" and i + 2 < len(toks) and IDENT.fullmatch(toks[i + 1]) and toks[i + 2] == ";":
            if in_test:
                test_files.append(base + [s[0] for s in stack] + [toks[i + 1]])
            pending_test = False
            i += 3
            continue
        if t == "{":
            depth += 1
            if pending_test and test_until is None:
                test_until = depth
            pending_test = False
        elif t == "}":
            if stack and stack[-1][1] == depth:
                stack.pop()
            if test_until == depth:
                test_until = None
            depth -= 1
        elif t == ";":
            pending_test = False
        here = base + [s[0] for s in stack]
        target: list[int] = []
        if t == "crate" and toks[i + 1 : i + 2] == ["::"] and (i == 0 or toks[i - 1] != "$"):
            j = i + 2
            if j < len(toks) and toks[j] == "{":
                target = group_heads(toks, j)
            else:
                target = [j]
            for h in target:
                if h < len(toks) and toks[h] in top:
                    for path in two_levels(toks, h, []):
                        found.append((path, in_test))
        elif t == "super" and (i == 0 or toks[i - 1] != "::"):
            ups, j = 0, i
            while j + 1 < len(toks) and toks[j] == "super" and toks[j + 1] == "::":
                ups += 1
                j += 2
            if j < len(toks):
                base_path = here[: max(len(here) - ups, 0)]
                heads = group_heads(toks, j) if toks[j] == "{" else [j]
                for h in heads:
                    for path in two_levels(toks, h, base_path):
                        if path[0] in top:
                            found.append((path, in_test))
            i = max(j, i + 1)
            continue
        i += 1
    return found, test_files


def top_modules(src: Path = SRC) -> set[str]:
    """The top-level modules: src/X/mod.rs and src/X.rs."""
    names = set()
    for p in src.iterdir():
        if p.is_dir() and (p / "mod.rs").exists():
            names.add(p.name)
        elif p.suffix == ".rs" and p.stem not in ("lib", "main"):
            names.add(p.stem)
    return names


Edges = dict[str, dict[str, set[str]]]  # module -> module it uses -> files


def graph(src: Path = SRC) -> tuple[Edges, Edges]:
    """Edges between top-level modules, with the files that make them: of
    the library, and of its tests."""
    top = top_modules(src)
    edges: Edges = {m: defaultdict(set) for m in top}
    test_edges: Edges = defaultdict(lambda: defaultdict(set))
    read = {}
    test_files: list[list[str]] = []
    for file in sorted(src.rglob("*.rs")):
        path = module_path(file, src)
        if not path or file == src / "main.rs":
            continue
        read[file], declared = references(file.read_text(encoding="utf-8"), path, top)
        test_files.extend(declared)
    for file, found in read.items():
        path = module_path(file, src)
        test_file = any(path[: len(t)] == t for t in test_files)
        owner = path[0]
        name = str(file.relative_to(src.parent))
        for target, in_test in found:
            if target[0] != owner:
                (test_edges if in_test or test_file else edges)[owner][target[0]].add(name)
    return edges, test_edges


REEXPORT = re.compile(r"^\s*pub(?:\([a-z]+\))?\s+use\s+(?:self::)?([a-z_][a-z0-9_]*)::(\{[^}]*\}|[A-Za-z_][A-Za-z0-9_]*)\s*;", re.M)


def file_graph(module: str, src: Path = SRC) -> Edges:
    """Edges between the files of top-level module `module` (a file is named
    by its module: `spec` for src/jobs/spec.rs, `mod` for src/jobs/mod.rs; a
    folder below is one). A name the module's mod.rs re-exports
    (`pub use registry::{Job, …}`) stands for the file it comes from: the
    re-export is not itself an edge."""
    folder = src / module
    top = top_modules(src)
    units = {p.stem for p in folder.glob("*.rs") if p.stem != "mod"}
    units |= {p.name for p in folder.iterdir() if p.is_dir()}
    origin: dict[str, str] = {}
    for m in REEXPORT.finditer((folder / "mod.rs").read_text(encoding="utf-8")):
        names = m.group(2).strip("{}").split(",")
        for name in names:
            name = name.strip().split(" as ")[-1].strip()
            if name and m.group(1) in units:
                origin[name] = m.group(1)
    edges: Edges = {u: defaultdict(set) for u in units | {"mod"}}
    test_files: list[list[str]] = []
    read = {}
    for file in sorted(folder.rglob("*.rs")):
        path = module_path(file, src)
        read[file], declared = references(file.read_text(encoding="utf-8"), path, top)
        test_files.extend(declared)
    for file, found in read.items():
        path = module_path(file, src)
        if any(path[: len(t)] == t for t in test_files):
            continue
        unit = path[1] if len(path) > 1 else "mod"
        for target, in_test in found:
            if in_test or target[0] != module or len(target) < 2:
                continue
            other = target[1] if target[1] in units else origin.get(target[1], "mod")
            if other != unit:
                edges[unit][other].add(str(file.relative_to(src.parent)))
    return edges


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def self_check() -> None:
    """The reader on the cases it must get right."""
    top = {"api", "service", "store", "jobs"}

    def refs(text: str, path: list[str]) -> list[tuple[str, bool]]:
        return references(text, path, top)[0]

    # Paths, groups, nested groups; not comments, strings, or `pub(crate)`.
    text = """
        //! [`crate::api::router`] in a doc comment
        /* crate::api */ use crate::{store::X, jobs::{a, b}};
        pub(crate) fn f() -> &'static str { let _ = 'c'; "crate::api" }
        let r = r#"crate::api "quoted" "#; let y = crate::service::AppState::new;
        macro_rules! m { () => { $crate::api::x } }
    """
    assert refs(text, ["service", "x"]) == [
        (("store", "X"), False), (("jobs", "a"), False), (("jobs", "b"), False),
        (("service", "AppState"), False),
    ], refs(text, ["service", "x"])
    # `super` climbing out of the module, inline modules, cfg(test).
    text = """
        use super::super::store::Y; use super::problem::P;
        mod inner { use super::super::super::jobs::J; }
        #[cfg(test)]
        mod tests { use crate::api::T; }
        #[cfg(test)]
        use crate::jobs::U;
        #[cfg(test)]
        mod more;
    """
    assert refs(text, ["service", "x"]) == [
        (("store", "Y"), False), (("service", "problem"), False), (("jobs", "J"), False),
        (("api", "T"), True), (("jobs", "U"), True),
    ], refs(text, ["service", "x"])
    assert references(text, ["service", "x"], top)[1] == [["service", "x", "more"]]

    # Files of one module: a re-exported name leads to its file; a folder
    # counts with its file; tests are left out.
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp)
        (src / "m" / "c").mkdir(parents=True)
        (src / "lib.rs").write_text("pub mod m;")
        files = {
            "m/mod.rs": "pub mod a; pub mod b; pub mod c;\npub use a::{A, Other as O};",
            "m/a.rs": "use super::b::B;",
            "m/b.rs": "use crate::m::A;\n#[cfg(test)]\nmod tests { use super::super::c::C; }",
            "m/c.rs": "use super::O;",
            "m/c/inner.rs": "use crate::m::b::B;",
        }
        for name, text in files.items():
            (src / name).write_text(text)
        got = file_graph("m", src)
        assert {a: sorted(bs) for a, bs in got.items() if bs} == {
            "a": ["b"], "b": ["a"], "c": ["a", "b"]
        }, got
        assert cycles({a: set(bs) for a, bs in got.items()}) == [["a", "b"]]


def main() -> int:
    self_check()
    edges, test_edges = graph()
    if "--dot" in sys.argv:
        print("digraph modules {")
        for a in sorted(edges):
            for b in sorted(edges[a]):
                style = " [style=dashed]" if (a, b) in SET_ASIDE else ""
                print(f"  {a} -> {b}{style};")
        print("}")
        return 0
    for a in sorted(edges):
        print(f"{a} -> {', '.join(sorted(edges[a])) or '(nothing)'}")
    extra = {a: set(bs) - set(edges.get(a, {})) for a, bs in test_edges.items()}
    extra = {a: bs for a, bs in extra.items() if bs}
    if extra:
        print("in tests only (not part of the graph):")
        for a in sorted(extra):
            print(f"  {a} -> {', '.join(sorted(extra[a]))}")
    for (a, b), why in sorted(SET_ASIDE.items()):
        if b in edges.get(a, {}):
            files = ", ".join(sorted(edges[a][b]))
            print(f"set aside: {a} -> {b} ({files}): {why}")
        else:
            print(f"note: {a} -> {b} is gone; remove it from SET_ASIDE in {Path(__file__).name}")
    kept = {a: {b for b in bs if (a, b) not in SET_ASIDE} for a, bs in edges.items()}
    found = cycles(kept)
    for c in found:
        members = set(c)
        inside = [
            f"{a} -> {b} ({', '.join(sorted(edges[a][b]))})"
            for a in c
            for b in sorted(kept[a])
            if b in members
        ]
        print(f"import circle among {', '.join(c)}:", file=sys.stderr)
        for line in inside:
            print(f"  {line}", file=sys.stderr)
    inner = 0
    for module in sorted(top_modules()):
        if not (SRC / module).is_dir():
            continue
        files = file_graph(module)
        for c in cycles({a: set(bs) for a, bs in files.items()}):
            inner += 1
            members = set(c)
            print(f"import circle among the files of {module}: {', '.join(c)}:", file=sys.stderr)
            for a in c:
                for b in sorted(files[a]):
                    if b in members:
                        print(f"  {a} -> {b} ({', '.join(sorted(files[a][b]))})", file=sys.stderr)
    if found or inner:
        return 1
    print("no import circle between top-level modules, nor between the files of one")
    return 0


if __name__ == "__main__":
    sys.exit(main())
