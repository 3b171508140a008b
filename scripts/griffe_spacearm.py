"""Griffe extension for the API pages (mkdocs.yml, mkdocstrings' Python handler).

mkdocstrings reads the package statically (griffe), which misses two kinds of documentation the
package has:

- ``#:`` comments above a module- or class-level assignment, the package's way of documenting a
  constant (``#: Preset names, as accepted by get and the CLI.`` above ``NAMES = (...)``):
  griffe only knows docstrings placed after the assignment, so these become the attribute's
  docstring here;
- result types built by the library (a [`Robot`][spacearm.Robot] from a preset or a loader, the
  records [`rollout`][spacearm.rollout] returns, a plan, a capture...): their constructor is
  internal, so the page shows the class without it (INTERNAL_CONSTRUCTORS);
- docstrings set at import time (``spacearm/errors.py`` gives the extension's exception classes
  their ``__doc__``) or written in Rust (the extension's classes, declared in ``_core.pyi``
  without one): an object the static pass leaves without a docstring gets its runtime
  ``__doc__``.
"""

from __future__ import annotations

import ast
import importlib
import inspect
from typing import Any

import griffe

_logger = griffe.get_logger("griffe_spacearm")

#: Classes users get from the library, never build: the API pages show no constructor signature.
INTERNAL_CONSTRUCTORS = {
    "spacearm.model.robot.Robot",
    "spacearm.sim.rollout.Rollouts",
    "spacearm.sim.trajectory.Trajectory",
    "spacearm.capture.sequence.CaptureResult",
    "spacearm.campaign.results.CampaignResult",
    "spacearm.plan.result.Plan",
    "spacearm.analysis.singularities.SingularityMap",
    "spacearm.identify.estimate.PayloadEstimate",
}


def _comment_above(lines: list[str], lineno: int) -> str | None:
    """The ``#:`` comment lines right above line ``lineno`` (1-based), joined; None if none."""
    found = []
    i = lineno - 2
    while i >= 0 and lines[i].strip().startswith("#:"):
        found.append(lines[i].strip()[2:].strip())
        i -= 1
    return "\n".join(reversed(found)) if found else None


def _comment_after(lines: list[str], node: ast.AST) -> str | None:
    """The ``#:`` comment ending the assignment's own (last) line: ``t: np.ndarray  #: (T,)``."""
    line = lines[getattr(node, "end_lineno", node.lineno) - 1]
    mark = line.find("#:")
    return line[mark + 2:].strip() or None if mark >= 0 else None


def _runtime_doc(path: str) -> str | None:
    """``__doc__`` of the object at the dotted ``path`` (imported), when it has one of its own."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for name in parts[cut:]:
                obj = getattr(obj, name)
        except AttributeError:
            return None
        if inspect.ismodule(obj) and cut < len(parts):
            return None
        doc = obj.__dict__.get("__doc__") if isinstance(obj, type) else getattr(obj, "__doc__", None)
        return inspect.cleandoc(doc) if isinstance(doc, str) and doc.strip() else None
    return None


class SpacearmDocs(griffe.Extension):
    def on_attribute_instance(self, *, node: Any, attr: griffe.Attribute, agent: Any, **kwargs: Any) -> None:
        if attr.docstring is not None or not isinstance(node, ast.AST):
            return
        module = attr.module
        if module.filepath is None or not hasattr(node, "lineno"):
            return
        text = _comment_above(module.lines, node.lineno) or _comment_after(module.lines, node)
        if text:
            attr.docstring = griffe.Docstring(text, lineno=node.lineno, parent=attr)

    def on_package(self, *, pkg: griffe.Module, **kwargs: Any) -> None:
        if pkg.name != "spacearm":
            return
        for path in INTERNAL_CONSTRUCTORS:
            try:
                cls = pkg.modules_collection.get_member(path) if hasattr(pkg, "modules_collection") else None
            except (KeyError, AttributeError):
                cls = None
            if cls is None:
                cls = pkg.get_member(path.split(".", 1)[1])
            cls.members.pop("__init__", None)
            # A dataclass would get its __init__ back from griffe's dataclasses extension.
            cls.decorators = [d for d in cls.decorators if "dataclass" not in str(d.value)]
        self._fill(pkg.get_member("_core"))
        self._exports(pkg)

    def _exports(self, module: griffe.Module) -> None:
        """A module whose ``__all__`` the static pass cannot read (``from .functions import
        __all__``) gets its runtime ``__all__``."""
        if module.exports is None and not module.name.startswith("_"):
            try:
                names = getattr(importlib.import_module(module.path), "__all__", None)
            except ImportError:
                names = None
            if names is not None:
                module.exports = list(names)
        for sub in module.modules.values():
            if not sub.is_alias:
                self._exports(sub)

    def _fill(self, module: griffe.Object) -> None:
        """Runtime docstrings for the extension's classes and functions (the stub may lack them)."""
        for member in module.members.values():
            if member.is_alias:
                continue
            if member.docstring is None and (member.is_class or member.is_function):
                doc = _runtime_doc(member.path)
                if doc and not doc.startswith(f"{member.name}("):  # not a bare text signature
                    member.docstring = griffe.Docstring(doc, parent=member)
            if member.is_class:
                self._fill(member)
