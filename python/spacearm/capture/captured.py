"""The captured system: after a rigid grasp the target is a payload of the gripper link
(:func:`attach_target`); before it, in a soft capture, a spring–damper at the grasp couples two
free bodies (:func:`soft_capture`).

Rigid: the target becomes a link on a fixed joint of the gripper body
(``RobotBuilder.attach_payload``) at the relative pose it has at that instant. The joint space is
unchanged and the base is the same body, so the state maps identically: ``x`` and ``u`` of the
robot are the combined model's, and since the grasp impulse left no relative twist, the payload
moves exactly as the target did — momentum and energy carry over to rounding.

Soft: the robot and the target stay free; a wrist impedance acts at the robot's grasp point
``X``: the force ``f = K (p − X) + D (ṗ − Ẋ)`` (``p`` the target's grasp point) and the couple
``n = K_r θ + D_r (ω_t − ω_g)`` (``θ`` the rotation vector taking the gripper's frame, carried
with the relative attitude it had at contact, to the target's) act on the robot at ``X`` and
their opposites on the target's material point at ``X``: an internal wrench, so robot + target
momentum is conserved. ``simulate`` takes no external wrench, so this phase is integrated here:
classical fixed-step RK4 on both bodies (:mod:`spacearm.capture._rk4`), each through its own
``forward_dynamics(wrenches=...)``.
"""

from __future__ import annotations

from typing import Callable, NamedTuple, Optional

import numpy as np

from .._util.arrays import number, vector
from ..errors import ArgumentError, SimulationError
from ..model.robot import ExternalWrench
from ..rotations import quat_from_matrix, rotation_vector
from ._rk4 import rk4_step
from .impact import _check_target, _robot_point, inverse_inertia

__all__ = ["CapturedSystem", "attach_target", "SoftCaptureRun", "soft_capture", "relative_twist"]


def tb_rotation(target, state, body: int) -> np.ndarray:
    """Rotation (body axes -> 𝒥) of a body of the target's model."""
    return target.body.forward_kinematics(target.xu(state)[0]).body_to_world[body]


class CapturedSystem(NamedTuple):
    """A rigid capture: the combined model and its state."""

    robot: object  #: the combined spacearm.Robot (the target is the link ``payload``)
    x: np.ndarray  #: configuration (the robot's, unchanged)
    u: np.ndarray  #: generalized velocity (the robot's, unchanged)
    payload: str  #: the target's link name in the combined model
    gripper: str  #: the body it is attached to


