"""The package's import graph: module-level imports form no cycle, and the only cycles through
function-level imports are the Robot constructors (``Robot.from_toml`` and friends import the
module that builds a Robot). Read from the source with ast, so a cycle fails here before it
turns into an ImportError that depends on import order."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "python" / "spacearm"

#: Function-level imports allowed to close a cycle: Robot's classmethod constructors, which
#: import the modules that build a Robot (they import robot.py at module level).
ALLOWED_LAZY_CYCLE = {"spacearm.robot", "spacearm.builder", "spacearm.dh", "spacearm.model_file", "spacearm.urdf"}


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
    assert "spacearm.robot" in top["spacearm.builder"]
    assert "spacearm._core" in top["spacearm.robot"]
    assert "spacearm.cli_model" in top["spacearm.cli"]
    assert "spacearm.builder" in lazy["spacearm.robot"]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [{"a", "b", "c"}]


def test_module_level_imports_form_no_cycle():
    top, _ = _graph()
    assert _cycles(top) == []


def test_function_level_imports_close_no_cycle_but_the_robot_constructors():
    top, lazy = _graph()
    both = {m: top[m] | lazy[m] for m in top}
    for component in _cycles(both):
        assert component <= ALLOWED_LAZY_CYCLE, f"an import cycle through function-level imports: {sorted(component)}"
