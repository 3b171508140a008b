"""Building a model in Python, link by link.

Frames (DESIGN.md §1): every body frame has its origin at the body's CM. A joint sits at
``origin`` in the parent's frame; the child's axes are the parent's rotated by ``rotation``
(quaternion ``[x, y, z, w]``) or ``rpy`` (URDF roll-pitch-yaw) and then by the joint motion;
``axis`` is given in the child's frame; ``com`` is the child's CM measured from the joint, in
the child's frame. See ``docs/model-format.md`` for a worked example.

>>> import spacearm
>>> b = spacearm.Robot.builder("demo", base_mass=100.0, base_inertia=[10, 10, 10])
>>> b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0),
...            com=(0.5, 0, 0), mass=5.0, inertia=[0.01, 0.4, 0.4])
>>> b.add_point("tip", body="arm", offset=(0.5, 0, 0)); b.set_end_effector("tip")
>>> robot = b.build()
"""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from . import _core
from ._arrays import matrix3, quaternion, vector
from .rotations import IDENTITY_QUAT, quat_from_rpy
from .robot import Robot
from .errors import ArgumentError, ModelError

__all__ = ["RobotBuilder"]


class RobotBuilder:
    """Accumulates a base and links, validating each addition; :meth:`build` returns a
    :class:`~spacearm.Robot`."""

    def __init__(self, name: str, base_mass: float, base_inertia, base_name: str = "base"):
        self._b = _core.ModelBuilder(str(name), str(base_name), float(base_mass), matrix3(base_inertia, "base_inertia"))
        self._base_name = str(base_name)
        self._n_wheels = 0

    def add_link(
        self,
        name: str,
        *,
        parent: str = "base",
        joint: str = "revolute",
        axis: Sequence[float] = (0.0, 0.0, 1.0),
        origin: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
        com: Sequence[float] = (0.0, 0.0, 0.0),
        mass: float,
        inertia,
        joint_name: Optional[str] = None,
        limits: Optional[dict] = None,
    ) -> "RobotBuilder":
        """Add a link attached to ``parent`` through a joint.

        ``joint``: ``"revolute"``, ``"prismatic"`` or ``"fixed"``. ``axis`` (normalized) in
        the link frame. ``rotation`` (quaternion ``[x, y, z, w]`` or scipy ``Rotation``) or ``rpy`` (rad) orients
        the link frame in the parent frame at ``q = 0`` (default: aligned). ``inertia`` is about
        the link CM in link axes (3×3, or its 3 diagonal entries). ``limits``: optional dict
        with any of ``lower``, ``upper``, ``velocity``, ``effort``.
        """
        if rotation is not None and rpy is not None:
            raise ArgumentError(f"link '{name}': give rotation or rpy, not both")
        if rpy is not None:
            quat = quat_from_rpy(*vector(rpy, f"link '{name}' rpy", 3))
        elif rotation is not None:
            quat = quaternion(rotation, f"link '{name}' rotation")
        else:
            quat = IDENTITY_QUAT
        lim = None
        if limits is not None:
            unknown = set(limits) - {"lower", "upper", "velocity", "effort"}
            if unknown:
                raise ArgumentError(f"link '{name}': unknown limit keys {sorted(unknown)}; expected lower, upper, velocity, effort")
            lim = [
                float(limits.get("lower", -np.inf)),
                float(limits.get("upper", np.inf)),
                float(limits.get("velocity", np.inf)),
                float(limits.get("effort", np.inf)),
            ]
        self._b.add_link(
            str(name),
            str(parent),
            str(joint),
            list(vector(origin, f"link '{name}' origin", 3)),
            list(quat),
            list(vector(axis, f"link '{name}' axis", 3)),
            list(vector(com, f"link '{name}' com", 3)),
            float(mass),
            matrix3(inertia, f"link '{name}' inertia"),
            joint_name,
            lim,
        )
        return self

    def add_reaction_wheel(
        self,
        axis: Sequence[float],
        rotor_inertia: float,
        position: Sequence[float] = (0.0, 0.0, 0.0),
        max_torque: float = np.inf,
        max_speed: float = np.inf,
        *,
        name: Optional[str] = None,
        mass: float = 0.0,
        transverse_inertia: Optional[float] = None,
    ) -> "RobotBuilder":
        """Add a reaction wheel: a symmetric rotor on a revolute joint of the base (DESIGN §2).

        The wheel is an ordinary link (``wheel1``, ``wheel2``, … unless ``name`` is given; joint
        ``<name>_joint``) whose coordinate is the rotor angle, so its torque is an internal
        joint torque and the momentum bookkeeping stays exact. ``axis``: spin axis in the base
        frame (normalized); ``rotor_inertia``: spin-axis moment, kg·m²; ``position``: rotor CM
        from the base CM in the base frame, m; ``max_torque`` (N·m) and ``max_speed`` (rad/s)
        are kept as the joint's effort and velocity limits. ``mass`` (kg, default 0: the wheel's
        mass counted in the base) and ``transverse_inertia`` (default ``0.6 · rotor_inertia``: a
        disc 0.77 radii thick; 0.5 is the thin-disc limit, where the triangle inequality of
        the inertia is an equality that MuJoCo rejects) complete the rotor; its inertia ``I_t E + (I_s − I_t) k kᵀ`` is symmetric
        about the axis, so it does not change as the rotor spins.
        """
        k = vector(axis, "reaction wheel axis", 3)
        norm = float(np.linalg.norm(k))
        if not np.isfinite(norm) or norm <= 1e-9:
            raise ModelError(f"reaction wheel axis must be a finite non-zero vector, got {list(k)}")
        k = k / norm
        i_s = float(rotor_inertia)
        if not (np.isfinite(i_s) and i_s > 0):
            raise ModelError(f"reaction wheel rotor_inertia must be > 0 kg m^2, got {rotor_inertia}")
        i_t = 0.6 * i_s if transverse_inertia is None else float(transverse_inertia)
        for what, v in (("max_torque", max_torque), ("max_speed", max_speed)):
            if not float(v) > 0:
                raise ModelError(f"reaction wheel {what} must be > 0, got {v}")
        self._n_wheels += 1
        name = f"wheel{self._n_wheels}" if name is None else str(name)
        inertia = i_t * np.eye(3) + (i_s - i_t) * np.outer(k, k)
        return self.add_link(name, parent=self._base_name, joint="revolute", axis=k, origin=position,
                             com=(0.0, 0.0, 0.0), mass=mass, inertia=inertia, joint_name=f"{name}_joint",
                             limits={"velocity": float(max_speed), "effort": float(max_torque)})

    def add_point(self, name: str, *, body: str, offset: Sequence[float] = (0.0, 0.0, 0.0)) -> "RobotBuilder":
        """Add a named point fixed to ``body`` at ``offset`` (body frame, from its CM)."""
        self._b.add_point(str(name), str(body), list(vector(offset, f"point '{name}' offset", 3)))
        return self

    def set_end_effector(self, name: str) -> "RobotBuilder":
        """Designate the named point as the end effector."""
        self._b.set_end_effector(str(name))
        return self

    def set_initial_q(self, q: Sequence[float]) -> "RobotBuilder":
        """Initial (nominal) joint coordinates, length N."""
        self._b.set_initial_q(list(vector(q, "initial q")))
        return self

    def build(self) -> Robot:
        """Validate the whole model and return the immutable :class:`~spacearm.Robot`."""
        return Robot(self._b.build())
