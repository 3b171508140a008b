"""Optimal point-to-point maneuvers of a free-floating spacecraft manipulator (optional extra
``optimal-control``): direct multiple shooting with IPOPT through CasADi on the functions of
[`spacearm.casadi`][spacearm.casadi], warm-started from the reactionless resolved-motion-rate motion.
docs/optimal-control.md gives the transcription, the cost and the constraints.
"""

from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from .._util.arrays import integer, number, vector
from ..errors import ArgumentError, SpacearmTypeError
from .limits import JointBounds
from .problem import OBJECTIVES
from .result import Plan

__all__ = ["point_to_point", "Plan", "JointBounds", "OBJECTIVES"]


def point_to_point(
    robot,
    target,
    *,
    duration: float = 4.0,
    nodes: int = 20,
    objective: str = "attitude",
    x0=None,
    u0=None,
    point=None,
    position_limits=None,
    velocity_limit=None,
    effort_limit=None,
    rest_at_end: bool = True,
    reactionless_end: bool = False,
    substeps: int = 2,
    warm_start: str = "reactionless",
    effort_weight: float = 1e-6,
    max_iter: int = 500,
    hessian: str = "objective",
    progress: Optional[Callable[[int, float], None]] = None,
) -> Plan:
    """Plan a motion of ``point`` (default: the end effector) to ``target`` (3 values, m, in 𝒥)
    in ``duration`` seconds with the base free floating (no base wrench).

    Parameters
    ----------
    robot : Robot
    target : 3 floats
        Final position of the point in 𝒥 (reached exactly, as a constraint).
    duration : float
        Maneuver time ``T`` (s).
    nodes : int
        Number of knot intervals ``K`` (torques are piecewise constant on them).
    objective : ``"attitude"`` or ``"effort"``
        Minimise the base attitude disturbance ``(1/T) ∫ |θ|² dt`` (plus ``effort_weight``
        times the effort term) or the joint effort ``(1/T) ∫ |tau|² dt``.
    x0, u0 : arrays, optional
        Initial state (default: ``robot.neutral_configuration()``, at rest).
    position_limits, velocity_limit, effort_limit : optional
        Override the model's joint limits: ``(lower, upper)``, and a number or one per joint
        ([`JointBounds`][spacearm.plan.JointBounds]). Infinite means unbounded; the presets have no limits.
    rest_at_end : bool
        Joint speeds zero at ``T`` (with zero momentum, the whole system at rest).
    reactionless_end : bool
        Base angular velocity zero at ``T``.
    substeps : int
        RK4 steps per interval in the shooting map.
    warm_start : ``"reactionless"`` or ``"hold"``
        Initial guess: the reactionless RMRC motion to the target (the minimum-disturbance
        one where the reactionless motion cannot reach it), or the initial state held.
    max_iter : int
        IPOPT's iteration limit.
    hessian : ``"objective"`` or ``"exact"``
        The Hessian IPOPT uses: the objective's alone (default; the shooting constraints'
        curvature left out, a Gauss–Newton-type approximation) or the exact Hessian of the
        Lagrangian (several times slower per iteration; docs/optimal-control.md).
    progress : callable, optional
        Called after each IPOPT iteration with ``(iteration, objective value)``.

    Returns
    -------
    Plan
        Check ``Plan.success``; [`Plan.resimulate`][spacearm.plan.Plan.resimulate] runs it in the native simulator.
    """
    from ..model.robot import Robot
    from .problem import solve
    from .warm_start import hold_guess, reactionless_guess

    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"point_to_point needs a spacearm.Robot, got {type(robot).__name__}")
    if objective not in OBJECTIVES:
        raise ArgumentError(f"objective must be one of {', '.join(OBJECTIVES)}, got {objective!r}")
    if warm_start not in ("reactionless", "hold"):
        raise ArgumentError(f"warm_start must be 'reactionless' or 'hold', got {warm_start!r}")
    tgt = vector(target, "target", 3)
    if not np.all(np.isfinite(tgt)):
        raise ArgumentError(f"target must be finite, got {tgt}")
    T = number(duration, "duration")
    if not (np.isfinite(T) and T > 0):
        raise ArgumentError(f"duration must be a positive number of seconds, got {duration!r}")
    K = integer(nodes, "nodes")
    if K < 2:
        raise ArgumentError(f"nodes must be at least 2, got {K}")
    m = integer(substeps, "substeps")
    if m < 1:
        raise ArgumentError(f"substeps must be at least 1, got {m}")
    xs = robot.neutral_configuration() if x0 is None else robot.configuration_plus(x0, np.zeros(robot.nu))
    us = robot.zero_velocity() if u0 is None else vector(u0, "u0", robot.nu)
    robot.resolve_point(point)  # an unknown point fails here, before any work
    bounds = JointBounds.of(robot, position_limits, velocity_limit, effort_limit)
    q0 = xs[7:]
    if np.any(q0 < bounds.lower) or np.any(q0 > bounds.upper):
        raise ArgumentError(f"the initial joint configuration {q0} is outside the position limits")
    times = np.linspace(0.0, T, K + 1)
    if warm_start == "reactionless":
        xg, ug, taug, motion = reactionless_guess(robot, xs, us, tgt, point, times, bounds)
    else:
        xg, ug, taug, motion = hold_guess(robot, xs, us, times)
    report = solve(robot, xs, us, tgt, point, T, K, m, objective, bounds, (xg, ug, taug), bool(rest_at_end),
                   bool(reactionless_end), number(effort_weight, "effort_weight"), integer(max_iter, "max_iter"), progress,
                   hessian)
    return Plan(robot=robot, objective=objective, target=tgt, point=point, t=times, substeps=m, warm_start=motion, **report)
