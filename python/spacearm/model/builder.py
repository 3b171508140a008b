"""Building a model in Python, link by link.

Frames (``docs/conventions.md``): every body frame has its origin at the body's CM. A joint sits at
``origin`` in the parent's frame; the child's axes are the parent's rotated by ``rotation``
(quaternion ``[x, y, z, w]``) or ``rpy`` (URDF roll-pitch-yaw) and then by the joint motion;
``axis`` is given in the child's frame; ``com`` is the child's CM measured from the joint, in
the child's frame. See ``docs/model-format.md`` for a worked example.

A model is edited through a builder too: [`RobotBuilder.from_robot`][spacearm.RobotBuilder.from_robot] (or
[`Robot.to_builder`][spacearm.Robot.to_builder]) holds an existing model exactly, and [`add_link`][spacearm.RobotBuilder.add_link],
[`attach_payload`][spacearm.RobotBuilder.attach_payload] and [`remove_body`][spacearm.RobotBuilder.remove_body] change it before
[`build`][spacearm.RobotBuilder.build] makes a new, validated Robot (a Robot itself never changes).
One edit at a time is the core's, without replaying the model:
[`Robot.attach_body`][spacearm.Robot.attach_body], [`Robot.attach`][spacearm.Robot.attach] (a whole model) and
[`Robot.remove_subtree`][spacearm.Robot.remove_subtree] (``model/edit.rs``).

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

from .. import _core
from .._util.arrays import matrix3, number, quaternion, vector
from ..errors import ArgumentError, ModelError, SpacearmTypeError
from ..rotations import IDENTITY_QUAT, quat_from_rpy
from .robot import Robot, warn_nonphysical_inertia

__all__ = ["RobotBuilder"]


def link_limits(name: str, limits: Optional[dict]) -> Optional[list]:
    """``[lower, upper, velocity, effort]`` for the core from the dict ``limits`` (missing keys
    unlimited), ``None`` for none."""
    if limits is None:
        return None
    unknown = set(limits) - {"lower", "upper", "velocity", "effort"}
    if unknown:
        raise ArgumentError(f"link '{name}': unknown limit keys {sorted(unknown)}; expected lower, upper, velocity, effort")
    return [number(limits.get(key, default), f"link '{name}' limit {key}")
            for key, default in (("lower", -np.inf), ("upper", np.inf), ("velocity", np.inf), ("effort", np.inf))]


def frame_rotation(rotation, rpy, who: str):
    """A frame's rotation (a link's axes in its parent's, a part's or a geometry's in its
    body's) given as a quaternion ``[x, y, z, w]`` (or scipy ``Rotation``) or as ``rpy`` (rad),
    not both, or the identity; ``who`` names the frame in the errors."""
    if rotation is not None and rpy is not None:
        raise ArgumentError(f"{who}: give rotation or rpy, not both")
    if rpy is not None:
        return quat_from_rpy(*vector(rpy, f"{who} rpy", 3))
    if rotation is not None:
        return quaternion(rotation, f"{who} rotation")
    return IDENTITY_QUAT


def _numbers(who: str, **values) -> dict:
    """Each named scalar as a float, the error of one that is not naming ``who`` and its name
    (e.g. ``probe 'p' length``); range checks are the core's."""
    return {key: number(value, f"{who} {key}") for key, value in values.items()}


def _optional_numbers(who: str, **values) -> dict:
    """As ``_numbers``, ``None`` kept (the core's default applies)."""
    return {key: None if value is None else number(value, f"{who} {key}") for key, value in values.items()}


def _vectors3(who: str, **values) -> dict:
    """Each named 3-vector as a list of floats (``who``'s name in its error)."""
    return {key: list(vector(value, f"{who} {key}", 3)) for key, value in values.items()}


