"""Small reprs for result objects: the class name and each field in a few characters (an array
by its shape and dtype, a number to four digits, a nested result by its own repr), never the
arrays themselves (kilobytes of numbers in a REPL or a log)."""

from __future__ import annotations

import dataclasses

import numpy as np

#: The longest repr of one field; a longer one is cut with "…".
FIELD_WIDTH = 60


def _field(value) -> str:
    if isinstance(value, np.ndarray):
        return f"array{value.shape} {value.dtype}"
    if isinstance(value, (bool, np.bool_)) or value is None:
        return repr(value)
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.4g}"
    if isinstance(value, dict):
        return "{" + ", ".join(map(str, value)) + "}"
    text = repr(value)
    return text if len(text) <= FIELD_WIDTH else text[: FIELD_WIDTH - 1] + "…"


def summary_repr(obj) -> str:
    """``<Name: field=…, …>`` of a NamedTuple or a dataclass (its fields in order)."""
    if dataclasses.is_dataclass(obj):
        names = [f.name for f in dataclasses.fields(obj) if f.repr]
    else:
        names = list(obj._fields)
    return f"<{type(obj).__name__}: " + ", ".join(f"{n}={_field(getattr(obj, n))}" for n in names) + ">"


def controller_label(name) -> str:
    """The words a person reads for a controller name of a run's records (``meta["controller"]``:
    ``"computed_torque"`` → ``"computed torque"``), from the core's one table
    (``_core.CONTROLLER_LABELS``); a name it lacks, with its underscores as spaces; none: "no control"."""
    from .. import _core

    if not name or name == "none":
        return _core.CONTROLLER_LABELS["none"]
    return _core.CONTROLLER_LABELS.get(name, str(name).replace("_", " "))
