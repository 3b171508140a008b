"""Interoperability with Pinocchio, MuJoCo, SPART and SpaceDyn: model export and convention converters.

spacearm, Pinocchio and MuJoCo describe the same free-flying multibody system with different
coordinates. This module builds the equivalent model in each engine and maps states, forces,
accelerations and mass matrices between the three layouts, so that a user (or a test) can
compute a quantity in one and compare it with the other.

Conventions (``docs/conventions.md``; every formula below was verified numerically by
``tests/interop/test_pinocchio.py``, ``tests/interop/test_mujoco.py`` and ``tests/interop/test_interop_spart.py``)::

    spacearm   x = [r0, quat0 (x, y, z, w), q]          u = [v0 (𝒥), ω0 (𝒥), q̇]
    Pinocchio  q = [r0, quat0 (x, y, z, w), P_eᵀ q]      v = [R0ᵀ v0, R0ᵀ ω0, P_eᵀ q̇]
    MuJoCo     qpos = [r0, quat0 (w, x, y, z), P_eᵀ q]   qvel = [v0, R0ᵀ ω0, P_eᵀ q̇]
    SPART      R0, r0, qm = q                          u0 = [R0ᵀ ω0, v0], um = q̇
    SpaceDyn   R0 = r0, A0 = R0, q                      v0, w0 = ω0, qd = q̇

SPART and SpaceDyn are MATLAB libraries: their "state" is a set of separate arrays, returned
here as the named tuples :class:`SpartState` and :class:`SpaceDynState`. Both put the base
frame at the base centre of mass and use a rotation matrix mapping base-frame vectors to the
inertial frame (SPART's ``R0``, SpaceDyn's ``A0``). SPART's base velocity ``u0`` puts the
angular velocity first, in the base frame, then the linear velocity of the base CM in the
inertial frame (its ``Velocities`` builds the base twist as ``t0 = blkdiag(R0, E) u0``);
SpaceDyn's ``v0`` and ``w0`` are both in the inertial frame, like spacearm's. Both number the
joints in the order of their robot description: a serial chain has spacearm's order, which these
converters keep (no permutation).

All three put the base frame origin at the base centre of mass (the exported models are built
that way), so the base "origin velocity" of each engine is the base CM velocity ``v0``.

``P_e`` is the N×N permutation from the engines' joint order to spacearm's. spacearm numbers
its degrees of freedom in link order, which is only *topological* (each link after its
parent); Pinocchio's recursive algorithms (their ``nvSubtree`` blocks) and MuJoCo's nested
body tree both need a *depth-first* order, so the exported models number the joints by a
depth-first traversal of the tree (children in link order). :func:`engine_dof_order` gives it:
``q_engine = q[order]``. For a serial chain ``order`` is the identity.

With the block-diagonal matrices

    T_pin = blkdiag(R0, R0, P_e)        (u = T_pin v)
    T_mj  = blkdiag(E,  R0, P_e)        (u = T_mj qvel)

power invariance (``fᵀ u = τ_engineᵀ v_engine``) and the kinetic energy ``½ uᵀ H u`` give

    H = T M Tᵀ,     f = T τ_engine,     τ_engine = Tᵀ f,

and differentiating ``u = T v`` gives the accelerations:

- Pinocchio's base linear velocity ``R0ᵀ v0`` is in the *moving* base frame, so
  ``d/dt(R0ᵀ v0) = R0ᵀ (v̇0 − ω0 × v0)``:  ``u̇ = T_pin a + [ω0 × v0; 0; 0]`` and
  ``c = T_pin nle − H[:, :3] (ω0 × v0)``.
- MuJoCo's base linear velocity is already in 𝒥 and ``d/dt(R0ᵀ ω0) = R0ᵀ ω̇0`` (``ω0 × ω0 =
  0``): ``u̇ = T_mj qacc`` and ``c = T_mj qfrc_bias`` with no extra term.

Quantities that do not depend on the base-velocity coordinates (the generalized inertia
``H*``, the Generalized Jacobian ``J*``, momentum, kinetic energy) compare directly once the
joint order is mapped.

Pinocchio (``pip install pin``) and MuJoCo (``pip install mujoco``) are optional: they are
imported only inside the functions that need them.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import List, NamedTuple, Optional, Tuple

import numpy as np

from ._util.arrays import vector
from .model.description import PointDescription
from .errors import ArgumentError, MissingDependencyError, NonFiniteError, QuaternionError, ShapeError
from .rotations import quat_from_matrix, quat_to_matrix

__all__ = [
    "engine_dof_order",
    # Pinocchio
    "to_pinocchio",
    "to_pinocchio_state",
    "from_pinocchio_state",
    "to_pinocchio_force",
    "from_pinocchio_force",
    "to_pinocchio_acceleration",
    "acceleration_from_pinocchio",
    "mass_matrix_from_pinocchio",
    "bias_from_pinocchio",
    "pinocchio_transform",
    "aba_derivatives_from_pinocchio",
    # MuJoCo
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
    # SPART and SpaceDyn (MATLAB)
    "SpartState",
    "to_spart_state",
    "from_spart_state",
    "SpaceDynState",
    "to_spacedyn_state",
    "from_spacedyn_state",
]

#: Name of the free-flyer / free joint of the base in the exported models.
ROOT_JOINT = "root_joint"


# ---------------------------------------------------------------------------------------------
# optional dependencies
# ---------------------------------------------------------------------------------------------
def _import_pinocchio():
    try:
        import pinocchio
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError(
            "spacearm.interop needs Pinocchio for this function: install it with `pip install pin`"
        ) from exc
    return pinocchio


def _import_mujoco():
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError(
            "spacearm.interop needs MuJoCo for this function: install it with `pip install mujoco`"
        ) from exc
    return mujoco


# ---------------------------------------------------------------------------------------------
# the model's tree, read from Robot.description
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Body:
    index: int  # spacearm body index (0 = base)
    name: str
    parent: int  # -1 for the base
    kind: str  # "base", "revolute", "prismatic" or "fixed"
    joint: Optional[str]
    origin: np.ndarray  # joint position in the parent frame (from the parent CM)
    rotation: np.ndarray  # 3×3, child frame in parent frame at q = 0
    axis: np.ndarray  # unit axis in the child frame
    com: np.ndarray  # child CM from the joint, in the child frame
    mass: float
    inertia: np.ndarray  # 3×3 about the CM, child axes
    dof: Optional[int]  # spacearm dof index, None for the base and fixed joints


def _tree(robot) -> Tuple[List[_Body], List[List[int]], Tuple[PointDescription, ...]]:
    """Bodies (index order), children lists (link order) and points of ``robot``."""
    d = robot.description
    bodies = [
        _Body(0, d.base.name, -1, "base", None, np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3),
              d.base.mass, np.array(d.base.inertia), None)
    ]
    # Writable copies: the engines' bindings may not accept read-only arrays.
    for k, link in enumerate(d.links):
        bodies.append(_Body(
            k + 1, link.name, link.parent_index, link.type, link.joint,
            np.array(link.origin), quat_to_matrix(link.rotation), np.array(link.axis), np.array(link.com),
            link.mass, np.array(link.inertia), link.dof,
        ))
    children: List[List[int]] = [[] for _ in bodies]
    for b in bodies[1:]:
        children[b.parent].append(b.index)
    return bodies, children, d.points


def _depth_first(children: List[List[int]]) -> List[int]:
    """Body indices in depth-first pre-order from the base (children in link order)."""
    order, stack = [], [0]
    while stack:
        b = stack.pop()
        order.append(b)
        stack.extend(reversed(children[b]))
    return order


def engine_dof_order(robot) -> np.ndarray:
    """spacearm dof index of each joint dof of the exported Pinocchio and MuJoCo models.

    Both engines number joints depth-first (see the module docstring), so
    ``q_engine = q[order]`` and ``q[order] = q_engine``; the permutation matrix ``P_e`` of the
    converters has ``P_e[order[k], k] = 1``. The identity for a serial chain.
    """
    bodies, children, _ = _tree(robot)
    return np.array([bodies[b].dof for b in _depth_first(children) if bodies[b].dof is not None], dtype=int)


# ---------------------------------------------------------------------------------------------
# argument helpers
# ---------------------------------------------------------------------------------------------
def _split_x(robot, x) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = vector(x, "x", robot.nx)
    return x[:3], x[3:7], x[7:]


def _base_rotation(robot, x) -> np.ndarray:
    return quat_to_matrix(_split_x(robot, x)[1])


def _block_transform(robot, x, linear_rotated: bool) -> np.ndarray:
    """``blkdiag(R0 or E, R0, P_e)`` at configuration ``x``."""
    n = robot.n_dof
    r0 = _base_rotation(robot, x)
    t = np.zeros((6 + n, 6 + n))
    t[:3, :3] = r0 if linear_rotated else np.eye(3)
    t[3:6, 3:6] = r0
    order = engine_dof_order(robot)
    t[6 + order, 6 + np.arange(n)] = 1.0
    return t


def _square(m, n: int, name: str) -> np.ndarray:
    m = np.asarray(m, dtype=float)
    if m.shape != (n, n):
        raise ShapeError(f"{name} must be {n}×{n} (6+N), got shape {m.shape}")
    return m


# ---------------------------------------------------------------------------------------------
# Pinocchio
# ---------------------------------------------------------------------------------------------
def to_pinocchio(robot):
    """The Pinocchio ``Model`` of ``robot``.

    - Root: a ``JointModelFreeFlyer`` named ``"root_joint"`` whose frame is the base CM frame
      (so Pinocchio's ``q[:7]`` equals spacearm's ``x[:7]``); gravity is set to zero (orbit).
    - Each revolute/prismatic link: a ``JointModelRevoluteUnaligned`` /
      ``JointModelPrismaticUnaligned`` about its (unit) axis, with the joint frame at the joint
      position and oriented as the link frame at ``q = 0``; the link inertia sits at the CM
      offset ``com`` in that joint frame (Pinocchio's moved joint frame is the spacearm link
      frame translated by ``-com``, for both joint types).
    - Fixed links are merged: their inertia is appended to the nearest moving ancestor joint
      (``appendBodyToJoint``) and their frame is kept as a ``BODY`` frame.
    - Frames: a ``BODY`` frame per spacearm body (same name, origin at its CM, link axes) and
      an ``OP_FRAME`` per named point.

    Joints are added depth-first (see :func:`engine_dof_order`), which Pinocchio's algorithms
    require; the joint names are spacearm's joint names.
    """
    pin = _import_pinocchio()
    bodies, children, points = _tree(robot)
    model = pin.Model()
    model.name = robot.name
    model.gravity = pin.Motion.Zero()

    root = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), ROOT_JOINT)
    base = bodies[0]
    model.appendBodyToJoint(root, pin.Inertia(base.mass, np.zeros(3), base.inertia), pin.SE3.Identity())
    root_frame = model.addJointFrame(root, 0)

    # support[b]: Pinocchio joint carrying body b; placement[b]: pose of b's CM frame in it.
    support = {0: root}
    placement = {0: pin.SE3.Identity()}
    frame_of = {0: model.addFrame(pin.Frame(base.name, root, root_frame, pin.SE3.Identity(), pin.FrameType.BODY), False)}

    for b in _depth_first(children)[1:]:
        body = bodies[b]
        # joint frame of b expressed in the parent's support-joint frame
        joint_in_parent = placement[body.parent] * pin.SE3(body.rotation, body.origin)
        com_offset = pin.SE3(np.eye(3), body.com)
        if body.kind == "fixed":
            support[b] = support[body.parent]
            placement[b] = joint_in_parent * com_offset
            jframe = model.addFrame(pin.Frame(body.joint, support[b], frame_of[body.parent], joint_in_parent, pin.FrameType.FIXED_JOINT), False)
        else:
            jmodel = (pin.JointModelRevoluteUnaligned(body.axis) if body.kind == "revolute"
                      else pin.JointModelPrismaticUnaligned(body.axis))
            support[b] = model.addJoint(support[body.parent], jmodel, joint_in_parent, body.joint)
            placement[b] = com_offset
            jframe = model.addJointFrame(support[b], frame_of[body.parent])
        model.appendBodyToJoint(support[b], pin.Inertia(body.mass, np.zeros(3), body.inertia), placement[b])
        frame_of[b] = model.addFrame(pin.Frame(body.name, support[b], jframe, placement[b], pin.FrameType.BODY), False)

    for p in points:
        b = robot.body_index(p.body)
        pose = placement[b] * pin.SE3(np.eye(3), np.array(p.offset))
        model.addFrame(pin.Frame(p.name, support[b], frame_of[b], pose, pin.FrameType.OP_FRAME), False)
    return model


def pinocchio_transform(robot, x) -> np.ndarray:
    """``T_pin = blkdiag(R0, R0, P_e)`` at ``x``: ``u = T_pin v``, ``v = T_pinᵀ u``."""
    return _block_transform(robot, x, linear_rotated=True)


def to_pinocchio_state(robot, x, u) -> Tuple[np.ndarray, np.ndarray]:
    """spacearm ``(x, u)`` → Pinocchio ``(q, v)``.

    ``q = [r0, quat0 (xyzw), q[order]]`` and ``v = T_pinᵀ u = [R0ᵀ v0, R0ᵀ ω0, q̇[order]]``.
    """
    r0, quat, q = _split_x(robot, x)
    u = vector(u, "u", robot.nu)
    order = engine_dof_order(robot)
    return np.concatenate([r0, quat, q[order]]), pinocchio_transform(robot, x).T @ u


def from_pinocchio_state(robot, q, v) -> Tuple[np.ndarray, np.ndarray]:
    """Pinocchio ``(q, v)`` → spacearm ``(x, u)``: ``x = [q[:7], P_e q[7:]]``, ``u = T_pin v``."""
    q = vector(q, "q", robot.nx)
    v = vector(v, "v", robot.nu)
    order = engine_dof_order(robot)
    joints = np.empty(robot.n_dof)
    joints[order] = q[7:]
    x = np.concatenate([q[:7], joints])
    return x, pinocchio_transform(robot, x) @ v


def to_pinocchio_force(robot, x, f) -> np.ndarray:
    """spacearm generalized force ``f = [F0, N0, τ]`` → Pinocchio ``τ_pin = T_pinᵀ f``
    (base force and torque in the base frame, at the base CM)."""
    return pinocchio_transform(robot, x).T @ vector(f, "f", robot.nu)


def from_pinocchio_force(robot, x, tau) -> np.ndarray:
    """Pinocchio generalized force ``τ_pin`` → spacearm ``f = T_pin τ_pin``."""
    return pinocchio_transform(robot, x) @ vector(tau, "tau", robot.nu)


def _omega_cross_v(robot, u) -> np.ndarray:
    u = vector(u, "u", robot.nu)
    s = np.zeros(robot.nu)
    s[:3] = np.cross(u[3:6], u[:3])
    return s


def acceleration_from_pinocchio(robot, x, u, a) -> np.ndarray:
    """Pinocchio acceleration ``a = v̇`` → spacearm ``u̇ = T_pin a + [ω0 × v0; 0; 0]``
    (Pinocchio's base linear velocity lives in the rotating base frame)."""
    return pinocchio_transform(robot, x) @ vector(a, "a", robot.nu) + _omega_cross_v(robot, u)


def to_pinocchio_acceleration(robot, x, u, du) -> np.ndarray:
    """spacearm ``u̇`` → Pinocchio ``a = T_pinᵀ (u̇ − [ω0 × v0; 0; 0])``."""
    return pinocchio_transform(robot, x).T @ (vector(du, "du", robot.nu) - _omega_cross_v(robot, u))


def mass_matrix_from_pinocchio(robot, x, M) -> np.ndarray:
    """Pinocchio mass matrix → spacearm ``H = T_pin M T_pinᵀ``.

    ``M`` may be the upper triangle that ``pinocchio.crba`` fills: it is symmetrized from its
    upper triangle first (a full symmetric ``M`` is unaffected).
    """
    m = _square(M, robot.nu, "M")
    m = np.triu(m) + np.triu(m, 1).T
    t = pinocchio_transform(robot, x)
    return t @ m @ t.T


def bias_from_pinocchio(robot, x, u, nle, M) -> np.ndarray:
    """Pinocchio ``nle`` (with zero gravity: the velocity-product terms) → spacearm
    ``c = T_pin nle − H[:, :3] (ω0 × v0)`` with ``H`` from :func:`mass_matrix_from_pinocchio`."""
    h = mass_matrix_from_pinocchio(robot, x, M)
    t = pinocchio_transform(robot, x)
    return t @ vector(nle, "nle", robot.nu) - h @ _omega_cross_v(robot, u)


# ---------------------------------------------------------------------------------------------
# MuJoCo
# ---------------------------------------------------------------------------------------------
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
    - ``<option gravity="0 0 0">``, contacts disabled (and there are no geoms), joint damping,
      stiffness, armature and friction loss explicitly zero, no limits, RK4 (the integrator
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
                              damping="0", stiffness="0", armature="0", frictionloss="0")
        _inertial(el, body.mass, body.inertia)
        for name, offset in points_on.get(b, []):
            ET.SubElement(el, "site", name=name, pos=_fmt(offset))
        for c in children[b]:
            emit(el, c)

    emit(world, 0)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")


def to_mujoco(robot):
    """The compiled ``mujoco.MjModel`` of :func:`to_mjcf`."""
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


# ---------------------------------------------------------------------------------------------
# Pinocchio: forward-dynamics derivatives (docs/derivatives.md)
# ---------------------------------------------------------------------------------------------
def _skew(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _cross_columns(nu: int, w) -> np.ndarray:
    """The map ``δx ↦ [w_lin × δθ; w_ang × δθ; 0]`` (non-zero in columns 3:6 only)."""
    out = np.zeros((nu, nu))
    out[0:3, 3:6] = _skew(w[0:3])
    out[3:6, 3:6] = _skew(w[3:6])
    return out


def aba_derivatives_from_pinocchio(robot, x, u, f, ddq_dq, ddq_dv, minv, ddq):
    """Pinocchio's ``computeABADerivatives`` results → spacearm's
    ``(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f)`` (:meth:`spacearm.Robot.forward_dynamics_derivatives`).

    Pinocchio computes ``a = ABA(q, v, τ_p)`` with ``v = Tᵀ u``, ``τ_p = Tᵀ f`` and spacearm's
    ``u̇ = T a + [ω0 × v0; 0; 0]``, ``T = blkdiag(R0, R0, P_e)``. Its configuration tangent is
    the local increment ``δ_p = Tᵀ δx`` of spacearm's ``δx = [δr0, δθ, δq]`` (``R0 ← exp(δθ̃) R0``).
    Perturbing the attitude changes the maps: ``δ(Tᵀ w) = Tᵀ C(w) δx`` with
    ``C(w) δx = [w_lin × δθ; w_ang × δθ; 0]``, and ``δT a = −C(T a) δx``. The chain rule gives

    - ``∂u̇/∂x = T (A_q + A_v C(u) + M⁻¹ C(f)) Tᵀ``-wise: ``T A_q Tᵀ + T A_v Tᵀ C(u) + T M⁻¹ Tᵀ C(f) − C(T a)``,
    - ``∂u̇/∂u = T A_v Tᵀ + ∂(ω0 × v0)/∂u`` (``ω̃0`` in the ``v0`` columns, ``−ṽ0`` in the ``ω0`` ones),
    - ``∂u̇/∂f = T M⁻¹ Tᵀ``,

    with ``A_q = ddq_dq``, ``A_v = ddq_dv``, ``M⁻¹ = minv`` (symmetrized from its upper triangle,
    which is all Pinocchio fills) and ``a = ddq`` (Pinocchio's ``data.ddq``).
    """
    nu = robot.nu
    u = vector(u, "u", nu)
    f = vector(f, "f", nu)
    t = pinocchio_transform(robot, x)
    a_q = _square(ddq_dq, nu, "ddq_dq")
    a_v = _square(ddq_dv, nu, "ddq_dv")
    m = _square(minv, nu, "minv")
    m = np.triu(m) + np.triu(m, 1).T
    ta = t @ vector(ddq, "ddq", nu)
    tm = t @ m @ t.T
    tav = t @ a_v @ t.T
    d_dx = t @ a_q @ t.T + tav @ _cross_columns(nu, u) + tm @ _cross_columns(nu, f) - _cross_columns(nu, ta)
    d_du = tav.copy()
    d_du[0:3, 0:3] += _skew(u[3:6])
    d_du[0:3, 3:6] -= _skew(u[0:3])
    return d_dx, d_du, tm


# ---------------------------------------------------------------------------------------------
# SPART and SpaceDyn (MATLAB libraries; states only)
# ---------------------------------------------------------------------------------------------
#: How far from orthonormal (max |RᵀR − E|) a rotation matrix given to a converter may be.
ROTATION_TOLERANCE = 1e-6


class SpartState(NamedTuple):
    """A spacearm state in SPART's variables (``R0, r0, qm, u0, um`` of SPART's kinematics)."""

    R0: np.ndarray  #: 3×3 rotation, base frame → inertial frame
    r0: np.ndarray  #: base CM position in the inertial frame
    qm: np.ndarray  #: joint positions (N)
    u0: np.ndarray  #: ``[ω0 in the base frame; ṙ0 in the inertial frame]`` (angular first)
    um: np.ndarray  #: joint velocities (N)


class SpaceDynState(NamedTuple):
    """A spacearm state in SpaceDyn's variables (``R0, A0, v0, w0, q, qd``).

    Beware the names: SpaceDyn's ``R0`` is the base CM *position* and ``A0`` the base rotation.
    """

    R0: np.ndarray  #: base CM position in the inertial frame
    A0: np.ndarray  #: 3×3 rotation, base frame → inertial frame
    v0: np.ndarray  #: base CM velocity, inertial frame
    w0: np.ndarray  #: base angular velocity, inertial frame
    q: np.ndarray  #: joint positions (N)
    qd: np.ndarray  #: joint velocities (N)


def _checked_state(robot, x, u) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(r0, R0, q, u)`` of a spacearm state, checked as :class:`~spacearm.Robot` checks it."""
    x = vector(x, "x", robot.nx)
    u = vector(u, "u", robot.nu)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(u))):
        raise NonFiniteError("x and u must be finite")
    norm = np.linalg.norm(x[3:7])
    if abs(norm - 1.0) > 1e-6:
        raise QuaternionError(f"the base quaternion x[3:7] must have unit norm (within 1e-6), got norm {norm:.9g}")
    return x[:3].copy(), quat_to_matrix(x[3:7]), x[7:].copy(), u


def _rotation(value, name: str) -> np.ndarray:
    try:
        r = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 3×3 rotation matrix of numbers, got {value!r}") from exc
    if r.shape != (3, 3):
        raise ShapeError(f"{name} must be a 3×3 rotation matrix, got shape {r.shape}")
    if not np.all(np.isfinite(r)):
        raise NonFiniteError(f"{name} must be finite")
    err = np.max(np.abs(r.T @ r - np.eye(3)))
    if err > ROTATION_TOLERANCE or np.linalg.det(r) <= 0:
        raise ArgumentError(f"{name} must be a proper rotation matrix (orthonormal within {ROTATION_TOLERANCE:g}, "
                            f"determinant +1); got max|{name}ᵀ{name} − E| = {err:.3g}, det = {np.linalg.det(r):.6g}")
    return r


def _finite(value, name: str, length: int) -> np.ndarray:
    v = vector(value, name, length)
    if not np.all(np.isfinite(v)):
        raise NonFiniteError(f"{name} must be finite, got {v}")
    return v


def to_spart_state(robot, x, u) -> SpartState:
    """spacearm ``(x, u)`` → SPART's ``(R0, r0, qm, u0, um)``.

    ``R0`` is the base rotation of the quaternion ``x[3:7]``; ``u0 = [R0ᵀ ω0; v0]`` (SPART's
    base angular velocity is in the base frame and comes first; its linear velocity is the
    base CM velocity in the inertial frame).
    """
    r0, rot, q, u = _checked_state(robot, x, u)
    return SpartState(rot, r0, q, np.concatenate([rot.T @ u[3:6], u[0:3]]), u[6:].copy())


def from_spart_state(robot, R0, r0, qm, u0, um) -> Tuple[np.ndarray, np.ndarray]:
    """SPART's ``(R0, r0, qm, u0, um)`` → spacearm ``(x, u)``: ``x = [r0, quat(R0), qm]``,
    ``u = [u0[3:6], R0 u0[0:3], um]``. ``R0`` must be a rotation matrix (base → inertial)."""
    n = robot.n_dof
    rot = _rotation(R0, "R0")
    u0 = _finite(u0, "u0", 6)
    x = np.concatenate([_finite(r0, "r0", 3), quat_from_matrix(rot), _finite(qm, "qm", n)])
    return x, np.concatenate([u0[3:6], rot @ u0[0:3], _finite(um, "um", n)])


def to_spacedyn_state(robot, x, u) -> SpaceDynState:
    """spacearm ``(x, u)`` → SpaceDyn's ``(R0, A0, v0, w0, q, qd)``: the same vectors (SpaceDyn's
    ``v0``, ``w0`` are in the inertial frame), with the base attitude as the rotation matrix
    ``A0`` (base → inertial) instead of a quaternion."""
    r0, rot, q, u = _checked_state(robot, x, u)
    return SpaceDynState(r0, rot, u[0:3].copy(), u[3:6].copy(), q, u[6:].copy())


def from_spacedyn_state(robot, R0, A0, v0, w0, q, qd) -> Tuple[np.ndarray, np.ndarray]:
    """SpaceDyn's ``(R0, A0, v0, w0, q, qd)`` → spacearm ``(x, u)``. ``R0`` is SpaceDyn's base
    CM position, ``A0`` its base rotation matrix (base → inertial)."""
    n = robot.n_dof
    rot = _rotation(A0, "A0")
    x = np.concatenate([_finite(R0, "R0", 3), quat_from_matrix(rot), _finite(q, "q", n)])
    u = np.concatenate([_finite(v0, "v0", 3), _finite(w0, "w0", 3), _finite(qd, "qd", n)])
    return x, u
