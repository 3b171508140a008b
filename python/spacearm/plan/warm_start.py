"""The initial guess of a plan: the reactionless resolved-motion-rate motion
([`spacearm.analysis.reactionless.move_to`][spacearm.analysis.move_to]) sampled at the knots."""

from __future__ import annotations

import numpy as np

from ..analysis.reactionless import move_to


#: The reactionless motion is used as the guess only if it ends this close to the target (m).
REACH_TOLERANCE = 0.01


def reactionless_guess(robot, x0, u0, target, point, times, bounds):
    """``(x, u, tau, motion)`` at the knots ``times`` (K+1) from the reactionless RMRC motion
    to ``target`` over ``times[-1]``, or from the minimum-disturbance RMRC motion (the task
    first, the base angular velocity minimised in its null space) when the reactionless one
    ends farther than ``REACH_TOLERANCE`` from the target (the arm has too few joints for the
    task and a still base, as spatial6 for a position task: 6 = 3 + 3, so the reaction null
    space restricted to the task is empty). Configurations and joint rates from the motion, base
    velocities from the system momentum of ``(x0, u0)`` (``Robot.base_velocity_from_momentum``),
    and joint torques ``H* qdd + c*`` with ``qdd`` by finite differences of the rates, clipped
    to the effort limits. The motion itself is returned too (the planner's figure compares
    with it)."""
    duration = float(times[-1])
    dt = duration / (4 * (len(times) - 1))
    motion = move_to(robot, target, x0=x0, point=point, strategy="reactionless", duration=duration, settle=0.0, dt=dt)
    if motion.final_position_error > REACH_TOLERANCE:
        motion = move_to(robot, target, x0=x0, point=point, strategy="minimum_disturbance", duration=duration, settle=0.0, dt=dt)
    idx = np.clip(np.searchsorted(motion.times, times - 1e-9 * duration), 0, len(motion.times) - 1)
    x = motion.x[idx].copy()
    qd = motion.qd[idx].copy()
    qd[0] = u0[6:]
    mom = robot.momentum(x0, u0)
    u = np.array([np.concatenate([robot.base_velocity_from_momentum(xk, qk, mom.P, mom.L_origin), qk]) for xk, qk in zip(x, qd)])
    qdd = np.gradient(qd, times, axis=0)
    tau = np.array([robot.generalized_inertia(x[k]) @ qdd[k] + robot.generalized_bias(x[k], u[k]) for k in range(len(times))])
    tau = np.clip(tau, -bounds.effort, bounds.effort)
    return x, u, tau, motion


def hold_guess(robot, x0, u0, times):
    """``(x, u, tau, None)``: the initial state held at every knot, zero torques."""
    k = len(times)
    return np.tile(x0, (k, 1)), np.tile(u0, (k, 1)), np.zeros((k, robot.n_dof)), None
