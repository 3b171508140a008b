"""The typed description of a model: what :attr:`Robot.description` returns.

A :class:`ModelDescription` states a model's parameters as the Rust core holds them, with each
field's frame and unit (``docs/conventions.md``, "A model's frames, concretely"): every body
frame has its origin at the body's centre of mass (CM); a joint's ``origin`` and ``rotation``
are in the parent's frame; its ``axis`` is in the link frame; a link's ``com`` is measured from
its joint in the link frame; inertias are about the CM in the body's axes. SI units throughout.

The classes are frozen and their arrays read-only: a description is a snapshot of an immutable
model, read from the extension's typed description (``spacearm._core.ModelInfo``).
:meth:`ModelDescription.to_dict` gives the plain-data form that :meth:`Robot.describe` returns.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace
from typing import Optional, Tuple

import numpy as np

from ..errors import NotFoundError

__all__ = ["ModelDescription", "BaseDescription", "LinkDescription", "PointDescription", "JointLimits"]


def _readonly(values, shape: tuple) -> np.ndarray:
    """A float copy of ``values`` with the given shape, made read-only."""
    a = np.array(values, dtype=float).reshape(shape)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class JointLimits:
    """A joint's limits. ``lower``/``upper``: position bounds (rad for a revolute joint, m for a
    prismatic one; ``-inf``/``inf`` when unbounded); ``velocity``: speed bound (rad/s or m/s);
    ``effort``: torque (N·m) or force (N) bound. Unbounded entries are infinite."""

    lower: float
    upper: float
    velocity: float
    effort: float

    def to_list(self) -> list:
        """``[lower, upper, velocity, effort]``, the order of :meth:`Robot.describe`."""
        return [self.lower, self.upper, self.velocity, self.effort]


@dataclass(frozen=True, eq=False)
class BaseDescription:
    """The spacecraft base (body 0). Its frame has its origin at the base CM."""

    name: str
    mass: float  #: kg
    inertia: np.ndarray  #: (3, 3) kg·m², about the base CM in base-frame axes (read-only)


@dataclass(frozen=True, eq=False)
class LinkDescription:
    """One link (a body other than the base) and the joint that connects it to its parent.

    The link frame has its origin at the link's CM; at ``q = 0`` its axes are those of the
    parent frame rotated by ``rotation``.
    """

    name: str
    parent: str  #: name of the parent body (the base's name for a link on the base)
    parent_index: int  #: body index of the parent (0 = base)
    joint: str  #: name of the joint
    type: str  #: ``"revolute"``, ``"prismatic"`` or ``"fixed"``
    axis: np.ndarray  #: (3,) unit joint axis in the link frame (unused by a fixed joint: as given, or z if given zero)
    origin: np.ndarray  #: (3,) m, joint position in the parent frame, measured from the parent's CM
    rotation: np.ndarray  #: (4,) ``[x, y, z, w]`` unit quaternion, link frame in the parent frame at q = 0
    com: np.ndarray  #: (3,) m, the link's CM measured from the joint, in the link frame
    mass: float  #: kg
    inertia: np.ndarray  #: (3, 3) kg·m², about the link's CM in link-frame axes
    limits: JointLimits
    dof: Optional[int]  #: index of the joint's coordinate in ``q``; ``None`` for a fixed joint


@dataclass(frozen=True, eq=False)
class PointDescription:
    """A named point fixed to a body (an end effector, a grasp point)."""

    name: str
    body: str  #: name of the body carrying the point
    offset: np.ndarray  #: (3,) m, from the body's CM, in the body frame


@dataclass(frozen=True, eq=False)
class ModelDescription:
    """A whole model: base, links in tree order (a parent before its children; link ``i`` is
    body ``i + 1``), named points, end effector and initial joint coordinates."""

    name: str
    base: BaseDescription
    links: Tuple[LinkDescription, ...]
    points: Tuple[PointDescription, ...]
    end_effector: Optional[str]  #: name of the end-effector point, or ``None``
    initial_q: np.ndarray  #: (N,) initial joint coordinates (rad or m per joint type)

    @classmethod
    def from_core(cls, info) -> "ModelDescription":
        """Build from the extension's typed description, ``Model.describe()`` (a
        ``spacearm._core.ModelInfo``: crates/spacearm-py/src/description_py.rs), or from the
        plain-data form of :meth:`Robot.describe` (see :meth:`from_dict`)."""
        if isinstance(info, dict):
            return cls.from_dict(info)
        base = info.base
        return cls(
            name=info.name,
            base=BaseDescription(name=base.name, mass=float(base.mass), inertia=_readonly(base.inertia, (3, 3))),
            links=tuple(
                LinkDescription(
                    name=link.name,
                    parent=link.parent,
                    parent_index=int(link.parent_index),
                    joint=link.joint,
                    type=link.type,
                    axis=_readonly(link.axis, (3,)),
                    origin=_readonly(link.origin, (3,)),
                    rotation=_readonly(link.rotation, (4,)),
                    com=_readonly(link.com, (3,)),
                    mass=float(link.mass),
                    inertia=_readonly(link.inertia, (3, 3)),
                    limits=JointLimits(float(link.limits.lower), float(link.limits.upper), float(link.limits.velocity),
                                       float(link.limits.effort)),
                    dof=None if link.dof is None else int(link.dof),
                )
                for link in info.links
            ),
            points=tuple(PointDescription(name=p.name, body=p.body, offset=_readonly(p.offset, (3,))) for p in info.points),
            end_effector=info.end_effector,
            initial_q=_readonly(info.initial_q, (-1,)),
        )

    @classmethod
    def from_dict(cls, d: dict) -> "ModelDescription":
        """Build from the plain-data form of :meth:`to_dict` and :meth:`Robot.describe` (read
        through the same field mapping as :meth:`from_core`)."""
        ns = SimpleNamespace
        limit_names = ("lower", "upper", "velocity", "effort")
        return cls.from_core(ns(
            name=d["name"],
            base=ns(**d["base"]),
            links=[ns(**{**link, "limits": ns(**dict(zip(limit_names, link["limits"])))}) for link in d["links"]],
            points=[ns(name=n, body=b, offset=o) for n, b, o in d["points"]],
            end_effector=d["end_effector"],
            initial_q=d["initial_q"],
        ))

    def to_dict(self) -> dict:
        """The plain-data form, exactly as :meth:`Robot.describe` returns it."""
        return {
            "name": self.name,
            "base": {"name": self.base.name, "mass": self.base.mass, "inertia": self.base.inertia.tolist()},
            "links": [
                {
                    "name": link.name,
                    "parent": link.parent,
                    "parent_index": link.parent_index,
                    "joint": link.joint,
                    "type": link.type,
                    "origin": link.origin.tolist(),
                    "rotation": link.rotation.tolist(),
                    "axis": link.axis.tolist(),
                    "com": link.com.tolist(),
                    "mass": link.mass,
                    "inertia": link.inertia.tolist(),
                    "limits": link.limits.to_list(),
                    "dof": link.dof,
                }
                for link in self.links
            ],
            "points": [(p.name, p.body, p.offset.tolist()) for p in self.points],
            "end_effector": self.end_effector,
            "initial_q": self.initial_q.tolist(),
        }

    def link(self, name: str) -> LinkDescription:
        """The link called ``name`` (raises :class:`~spacearm.NotFoundError` if there is none)."""
        for link in self.links:
            if link.name == name:
                return link
        raise NotFoundError(f"no link named {name!r} (links: {', '.join(link.name for link in self.links) or 'none'})")

    def point(self, name: str) -> PointDescription:
        """The point called ``name`` (raises :class:`~spacearm.NotFoundError` if there is none)."""
        for p in self.points:
            if p.name == name:
                return p
        raise NotFoundError(f"no point named {name!r} (points: {', '.join(p.name for p in self.points) or 'none'})")
