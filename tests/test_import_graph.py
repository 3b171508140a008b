"""The package's import graph and its layers (docs/architecture.md), read from the source with
ast, so a broken rule fails here before it turns into an ImportError that depends on import
order: module-level imports form no cycle and go down the layers; function-level imports go
down too, but into viz/ (a result's ``.plot()``); the one cycle is inside model/ (``Robot.builder``
imports builder.py, which imports robot.py); and no module outside model/ reaches into a Robot's
core handle ``._m`` (it calls the Robot's methods, or ``Robot.core_model`` to hand the model to
the core)."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "python" / "spacearm"

#: Function-level imports allowed to close a cycle, within model/: ``Robot.builder()`` and
#: ``Robot.to_builder()`` import builder.py, which imports robot.py at module level.
ALLOWED_LAZY_CYCLE = {"spacearm.model.robot", "spacearm.model.builder"}


def _modules():
    mods = {"spacearm._core": None}  # the compiled extension
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = path
    return mods


def _graph():
    """``(module_level, function_level)``: module -> the package modules it imports."""
    mods = _modules()
    top, lazy = {}, {}
    for mod, path in mods.items():
        if path is None:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        package = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
        module_level = {id(n) for n in tree.body}
        for block in tree.body:  # imports under a module-level if/try still run at import time
            if isinstance(block, (ast.If, ast.Try)):
                module_level |= {id(n) for n in ast.walk(block)}
        top[mod], lazy[mod] = set(), set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                base = package[: len(package) - node.level + 1] if node.level else []
                target = ".".join(base + ([node.module] if node.module else []))
                subs = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in mods]
                names = subs if len(subs) == len(node.names) else [target] + subs
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            for name in names:
                if name in mods and name != mod:
                    (top if id(node) in module_level else lazy)[mod].add(name)
    return top, lazy


def _cycles(graph):
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(component)

    for v in list(graph):
        if v not in index:
            visit(v)
    return found


def test_the_graph_is_read():
    top, lazy = _graph()
    # Known edges, so that a parser that reads nothing cannot pass the tests below.
    assert "spacearm.model.robot" in top["spacearm.model.builder"]
    assert "spacearm._core" in top["spacearm.model.robot"]
    assert "spacearm.cli.model_options" in top["spacearm.cli"]
    assert "spacearm.model.builder" in lazy["spacearm.model.robot"]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [{"a", "b", "c"}]


def test_module_level_imports_form_no_cycle():
    top, _ = _graph()
    assert _cycles(top) == []


def test_function_level_imports_close_no_cycle_but_robot_builder():
    top, lazy = _graph()
    both = {m: top[m] | lazy[m] for m in top}
    for component in _cycles(both):
        assert component <= ALLOWED_LAZY_CYCLE, f"an import cycle through function-level imports: {sorted(component)}"


#: The layers of docs/architecture.md: an import goes to a lower layer or stays in its own
#: folder, at module level and in a function alike (see LAZY_UPWARD_TARGETS for the one exception).
LAYERS = {
    "_core": -1, "errors": 0, "_util": 1, "examples": 1, "c": 1, "rotations": 2, "model": 3,
    "io": 4, "presets": 4, "control": 4, "interop": 4, "orbit": 4, "contact": 4, "events": 4,
    "sim": 5, "analysis": 5, "symbolic": 5, "casadi": 5, "identify": 5,
    "viz": 6, "fmi": 6, "campaign": 6, "capture": 6, "plan": 6, "mpc": 6, "basilisk": 6, "gym": 7, "cli": 7, "": 8, "__main__": 9,
}


def _folder(module):
    parts = module.split(".")[1:]
    return parts[0] if parts else ""


def test_module_level_imports_follow_the_layers():
    top, _ = _graph()
    upward = []
    for mod, targets in top.items():
        for target in targets:
            a, b = _folder(mod), _folder(target)
            if a != b and LAYERS.get(a, 99) <= LAYERS.get(b, 99):
                upward.append(f"{mod} -> {target}")
    assert not upward, "module-level imports against the layers of docs/architecture.md:\n" + "\n".join(sorted(upward))


def test_every_folder_has_a_layer():
    top, _ = _graph()
    missing = {_folder(m) for m in top} - set(LAYERS)
    assert not missing, f"give these folders a layer in LAYERS and docs/architecture.md: {sorted(missing)}"


#: The one exception to the layers for function-level imports: into viz/, the figures. A result's
#: ``.plot()`` / ``.animate()`` (Trajectory, the capture results) imports its figure module when
#: called, since viz/ imports the result types it draws and matplotlib is optional.
LAZY_UPWARD_TARGETS = {"viz"}


def _against_layers(edges, exempt=()):
    bad = []
    for mod, targets in edges.items():
        for target in targets:
            a, b = _folder(mod), _folder(target)
            if a != b and LAYERS.get(a, 99) <= LAYERS.get(b, 99) and b not in exempt:
                bad.append(f"{mod} -> {target}")
    return sorted(bad)


def test_function_level_imports_follow_the_layers():
    _, lazy = _graph()
    upward = _against_layers(lazy, exempt=LAZY_UPWARD_TARGETS)
    assert not upward, "function-level imports against the layers of docs/architecture.md:\n" + "\n".join(upward)


def test_model_imports_nothing_above_it():
    """model/ holds Robot: nothing in it imports a layer above, not even in a function (the
    loaders live in io/, the grasp impulse in capture/)."""
    top, lazy = _graph()
    model = {m: top[m] | lazy[m] for m in top if _folder(m) == "model"}
    assert model and not _against_layers(model), _against_layers(model)


def test_the_layer_checks_see_function_level_imports():
    # A function-level import upwards (model -> io) and one into viz (sim -> viz): the first is
    # refused, the second is the allowed exception.
    edges = {"spacearm.model.robot": {"spacearm.io.dh"}, "spacearm.sim.trajectory": {"spacearm.viz.plotting"}}
    assert _against_layers(edges, exempt=LAZY_UPWARD_TARGETS) == ["spacearm.model.robot -> spacearm.io.dh"]
    tree = ast.parse("def f():\n    from ..io import dh\n")
    assert isinstance(tree.body[0].body[0], ast.ImportFrom)  # the walk in _graph reaches function bodies


#: Files outside model/ that still use a Robot's core handle ``._m``: being removed (the files
#: under rewrite); empty this set as each file goes over to the Robot's methods.
CORE_HANDLE_ALLOWED: set = set()


def _core_handle_uses(source: str):
    """Line numbers of every attribute access ``<anything>._m`` in ``source``."""
    return sorted(n.lineno for n in ast.walk(ast.parse(source)) if isinstance(n, ast.Attribute) and n.attr == "_m")


def test_core_handle_uses_are_found():
    assert _core_handle_uses("a = robot._m.point(1)\nb = t.body._m\nc = robot._mx\n# robot._m\n") == [1, 2]


def test_no_core_handle_outside_model():
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel.startswith("model/"):
            continue
        lines = _core_handle_uses(path.read_text(encoding="utf-8"))
        if lines:
            found[rel] = lines
    outside = {rel: lines for rel, lines in found.items() if rel not in CORE_HANDLE_ALLOWED}
    assert not outside, ("._m outside model/ (call the Robot's methods, or Robot.core_model to hand the model to "
                         f"the core): {outside}")
    stale = CORE_HANDLE_ALLOWED - set(found)
    assert not stale, f"these files no longer use ._m: remove them from CORE_HANDLE_ALLOWED: {sorted(stale)}"
