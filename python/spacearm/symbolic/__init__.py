"""Closed-form (SymPy) equations of motion of a spacearm model: kinematics, the paper's inertia
matrices, the Schur-complement inverse of ``H0``, ``H*``, ``c*``, ``J*``, ``Ḣ`` and ``∂H/∂q``,
with LaTeX, NumPy and C output. Tutorial: ``docs/symbolic.md``.

Needs SymPy (``pip install "spacearm[symbolic]"``); without it, importing this package raises
[`MissingDependencyError`][spacearm.MissingDependencyError] naming that extra.
"""

from .._util.optional import require

require("sympy", "closed-form derivation (spacearm.symbolic, spacearm derive)")

from .derivation import Derivation, Quantity, derive
from .parameters import Parameters

__all__ = ["Derivation", "Quantity", "derive", "Parameters"]
