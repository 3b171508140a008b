"""Pickling that re-validates: a data object is unpickled through its constructor, so the values
a pickle carries pass the same checks as the values a caller gives (a tampered or bit-flipped
pickle is refused with the constructor's ``spacearm.errors`` exception, never loaded as is).

The default pickling of a (frozen) dataclass restores its ``__dict__`` without calling
``__init__`` / ``__post_init__``: its checks are skipped. ``reduce_through_constructor`` is the
``__reduce__`` of such a class: ``(rebuild, (cls, fields))``, and ``rebuild`` calls ``cls(**fields)``.
"""

from __future__ import annotations

import dataclasses

from ..errors import SpacearmTypeError

__all__ = ["reduce_through_constructor", "rebuild"]


def rebuild(cls, fields: dict):
    """``cls(**fields)``: the data object a pickle names, built by its validating constructor."""
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__.startswith("spacearm.")):
        raise SpacearmTypeError(f"a spacearm pickle rebuilds spacearm data classes only, got {cls!r}")
    if not isinstance(fields, dict):
        raise SpacearmTypeError(f"a pickled {cls.__name__} carries its fields as a dict, got {type(fields).__name__}")
    return cls(**fields)


def reduce_through_constructor(self):
    """``__reduce__`` of a dataclass: its ``init`` fields, rebuilt through the constructor."""
    fields = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.init}
    return (rebuild, (type(self), fields))
