"""The package's import graph: module-level imports form no cycle, and the only cycles through
function-level imports are the Robot constructors (``Robot.from_toml`` and friends import the
module that builds a Robot). Read from the source with ast, so a cycle fails here before it
turns into an ImportError that depends on import order."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "python" / "spacearm"

#: Function-level imports allowed to close a cycle: Robot's classmethod constructors, which
#: import the modules that build a Robot (they import robot.py at module level).
ALLOWED_LAZY_CYCLE = {"spacearm.model.robot", "spacearm.model.builder", "spacearm.io.dh", "spacearm.io.model_file", "spacearm.io.urdf"}


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


def test_function_level_imports_close_no_cycle_but_the_robot_constructors():
    top, lazy = _graph()
    both = {m: top[m] | lazy[m] for m in top}
    for component in _cycles(both):
        assert component <= ALLOWED_LAZY_CYCLE, f"an import cycle through function-level imports: {sorted(component)}"


#: The layers of docs/architecture.md: a module-level import goes to a lower layer or stays in
#: its own folder. Function-level imports may go up (a result's .plot() importing viz, Robot's
#: constructors importing io): they run only when called.
LAYERS = {
    "_core": 0, "errors": 0, "_util": 1, "rotations": 2, "model": 3,
    "io": 4, "presets": 4, "control": 4, "interop": 4,
    "sim": 5, "analysis": 5, "symbolic": 5, "casadi": 5, "identify": 5,
    "viz": 6, "campaign": 6, "capture": 6, "plan": 6, "cli": 7, "": 8, "__main__": 9,
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
