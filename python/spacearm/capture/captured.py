"""The captured system: after a rigid grasp the target is a payload of the gripper link
([`attach_target`][spacearm.capture.attach_target]); before it, in a soft capture, a spring–damper at the grasp couples two
free bodies ([`soft_capture`][spacearm.capture.soft_capture]).

Rigid: the target becomes a link on a fixed joint of the gripper body at the relative pose it
has at that instant: the core attaches the target's model to the robot's
([`Robot.attach`][spacearm.Robot.attach], ``model/edit.rs``), no builder replay. The joint space is
unchanged and the base is the same body, so the state maps identically: ``x`` and ``u`` of the
robot are the combined model's, and since the grasp impulse left no relative twist, the payload
moves exactly as the target did — momentum and energy carry over to rounding.

Soft: the robot and the target stay free; a wrist impedance acts at the robot's grasp point
``X``: the force ``f = K (p − X) + D (ṗ − Ẋ)`` (``p`` the target's grasp point) and the couple
``n = K_r θ + D_r (ω_t − ω_g)`` (``θ`` the rotation vector taking the gripper's frame, carried
with the relative attitude it had at contact, to the target's) act on the robot at ``X`` and
their opposites on the target's material point at ``X``: an internal wrench, so robot + target
momentum is conserved. The phase runs in the core (``spacearm_core::sim::soft_capture``): the
robot and the target are two plants of the simulation loop, the impedance's wrench a body wrench of
each at every stage, integrated as one system by the core's RK4 or DOPRI5 and recorded by its
recorder; the robot's joint law is a native controller.
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

from .. import _core
from .._util.summary import summary_repr
from .._util.arrays import number, vector
from ..errors import ArgumentError
from ..rotations import quat_from_matrix
from ..sim.simulation import _recorded_floating_run
from ..sim.trajectory import Trajectory
from .impact import _check_target, _robot_point

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

    def __repr__(self) -> str:
        # A summary, not the arrays (issue 37 item 3: info["captured"] of the Capture env
        # printed every array of the state).
        return (f"<CapturedSystem {self.robot.name!r}: payload {self.payload!r} on {self.gripper!r}, "
                f"N = {self.robot.n_dof}, total mass {self.robot.total_mass:.6g} kg>")


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

    ``(x, u)`` and ``target_state`` are the states just after [`grasp_impulse`][spacearm.capture.grasp_impulse] (the relative
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
    combined = combined_model(robot, target, gripper, Rb.T @ (s[:3] - rb), quat_from_matrix(Rb.T @ Rt), payload)
    return CapturedSystem(combined, xv.copy(), uv.copy(), payload, gripper)


def combined_model(robot, target, gripper: str, origin, rotation, payload: Optional[str] = None):
    """``robot`` with the rigid ``target`` attached to body ``gripper`` as the payload link
    ``payload`` (default: the target's name), its CM at ``origin`` and its axes at ``rotation``
    (quaternion ``[x, y, z, w]``) in the gripper's frame: the core's model edit
    ([`Robot.attach`][spacearm.Robot.attach], ``model/edit.rs``), the robot's part bit for bit.
    The target's shapes (docs/geometry.md) and grasp points ride with it, named
    ``<payload>_<name>``."""
    payload = target.name if payload is None else str(payload)
    return robot.attach(target.body, body=gripper, origin=origin, rotation=rotation, prefix=f"{payload}_", name=payload,
                        model_name=f"{robot.name}+{payload}")


class SoftCaptureRun(NamedTuple):
    """The soft-capture phase, sample by sample (``t`` from 0)."""

    t: np.ndarray  #: (T,)
    x: np.ndarray  #: (T, 7+N) robot configurations
    u: np.ndarray  #: (T, 6+N) robot velocities
    target: np.ndarray  #: (T, 13) target states (``[x, u]`` of a jointed target)
    wrench: np.ndarray  #: (T, 6) the impedance's wrench on the robot at X ([force; couple], 𝒥)
    tau: np.ndarray  #: (T, N) joint torques applied
    gains: dict  #: the impedance used (stiffness, damping, rotational_stiffness, rotational_damping)
    drift: dict  #: robot + target momentum drift over the samples, ``{"P": ..., "L": ...}`` (the core's definition)
    trajectory: object  #: the robot's spacearm.Trajectory (its records and meta: integrator, steps, ...)

    __repr__ = summary_repr


def soft_capture(robot, x, u, target, target_state, duration: float, *, frequency: float = 3.0, damping_ratio: float = 0.7,
                 stiffness: Optional[float] = None, damping: Optional[float] = None,
                 rotational_stiffness: Optional[float] = None, rotational_damping: Optional[float] = None, point=None,
                 grasp: Optional[str] = None, dt: float = 1e-3, controller=None, integrator: str = "rk4",
                 rtol: float = 1e-10, atol: Optional[float] = None) -> SoftCaptureRun:
    """Integrate the soft-capture phase for ``duration`` s (module docstring for the law).

    ``stiffness`` (N/m), ``damping`` (N·s/m), ``rotational_stiffness`` (N·m/rad),
    ``rotational_damping`` (N·m·s/rad); each one not given is set from ``frequency`` ω (rad/s)
    and ``damping_ratio`` ζ on the lightest direction of the grasp, ``K = ω² / g``, ``D = 2ζω / g``
    with ``g`` the largest eigenvalue of the translational (rotational) block of
    ``G_robot + G_target`` ([`inverse_inertia`][spacearm.capture.inverse_inertia]), so that no direction
    rings faster than ω and a fixed step ``dt`` well below 1/ω is stable. The rest pose is the
    relative pose at the start with the two grasp points together.

    ``controller``: the robot's joint law, a native [`spacearm.control`][spacearm.control] controller (default
    ``None``: zero torques; the capture sequence passes the hold law, ``ComputedTorque`` with a
    constant reference). The whole phase runs in the core (``spacearm_core::sim::soft_capture``):
    ``integrator="rk4"`` with fixed step ``dt``, or ``"dopri5"`` with ``rtol``/``atol`` (default
    ``rtol * 1e-2``) and samples every ``dt``; floating mode, the joints' effort and speed limits
    apply as in ``spacearm.simulate``.
    """
    _check_target(target)
    xv, uv = vector(x, "x", robot.nx), vector(u, "u", robot.nu)
    s = target.check_state(target_state)
    duration = number(duration, "duration")
    dt = number(dt, "dt")
    body, offset = _robot_point(robot, xv, point, (0.0, 0.0, 0.0))
    tbody, tpoint = target.point(grasp)
    # The core judges the values (duration, dt, frequency, damping_ratio, the gains); Python
    # converts them.
    omega, zeta = number(frequency, "frequency"), number(damping_ratio, "damping_ratio")
    names = ("stiffness", "damping", "rotational_stiffness", "rotational_damping")
    given = [None if v is None else number(v, name) for v, name in zip((stiffness, damping, rotational_stiffness, rotational_damping), names)]
    options, spec = _recorded_floating_run(robot, controller, integrator, dt, rtol, atol)
    tx, tu = target.xu(s)
    res = _core.soft_capture(robot.core_model, xv, uv, int(body), np.asarray(offset, dtype=float), target.body.core_model, tx, tu,
                             int(tbody), np.asarray(tpoint, dtype=float), duration, options, spec, frequency=omega, damping_ratio=zeta,
                             stiffness=given[0], damping=given[1], rotational_stiffness=given[2], rotational_damping=given[3])
    rd = {**res.robot.records.to_dict(), **res.robot.events.to_dict()}
    td = res.target.records.to_dict()
    meta = res.robot.meta.to_dict()
    meta["duration"], meta["robot"] = duration, robot.name
    gains = dict(zip(names, (res.stiffness, res.damping, res.rotational_stiffness, res.rotational_damping)))
    return SoftCaptureRun(rd["t"], rd["x"], rd["u"], np.hstack([td["x"], td["u"]]), np.asarray(res.wrench), rd["tau"], gains,
                          {"P": res.drift_linear, "L": res.drift_angular}, Trajectory._adopt(robot, rd, meta))
