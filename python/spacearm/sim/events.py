"""Stop conditions of a run ([`simulate`][spacearm.simulate]``(..., stop=...)``): the run ends at
the first event, located by the core within the step in which it holds (docs/simulation-core.md,
"Events"); ``Trajectory.meta["stop"]`` says which condition ended it, when, and its value.

>>> import spacearm
>>> from spacearm.sim.events import StopAtTime
>>> traj = spacearm.simulate(spacearm.presets.spatial6(), 2.0, stop=StopAtTime(0.5))
>>> traj.meta["stop"]["t"], float(traj.t[-1])
(0.5, 0.5)
"""

from __future__ import annotations

from .. import _core
from .._util.arrays import number
from ..errors import ArgumentError

__all__ = ["StopAtTime", "StopAtGap", "stop_specs"]


class StopAtTime:
    """Stop the run at time ``t`` (s, > 0) if it gets there."""

    def __init__(self, t: float):
        self.t = number(t, "t")
        self._core_spec = _core.StopCondition.time(self.t)

    def _spec(self, robot) -> "_core.StopCondition":
        return self._core_spec

    def __repr__(self) -> str:
        return f"StopAtTime({self.t!r})"


class StopAtGap:
    """Stop the run when the robot's ``point`` (``None``: the end effector, a point or body
    name, or ``(body, offset)``) comes within ``tolerance`` (m, > 0) of the controller's point
    reference (a [`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate], alone or as the arm
    of a combined controller): ``|p_ref(t) − p(t)| ≤ tolerance``."""

    def __init__(self, point=None, tolerance: float = 0.01):
        self.point = point
        self.tolerance = number(tolerance, "tolerance")

    def _spec(self, robot) -> "_core.StopCondition":
        body, offset = robot.resolve_point(self.point)
        return _core.StopCondition.gap(int(body), offset, self.tolerance)

    def __repr__(self) -> str:
        return f"StopAtGap(point={self.point!r}, tolerance={self.tolerance!r})"


def stop_specs(robot, stop) -> list:
    """``stop`` (None, one condition or a sequence of them) as the core's conditions for ``robot``."""
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
    return [c._spec(robot) for c in items]
