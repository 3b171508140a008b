"""The one reader that turns a description of what to run — a ``spacearm.control`` controller,
reference, shaper or thruster limits — into the core's data (``control/spec.rs``; docs/architecture.md,
"A run is data").

It knows no class: a dataclass becomes a dict of its fields (``kind`` from the class's ``_kind``
where it has one; a field left ``None`` is left out, so the core's default applies), sequences
become lists, numpy values plain numbers, an object with a ``to_data()`` method (a
[`spacearm.mpc.Problem`][spacearm.mpc.Problem]) what it returns, an object with a ``_data()`` method (a
[`Robot`][spacearm.Robot]: its model file text; an [`Orbit`][spacearm.Orbit]) its data, a scipy
``Rotation`` its quaternion ``[x, y, z, w]``, and a Python callable in a controller's place an
``external`` controller the binding calls. The core's serde types name every field and check
every value; nothing is checked here but that the value is data.
"""

from __future__ import annotations

import dataclasses
import numbers

import numpy as np

from .. import _core
from ..errors import ArgumentError
from .arrays import quaternion, _is_scipy_rotation

__all__ = ["data", "controller_spec", "check"]


def data(value, externals: list, where: str = "value"):
    """The plain data of ``value``; callables met in a controller's place are appended to
    ``externals`` and stand as ``{"kind": "external", "index": i}``."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            raise ArgumentError(f"{where} must hold real numbers, got an array of dtype {value.dtype}")
        return value.tolist()
    if getattr(type(value), "_kind", None) == "external":
        externals.append(value.fn)
        return {"kind": "external", "index": len(externals) - 1}
    if callable(getattr(value, "to_data", None)) and not isinstance(value, type):
        return value.to_data()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        out = {} if getattr(type(value), "_kind", None) is None else {"kind": type(value)._kind}
        for f in dataclasses.fields(value):
            v = getattr(value, f.name)
            if v is not None:
                out[f.name] = data(v, externals, f"{type(value).__name__} {f.name}")
        return out
    if _is_scipy_rotation(value):
        return quaternion(value, where).tolist()
    if hasattr(value, "_data"):
        return value._data()
    if isinstance(value, dict):
        return {str(k): data(v, externals, f"{where}[{k!r}]") for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [data(v, externals, f"{where}[{i}]") for i, v in enumerate(value)]
    raise ArgumentError(f"{where} must be a number, a sequence or a spacearm.control object, got {type(value).__name__}")


def controller_spec(controller) -> _core.ControllerSpec:
    """The core's spec of a ``spacearm.control`` controller (``None``: no control)."""
    if controller is None:
        return _core.ControllerSpec({"kind": "none"})
    if not (dataclasses.is_dataclass(controller) and getattr(type(controller), "_kind", None)):
        raise ArgumentError(f"a controller must be a spacearm.control controller, got {type(controller).__name__}")
    externals: list = []
    spec = data(controller, externals, type(controller).__name__)
    return _core.ControllerSpec(spec, externals)


def check(family: str, value) -> None:
    """Check ``value`` (a spacearm.control object) as a spec of ``family`` in the core."""
    if family == "controller":
        controller_spec(value)
    else:
        _core.check_spec(family, data(value, [], type(value).__name__))
