"""Optimal point-to-point maneuvers of a free-floating spacecraft manipulator (optional extra
``optimal-control``): direct multiple shooting with IPOPT through CasADi on the functions of
[`spacearm.casadi`][spacearm.casadi], warm-started from the reactionless resolved-motion-rate motion.
docs/optimal-control.md gives the transcription, the cost and the constraints.
"""

from __future__ import annotations

import warnings
from typing import Callable, Optional

import numpy as np

from .._util.arrays import integer, number, vector
from ..errors import ArgumentError, PlanCheckWarning, SpacearmTypeError
from .limits import JointBounds
from .problem import OBJECTIVES
from .result import Plan
from .verify import Verification

__all__ = ["point_to_point", "Plan", "JointBounds", "Verification", "OBJECTIVES", "MAX_NODES", "MAX_STEPS", "MAX_ITER"]

#: The largest number of knot intervals a plan takes (the problem grows linearly with it; the
#: presets need 10–40).
MAX_NODES = 400
#: The largest number of RK4 steps of the transcription, ``nodes * substeps``.
MAX_STEPS = 2000
#: The largest IPOPT iteration limit.
MAX_ITER = 10000


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
    smoothness_weight: float = 1e-8,
    progress: Optional[Callable[[int, float], None]] = None,
) -> Plan:
    r"""Plan a motion of ``point`` (default: the end effector) to ``target`` (3 values, m, in 𝒥)
    in ``duration`` seconds with the base free floating (no base wrench).

    Parameters
    ----------
    robot : Robot
    target : 3 floats
        Final position of the point in 𝒥 (reached exactly, as a constraint).
    duration : float
        Maneuver time ``T`` (s).
    nodes : int
        Number of knot intervals ``K`` (torques are linear on them), at most ``MAX_NODES``.
    objective : ``"attitude"`` or ``"effort"``
        Minimise the base attitude disturbance $\frac1T \int_0^T \lVert\theta\rVert^2 dt$ (plus ``effort_weight``
        times the effort term) or the joint effort $\frac1T \int_0^T \lVert\tau\rVert^2 dt$.
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
        RK4 steps per interval in the shooting map (``nodes * substeps`` at most ``MAX_STEPS``).
    warm_start : ``"reactionless"`` or ``"hold"``
        Initial guess: the reactionless RMRC motion to the target (the minimum-disturbance
        one where the reactionless motion cannot reach it), or the initial state held.
    max_iter : int
        IPOPT's iteration limit (1 to ``MAX_ITER``).
    hessian : ``"objective"`` or ``"exact"``
        The Hessian IPOPT uses: the objective's alone (default; the shooting constraints'
        curvature left out, a Gauss–Newton-type approximation) or the exact Hessian of the
        Lagrangian (several times slower per iteration; docs/optimal-control.md).
    smoothness_weight : float
        Weight $w$ of the torque-rate term $\frac{w}{T} \sum_k \lVert\tau_{k+1} - \tau_k\rVert^2 / \Delta t$ added to the
        cost ($\approx \frac{w}{T} \int_0^T \lVert\dot\tau\rVert^2 dt$; 0 drops it). Without it the attitude objective
        leaves the torques nearly free and the optimiser spends them on knot-to-knot zigzags
        that exploit the error of the RK4 map: a plan that its re-simulation refutes
        (docs/optimal-control.md, spatial6).
    progress : callable, optional
        Called after each IPOPT iteration with ``(iteration, objective value)``; an exception
        it raises stops the solve and is raised.

    Returns
    -------
    Plan
        Verified before it is returned (`spacearm.plan.verify`): [`Plan.success`][spacearm.plan.Plan.success] holds
        only if IPOPT converged *and* the plan's shooting defect and its re-simulation in the
        native simulator ([`Plan.resimulation`][spacearm.plan.Plan.resimulation]) are within tolerance; otherwise a
        [`PlanCheckWarning`][spacearm.errors.PlanCheckWarning] is issued and [`Plan.failure`][spacearm.plan.Plan.failure] says why.

    Raises
    ------
    ArgumentError
        Before any solve: a target out of reach of the free-floating system, off the plane of
        a planar one, an initial configuration outside the joint limits
        (`spacearm.plan.target`), a problem larger than the bounds above.
    KeyboardInterrupt
        Ctrl-C during the solve (IPOPT is stopped).
    """
    from ..model.robot import Robot
    from .problem import solve
    from .target import check_target
    from .verify import verify
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
    if not 2 <= K <= MAX_NODES:
        raise ArgumentError(f"nodes must be between 2 and {MAX_NODES} (the planner's bound on the problem size, "
                            f"docs/optimal-control.md), got {K}")
    m = integer(substeps, "substeps")
    if m < 1:
        raise ArgumentError(f"substeps must be at least 1, got {m}")
    if K * m > MAX_STEPS:
        raise ArgumentError(f"nodes * substeps must be at most {MAX_STEPS} RK4 steps (the planner's bound on the problem "
                            f"size, docs/optimal-control.md), got {K} * {m} = {K * m}")
    smoothness = number(smoothness_weight, "smoothness_weight")
    if not (np.isfinite(smoothness) and smoothness >= 0):
        raise ArgumentError(f"smoothness_weight must be finite and >= 0, got {smoothness_weight!r}")
    iterations = integer(max_iter, "max_iter")
    if not 1 <= iterations <= MAX_ITER:
        raise ArgumentError(f"max_iter must be between 1 and {MAX_ITER} IPOPT iterations, got {iterations}")
    if progress is not None and not callable(progress):
        raise SpacearmTypeError(f"progress must be a callable (iteration, objective) or None, got {type(progress).__name__}")
    xs = robot.neutral_configuration() if x0 is None else robot.configuration_plus(x0, np.zeros(robot.nu))
    us = robot.zero_velocity() if u0 is None else vector(u0, "u0", robot.nu)
    robot.resolve_point(point)  # an unknown point fails here, before any work
    bounds = JointBounds.of(robot, position_limits, velocity_limit, effort_limit)
    check_target(robot, xs, us, tgt, point, T, bounds)  # an impossible target is refused here, before any work
    times = np.linspace(0.0, T, K + 1)
    if warm_start == "reactionless":
        xg, ug, taug, motion = reactionless_guess(robot, xs, us, tgt, point, times, bounds)
    else:
        xg, ug, taug, motion = hold_guess(robot, xs, us, times)
    report = solve(robot, xs, us, tgt, point, T, K, m, objective, bounds, (xg, ug, taug), bool(rest_at_end),
                   bool(reactionless_end), number(effort_weight, "effort_weight"), iterations, progress, hessian,
                   smoothness)
    plan = Plan(robot=robot, objective=objective, target=tgt, point=point, t=times, substeps=m, warm_start=motion, **report)
    plan.verification = verify(plan)
    if not plan.success:
        warnings.warn(PlanCheckWarning(f"the plan of {robot.name} to {tgt} is not a plan: {plan.failure}"), stacklevel=2)
    return plan
