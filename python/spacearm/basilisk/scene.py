"""A spacearm robot as a Basilisk ``MJScene``, and the scene's state as spacearm's ``x, u``.

The scene is the MJCF of [`spacearm.interop.to_mjcf`][spacearm.interop.to_mjcf] (every MuJoCo body
frame at the spacearm body's CM, the base on a free joint), so the convention map is the one of
``docs/conventions.md`` ("Mapping to Pinocchio and MuJoCo"), applied here and only here through
[`to_mujoco_state`][spacearm.interop.to_mujoco_state] / [`from_mujoco_state`][spacearm.interop.from_mujoco_state]:

    spacearm  x = [r0, quat0 (x, y, z, w), q]       u = [v0 (𝒥), ω0 (𝒥), q̇]
    MJScene   qpos = [r0, quat0 (w, x, y, z), q_e]  qvel = [v0 (𝒥), R0ᵀ ω0 (base axes), q̇_e]

(``q_e = q[order]``: MuJoCo's depth-first joint order, [`engine_dof_order`][spacearm.interop.engine_dof_order]).
An ``MJScene`` keeps ``qpos`` and ``qvel`` as two Basilisk states (``mujocoQpos``,
``mujocoQvel``) in MuJoCo's layout; [`state_from_scene`][spacearm.basilisk.state_from_scene] reads
them (at an integrator stage inside the scene's dynamics task, the stage's state) and
[`state_to_scene`][spacearm.basilisk.state_to_scene] writes them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from ..errors import ArgumentError, ModelError, SpacearmTypeError
from ..interop.mujoco import from_mujoco_state, mjcf_body_name, to_mjcf, to_mujoco_state
from ..model.robot import Robot
from . import _bsk

__all__ = ["ActuatorMap", "to_mjscene", "state_from_scene", "state_to_scene", "scene_qpos_qvel"]

#: The names of the six base actuators of a scene made with ``base_actuators=True``: the force
#: ``F0`` and torque ``N0`` on the base CM along the axes of 𝒥 (spacearm's base wrench).
BASE_ACTUATORS = ("base_fx", "base_fy", "base_fz", "base_tx", "base_ty", "base_tz")


#: The fraction of a parent's mass a massless rotor borrows in the scene's MJCF (``to_mjcf``'s
#: ``lent_mass``; exact: the point sits on the rotor's axis at its CM). Larger than MuJoCo's
#: export default: it keeps the lender's CM off its origin by well over a micrometre (below).
LENT_MASS = 1e-3
#: Basilisk 2.12's MJScene recompiles its model until a body's CM site leaves the body origin's
#: frame; a CM between 1e-9 m and about 1e-6 m from the origin loops (a crash, measured: 6e-7 m
#: crashes, 3e-6 m runs). The band refused here:
_CM_OFFSET_BAND = (1e-9, 1e-5)


def _check_body_origins(xml: str) -> None:
    import xml.etree.ElementTree as ET

    for body in ET.fromstring(xml).iter("body"):
        inertial = body.find("inertial")
        if inertial is None:
            continue
        offset = float(np.linalg.norm([float(v) for v in inertial.get("pos", "0 0 0").split()]))
        if _CM_OFFSET_BAND[0] < offset < _CM_OFFSET_BAND[1]:
            raise ModelError(f"body '{body.get('name')}' of the scene has its CM {offset:.3g} m from its frame's origin, "
                             f"in ({_CM_OFFSET_BAND[0]:g}, {_CM_OFFSET_BAND[1]:g}) m, where Basilisk's MJScene recompiles "
                             "without end (it crashes): move the rotors it carries by a few millimetres")


@dataclass(frozen=True)
class ActuatorMap:
    """The actuators of a scene made by [`to_mjscene`][spacearm.basilisk.to_mjscene], by the names a
    Basilisk user addresses them with (``scene.getSingleActuator(name).actuatorInMsg``; each takes
    a ``SingleActuatorMsgPayload(input=...)``, N·m or N).

    ``joints``: ``(dof, name)`` for every actuated joint in spacearm's ``q`` order, reaction
    wheels included (``<joint>_motor``); ``wheels``: the names among them that drive reaction
    wheels; ``base``: the six base actuators ``base_fx .. base_tz`` (``[F0, N0]`` at the base CM
    in 𝒥: spacearm's thrusters) or ``()``; ``bodies``: spacearm body index → MJCF body name (a
    massless link merged into its child has none).
    """

    joints: Tuple[Tuple[int, str], ...]
    wheels: Tuple[str, ...]
    base: Tuple[str, ...]
    bodies: Tuple[Tuple[int, str], ...]

    @property
    def names(self) -> Tuple[str, ...]:
        """Every actuator name: the joints' in ``q`` order, then the base's."""
        return tuple(n for _, n in self.joints) + self.base


def _actuator_map(robot: Robot, base_actuators: bool, wheels) -> ActuatorMap:
    links = robot.description.links
    joints = tuple((link.dof, f"{link.joint}_motor") for link in sorted(
        (l for l in links if l.dof is not None and l.actuated), key=lambda l: l.dof))
    wheel_dofs = set(robot.wheel_dofs if wheels is None else wheels)
    wheel_names = tuple(n for d, n in joints if d in wheel_dofs)
    massless = {i + 1 for i, l in enumerate(links) if l.mass == 0.0 and not np.any(np.asarray(l.inertia))}
    bodies = tuple((b, mjcf_body_name(name)) for b, name in enumerate(robot.body_names) if b not in massless)
    return ActuatorMap(joints, wheel_names, BASE_ACTUATORS if base_actuators else (), bodies)


def to_mjscene(robot: Robot, *, base_actuators: bool = True, geometry=(), wheels=None):
    """``robot`` as a Basilisk ``MJScene`` and its [`ActuatorMap`][spacearm.basilisk.ActuatorMap]:
    ``scene, actuators = to_mjscene(robot)``.

    The scene is ``MJScene(to_mjcf(robot, ...))``: one ``<motor>`` (gear 1) per actuated joint
    (arm joints and reaction wheels, named ``<joint>_motor``), with ``base_actuators`` six base
    motors ``base_fx .. base_tz`` (force and torque on the base CM along 𝒥's axes: the thrusters
    of spacearm's flying modes), ``geometry`` the shape roles exported (default none: Basilisk
    needs no geometry for the dynamics). ``wheels``: the reaction-wheel dofs (default: the
    model's, ``Robot.wheel_dofs``). The scene starts at MuJoCo's ``qpos0`` (the base at the
    origin, the joints at 0), at rest: write a state with
    [`state_to_scene`][spacearm.basilisk.state_to_scene] after ``InitializeSimulation`` (the
    scene's states exist only then). ``scene.highOrderAttitudeIntegration`` is set: Basilisk's
    RK4 then keeps its fourth order on the base attitude (the default is second order there).
    """
    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"to_mjscene needs a spacearm.Robot, got {type(robot).__name__}")
    mj = _bsk.mujoco()
    xml = to_mjcf(robot, geometry=geometry, actuators=True, base_actuators=bool(base_actuators), lent_mass=LENT_MASS)
    _check_body_origins(xml)
    scene = mj.MJScene(xml, [])
    # The quaternion of qpos integrated as a four-component rate at every stage: Basilisk's
    # default (MuJoCo's exponential map per stage) makes its RK4 second order in the attitude
    # (measured: tests/basilisk/test_scene.py); this keeps the integrator's fourth order.
    scene.highOrderAttitudeIntegration = True
    return scene, _actuator_map(robot, bool(base_actuators), wheels)


def _states(scene):
    try:
        manager = scene.dynManager
        return manager.getStateObject("mujocoQpos"), manager.getStateObject("mujocoQvel")
    except Exception as exc:  # SWIG raises plain errors for a state not registered yet
        raise ArgumentError("the scene has no state yet: call the simulation's InitializeSimulation() first "
                            f"({exc})") from None


def scene_qpos_qvel(scene) -> Tuple[np.ndarray, np.ndarray]:
    """The scene's MuJoCo ``qpos``, ``qvel`` (copies) from its Basilisk states."""
    qs, vs = _states(scene)
    return np.asarray(qs.getState(), dtype=float).ravel(), np.asarray(vs.getState(), dtype=float).ravel()


def state_from_scene(robot: Robot, scene) -> Tuple[np.ndarray, np.ndarray]:
    """The scene's state as spacearm's ``(x, u)`` (``docs/conventions.md``): the quaternion put
    scalar last, the base angular velocity rotated from base axes into 𝒥, the joints put back
    in spacearm's order."""
    qpos, qvel = scene_qpos_qvel(scene)
    if qpos.size != robot.nx or qvel.size != robot.nu:
        raise ArgumentError(f"the scene has {qpos.size} qpos and {qvel.size} qvel entries; '{robot.name}' needs "
                            f"{robot.nx} and {robot.nu}: is it the scene of this robot (to_mjscene)?")
    return from_mujoco_state(robot, qpos, qvel)


def state_to_scene(robot: Robot, scene, x, u) -> None:
    """Write spacearm's ``(x, u)`` into the scene's states (the inverse of
    [`state_from_scene`][spacearm.basilisk.state_from_scene]: the round trip is exact but for the
    rotation of ``ω0`` into base axes and back, a few ulps)."""
    qpos, qvel = to_mujoco_state(robot, x, u)
    qs, vs = _states(scene)
    if len(qs.getState()) != qpos.size or len(vs.getState()) != qvel.size:
        raise ArgumentError(f"the scene's state has {len(qs.getState())} qpos and {len(vs.getState())} qvel entries; "
                            f"'{robot.name}' has {qpos.size} and {qvel.size}: is it the scene of this robot (to_mjscene)?")
    qs.setState(qpos.reshape(-1, 1).tolist())
    vs.setState(qvel.reshape(-1, 1).tolist())

