"""Pinocchio: the equivalent ``pinocchio.Model`` of a spacearm model and the maps of states,
forces, accelerations, mass matrices, bias forces and ABA derivatives between the two layouts
(``T_pin = blkdiag(R0, R0, P_e)``: the docstring of [`spacearm.interop`][spacearm.interop]). Pinocchio
(``pip install pin``) is imported only inside the functions that need it."""

from __future__ import annotations

from typing import Tuple

import numpy as np

from .._util.arrays import vector
from .._util.optional import require
from ..rotations import skew
from ._common import ROOT_JOINT, _block_transform, _depth_first, _split_x, _square, _tree, engine_dof_order

__all__ = [
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
]


def _import_pinocchio():
    return require("pinocchio", "spacearm.interop's Pinocchio functions")


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

    Joints are added depth-first (see [`engine_dof_order`][spacearm.interop.engine_dof_order]), which Pinocchio's algorithms
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
    ``c = T_pin nle − H[:, :3] (ω0 × v0)`` with ``H`` from [`mass_matrix_from_pinocchio`][spacearm.interop.mass_matrix_from_pinocchio]."""
    h = mass_matrix_from_pinocchio(robot, x, M)
    t = pinocchio_transform(robot, x)
    return t @ vector(nle, "nle", robot.nu) - h @ _omega_cross_v(robot, u)


# ---------------------------------------------------------------------------------------------
# forward-dynamics derivatives (docs/derivatives.md)
# ---------------------------------------------------------------------------------------------
def _cross_columns(nu: int, w) -> np.ndarray:
    """The map ``δx ↦ [w_lin × δθ; w_ang × δθ; 0]`` (non-zero in columns 3:6 only)."""
    out = np.zeros((nu, nu))
    out[0:3, 3:6] = skew(w[0:3])
    out[3:6, 3:6] = skew(w[3:6])
    return out


def aba_derivatives_from_pinocchio(robot, x, u, f, ddq_dq, ddq_dv, minv, ddq):
    """Pinocchio's ``computeABADerivatives`` results → spacearm's
    ``(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f)`` ([`spacearm.Robot.forward_dynamics_derivatives`][spacearm.Robot.forward_dynamics_derivatives]).

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
    d_du[0:3, 0:3] += skew(u[3:6])
    d_du[0:3, 3:6] -= skew(u[0:3])
    return d_dx, d_du, tm
