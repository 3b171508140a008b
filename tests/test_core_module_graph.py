"""The Rust core's module graph (crates/spacearm-core/src, docs/architecture.md "The core's
layers"), read from the source: no cycle between the core's folders (``sim``, ``control``,
``model``, ...) and none between the files of one folder.

An edge ``a -> b`` means that file ``a`` names an item of file ``b``: through a ``use`` (``crate::``,
``super::``, ``self::`` or a child module's name) or a path written in the code (``crate::x::y``,
``super::y``). A path to a module's re-export (``crate::model::Model``, which ``model/mod.rs``
re-exports from ``model/system.rs``) is followed to the file that defines the item, so a re-export
in ``mod.rs`` is an edge from ``mod.rs`` down to the file it re-exports and no more. Not edges:
``mod x;`` declarations, comments and doc links, string literals, and ``#[cfg(test)]`` modules (a
file's unit tests may use any module; they are no part of the library's layering).
"""

import re
from functools import lru_cache
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / "crates" / "spacearm-core" / "src"


# --- reading the source -------------------------------------------------------------------------


_RAW = re.compile(r'b?r(#*)"')
_CHAR = re.compile(r"'(\\(x..|u\{[0-9a-fA-F]+\}|.)|[^\\'])'")


def _strip(source: str) -> str:
    """``source`` with comments, string and char literals blanked (newlines kept)."""
    out, i, n = [], 0, len(source)
    while i < n:
        c = source[i]
        if source.startswith("//", i):
            j = source.find("\n", i)
            i = n if j < 0 else j
        elif source.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if source.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif source.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append("\n" * source.count("\n", i, j))
            i = j
        elif (m := _RAW.match(source, i)) and (i == 0 or not (source[i - 1].isalnum() or source[i - 1] == "_")):
            end = source.find('"' + m.group(1), m.end())
            j = n if end < 0 else end + 1 + len(m.group(1))
            out.append('""' + "\n" * source.count("\n", i, j))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and source[j] != '"':
                j += 2 if source[j] == "\\" else 1
            out.append('""' + "\n" * source.count("\n", i, j))
            i = j + 1
        elif c == "'" and (m := _CHAR.match(source, i)):
            out.append("' '")
            i = m.end()
        else:
            out.append(c)
            i += 1
    return "".join(out)


def _drop_test_modules(code: str) -> str:
    """``code`` without its ``#[cfg(test)]`` items (a ``mod tests { ... }`` or a ``use``)."""
    while m := re.search(r"#\[cfg\(test\)\]", code):
        j = m.end()
        k_brace, k_semi = code.find("{", j), code.find(";", j)
        if k_semi >= 0 and (k_brace < 0 or k_semi < k_brace):
            end = k_semi + 1
        else:
            depth, end = 0, k_brace
            while True:
                if code[end] == "{":
                    depth += 1
                elif code[end] == "}":
                    depth -= 1
                    if depth == 0:
                        break
                end += 1
            end += 1
        code = code[: m.start()] + "\n" * code.count("\n", m.start(), end) + code[end:]
    return code


def _expand(tree: str) -> list[str]:
    """``a::{b, c::{d, e as f}, self}`` -> ``["a::b", "a::c::d", "a::c::e", "a"]``."""
    tree = re.sub(r"\s+", "", tree)
    depth, split = 0, None
    for k, ch in enumerate(tree):
        if ch == "{":
            if depth == 0 and split is None:
                split = k
            depth += 1
        elif ch == "}":
            depth -= 1
    if split is None:
        return [tree]
    prefix, inner = tree[:split], tree[split + 1 : tree.rindex("}")]
    parts, depth, start = [], 0, 0
    for k, ch in enumerate(inner):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(inner[start:k])
            start = k + 1
    parts.append(inner[start:])
    paths = []
    for part in filter(None, parts):
        for sub in _expand(part):
            paths.append(prefix.rstrip(":").rstrip(":") if sub == "self" else prefix + sub)
    return paths


def _use_paths(code: str) -> list[str]:
    """Every path named by a ``use`` in ``code``, the ``as`` renames dropped."""
    paths = []
    for m in re.finditer(r"\buse\s+([^;]+);", code):
        body = re.sub(r"\s+as\s+\w+", "", m.group(1))
        paths += [re.sub(r"::self$", "", p.lstrip(":")) for p in _expand(body)]
    return paths


# --- resolving paths to files ------------------------------------------------------------------


def _module_of(path: Path, root: Path) -> tuple:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts = parts[:-1]
    return tuple(parts)


def _read_tree(root: Path) -> dict:
    """module path (tuple) -> the file's code (stripped, its test modules dropped)."""
    return {_module_of(p, root): _drop_test_modules(_strip(p.read_text(encoding="utf-8"))) for p in sorted(root.rglob("*.rs"))}


