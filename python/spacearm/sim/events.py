"""Stop conditions of a run ([`simulate`][spacearm.simulate]``(..., stop=...)``): the run ends at
the first event, located by the core within the step in which it holds (docs/simulation-core.md,
"Events"); ``Trajectory.meta["stop"]`` says which condition ended it, when, and its value.

Like the controllers, a condition is a description: the core's ``StopCondition``
(``crates/spacearm-core/src/sim/events.rs``) as data, checked by the core when it is made.

>>> import spacearm
>>> from spacearm.sim.events import StopAtTime
>>> traj = spacearm.simulate(spacearm.presets.spatial6(), 2.0, stop=StopAtTime(0.5))
>>> stop = traj.meta["stop"]
>>> stop["t"], float(traj.t[-1])
(0.5, 0.5)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from .._util.spec import check, data
from ..errors import ArgumentError

__all__ = ["StopAtTime", "StopAtGap", "stop_data"]


@dataclass(frozen=True)
class StopAtTime:
    """Stop the run at time ``t`` (s, > 0) if it gets there."""

    _kind: ClassVar[str] = "time"

    t: float

    def __post_init__(self):
        check("stop", self)


@dataclass(frozen=True)
class StopAtGap:
    """Stop the run when the robot's ``point`` (``None``: the end effector, a point or body
    name, or ``(body, offset)``) comes within ``tolerance`` (m, > 0) of the controller's point
    reference (a [`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate], alone or as the arm
    of a combined controller): ``|p_ref(t) − p(t)| ≤ tolerance``. The point is resolved on the
    plant by the core when the run starts."""

    _kind: ClassVar[str] = "gap"

    point: Any = None
    tolerance: float = 0.01

    def __post_init__(self):
        check("stop", self)


def stop_data(stop) -> list:
    """``stop`` (None, one condition or a sequence of them) as the core's data."""
    if stop is None:
        return []
    items = [stop] if isinstance(stop, (StopAtTime, StopAtGap)) else stop
    try:
        items = list(items)
    except TypeError:
        items = [items]
    for c in items:
        if not isinstance(c, (StopAtTime, StopAtGap)):
            raise ArgumentError(f"stop takes StopAtTime, StopAtGap or a list of them, got {type(c).__name__}")
    return [data(c, [], type(c).__name__) for c in items]
