"""Detumbling the captured system ([`detumble`][spacearm.capture.detumble]), and the wrench at the grasp from a run.

Joints (both modes): the arm holds the posture it had at capture through the reduced dynamics,
``τ = H* (k_p (q_hold − q) − k_d q̇) + c*`` (eq. 45 and its bias), clamped to
``±max_joint_torque``: the relative motion of base, arm and target is damped out. This is the
native [`ComputedTorque`][spacearm.control.ComputedTorque] with a constant reference (paper eqs. 112–115);
in the flying mode it also compensates the thrusters' wrench (the ``H0mᵀ H0⁻¹ F_b`` term), so
the arm holds its posture exactly while the base is driven. Reaction wheels (the model's default
wheels) are not arm joints: nothing drives them here.

- ``mode="floating"`` (no base actuation): robot + target momentum is conserved, so the best
  the arm can do is redistribute it: the target's tumble passes through the arm into the base
  until everything turns as one rigid body with ``ω = I⁻¹ L`` (the residual spin, reported).
  Detumbled: every joint rate below ``rate_tolerance``.
- ``mode="flying"`` (base thrusters): the base wrench drives the system momentum to zero with
  time constant ``time_constant``: ``F0 = −P / τ_d`` and ``N0 = −L_com / τ_d − (r0 − r_g) × F0``
  (so that ``dL_com/dt = N0 + (r0 − r_g) × F0 = −L_com / τ_d`` exactly), each clamped to
  ``max_force`` / ``max_torque``. Detumbled: base angular velocity and joint rates below
  ``rate_tolerance``. This is the native [`MomentumDamping`][spacearm.control.MomentumDamping], composed
  with the joint law by [`Combined`][spacearm.control.Combined].
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional

import numpy as np

from .. import _core
from .._util.summary import summary_repr
from .._util.arrays import number
from ..control import Combined, ComputedTorque, MomentumDamping, TorqueLimit
from ..errors import ArgumentError
from ..sim.simulation import simulate

__all__ = ["DetumbleRun", "detumble", "detumble_controller", "grasp_wrench", "time_to_rest", "DETUMBLE_MODES"]

DETUMBLE_MODES = ("floating", "flying")


class DetumbleRun(NamedTuple):
    trajectory: object  #: the spacearm.Trajectory of the combined model
    time_to_detumble: float  #: s from the start of the run (inf when not reached)
    peak_joint_torque: float  #: N·m, largest |τ_j| applied
    residual_spin: float  #: |ω0| at the end, rad/s

    __repr__ = summary_repr


def detumble_controller(robot, x, *, mode: str, q_hold, kp: float, kd: float, time_constant: float, max_joint_torque: float,
                        max_force: float, max_torque: float, model=None):
    """The native controller of the module docstring for ``robot`` (a spacearm.control
    controller, or ``None`` when there is nothing to drive)."""
    arm_dofs = robot.actuated_arm_dofs  # the passive joints take no reference (docs/flexibility.md)
    arm = (ComputedTorque(kp=kp, kd=kd, reference=np.asarray(q_hold, dtype=float)[arm_dofs], model=model) if arm_dofs else None)
    ctrl = arm
    if mode == "flying":
        base = MomentumDamping(time_constant, max_force=max_force, max_torque=max_torque, model=model)
        ctrl = base if arm is None else Combined(arm=arm, base=base)
    if ctrl is not None and math.isfinite(max_joint_torque):
        ctrl = TorqueLimit(ctrl, max_joint_torque)
    return ctrl


def time_to_rest(t: np.ndarray, rates: np.ndarray, tolerance: float) -> float:
    """The first time after which every rate stays below ``tolerance`` (inf if never)."""
    above = np.nonzero(np.max(np.abs(rates), axis=1) >= tolerance)[0]
    if above.size == 0:
        return float(t[0])
    if above[-1] == len(t) - 1:
        return math.inf
    return float(t[above[-1] + 1])


def grasp_wrench(captured, trajectory) -> np.ndarray:
    """The wrench ``[f; n]`` (T, 6, in 𝒥, the moment about the target's CM) that holds the
    captured target (the payload of ``captured``, [`attach_target`][spacearm.capture.attach_target])
    on the motion of ``trajectory`` (a run of ``captured.robot``): ``f = m a_c`` and
    ``n = d(I ω)/dt``, exactly, from the recorded states and accelerations: the core's RNEA force
    across the payload's joint (``spacearm_core::algorithms::rnea::joint_wrench``)."""
    robot = captured.robot
    return _core.joint_wrenches(robot.core_model, trajectory.x, trajectory.u, trajectory.du, robot.body_index(captured.payload))


def detumble(robot, x, u, duration: float, *, mode: str = "floating", q_hold=None, kp: float = 1.0, kd: float = 2.0,
             time_constant: float = 5.0, max_joint_torque: float = math.inf, max_force: float = math.inf,
             max_torque: float = math.inf, rate_tolerance: float = 1e-3, dt: float = 0.01, model=None,
             rtol: Optional[float] = 1e-10, orbit=None, gravity_gradient: Optional[bool] = None) -> DetumbleRun:
    """Run the detumbling controller of the module docstring on ``robot`` (the captured system)
    from ``(x, u)`` for ``duration`` s (``spacearm.simulate``; ``rtol`` below says how).
    ``q_hold`` defaults to the joint angles of ``x``; gains ``kp`` (1/s²) and ``kd`` (1/s) act
    through ``H*``; ``time_constant`` (s) sets the flying-mode momentum decay. ``model``: the
    controller's model of the plant (default the plant itself), e.g. the captured system built
    with an estimated target inertia: ``H*``, ``c*`` and the momenta of the laws come from it.
    ``rtol``: adaptive DOPRI5 with this relative tolerance (``dt`` the output interval), or
    ``None`` for fixed-step RK4 with step ``dt``. The laws run natively in the simulation loop
    (``detumble_controller``). ``orbit``, ``gravity_gradient``: run in orbit, as
    [`simulate`][spacearm.simulate] (``x``, ``u`` relative to the orbit's point; docs/orbit.md)."""
    if mode not in DETUMBLE_MODES:
        raise ArgumentError(f"mode must be one of {list(DETUMBLE_MODES)}, got {mode!r}")
    x = np.asarray(x, dtype=float)
    q_hold = x[7:].copy() if q_hold is None else np.asarray(q_hold, dtype=float)
    kp, kd, tc = number(kp, "kp"), number(kd, "kd"), number(time_constant, "time_constant")
    limits = [number(v, name) for v, name in ((max_joint_torque, "max_joint_torque"), (max_force, "max_force"), (max_torque, "max_torque"))]
    if min(limits) <= 0 or not tc > 0:
        raise ArgumentError(f"limits and time_constant must be > 0, got limits {limits}, time_constant {tc}")
    mjt, mf, mt = limits
    model = robot if model is None else model
    if model.nu != robot.nu:
        raise ArgumentError(f"the controller's model has {model.n_dof} joints, the plant {robot.n_dof}")

    ctrl = detumble_controller(robot, x, mode=mode, q_hold=q_hold, kp=kp, kd=kd, time_constant=tc, max_joint_torque=mjt,
                               max_force=mf, max_torque=mt, model=None if model is robot else model)
    if rtol is None:
        traj = simulate(robot, duration, x0=x, u0=u, mode=mode, dt=dt, controller=ctrl, orbit=orbit,
                        gravity_gradient=gravity_gradient)
    else:
        traj = simulate(robot, duration, x0=x, u0=u, mode=mode, dt=dt, controller=ctrl, integrator="dopri5",
                        rtol=rtol, atol=rtol * 1e-2, orbit=orbit, gravity_gradient=gravity_gradient)
    uu = traj.u
    rates = uu[:, 6:] if mode == "floating" else uu[:, 3:]
    if rates.shape[1] == 0:
        rates = np.zeros((uu.shape[0], 1))
    return DetumbleRun(traj, time_to_rest(traj.t, rates, rate_tolerance),
                       float(np.abs(traj.tau).max()) if robot.n_dof else 0.0, float(np.linalg.norm(uu[-1, 3:6])))
