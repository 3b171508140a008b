"""MuJoCo: the MJCF text and compiled ``mujoco.MjModel`` of a spacearm model and the maps of
states, forces, accelerations, mass matrices and bias forces between the two layouts
(``T_mj = blkdiag(E, R0, P_e)``: the docstring of [`spacearm.interop`][spacearm.interop]). MuJoCo
(``pip install mujoco``) is imported only inside [`to_mujoco`][spacearm.interop.to_mujoco]."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Tuple

import numpy as np

from .._util.arrays import vector
from ..errors import MissingDependencyError
from ..rotations import quat_from_matrix
from ._common import ROOT_JOINT, _block_transform, _split_x, _square, _tree, engine_dof_order

__all__ = [
    "to_mjcf",
    "to_mujoco",
    "to_mujoco_state",
    "from_mujoco_state",
    "to_mujoco_force",
    "from_mujoco_force",
    "to_mujoco_acceleration",
    "acceleration_from_mujoco",
    "mass_matrix_from_mujoco",
    "bias_from_mujoco",
    "mujoco_transform",
]


def _import_mujoco():
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError(
            "spacearm.interop needs MuJoCo for this function: install it with `pip install mujoco`"
        ) from exc
    return mujoco


def _fmt(values) -> str:
    # repr-precision floats: the exported model must reproduce spacearm's to the last bit
    return " ".join(repr(float(v)) for v in np.ravel(values))


def _quat_wxyz(r: np.ndarray) -> np.ndarray:
    x, y, z, w = quat_from_matrix(r)
    return np.array([w, x, y, z])


def _inertial(parent: ET.Element, mass: float, inertia: np.ndarray) -> None:
    i = inertia
    ET.SubElement(parent, "inertial", pos="0 0 0", mass=repr(float(mass)),
                  fullinertia=_fmt([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]))


def to_mjcf(robot) -> str:
    """The MJCF (MuJoCo XML) text of ``robot``.

    - Every MuJoCo body frame IS the spacearm body frame (origin at the CM, link axes), so the
      inertial sits at ``pos="0 0 0"`` with the full inertia tensor (``fullinertia``) and named
      points become ``<site>`` elements at their offsets.
    - Base: a ``<freejoint>`` (not re-aligned to the principal axes: ``align="false"``), so
      ``qpos[:3]`` is the base CM and ``qvel[3:6]`` the angular velocity in base axes.
    - Link: body ``pos = origin + R_rot com`` and ``quat = rotation`` (wxyz) in the parent body
      frame; a hinge/slide joint at ``pos = -com`` (the joint position, in the link frame)
      about ``axis``. A fixed link is a body without a joint (welded; ``fusestatic`` off keeps
      it as its own body).
    - A joint's spring–damper (docs/flexibility.md) as the joint's ``stiffness``, ``springref``
      (the rest coordinate) and ``damping``: MuJoCo's ``qfrc_passive`` is then spacearm's
      passive force ``-k (q - rest) - c q̇``. There are no actuators (a model's forces are
      applied as ``qfrc_applied``), so a passive joint needs no marking.
    - ``<option gravity="0 0 0">``, contacts disabled (and there are no geoms), armature and
      friction loss explicitly zero (damping and stiffness zero unless the joint has them), no limits, RK4 (the integrator
      changes no term of the continuous-time dynamics), and the ``energy`` flag on so that
      ``MjData.energy`` holds the kinetic energy.
    """
    bodies, children, points = _tree(robot)
    root = ET.Element("mujoco", model=robot.name)
    ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true",
                  alignfree="false", fusestatic="false", boundmass="0", boundinertia="0", balanceinertia="false")
    option = ET.SubElement(root, "option", gravity="0 0 0", integrator="RK4", density="0", viscosity="0")
    ET.SubElement(option, "flag", contact="disable", energy="enable")
    world = ET.SubElement(root, "worldbody")

    points_on = {}
    for p in points:
        points_on.setdefault(robot.body_index(p.body), []).append((p.name, p.offset))

    def emit(parent_el: ET.Element, b: int) -> None:
        body = bodies[b]
        if b == 0:
            el = ET.SubElement(parent_el, "body", name=body.name, pos="0 0 0")
            ET.SubElement(el, "freejoint", name=ROOT_JOINT, align="false")
        else:
            pos = body.origin + body.rotation @ body.com
            el = ET.SubElement(parent_el, "body", name=body.name, pos=_fmt(pos), quat=_fmt(_quat_wxyz(body.rotation)))
            if body.kind != "fixed":
                ET.SubElement(el, "joint", name=body.joint, type="hinge" if body.kind == "revolute" else "slide",
                              pos=_fmt(-body.com), axis=_fmt(body.axis), limited="false",
                              damping=repr(float(body.damping)), stiffness=repr(float(body.stiffness)),
                              springref=repr(float(body.rest)), armature="0", frictionloss="0")
        _inertial(el, body.mass, body.inertia)
        for name, offset in points_on.get(b, []):
            ET.SubElement(el, "site", name=name, pos=_fmt(offset))
        for c in children[b]:
            emit(el, c)

    emit(world, 0)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")


def to_mujoco(robot):
    """The compiled ``mujoco.MjModel`` of [`to_mjcf`][spacearm.interop.to_mjcf]."""
    mujoco = _import_mujoco()
    return mujoco.MjModel.from_xml_string(to_mjcf(robot))


def mujoco_transform(robot, x) -> np.ndarray:
    """``T_mj = blkdiag(E, R0, P_e)`` at ``x``: ``u = T_mj qvel``, ``qvel = T_mjᵀ u``."""
    return _block_transform(robot, x, linear_rotated=False)


def to_mujoco_state(robot, x, u) -> Tuple[np.ndarray, np.ndarray]:
    """spacearm ``(x, u)`` → MuJoCo ``(qpos, qvel)``.

    ``qpos = [r0, w, x, y, z, q[order]]`` (quaternion scalar first) and
    ``qvel = T_mjᵀ u = [v0, R0ᵀ ω0, q̇[order]]``.
    """
    r0, quat, q = _split_x(robot, x)
    u = vector(u, "u", robot.nu)
    order = engine_dof_order(robot)
    qpos = np.concatenate([r0, [quat[3]], quat[:3], q[order]])
    return qpos, mujoco_transform(robot, x).T @ u


def from_mujoco_state(robot, qpos, qvel) -> Tuple[np.ndarray, np.ndarray]:
    """MuJoCo ``(qpos, qvel)`` → spacearm ``(x, u)``: the quaternion goes scalar last and
    ``u = T_mj qvel``."""
    qpos = vector(qpos, "qpos", robot.nx)
    qvel = vector(qvel, "qvel", robot.nu)
    order = engine_dof_order(robot)
    joints = np.empty(robot.n_dof)
    joints[order] = qpos[7:]
    x = np.concatenate([qpos[:3], qpos[4:7], qpos[3:4], joints])
    return x, mujoco_transform(robot, x) @ qvel


def to_mujoco_force(robot, x, f) -> np.ndarray:
    """spacearm ``f`` → MuJoCo generalized force (e.g. ``qfrc_applied``) ``T_mjᵀ f =
    [F0, R0ᵀ N0, τ[order]]``."""
    return mujoco_transform(robot, x).T @ vector(f, "f", robot.nu)


def from_mujoco_force(robot, x, qfrc) -> np.ndarray:
    """MuJoCo generalized force → spacearm ``f = T_mj qfrc``."""
    return mujoco_transform(robot, x) @ vector(qfrc, "qfrc", robot.nu)


def acceleration_from_mujoco(robot, x, qacc) -> np.ndarray:
    """MuJoCo ``qacc`` → spacearm ``u̇ = T_mj qacc`` (no velocity-product term: the free
    joint's linear velocity is in 𝒥 and ``d/dt(R0ᵀ ω0) = R0ᵀ ω̇0``)."""
    return mujoco_transform(robot, x) @ vector(qacc, "qacc", robot.nu)


def to_mujoco_acceleration(robot, x, du) -> np.ndarray:
    """spacearm ``u̇`` → MuJoCo ``qacc = T_mjᵀ u̇``."""
    return mujoco_transform(robot, x).T @ vector(du, "du", robot.nu)


def mass_matrix_from_mujoco(robot, x, M) -> np.ndarray:
    """MuJoCo dense mass matrix (``mujoco.mj_fullM``) → spacearm ``H = T_mj M T_mjᵀ``."""
    t = mujoco_transform(robot, x)
    return t @ _square(M, robot.nu, "M") @ t.T


def bias_from_mujoco(robot, x, qfrc_bias) -> np.ndarray:
    """MuJoCo ``qfrc_bias`` (zero gravity) → spacearm ``c = T_mj qfrc_bias``."""
    return mujoco_transform(robot, x) @ vector(qfrc_bias, "qfrc_bias", robot.nu)