def file_graph(root: Path = SRC) -> dict:
    """``{file: {files it names items of}}``, files named by their path under ``root`` (``sim/stepper.rs``)."""
    code = _read_tree(root)
    files = {}
    for p in root.rglob("*.rs"):
        files[_module_of(p, root)] = p.relative_to(root).as_posix()
    # Each module's re-exports: name -> absolute path (tuple) of what it names.
    reexports = {}
    for mod, text in code.items():
        table = {}
        for m in re.finditer(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]+);", text):
            for raw in _expand(re.sub(r"\s+as\s+\w+", "", m.group(1))):
                absolute = _absolute(raw.lstrip(":").split("::"), mod, code)
                if absolute is not None:
                    table[raw.split("::")[-1]] = absolute
        # `pub use x as y` renames: the table keys by the new name
        for m in re.finditer(r"\bpub(?:\([^)]*\))?\s+use\s+([\w:]+)\s+as\s+(\w+)\s*;", text):
            absolute = _absolute(m.group(1).split("::"), mod, code)
            if absolute is not None:
                table[m.group(2)] = absolute
        reexports[mod] = table

    def resolve(absolute, seen=()):
        """The module (tuple) that defines the item at ``absolute`` (tuple of names)."""
        k = len(absolute)
        while k > 0 and absolute[:k] not in code:
            k -= 1
        mod = absolute[:k]
        rest = absolute[k:]
        if rest and rest[0] in reexports.get(mod, {}) and (mod, rest[0]) not in seen:
            target = reexports[mod][rest[0]] + rest[1:]
            return resolve(target, seen + ((mod, rest[0]),))
        return mod

    graph = {}
    for mod, text in code.items():
        targets = set()
        paths = [p.split("::") for p in _use_paths(text)]
        body = re.sub(r"\buse\s+[^;]+;", "", text)
        paths += [m.group(0).split("::") for m in re.finditer(r"(?<![\w$])(?:\$?crate|super|self)(?:::\w+)+", body)]
        for segments in paths:
            absolute = _absolute([s.lstrip("$") for s in segments], mod, code)
            if absolute is None:
                continue
            target = resolve(absolute)
            if target != mod and target in files:
                targets.add(files[target])
        graph[files[mod]] = targets
    return graph


def _absolute(segments, mod, code):
    """The absolute module path (tuple) of a path written in module ``mod``, or None (an external crate)."""
    segments = [s for s in segments if s]
    if not segments:
        return None
    head = segments[0]
    if head == "crate":
        return tuple(segments[1:])
    if head in ("super", "self"):
        base = list(mod)
        while segments and segments[0] in ("super", "self"):
            if segments[0] == "super":
                base = base[:-1]
            segments = segments[1:]
        return tuple(base + segments)
    if mod + (head,) in code:  # a child module, named relatively (`use attitude::X` in control/mod.rs)
        return mod + tuple(segments)
    if mod == () and (head,) in code:
        return tuple(segments)
    return None


def folder_of(file: str) -> str:
    """``sim/stepper.rs`` -> ``sim``; a file at the top (``gjm.rs``) is its own folder, ``lib.rs`` is ``crate``."""
    if "/" in file:
        return file.split("/", 1)[0]
    return "crate" if file == "lib.rs" else file.removesuffix(".rs")


def folder_graph(graph: dict) -> dict:
    folders = {}
    for a, targets in graph.items():
        fa = folder_of(a)
        folders.setdefault(fa, set())
        for b in targets:
            if folder_of(b) != fa:
                folders[fa].add(folder_of(b))
    return folders