class RobotBuilder:
    """Accumulates a base and links, validating each addition; [`build`][spacearm.RobotBuilder.build] returns a
    [`Robot`][spacearm.Robot]."""

    def __init__(self, name: str, base_mass: float, base_inertia, base_name: str = "base", *,
                 allow_nonphysical_inertia: bool = False):
        """``allow_nonphysical_inertia``: accept inertias whose principal moments break the
        triangle inequality ``I1 + I2 >= I3`` (refused by default: no real body has them);
        [`build`][spacearm.RobotBuilder.build] then warns once per such body
        ([`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning]). For published identified data."""
        self._b = _core.ModelBuilder(str(name), str(base_name), number(base_mass, "base_mass"), matrix3(base_inertia, "base_inertia"),
                                     bool(allow_nonphysical_inertia))
        self._base_name = str(base_name)
        self._n_wheels = 0

    @classmethod
    def from_robot(cls, robot: Robot, name: Optional[str] = None, *,
                   allow_nonphysical_inertia: Optional[bool] = None, geometry: bool = True) -> "RobotBuilder":
        """A builder holding ``robot``'s model exactly: the base, every link with its joint,
        limits, passive dynamics and mass properties, the points, the end effector and the initial ``q``.

        It is the core's copy of the model (model/edit.rs ``ModelBuilder::from_model``, no replay
        through the builder's calls): built unchanged, it gives a model equal to ``robot`` bit for bit.
        The initial ``q`` is kept per link, so links added or removed afterwards keep the other
        joints' initial values (new joints start at their spring rest, 0 unless set) unless [`set_initial_q`][spacearm.RobotBuilder.set_initial_q] is called.
        ``allow_nonphysical_inertia`` defaults to ``robot``'s own choice. ``geometry=False``
        leaves out the model's shapes (docs/geometry.md).
        """
        if not isinstance(robot, Robot):
            raise ArgumentError(f"from_robot needs a spacearm.Robot, got {type(robot).__name__}")
        # The core's own copy of the model (model/edit.rs ModelBuilder::from_model): no replay.
        b = cls.__new__(cls)
        b._b = _core.ModelBuilder.from_model(robot.core_model)
        b._base_name = robot.description.base.name
        b._n_wheels = 0
        if name is not None:
            b._b.set_name(str(name))
        if allow_nonphysical_inertia is not None and bool(allow_nonphysical_inertia) != robot.allows_nonphysical_inertia:
            b._b.set_allow_nonphysical_inertia(bool(allow_nonphysical_inertia))
        if not geometry:
            b._b.clear_geometries()
        return b

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
        actuated: bool = True,
        stiffness: float = 0.0,
        damping: float = 0.0,
        rest: float = 0.0,
        compliant: Optional[dict] = None,
    ) -> "RobotBuilder":
        """Add a link attached to ``parent`` through a joint.

        ``joint``: ``"revolute"``, ``"prismatic"`` or ``"fixed"``. ``axis`` (normalized) in
        the link frame. ``rotation`` (quaternion ``[x, y, z, w]`` or scipy ``Rotation``) or ``rpy`` (rad) orients
        the link frame in the parent frame at ``q = 0`` (default: aligned). ``inertia`` is about
        the link CM in link axes (3×3, or its 3 diagonal entries). ``limits``: optional dict
        with any of ``lower``, ``upper``, ``velocity``, ``effort``.

        The joint's passive dynamics (``docs/flexibility.md``): ``actuated=False`` makes it a
        passive joint (no motor: the simulator applies no torque to it, whatever a controller
        commands); ``stiffness`` (N·m/rad or N/m), ``damping`` (N·m·s/rad or N·s/m) and
        ``rest`` (rad or m) give it a linear spring–damper, the generalized force
        ``-stiffness (q - rest) - damping q̇`` in every forward dynamics and simulation. A
        fixed joint takes none of them.

        ``compliant={"stiffness": k, "rotor_inertia": B, "damping": c, "gear_ratio": n}``
        (``damping`` default 0, ``gear_ratio`` default 1) makes a revolute joint elastic in
        Spong's manner (docs/flexibility.md, "Compliant joints"; the core's
        ``model/appendage.rs``): the joint (its name, origin, axis, limits) becomes an actuated
        motor joint carrying the rotor ``<name>_rotor`` (axial inertia ``n² B``), and the link
        follows on the passive joint ``<joint>_deflection`` about the same axis, whose coordinate
        ``δ = q_link − θ`` carries the series spring ``-k δ - c δ̇``. It takes no
        ``actuated``/``stiffness``/``damping``/``rest`` of its own.
        """
        quat = frame_rotation(rotation, rpy, f"link '{name}'")
        lim = link_limits(name, limits)
        # The link as the core reads it: `ModelBuilder.add_link`'s arguments but the dynamics.
        link = (
            str(name),
            str(parent),
            str(joint),
            list(vector(origin, f"link '{name}' origin", 3)),
            list(quat),
            list(vector(axis, f"link '{name}' axis", 3)),
            list(vector(com, f"link '{name}' com", 3)),
            number(mass, f"link '{name}' mass"),
            matrix3(inertia, f"link '{name}' inertia"),
            joint_name,
            lim,
        )
        if compliant is not None:
            return self._add_compliant(link, compliant, (actuated, stiffness, damping, rest))
        self._b.add_link(*link, self._joint_dynamics(name, actuated, stiffness, damping, rest))
        return self

    def _add_compliant(self, link, compliant, dynamics) -> "RobotBuilder":
        name = link[0]
        if not isinstance(compliant, dict):
            raise SpacearmTypeError(f"link '{name}': compliant must be a dict with stiffness, rotor_inertia, damping, "
                                    f"gear_ratio, got {type(compliant).__name__}")
        unknown = set(compliant) - {"stiffness", "rotor_inertia", "damping", "gear_ratio"}
        missing = {"stiffness", "rotor_inertia"} - set(compliant)
        if unknown or missing:
            raise ArgumentError(f"link '{name}': compliant takes stiffness, rotor_inertia (both needed), damping and "
                                f"gear_ratio; unknown {sorted(unknown)}, missing {sorted(missing)}")
        if self._joint_dynamics(name, *dynamics) is not None:
            raise ArgumentError(f"link '{name}': a compliant joint takes no actuated, stiffness, damping or rest of its "
                                "own (the motor joint is actuated, the spring is compliant['stiffness'])")
        parts = _core.compliant_parts(
            link,
            number(compliant["stiffness"], f"link '{name}' compliant stiffness"),
            number(compliant["rotor_inertia"], f"link '{name}' compliant rotor_inertia"),
            number(compliant.get("damping", 0.0), f"link '{name}' compliant damping"),
            number(compliant.get("gear_ratio", 1.0), f"link '{name}' compliant gear_ratio"))
        return self._add_parts(parts)

    def _add_parts(self, parts) -> "RobotBuilder":
        """Add the core's ``(links, points, geometries)`` of an appendage (``model/appendage.rs``)."""
        links, points, geometries = parts
        for args in links:
            self._b.add_link(*args)
        for point, body, offset in points:
            self.add_point(point, body=body, offset=offset)
        for gname, body, size, origin, rotation, rgba in geometries:
            self.add_geometry(body, "box", size=size, origin=origin, rotation=rotation, rgba=rgba, name=gname)
        return self

    def add_panel(
        self,
        name: str,
        *,
        parent: str = "base",
        hinge_position: Sequence[float],
        hinge_axis: Sequence[float],
        direction: Sequence[float],
        mass: float,
        size: Optional[Sequence[float]] = None,
        inertia=None,
        com_distance: Optional[float] = None,
        stiffness: Optional[float] = None,
        frequency: Optional[float] = None,
        damping: float = 0.0,
        rest: float = 0.0,
    ) -> "RobotBuilder":
        """Add a hinged rigid panel: a plate on a passive revolute joint ``<name>_hinge`` with a
        torsional spring (docs/flexibility.md, "Hinged panels"; the core's ``model/appendage.rs``).

        The hinge is at ``hinge_position`` (``parent``'s frame, from its CM) about
        ``hinge_axis``; the plate extends from the hinge line along ``direction``
        (perpendicular to the hinge). ``size = (length, width, thickness)``: a uniform plate,
        length along ``direction``, width along the hinge, CM at ``length/2`` (drawn as a box);
        or ``inertia`` (about the CM, parent axes, 3×3 or its diagonal) with ``com_distance``
        (the CM's distance from the hinge along ``direction``). The spring: ``stiffness``
        (N·m/rad) or ``frequency`` (rad/s on a clamped parent: ``k = I_h ω²``, ``I_h`` the
        moment about the hinge line). ``damping`` N·m·s/rad, ``rest`` rad.
        """
        parts = _core.panel_parts(
            str(name), str(parent), list(vector(hinge_position, f"panel '{name}' hinge_position", 3)),
            list(vector(hinge_axis, f"panel '{name}' hinge_axis", 3)), list(vector(direction, f"panel '{name}' direction", 3)),
            number(mass, f"panel '{name}' mass"), None if size is None else list(vector(size, f"panel '{name}' size", 3)),
            None if inertia is None else matrix3(inertia, f"panel '{name}' inertia"),
            None if com_distance is None else number(com_distance, f"panel '{name}' com_distance"),
            None if stiffness is None else number(stiffness, f"panel '{name}' stiffness"),
            None if frequency is None else number(frequency, f"panel '{name}' frequency"),
            number(damping, f"panel '{name}' damping"), number(rest, f"panel '{name}' rest"))
        return self._add_parts(parts)

    def add_beam(
        self,
        name: str,
        *,
        parent: str = "base",
        root_position: Sequence[float],
        axis: Sequence[float],
        length: float,
        segments: int,
        EI,
        rho_A: float,
        bending_axes: Optional[Sequence[Sequence[float]]] = None,
        GJ: Optional[float] = None,
        rho_J: float = 0.0,
        damping: Optional[float] = None,
        damping_ratio: Optional[float] = None,
    ) -> "RobotBuilder":
        """Add a flexible beam by the rigid finite element method (docs/flexibility.md, "Flexible
        beams"; the core's ``model/appendage.rs``): ``segments`` = N primary segments of
        ``l = length/N``; a root half-element ``<name>_root`` clamped to ``parent`` at
        ``root_position``, then at ``(i − ½) l`` along ``axis`` (``i = 1..N``) a passive revolute
        joint per bending axis with ``k = EI/l`` (and about ``axis`` with ``k = GJ/l`` when
        ``GJ`` is given) and the rigid element ``<name>_i`` (mass ``ρA`` per length), the last
        one of length ``l/2``; the point ``<name>_tip`` at the free end.

        ``bending_axes``: one or two axes perpendicular to ``axis`` (parent frame); default two:
        ``b₁``, the parent axis along ``axis``'s smallest component made perpendicular to it, and
        ``b₂ = axis × b₁``. ``EI`` (N·m²): one number for every bending axis or one per axis.
        ``rho_J``: mass moment of inertia per length about the axis (kg·m; needed with ``GJ``).
        ``damping`` (N·m·s/rad on every joint) or ``damping_ratio`` ζ (stiffness-proportional,
        ``c = 2ζk/ω₁`` with ``ω₁`` the first clamped Euler–Bernoulli frequency).
        """
        who = f"beam '{name}'"
        axes = None if bending_axes is None else [list(vector(b, f"{who} bending axis", 3)) for b in bending_axes]
        try:
            ei = [float(v) for v in np.atleast_1d(np.asarray(EI, dtype=float))]
        except (TypeError, ValueError):
            raise SpacearmTypeError(f"{who}: EI must be a number or a sequence of numbers, got {EI!r}") from None
        if isinstance(segments, bool) or not isinstance(segments, (int, np.integer)) or segments < 0:
            raise SpacearmTypeError(f"{who}: segments must be a positive integer, got {type(segments).__name__} {segments!r}")
        parts = _core.beam_parts(
            str(name), str(parent), list(vector(root_position, f"{who} root_position", 3)), list(vector(axis, f"{who} axis", 3)),
            number(length, f"{who} length"), int(segments), axes, ei,
            None if GJ is None else number(GJ, f"{who} GJ"), number(rho_A, f"{who} rho_A"), number(rho_J, f"{who} rho_J"),
            None if damping is None else number(damping, f"{who} damping"),
            None if damping_ratio is None else number(damping_ratio, f"{who} damping_ratio"))
        return self._add_parts(parts)

    @staticmethod
    def _joint_dynamics(name, actuated, stiffness, damping, rest) -> Optional[tuple]:
        """``(actuated, stiffness, damping, rest)`` for the core builder, ``None`` for an actuated
        joint without spring (the core's rules check the values)."""
        if not isinstance(actuated, (bool, np.bool_)):
            raise SpacearmTypeError(f"link '{name}': actuated must be True or False, got {type(actuated).__name__} {actuated!r}")
        values = (bool(actuated), number(stiffness, f"link '{name}' stiffness"), number(damping, f"link '{name}' damping"),
                  number(rest, f"link '{name}' rest"))
        return None if values == (True, 0.0, 0.0, 0.0) else values

    def add_slosh(
        self,
        name: str,
        *,
        parent: str = "base",
        model: str,
        mass: float,
        position: Sequence[float],
        axis: Sequence[float],
        stiffness: Optional[float] = None,
        frequency: Optional[float] = None,
        damping: float = 0.0,
        length: Optional[float] = None,
        hinge: Optional[Sequence[float]] = None,
    ) -> "RobotBuilder":
        """Add a propellant slosh mode as passive links (docs/flexibility.md, "Fuel slosh"; the
        geometry is the core's, ``model/slosh.rs``).

        ``model``: ``"spring-mass"`` (a point mass on a passive prismatic joint at ``position``,
        in ``parent``'s frame from its CM, sliding along ``axis``: the mass is at
        ``position + q·axis``, force ``-k q - c q̇``), ``"pendulum"`` (a point bob at
        ``length`` along ``axis`` from the pivot at ``position`` at ``q = 0``, one passive
        revolute joint about ``hinge``, perpendicular to ``axis``) or ``"spherical-pendulum"``
        (two passive revolute joints at the pivot, about ``hinge`` then ``axis × hinge``, with a
        massless link ``<name>_gimbal`` between them; singular at ``q₂ = ±π/2``). Give the
        restoring spring as ``stiffness`` (N/m, or N·m/rad per pendulum joint) or as the mode's
        ``frequency`` on a clamped tank (rad/s: ``k = m ω²``, ``k = m L² ω²``). ``damping`` acts
        per joint (N·s/m or N·m·s/rad). The fixed part of the propellant is a rigid mass: add it
        with [`attach_payload`][spacearm.RobotBuilder.attach_payload].
        """
        links = _core.slosh_links(
            str(name), str(parent), str(model), number(mass, f"slosh '{name}' mass"),
            list(vector(position, f"slosh '{name}' position", 3)), list(vector(axis, f"slosh '{name}' axis", 3)),
            None if hinge is None else list(vector(hinge, f"slosh '{name}' hinge", 3)),
            None if length is None else number(length, f"slosh '{name}' length"),
            None if stiffness is None else number(stiffness, f"slosh '{name}' stiffness"),
            None if frequency is None else number(frequency, f"slosh '{name}' frequency"),
            number(damping, f"slosh '{name}' damping"),
        )
        for args in links:
            self._b.add_link(*args)
        return self

    def attach_payload(
        self,
        name: str,
        *,
        body: str,
        mass: float,
        inertia=(0.0, 0.0, 0.0),
        origin: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
    ) -> "RobotBuilder":
        """Attach a rigid payload to ``body``: a link on a fixed joint, so the joint space is
        unchanged and the payload's mass properties merge with the body's.

        ``origin`` is the payload's CM in ``body``'s frame (from its CM, m); ``rotation``
        (quaternion ``[x, y, z, w]`` or scipy ``Rotation``) or ``rpy`` orients the payload's axes in ``body``'s frame;
        ``inertia`` is about the payload's CM in its own axes (3×3, or 3 diagonal entries;
        default 0: a point mass). A captured target or a grasped tool is attached this way.
        """
        return self.add_link(name, parent=body, joint="fixed", origin=origin, rotation=rotation, rpy=rpy,
                             com=(0.0, 0.0, 0.0), mass=mass, inertia=inertia, joint_name=f"{name}_joint")

    def remove_body(self, name: str) -> "RobotBuilder":
        """Remove link ``name``, every link below it, and the points and geometries on them (the
        end effector too, if it is one of them: set another with [`set_end_effector`][spacearm.RobotBuilder.set_end_effector]). The
        base cannot be removed. The core's edit (model/edit.rs ``remove_subtree``): the other
        links keep their order, parts and initial coordinates.
        """
        self._b.remove_subtree(str(name))
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
        """Add a reaction wheel: a symmetric rotor on a revolute joint of the base (``docs/simulation-core.md``).

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
        # The axis is the joint's: the core's joint-axis rule judges it in add_link below (the
        # same verdict and message as every other joint); the rotor inertia needs only its
        # direction (a zero or non-finite axis gets a placeholder that never reaches a model).
        norm = float(np.linalg.norm(k))
        unit = k / norm if np.isfinite(norm) and norm > 0 else np.zeros(3)
        i_s = number(rotor_inertia, "reaction wheel rotor_inertia")
        if not (np.isfinite(i_s) and i_s > 0):
            raise ModelError(f"reaction wheel rotor_inertia must be > 0 kg m^2, got {rotor_inertia}")
        i_t = 0.6 * i_s if transverse_inertia is None else number(transverse_inertia, "reaction wheel transverse_inertia")
        for what, v in (("max_torque", max_torque), ("max_speed", max_speed)):
            if not number(v, f"reaction wheel {what}") > 0:
                raise ModelError(f"reaction wheel {what} must be > 0, got {v}")
        name = f"wheel{self._n_wheels + 1}" if name is None else str(name)
        inertia = i_t * np.eye(3) + (i_s - i_t) * np.outer(unit, unit)
        self.add_link(name, parent=self._base_name, joint="revolute", axis=k, origin=position,
                      com=(0.0, 0.0, 0.0), mass=mass, inertia=inertia, joint_name=f"{name}_joint",
                      limits={"velocity": float(max_speed), "effort": float(max_torque)})
        self._n_wheels += 1  # counted once added: a refused wheel takes no number
        return self

    def add_cmg(
        self,
        name: str,
        *,
        parent: Optional[str] = None,
        position: Sequence[float] = (0.0, 0.0, 0.0),
        gimbal_axis: Sequence[float],
        spin_axis: Sequence[float],
        rotor_inertia: float,
        rotor_transverse_inertia: Optional[float] = None,
        gimbal_inertia=0.0,
        rotor_mass: float = 0.0,
        gimbal_mass: float = 0.0,
        variable_speed: bool = False,
        max_gimbal_rate: Optional[float] = None,
        max_wheel_speed: Optional[float] = None,
        max_gimbal_torque: Optional[float] = None,
        max_wheel_torque: Optional[float] = None,
    ) -> "RobotBuilder":
        """Add a control-moment gyro (docs/cmg.md; the core's ``model/cmg.rs``, the same rules
        as TOML ``[[cmg]]``): the gimbal link ``name`` on the revolute joint ``<name>_gimbal`` of
        ``parent`` (default: the base) at ``position`` (parent frame, from its CM), turning about
        ``gimbal_axis``; on it the rotor ``<name>_rotor`` on the joint ``<name>_spin`` about
        ``spin_axis`` (perpendicular to ``gimbal_axis``, parent frame at zero gimbal angle), both
        CMs at the gimbal joint.

        ``rotor_inertia`` ``J_s`` (kg·m²) about the spin axis, ``rotor_transverse_inertia``
        (default ``0.6 J_s``); ``gimbal_inertia``: one moment or three along
        ``(gimbal, spin, gimbal × spin)``. ``variable_speed=True`` makes a VSCMG (a motor on the
        spin joint, whose torque is a control); otherwise the rotor is free (no motor) and its
        absolute spin stays constant (a single-gimbal CMG). The limits are the joints' velocity
        and effort limits. The rotor's speed is the run's initial condition:
        ``u0 = robot.cmg_velocity(wheel_speed)``.
        """
        gi = np.atleast_1d(np.asarray(gimbal_inertia, dtype=float)).ravel()
        if gi.size == 1:
            gi = np.repeat(gi, 3)
        who = f"cmg '{name}'"
        spec = {
            "name": str(name),
            "parent": None if parent is None else str(parent),
            **_vectors3(who, position=position, gimbal_axis=gimbal_axis, spin_axis=spin_axis, gimbal_inertia=gi),
            **_numbers(who, rotor_inertia=rotor_inertia, rotor_mass=rotor_mass, gimbal_mass=gimbal_mass),
            **_optional_numbers(who, rotor_transverse_inertia=rotor_transverse_inertia, max_gimbal_rate=max_gimbal_rate,
                                max_wheel_speed=max_wheel_speed, max_gimbal_torque=max_gimbal_torque,
                                max_wheel_torque=max_wheel_torque),
            "variable_speed": bool(variable_speed),
        }
        return self._add_parts(_core.cmg_parts(spec, self._base_name))

    def add_gripper(
        self,
        name: str,
        *,
        parent: Optional[str] = None,
        position: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
        fingers: int = 2,
        finger_length: float,
        finger_radius: float,
        opening: float,
        finger_mass: float = 0.1,
        palm_mass: float = 0.5,
        max_force: Optional[float] = None,
    ) -> "RobotBuilder":
        """Add a gripper (docs/contact.md, "Grippers"; the core's ``model/gripper.rs``, the same
        rules as TOML ``[[gripper]]``): the palm link ``name`` on the fixed joint
        ``<name>_mount`` of ``parent`` (default: the base) at ``position`` (parent frame, from its
        CM) turned by ``rotation`` (``[x, y, z, w]``) or ``rpy``, its fingers along the palm's
        ``+z``; ``fingers=2``: a parallel gripper, fingers ``<name>_finger0/1`` on prismatic
        joints closing along the palm's ``x`` (finger axes ``opening − 2q`` apart at the joint
        value ``q``); ``fingers=3``: revolute fingers 120° apart on a circle of diameter
        ``opening``, tilting inward (tip ``opening/2 − finger_length·sin q`` from the axis). Each
        finger a capsule collision shape (``finger_radius``, ``finger_length``) with the point
        ``<name>_tip<i>`` at its tip; the palm the point ``<name>_center``. ``max_force``: the
        finger motors' effort limit (N, or N·m for revolute fingers).
        """
        who = f"gripper '{name}'"
        quat = frame_rotation(rotation, rpy, who)
        if isinstance(fingers, bool) or not isinstance(fingers, (int, np.integer)):
            raise ArgumentError(f"{who}: fingers must be 2 or 3, got {fingers!r}")
        spec = {
            "name": str(name),
            "parent": None if parent is None else str(parent),
            **_vectors3(who, position=position),
            "rotation": [float(v) for v in quat],
            "fingers": int(fingers),
            **_numbers(who, finger_length=finger_length, finger_radius=finger_radius, opening=opening,
                       finger_mass=finger_mass, palm_mass=palm_mass),
            **_optional_numbers(who, max_force=max_force),
        }
        links, points, geometries = _core.gripper_parts(spec, self._base_name)
        for args in links:
            self._b.add_link(*args)
        for point, body, offset in points:
            self.add_point(point, body=body, offset=offset)
        for gname, body, role, shape, radius, length, origin, rot in geometries:
            self.add_geometry(body, shape, role=role, radius=radius, length=length, origin=origin, rotation=rot, name=gname)
        return self

    def add_probe(
        self,
        name: str,
        *,
        body: Optional[str] = None,
        position: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
        length: float,
        radius: float,
        head_radius: Optional[float] = None,
    ) -> "RobotBuilder":
        """Add a docking probe (docs/contact.md, "Probe and drogue"; the core's
        ``model/docking.rs``): a capsule collision shape ``name`` of ``radius`` on ``body``
        (default: the base), its segment from ``position`` (body frame, from its CM) along the
        ``+z`` of ``rotation`` (``[x, y, z, w]``) or ``rpy`` for ``length``, its head
        ``<name>_head`` (a ball of ``head_radius``, default ``radius``) and the point
        ``<name>_tip`` at the segment's end. Name the head in the contact pairs: it is what
        meets a drogue."""
        who = f"probe '{name}'"
        return self._add_docking("probe", name, body, position, rotation, rpy,
                                 {**_numbers(who, length=length, radius=radius), **_optional_numbers(who, head_radius=head_radius)})

    def add_drogue(
        self,
        name: str,
        *,
        body: Optional[str] = None,
        position: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
        mouth_radius: float,
        throat_radius: float,
        depth: float,
        rib_radius: float,
        ribs: int = 12,
    ) -> "RobotBuilder":
        """Add a docking drogue (docs/contact.md, "Probe and drogue"; the core's
        ``model/docking.rs``): a cone on ``body`` (default: the base) whose throat's centre is at
        ``position`` and whose axis, out of the mouth, is the ``+z`` of ``rotation`` or ``rpy``,
        made of ``ribs`` capsules ``<name>_rib<i>`` (radius ``rib_radius``) from the throat's
        circle (``throat_radius``) to the mouth's (``mouth_radius``, ``depth`` above it), the
        throat closed by the plate ``<name>_throat_plate``; points ``<name>_throat`` and
        ``<name>_mouth``."""
        if isinstance(ribs, bool) or not isinstance(ribs, (int, np.integer)):
            raise ArgumentError(f"drogue '{name}': ribs must be an integer >= 3, got {ribs!r}")
        fields = _numbers(f"drogue '{name}'", mouth_radius=mouth_radius, throat_radius=throat_radius, depth=depth,
                          rib_radius=rib_radius)
        return self._add_docking("drogue", name, body, position, rotation, rpy, {**fields, "ribs": int(ribs)})

    def _add_docking(self, kind, name, body, position, rotation, rpy, fields) -> "RobotBuilder":
        quat = frame_rotation(rotation, rpy, f"{kind} '{name}'")
        spec = {"name": str(name), "body": self._base_name if body is None else str(body),
                **_vectors3(f"{kind} '{name}'", position=position), "rotation": [float(v) for v in quat], **fields}
        points, geometries = _core.docking_parts(kind, spec)
        for gname, gbody, role, shape, radius, length, origin, rot in geometries:
            self.add_geometry(gbody, shape, role=role, radius=radius, length=None if shape == "sphere" else length,
                              origin=origin, rotation=rot, name=gname)
        for point, pbody, offset in points:
            self.add_point(point, body=pbody, offset=offset)
        return self

    def add_point(self, name: str, *, body: str, offset: Sequence[float] = (0.0, 0.0, 0.0)) -> "RobotBuilder":
        """Add a named point fixed to ``body`` at ``offset`` (body frame, from its CM)."""
        offset = list(vector(offset, f"point '{name}' offset", 3))
        self._b.add_point(str(name), str(body), offset)
        return self

    def add_geometry(
        self,
        body: str,
        shape: str,
        *,
        role: str = "visual",
        size: Optional[Sequence[float]] = None,
        radius: Optional[float] = None,
        length: Optional[float] = None,
        file: Optional[str] = None,
        scale: Optional[Sequence[float]] = None,
        origin: Sequence[float] = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[float]] = None,
        rpy: Optional[Sequence[float]] = None,
        rgba: Optional[Sequence[float]] = None,
        name: Optional[str] = None,
    ) -> "RobotBuilder":
        """Add a visual or collision shape fixed to ``body`` (``docs/geometry.md``); it carries
        no mass (the body's mass properties are its own).

        ``shape``: ``"box"`` (``size``: full side lengths, m), ``"sphere"`` (``radius``),
        ``"cylinder"`` or ``"capsule"`` (``radius``, ``length``; along the geometry's z; a
        capsule's ``length`` is its cylinder part), ``"mesh"`` (``file``, STL, OBJ or DAE, and
        ``scale``). ``origin`` (m, from the body's CM, body frame) and ``rotation`` (quaternion
        ``[x, y, z, w]``) or ``rpy`` place the geometry frame in the body frame. ``role``:
        ``"visual"`` or ``"collision"``. ``rgba``: colour, each in [0, 1]. ``name``: unique
        (default ``<body>_<role><k>``).
        """
        who = f"geometry '{name}'" if name is not None else f"geometry on '{body}'"
        quat = frame_rotation(rotation, rpy, who)
        kwargs = dict(
            role=str(role), shape=str(shape), origin=list(vector(origin, f"{who} origin", 3)), rotation=list(quat),
            size=None if size is None else list(vector(size, f"{who} size", 3)),
            radius=None if radius is None else number(radius, f"{who} radius"),
            length=None if length is None else number(length, f"{who} length"),
            file=None if file is None else str(file),
            scale=None if scale is None else list(vector(scale, f"{who} scale", 3)),
            rgba=None if rgba is None else list(vector(rgba, f"{who} rgba", 4)),
            name=None if name is None else str(name),
        )
        self._b.add_geometry(str(body), **kwargs)
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
        """Validate the whole model and return the immutable [`Robot`][spacearm.Robot]."""
        return warn_nonphysical_inertia(Robot(self._b.build()))
