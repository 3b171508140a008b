"""Detumbling the captured system (:func:`detumble`), and the wrench at the grasp from a run.

Joints (both modes): the arm holds the posture it had at capture through the reduced dynamics,
``τ = H* (k_p (q_hold − q) − k_d q̇) + c*`` (eq. 45 and its bias), clamped to
``±max_joint_torque``: the relative motion of base, arm and target is damped out.

- ``mode="floating"`` (no base actuation): robot + target momentum is conserved, so the best
  the arm can do is redistribute it: the target's tumble passes through the arm into the base
  until everything turns as one rigid body with ``ω = I⁻¹ L`` (the residual spin, reported).
  Detumbled: every joint rate below ``rate_tolerance``.
- ``mode="flying"`` (base thrusters): the base wrench drives the system momentum to zero with
  time constant ``time_constant``: ``F0 = −P / τ_d`` and ``N0 = −L_com / τ_d − (r0 − r_g) × F0``
  (so that ``dL_com/dt = N0 + (r0 − r_g) × F0 = −L_com / τ_d`` exactly), each clamped to
  ``max_force`` / ``max_torque``. Detumbled: base angular velocity and joint rates below
  ``rate_tolerance``.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional

import numpy as np

from .._util.arrays import number
from ..control import Callback
from ..errors import ArgumentError
from ..sim.simulation import simulate

__all__ = ["DetumbleRun", "detumble", "hold_torque", "grasp_wrench", "time_to_rest", "DETUMBLE_MODES"]

DETUMBLE_MODES = ("floating", "flying")


class DetumbleRun(NamedTuple):
    trajectory: object  #: the spacearm.Trajectory of the combined model
    time_to_detumble: float  #: s from the start of the run (inf when not reached)
    peak_joint_torque: float  #: N·m, largest |τ_j| applied
    residual_spin: float  #: |ω0| at the end, rad/s


def _clamp_norm(v: np.ndarray, limit: float) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v if n <= limit else v * (limit / n)


def hold_torque(robot, x, u, q_hold, kp: float, kd: float, max_joint_torque: float) -> np.ndarray:
    """``clip(H* (kp (q_hold − q) − kd q̇) + c*, ±max_joint_torque)``."""
    if robot.n_dof == 0:
        return np.zeros(0)
    q, qd = x[7:], u[6:]
    tau = robot.generalized_inertia(x) @ (kp * (q_hold - q) - kd * qd) + robot.generalized_bias(x, u)
    return np.clip(tau, -max_joint_torque, max_joint_torque)


def momentum_damping_wrench(robot, x, u, time_constant: float, max_force: float, max_torque: float) -> np.ndarray:
    """The flying-mode base wrench ``[F0, N0]`` of the module docstring."""
    m = robot.momentum(x, u)
    f0 = _clamp_norm(-m.P / time_constant, max_force)
    lever = x[:3] - robot.center_of_mass(x)
    n0 = _clamp_norm(-m.L_com / time_constant - np.cross(lever, f0), max_torque)
    return np.r_[f0, n0]


def time_to_rest(t: np.ndarray, rates: np.ndarray, tolerance: float) -> float:
    """The first time after which every rate stays below ``tolerance`` (inf if never)."""
    above = np.nonzero(np.max(np.abs(rates), axis=1) >= tolerance)[0]
    if above.size == 0:
        return float(t[0])
    if above[-1] == len(t) - 1:
        return math.inf
    return float(t[above[-1] + 1])


def grasp_wrench(t: np.ndarray, target_states: np.ndarray, mass: float, inertia: np.ndarray) -> np.ndarray:
    """The wrench ``[f; n]`` (T, 6, in 𝒥) that holds a rigid target on its recorded motion:
    ``f = d(m v)/dt`` and ``n = dL/dt`` about its CM, by central differences of the recorded
    states (second order; the ends one-sided)."""
    from ..rotations import quat_to_matrix

    t = np.asarray(t, dtype=float)
    if t.size < 3:
        return np.zeros((t.size, 6))
    P = mass * target_states[:, 7:10]
    L = np.array([quat_to_matrix(s[3:7]) @ inertia @ quat_to_matrix(s[3:7]).T @ s[10:13] for s in target_states])
    return np.hstack([np.gradient(P, t, axis=0), np.gradient(L, t, axis=0)])


def detumble(robot, x, u, duration: float, *, mode: str = "floating", q_hold=None, kp: float = 1.0, kd: float = 2.0,
             time_constant: float = 5.0, max_joint_torque: float = math.inf, max_force: float = math.inf,
             max_torque: float = math.inf, rate_tolerance: float = 1e-3, dt: float = 0.01, model=None,
             rtol: Optional[float] = 1e-10) -> DetumbleRun:
    """Run the detumbling controller of the module docstring on ``robot`` (the captured system)
    from ``(x, u)`` for ``duration`` s (``spacearm.simulate``, RK4 with step ``dt``).
    ``q_hold`` defaults to the joint angles of ``x``; gains ``kp`` (1/s²) and ``kd`` (1/s) act
    through ``H*``; ``time_constant`` (s) sets the flying-mode momentum decay. ``model``: the
    controller's model of the plant (default the plant itself), e.g. the captured system built
    with an estimated target inertia: ``H*``, ``c*`` and the momenta of the laws come from it.
    ``rtol``: adaptive DOPRI5 with this relative tolerance (``dt`` the output interval), or
    ``None`` for fixed-step RK4 with step ``dt``."""
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

    def law(t, xs, us):
        tau = hold_torque(model, xs, us, q_hold, kp, kd, mjt)
        if mode == "flying":
            return tau, momentum_damping_wrench(model, xs, us, tc, mf, mt)
        return tau

    if rtol is None:
        traj = simulate(robot, duration, x0=x, u0=u, mode=mode, dt=dt, controller=Callback(law))
    else:
        traj = simulate(robot, duration, x0=x, u0=u, mode=mode, dt=dt, controller=Callback(law), integrator="dopri5",
                        rtol=rtol, atol=rtol * 1e-2)
    uu = traj.u
    rates = uu[:, 6:] if mode == "floating" else uu[:, 3:]
    if rates.shape[1] == 0:
        rates = np.zeros((uu.shape[0], 1))
    return DetumbleRun(traj, time_to_rest(traj.t, rates, rate_tolerance),
                       float(np.abs(traj.tau).max()) if robot.n_dof else 0.0, float(np.linalg.norm(uu[-1, 3:6])))
