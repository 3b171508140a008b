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

__all__ = ["StopAtTime", "StopAtGap", "StopAtRecord", "stop_data"]


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


@dataclass(frozen=True)
class StopAtRecord:
    """Stop the run when the scalar record ``name`` rises to ``above`` (``r ≥ above``) or falls
    to ``below`` (``r ≤ below``); give exactly one of the two. The records that can be watched
    are the core's table (``WatchedRecord`` in ``crates/spacearm-core/src/sim/stop.rs``):
    ``"cmg_envelope_fraction"`` (a CMG cluster nearing saturation), ``"cmg_measure"`` (nearing a
    singularity; docs/cmg.md, "Saturation and singularity events"), ``"tracking_error"`` and
    ``"attitude_error"``. The event is located within the step as a gap's is, and
    ``meta["stop"]["value"]`` is the record's value there (the threshold, to the located
    time's rounding)."""

    _kind: ClassVar[str] = "record"

    name: str
    above: float | None = None
    below: float | None = None

    def __post_init__(self):
        check("stop", self)


_CONDITIONS = (StopAtTime, StopAtGap, StopAtRecord)


def stop_data(stop) -> list:
    """``stop`` (None, one condition or a sequence of them) as the core's data."""
    if stop is None:
        return []
    items = [stop] if isinstance(stop, _CONDITIONS) else stop
    try:
        items = list(items)
    except TypeError:
        items = [items]
    for c in items:
        if not isinstance(c, _CONDITIONS):
            raise ArgumentError(f"stop takes StopAtTime, StopAtGap, StopAtRecord or a list of them, got {type(c).__name__}")
    return [data(c, [], type(c).__name__) for c in items]
