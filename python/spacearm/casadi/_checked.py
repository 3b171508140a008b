"""The ``casadi.Function`` subclass every builder of ``spacearm.casadi`` returns: called with
numbers, it checks them before CasADi evaluates, so that a bad input is a spacearm error and not
a NaN result (a CasADi function cannot raise once it evaluates).

Checked, for each input given as numbers (a float, a list, a NumPy array, a ``casadi.DM``):
real numbers (``SpacearmTypeError``), the input's size (``ShapeError``), finite entries
(``NonFiniteError``) and, for the state ``x``, a base quaternion ``x[3:7]`` with a direction
(``QuaternionError`` for a zero quaternion: the functions normalise it, and ``0/0`` is NaN).
Inputs given as symbols (``SX``, ``MX``, inside a graph or an NLP) are passed on unchecked: there
the check cannot run, and the problem must keep the quaternion away from zero itself (a unit-norm
constraint, or a start on the unit sphere with the normalising step of ``rk4_step``).
"""

from __future__ import annotations

import functools
from typing import Any, Optional

import numpy as np

from ..errors import NonFiniteError, QuaternionError, ShapeError, SpacearmTypeError

__all__ = ["checked_function"]

_STATE = "x"  # the input that holds [r0, quat0, q]
_QUAT = slice(3, 7)


def _numbers(ca, value) -> Optional[np.ndarray]:
    """``value`` as a float array when it is numbers, ``None`` when it is symbolic."""
    if isinstance(value, (ca.SX, ca.MX)):
        return None
    if isinstance(value, ca.DM):
        return np.asarray(value.full(), dtype=float).ravel(order="F")
    if isinstance(value, (list, tuple)) and any(isinstance(v, (ca.SX, ca.MX)) for v in value):
        return None
    try:
        array = np.asarray(value)
    except Exception:  # an object numpy cannot read: CasADi's own conversion decides
        return None
    if array.dtype.kind in "biuf":
        return array.astype(float).ravel(order="F")
    if array.dtype.kind == "c":
        raise SpacearmTypeError(f"complex numbers are not accepted, got dtype {array.dtype}")
    return None


def _check(function, name: str, value, index: int, ca) -> None:
    values = _numbers(ca, value)
    if values is None:
        return
    what = f"{function.name()}: input '{name}'"
    size = function.numel_in(index)
    if values.size not in (1, size):
        raise ShapeError(f"{what} must have {size} entries, got {values.size}")
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise NonFiniteError(f"{what} must be finite, but entry {bad[0]} is {values[bad[0]]}")
    if name == _STATE:
        quat = values[_QUAT] if values.size == size else np.repeat(values, 4)
        norm = float(np.sqrt(np.sum(quat * quat)))
        if not norm > 0.0 or not np.isfinite(norm):
            raise QuaternionError(
                f"{what}: the base quaternion x[3:7] = {quat.tolist()} has no direction (norm {norm:g}); the function normalises "
                "it, and a zero quaternion would give NaN: give a nonzero quaternion [x, y, z, w], normally of unit norm")


@functools.lru_cache(maxsize=None)
def _checked_class(ca):
    class CheckedFunction(ca.Function):
        """A ``casadi.Function`` that checks numeric inputs before evaluating
        (``spacearm.casadi._checked``)."""

        def _check_inputs(self, args, kwargs) -> None:
            names = self.name_in()
            if len(args) == 1 and not kwargs and isinstance(args[0], dict):
                kwargs, args = args[0], ()
            for index, value in enumerate(args[:len(names)]):
                _check(self, names[index], value, index, ca)
            for key, value in kwargs.items():
                if key in names:
                    _check(self, key, value, names.index(key), ca)

        def __call__(self, *args, **kwargs) -> Any:
            self._check_inputs(args, kwargs)
            return super().__call__(*args, **kwargs)

        def call(self, *args, **kwargs) -> Any:
            if args and isinstance(args[0], (list, tuple)):
                self._check_inputs(tuple(args[0]), {})
            elif args and isinstance(args[0], dict):
                self._check_inputs((), args[0])
            return super().call(*args, **kwargs)

    return CheckedFunction


def checked_function(ca, name: str, inputs, outputs, names_in, names_out):
    """``casadi.Function(name, inputs, outputs, names_in, names_out)`` whose numeric calls are
    checked (module docstring)."""
    return _checked_class(ca)(name, list(inputs), list(outputs), list(names_in), list(names_out))
