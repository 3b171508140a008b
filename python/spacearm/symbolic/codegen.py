"""Shared by the code generators: common-subexpression elimination of one quantity and the
names of its inputs, plus atomic file output.

A generated kernel computes the base-frame form of a quantity from ``q``, ``u_b`` and ``p``; a
wrapper turns the world state ``(x, u)`` into ``(q, u_b = Tᵀu)`` and rotates the result back
(``spacearm.symbolic.frames``).
"""

from __future__ import annotations

import re
from typing import List, Tuple

import sympy as sp

from .._util.atomic import write_text
from .derivation import Derivation, Quantity

__all__ = ["Kernel", "kernel", "identifier", "write_atomic"]


def identifier(name: str) -> str:
    """A C/Python identifier made of ``name``."""
    s = re.sub(r"\W", "_", name)
    return s if s and not s[0].isdigit() else "_" + s


class Kernel:
    """A quantity after CSE: ``assignments`` ``[(symbol, expr)]`` then ``outputs`` (row-major)."""

    def __init__(self, quantity: Quantity, assignments: List[Tuple[sp.Symbol, sp.Expr]], outputs: List[sp.Expr], inputs):
        self.quantity = quantity
        self.assignments = assignments
        self.outputs = outputs
        self.inputs = inputs  #: (q symbols, u_b symbols, parameter symbols)


def kernel(d: Derivation, q: Quantity) -> Kernel:
    """CSE of ``q.expr`` (``order="none"``: the canonical order costs ~40× more on spatial6)."""
    rows, cols = q.expr.shape
    flat = [q.expr[i, j] for i in range(rows) for j in range(cols)]
    reps, reduced = sp.cse(flat, symbols=sp.numbered_symbols("t"), order="none")
    return Kernel(q, reps, reduced, (list(d.q), list(d.u_b), list(d.params.symbols)))


def write_atomic(path: str, text: str) -> None:
    """Write ``text`` to ``path`` atomically (``spacearm._util.atomic``), so an interrupted
    run never leaves a truncated file."""
    write_text(path, text)