def cycles(graph: dict) -> list:
    """Strongly connected components with more than one node (Tarjan), each a sorted list."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def _describe(graph: dict, component: list) -> str:
    inside = set(component)
    return ", ".join(f"{a} -> {b}" for a in component for b in sorted(graph.get(a, ())) if b in inside)


def within_folders(graph: dict) -> dict:
    """The file graph restricted to edges between files of one folder."""
    return {a: {b for b in targets if folder_of(b) == folder_of(a)} for a, targets in graph.items()}


# --- the graph function on small synthetic trees -------------------------------------------------


def _write(root: Path, files: dict):
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def test_a_folder_cycle_is_found(tmp_path):
    _write(
        tmp_path,
        {
            "lib.rs": "pub mod a;\npub mod b;\npub use a::Thing;\n",
            "a/mod.rs": "pub mod one;\npub use one::Thing;\n",
            "a/one.rs": "use crate::b::{two::{Other, self}};\npub struct Thing;\n",
            "b/mod.rs": "pub mod two;\n",
            # a path in the code, not a use; the re-export in a/mod.rs is followed to a/one.rs
            "b/two.rs": "pub struct Other;\nfn f() -> crate::a::Thing { todo!() }\n",
        },
    )
    graph = file_graph(tmp_path)
    assert graph["a/one.rs"] == {"b/two.rs"}
    assert graph["b/two.rs"] == {"a/one.rs"}
    assert graph["a/mod.rs"] == {"a/one.rs"}
    assert graph["lib.rs"] == {"a/one.rs"}
    assert cycles(folder_graph(graph)) == [["a", "b"]]
    assert cycles(within_folders(graph)) == []


def test_a_file_cycle_is_found_and_test_modules_comments_strings_are_not_edges(tmp_path):
    _write(
        tmp_path,
        {
            "lib.rs": "pub mod m;\n",
            "m/mod.rs": "pub mod x;\npub mod y;\npub mod z;\n",
            "m/x.rs": "use super::y::Y;\npub struct X;\n",
            "m/y.rs": "pub struct Y;\nfn g() { let _ = super::z::Z; }\n",
            # lifetimes are not char literals: the path after them is still read
            "m/z.rs": "pub struct Z;\nfn h<'a>(_: &'a self::super::x::X, _: &'a str) {}\n",
        },
    )
    assert cycles(within_folders(file_graph(tmp_path))) == [["m/x.rs", "m/y.rs", "m/z.rs"]]
    # The same tree with z's edge back to x only in a comment, a string, a doc link and a test module.
    _write(
        tmp_path,
        {
            "m/z.rs": (
                "/// See [`super::x::X`].\npub struct Z; // super::x::X\nconst S: &str = \"crate::m::x::X\";\n"
                "#[cfg(test)]\nmod tests {\n    use crate::m::x::X;\n    fn t() { let _ = '{'; }\n}\n"
            )
        },
    )
    graph = file_graph(tmp_path)
    assert graph["m/z.rs"] == set()
    assert cycles(within_folders(graph)) == []


def test_use_trees_are_expanded():
    assert _use_paths("use crate::{a::b, c::{d, e as f}, g::self};\nuse super::*;") == [
        "crate::a::b", "crate::c::d", "crate::c::e", "crate::g", "super::*",
    ]


# --- the core -----------------------------------------------------------------------------------


@lru_cache(maxsize=1)
def _core() -> dict:
    return file_graph(SRC)


def test_the_core_graph_is_read():
    graph = _core()
    # Known edges, so that a reader that reads nothing cannot pass the tests below.
    assert "model/system.rs" in graph["algorithms/kinematics.rs"]
    assert "math/spatial.rs" in graph["algorithms/rnea.rs"]
    assert len(graph) > 70 and sum(map(len, graph.values())) > 300


def test_no_cycle_between_the_cores_folders():
    graph = _core()
    folders = folder_graph(graph)
    found = cycles(folders)
    assert not found, "cycles between the core's folders:\n" + "\n".join(
        _describe(folders, c) + "\n  through: " + "; ".join(
            f"{a} -> {b}" for a in sorted(graph) for b in sorted(graph[a]) if folder_of(a) in c and folder_of(b) in c and folder_of(a) != folder_of(b)
        )
        for c in found
    )


def test_no_cycle_between_the_files_of_a_folder():
    local = within_folders(_core())
    found = cycles(local)
    assert not found, "cycles between the files of one folder:\n" + "\n".join(_describe(local, c) for c in found)


#: The core's layers (lib.rs, docs/architecture.md "The core's layers"): a file imports from its
#: own folder or from a lower layer, never from its layer's other folders or above.
LAYERS = {
    "error": 0, "admission": 1, "math": 2, "model": 3, "io": 4, "algorithms": 4, "gjm": 5, "collision": 5,
    "derivatives": 6, "taped": 6, "scenario": 7, "analysis": 8, "control": 9, "sim": 10, "crate": 11,
}


def against_layers(folders: dict, layers: dict = LAYERS) -> list:
    """The folder edges ``a -> b`` with ``b`` not in a lower layer than ``a`` (unknown folders: top)."""
    top = max(layers.values()) + 1
    return sorted(f"{a} -> {b}" for a, targets in folders.items() for b in targets if layers.get(a, top) <= layers.get(b, top))


def test_the_layer_check_refuses_an_upward_or_sideways_edge():
    folders = {"sim": {"control", "math"}, "control": {"sim"}, "io": {"algorithms"}, "math": set()}
    assert against_layers(folders) == ["control -> sim", "io -> algorithms"]


def test_every_folder_has_a_layer():
    missing = set(folder_graph(_core())) - set(LAYERS)
    assert not missing, f"give these folders a layer in LAYERS, lib.rs and docs/architecture.md: {sorted(missing)}"


def test_imports_go_down_the_layers():
    graph = _core()
    bad = against_layers(folder_graph(graph))
    assert not bad, "imports against the core's layers (lib.rs, docs/architecture.md):\n" + "\n".join(
        f"{a} -> {b}" for a in sorted(graph) for b in sorted(graph[a]) if f"{folder_of(a)} -> {folder_of(b)}" in bad
    )
