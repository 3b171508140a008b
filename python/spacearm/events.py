"""Topology events of a run ([`simulate`][spacearm.simulate]``(..., events=[...])``,
docs/events.md): the robot welds the run's free target to one of its bodies
([`Attach`][spacearm.events.Attach]) and releases a rigid link
([`Detach`][spacearm.events.Detach]), each continuing the run in one trajectory with robot +
target momentum continuous across it.

An event is a description: the core's ``TopologyEvent`` (crates/spacearm-core/src/sim/topology_spec.rs)
as data. Nothing is checked here; the core checks every value when the run starts and refuses
a bad one with an [`ArgumentError`][spacearm.ArgumentError] naming it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Optional

from ._util.spec import data
from .errors import ArgumentError

__all__ = ["Attach", "Detach", "events_data"]


@dataclass(frozen=True)
class Attach:
    """Weld the free target (``simulate(..., target=, target_state=)``, or a link released
    earlier) to the robot at its ``point`` (``None``: the end effector; a point or body name,
    or ``(body, offset)``), the target held at its grasp point ``grasp`` (a point name;
    ``None``: its first point): the rigid grasp impulse (restitution 0), then the target a link
    on a fixed joint. At the commanded time ``at`` (s), or when every given threshold holds:
    the distance between the points below ``gap`` (m) and the relative linear (``speed``, m/s)
    and angular (``rate``, rad/s) velocity below theirs, located within the step (RK4)."""

    _kind: ClassVar[str] = "attach"

    at: Optional[float] = None
    point: Any = None
    grasp: Optional[str] = None
    gap: Optional[float] = None
    speed: Optional[float] = None
    rate: Optional[float] = None


@dataclass(frozen=True)
class Detach:
    """Release the rigid link ``body`` (``None``: the attached target) at time ``at`` (s): it
    flies on as the free target, pushed by the separation ``impulse`` (N·s, default 0: a plain
    split) along ``direction`` (in the inertial frame; ``None``: from its parent's CM to its
    CM), the robot pushed back."""

    _kind: ClassVar[str] = "detach"

    at: float
    body: Optional[str] = None
    impulse: float = 0.0
    direction: Any = None


def events_data(events) -> list:
    """``events`` (one event or a sequence of them) as the core's data."""
    items = [events] if isinstance(events, (Attach, Detach)) else events
    try:
        items = list(items)
    except TypeError:
        items = [items]
    for e in items:
        if not isinstance(e, (Attach, Detach)):
            raise ArgumentError(f"events takes spacearm.events.Attach, Detach or a list of them, got {type(e).__name__}")
    return [data(e, [], type(e).__name__) for e in items]
