"""Model parameters as SymPy quantities: numbers, or symbols where the user asks for them.

A [`Parameters`][spacearm.symbolic.Parameters] turns ``Robot.description`` (a [`ModelDescription`][spacearm.ModelDescription]) into SymPy values. Every numeric parameter can
be replaced by a symbol; joint coordinates are always symbols. Parameter names:

| name | meaning |
| --- | --- |
| ``m0``, ``m{i}`` | base mass, mass of body ``i`` (bodies are numbered as in the model, base = 0) |
| ``I0_xx`` … ``I{i}_yz`` | inertia about the CM in the body frame (``xx, yy, zz, xy, xz, yz``) |
| ``o{i}_x`` … | joint ``i``'s position in the parent frame (``origin``; a length) |
| ``c{i}_x`` … | body ``i``'s CM from its joint, in its frame (``com``; a length) |

``symbols`` selects what becomes a symbol: ``None`` (nothing), ``"all"``, or an iterable of
categories (``"masses"``, ``"inertias"``, ``"lengths"``) and/or names from the table. Entries that
are exactly zero in the model stay zero (they are the model's structure, e.g. a link along its x
axis), so a symbolic model keeps the sparsity of the numeric one. Joint axes and fixed rotations
are structure and stay numeric.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Dict, Iterable, List, Optional, Union

import sympy as sp

from ..model.description import ModelDescription
from ..errors import NotFoundError

__all__ = ["Parameters", "exact_number", "CATEGORIES"]

CATEGORIES = ("masses", "inertias", "lengths")
_INERTIA_KEYS = (("xx", 0, 0), ("yy", 1, 1), ("zz", 2, 2), ("xy", 0, 1), ("xz", 0, 2), ("yz", 1, 2))
_AXES = "xyz"


def exact_number(v: float) -> sp.Expr:
    """A float as a SymPy number: an exact small rational when the float is one to 1 ulp
    (0.5, 1/240, 41667/10000, ...), else a 53-bit ``Float``. Rationals keep the printed
    matrices readable and exact; the value differs from ``v`` by at most ~1e-16 relative."""
    v = float(v)
    if v == 0.0:
        return sp.S.Zero
    if v == int(v) and abs(v) < 2**53:
        return sp.Integer(int(v))
    fr = Fraction(v).limit_denominator(100000)
    if abs(float(fr) - v) <= 2.3e-16 * abs(v):
        return sp.Rational(fr.numerator, fr.denominator)
    return sp.Float(v, 17)


class Parameters:
    """The model's parameters as SymPy values, with the chosen ones replaced by symbols.

    ``values[name]`` is the SymPy value used in the derivation (a symbol or a number);
    ``symbols`` lists the symbols in a fixed order and ``defaults`` their numeric values (the
    model's), which the generated code uses as the default parameter vector ``p``.
    """

    def __init__(self, description: ModelDescription, symbols: Union[None, str, Iterable[str]] = None):
        self.description = description
        wanted = self._wanted(symbols)
        self.values: Dict[str, sp.Expr] = {}
        self.symbols: List[sp.Symbol] = []
        self.defaults: List[float] = []
        self.names: List[str] = []

        def put(name: str, category: str, value: float) -> sp.Expr:
            if value != 0.0 and (category in wanted or name in wanted):
                s = sp.Symbol(name, real=True, positive=(category == "masses"))
                self.symbols.append(s)
                self.defaults.append(float(value))
                self.names.append(name)
                self.values[name] = s
            else:
                self.values[name] = exact_number(value)
            return self.values[name]

        base = description.base
        self.mass = [put("m0", "masses", base.mass)]
        self.inertia = [self._inertia(put, 0, base.inertia)]
        self.origin = [None]
        self.com = [None]
        for i, link in enumerate(description.links, start=1):
            self.mass.append(put(f"m{i}", "masses", link.mass))
            self.inertia.append(self._inertia(put, i, link.inertia))
            self.origin.append(sp.Matrix([put(f"o{i}_{a}", "lengths", link.origin[k]) for k, a in enumerate(_AXES)]))
            self.com.append(sp.Matrix([put(f"c{i}_{a}", "lengths", link.com[k]) for k, a in enumerate(_AXES)]))
        unknown = wanted - set(CATEGORIES) - set(self.values)
        if unknown:
            raise NotFoundError(f"unknown parameter names {sorted(unknown)}; names are m0, m1, I0_xx, I1_xy, o1_x, c1_z, ... "
                                f"or the categories {', '.join(CATEGORIES)}")

    @staticmethod
    def _wanted(symbols) -> set:
        if symbols is None:
            return set()
        if isinstance(symbols, str):
            return set(CATEGORIES) if symbols == "all" else {symbols}
        return set(symbols)

    @staticmethod
    def _inertia(put, i: int, inertia) -> sp.Matrix:
        m = sp.zeros(3, 3)
        for key, r, c in _INERTIA_KEYS:
            v = put(f"I{i}_{key}", "inertias", float(inertia[r, c]))
            m[r, c] = v
            m[c, r] = v
        return m

    @property
    def total_mass(self) -> sp.Expr:
        return sp.Add(*self.mass)

    def substitution(self, p: Optional[Iterable[float]] = None) -> Dict[sp.Symbol, float]:
        """``{symbol: value}`` for the symbols (default: the model's values)."""
        vals = self.defaults if p is None else list(p)
        return dict(zip(self.symbols, vals))