def relative_twist(robot, x, u, target, target_state, point=None, grasp_offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Twist of the robot's grasp point minus the twist of the target's material point there (6, in 𝒥)."""
    xv, uv = vector(x, "x", robot.nx), vector(u, "u", robot.nu)
    s = target.check_state(target_state)
    body, offset = _robot_point(robot, xv, point, grasp_offset)
    X = robot.point_position(xv, (body, offset))
    j0, jm = robot.point_jacobian(xv, (body, offset))
    tx, tu = target.xu(s)
    t_body, t_offset = target.material_point(s, X)
    t0, tm = target.body.point_jacobian(tx, (t_body, t_offset))
    return j0 @ uv[:6] + jm @ uv[6:] - (t0 @ tu[:6] + tm @ tu[6:])


def attach_target(robot, x, u, target, target_state, *, point=None, grasp_offset=(0.0, 0.0, 0.0),
                  name: Optional[str] = None, tolerance: float = 1e-8) -> CapturedSystem:
    """The combined model after a rigid grasp, and its state.

    ``(x, u)`` and ``target_state`` are the states just after :func:`grasp_impulse` (the relative
    twist at the grasp point must be zero to ``tolerance`` times the motion's scale; otherwise
    the target cannot ride on the gripper without an impulse, and an ``ArgumentError`` says so).
    The target is attached to the grasp point's body at its current relative pose, as a
    payload named ``name`` (default: the target's name).
    """
    _check_target(target)
    if not target.is_rigid:
        raise ArgumentError(f"target '{target.name}' is a jointed model: only a rigid target can be attached as a payload")
    xv, uv = vector(x, "x", robot.nx), vector(u, "u", robot.nu)
    s = target.check_state(target_state)
    body, _ = _robot_point(robot, xv, point, grasp_offset)
    rel = relative_twist(robot, xv, uv, target, s, point, grasp_offset)
    scale = max(np.linalg.norm(s[7:]), np.linalg.norm(uv), 1e-300)
    if np.linalg.norm(rel) > tolerance * scale:
        raise ArgumentError(
            f"the target is not locked to the gripper (relative twist {np.linalg.norm(rel):.3g}); apply grasp_impulse(kind='rigid') first")
    kin = robot.forward_kinematics(xv)
    Rb, rb = kin.body_to_world[body], kin.com_in_world[body]
    Rt = target.rotation(s)
    gripper = robot.body_names[body]
    payload = target.name if name is None else str(name)
    if payload in robot.body_names:
        raise ArgumentError(f"the robot already has a body named '{payload}'; pass name= for the payload")
    combined = (robot.to_builder(name=f"{robot.name}+{payload}")
                .attach_payload(payload, body=gripper, mass=target.mass, inertia=target.inertia,
                                origin=Rb.T @ (s[:3] - rb), rotation=quat_from_matrix(Rb.T @ Rt))
                .build())
    return CapturedSystem(combined, xv.copy(), uv.copy(), payload, gripper)


class SoftCaptureRun(NamedTuple):
    """The soft-capture phase, sample by sample (``t`` from 0)."""

    t: np.ndarray  #: (T,)
    x: np.ndarray  #: (T, 7+N) robot configurations
    u: np.ndarray  #: (T, 6+N) robot velocities
    target: np.ndarray  #: (T, 13) target states (``[x, u]`` of a jointed target)
    wrench: np.ndarray  #: (T, 6) the impedance's wrench on the robot at X ([force; couple], 𝒥)
    tau: np.ndarray  #: (T, N) joint torques applied
    gains: dict  #: the impedance used (stiffness, damping, rotational_stiffness, rotational_damping)


def soft_capture(robot, x, u, target, target_state, duration: float, *, frequency: float = 3.0, damping_ratio: float = 0.7,
                 stiffness: Optional[float] = None, damping: Optional[float] = None,
                 rotational_stiffness: Optional[float] = None, rotational_damping: Optional[float] = None, point=None,
                 grasp: Optional[str] = None, dt: float = 1e-3,
                 torque: Optional[Callable[[float, np.ndarray, np.ndarray], np.ndarray]] = None) -> SoftCaptureRun:
    """Integrate the soft-capture phase for ``duration`` s (module docstring for the law).

    ``stiffness`` (N/m), ``damping`` (N·s/m), ``rotational_stiffness`` (N·m/rad),
    ``rotational_damping`` (N·m·s/rad); each one not given is set from ``frequency`` ω (rad/s)
    and ``damping_ratio`` ζ on the lightest direction of the grasp, ``K = ω² / g``, ``D = 2ζω / g``
    with ``g`` the largest eigenvalue of the translational (rotational) block of
    ``G_robot + G_target`` (:func:`~spacearm.capture.inverse_inertia`), so that no direction
    rings faster than ω and a fixed step ``dt`` well below 1/ω is stable. The rest pose is the
    relative pose at the start with the two grasp points together. ``torque(t, x, u)`` gives the joint torques (default zero).
    Classical RK4 with fixed step ``dt``.
    """
    _check_target(target)
    xv, uv = vector(x, "x", robot.nx), vector(u, "u", robot.nu)
    s = target.check_state(target_state)
    duration = number(duration, "duration")
    dt = number(dt, "dt")
    if not duration > 0 or not dt > 0:
        raise ArgumentError(f"duration and dt must be > 0, got {duration}, {dt}")
    body, offset = _robot_point(robot, xv, point, (0.0, 0.0, 0.0))
    tbody, tpoint = target.point(grasp)
    omega, zeta = number(frequency, "frequency"), number(damping_ratio, "damping_ratio")
    if not omega > 0 or zeta < 0:
        raise ArgumentError(f"frequency must be > 0 and damping_ratio >= 0, got {omega}, {zeta}")
    g = inverse_inertia(robot, xv, (body, offset)) + inverse_inertia(target.body, target.xu(s)[0], (tbody, tpoint))
    g_lin, g_rot = np.linalg.eigvalsh(g[:3, :3]).max(), np.linalg.eigvalsh(g[3:, 3:]).max()
    defaults = (omega**2 / g_lin, 2 * zeta * omega / g_lin, omega**2 / g_rot, 2 * zeta * omega / g_rot)
    given = (stiffness, damping, rotational_stiffness, rotational_damping)
    names = ("stiffness", "damping", "rotational_stiffness", "rotational_damping")
    gains = [dflt if v is None else number(v, name) for v, dflt, name in zip(given, defaults, names)]
    if min(gains) < 0:
        raise ArgumentError(f"impedance gains must be >= 0, got {dict(zip(names, gains))}")
    k, d, kr, dr = gains
    # gripper -> grasped body of the target, at contact
    rel0 = robot.forward_kinematics(xv).body_to_world[body].T @ tb_rotation(target, s, tbody)
    n = robot.n_dof
    tb = target.body

    def wrench(xr, ur, xt, ut):
        X = robot.point_position(xr, (body, offset))
        j0, jm = robot.point_jacobian(xr, (body, offset))
        tw_r = j0 @ ur[:6] + jm @ ur[6:]
        p = tb.point_position(xt, (tbody, tpoint))
        kin_t = tb.forward_kinematics(xt)
        Rt, ct = kin_t.body_to_world[tbody], kin_t.com_in_world[tbody]
        tp, tm = tb.point_jacobian(xt, (tbody, tpoint))
        tw_p = tp @ ut[:6] + tm @ ut[6:]
        Rg = robot.forward_kinematics(xr).body_to_world[body]
        theta = rotation_vector(Rt @ (Rg @ rel0).T)
        f = k * (p - X) + d * (tw_p[:3] - tw_r[:3])
        c = kr * theta + dr * (tw_p[3:] - tw_r[3:])
        return X, f, c, Rt, ct

    def rates(t, xr, ur, xt, ut):
        X, f, c, Rt, ct = wrench(xr, ur, xt, ut)
        tau = np.zeros(n) if torque is None else vector(torque(t, xr, ur), "soft-capture torque", n)
        dur = robot.forward_dynamics(xr, ur, tau=tau, wrenches=[ExternalWrench(body, f, c, offset)])
        dut = tb.forward_dynamics(xt, ut, wrenches=[ExternalWrench(tbody, -f, -c, Rt.T @ (X - ct))])
        return dur, dut, np.r_[f, c], tau

    steps = max(1, int(np.ceil(duration / dt)))
    h = duration / steps
    xr, ur = xv.copy(), uv.copy()
    xt, ut = (a.copy() for a in target.xu(s))
    T, X_, U_, S_, W_, TAU_ = [], [], [], [], [], []
    for i in range(steps + 1):
        t = i * h
        _, _, w, tau = rates(t, xr, ur, xt, ut)
        T.append(t), X_.append(xr.copy()), U_.append(ur.copy()), S_.append(np.r_[xt, ut]), W_.append(w), TAU_.append(tau)
        if i == steps:
            break
        (xr, xt), (ur, ut) = rk4_step(t, h, [xr, xt], [ur, ut], lambda tt, xx, uu: list(rates(tt, xx[0], uu[0], xx[1], uu[1])[:2]))
        if not (np.all(np.isfinite(ur)) and np.all(np.isfinite(ut))):
            raise SimulationError(f"the soft capture diverged at t = {t + h:.4g} s; lower the gains or dt")
    return SoftCaptureRun(np.array(T), np.array(X_), np.array(U_), np.array(S_), np.array(W_), np.array(TAU_), dict(zip(names, gains)))
