"""Two-arm grasps: a closed kinematic chain ([`simulate_closed_chain`][spacearm.capture.simulate_closed_chain]).

When a second gripper also holds the captured target, the captured model (the target a payload
of the first gripper, [`attach_target`][spacearm.capture.attach_target]) gains a loop: the frame of the
second gripper must keep its pose relative to the target. With ``J_c = J_b − J_a`` the difference
of the two frames' point Jacobians (6×(6+N), eqs. 104–108), the loop-closure constraint is
``J_c u = 0`` (both Jacobians taken at frame b's origin) and the dynamics become the index-1 system

    [ H    −J_cᵀ ] [ du ]   [ f − c                              ]
    [ J_c    0   ] [ λ  ] = [ −J̇_c u − 2α J_c u − α² e            ]

(``λ`` the constraint wrench, ``e = [p_b − p_a − R_a d; θ]`` the pose error against the grasp, the
last two terms Baumgarte's drift stabilisation with rate ``α``). The whole run is the core's
(``spacearm_core::sim::closed_chain``): the KKT solve (``algorithms/constrained.rs``), ``J̇_c u``
exact on dual numbers (``derivatives::loop_closure_bias``), the simulation loop's RK4 or DOPRI5,
its records, and a native controller for the joints ([`spacearm.control`][spacearm.control]).
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

from .. import _core
from .._util.summary import summary_repr
from .._util.arrays import number, vector
from ..sim.simulation import _recorded_floating_run
from ..sim.trajectory import Trajectory

__all__ = ["ClosedChainRun", "simulate_closed_chain", "loop_closure_terms"]


class ClosedChainRun(NamedTuple):
    """The result of [`simulate_closed_chain`][spacearm.capture.simulate_closed_chain]: the samples of the closed-chain run, the
    loop's constraint wrench and its pose error (docs/capture.md)."""

    t: np.ndarray  #: (T,)
    x: np.ndarray  #: (T, 7+N)
    u: np.ndarray  #: (T, 6+N)
    constraint_wrench: np.ndarray  #: (T, 6) λ: the wrench on frame b at its origin, [force; torque] in 𝒥 (body a gets −λ there)
    pose_error: np.ndarray  #: (T, 6) e = [position error (m); rotation error (rad)]
    trajectory: object  #: the run as a spacearm.Trajectory (tau, momentum, meta: integrator, steps, drift, ...)

    __repr__ = summary_repr


def _frames(robot, point_a, point_b):
    """The two frames as the core takes them; two on one body are the core's refusal
    (``LoopClosure::at``, algorithms/constrained.rs)."""
    ba, oa = robot.resolve_point(point_a)
    bb, ob = robot.resolve_point(point_b)
    return int(ba), np.asarray(oa, dtype=float), int(bb), np.asarray(ob, dtype=float)


def loop_closure_terms(robot, x, u, point_a, point_b):
    """``(J_c, J̇_c u)`` of the loop closing the frames at ``point_a`` and ``point_b`` at ``(x, u)``:
    the constraint Jacobian at b's origin (6×(6+N)) and its exact time derivative along ``u``
    times ``u`` (the core's dual numbers)."""
    terms = _core.loop_closure(robot.core_model, vector(x, "x", robot.nx), vector(u, "u", robot.nu), *_frames(robot, point_a, point_b))
    return terms.jacobian, terms.jdot_u


def simulate_closed_chain(robot, x0, u0, duration: float, point_a, point_b, *, dt: float = 1e-3, stabilization: float = 20.0,
                          controller=None, integrator: str = "rk4", rtol: float = 1e-10, atol: Optional[float] = None) -> ClosedChainRun:
    """Integrate ``robot`` with the frames at ``point_a`` and ``point_b`` (each a point name, a
    body, or ``(body, offset)``) welded at their relative pose at ``x0``.

    ``u0`` must satisfy the velocity constraint (``J_c u0 = 0`` to 1e-9 of ``|u0|``; an
    ``ArgumentError`` otherwise). ``controller``: the joint torques, a native
    [`spacearm.control`][spacearm.control] controller (default ``None``: zero torques); the base is free
    (floating mode). ``stabilization``: Baumgarte's rate ``α`` (1/s). ``integrator="rk4"`` with
    step ``dt``, or ``"dopri5"`` with ``rtol``/``atol`` (default ``rtol * 1e-2``) and samples every
    ``dt``.
    """
    x0, u0 = vector(x0, "x0", robot.nx), vector(u0, "u0", robot.nu)
    # The core judges duration, dt and stabilization; Python converts them.
    duration, dt, alpha = number(duration, "duration"), number(dt, "dt"), number(stabilization, "stabilization")
    frames = _frames(robot, point_a, point_b)
    options, spec = _recorded_floating_run(robot, controller, integrator, dt, rtol, atol)
    res = _core.simulate_closed_chain(robot.core_model, x0, u0, duration, *frames, options, spec, stabilization=alpha)
    data = {**res.run.records.to_dict(), **res.run.events.to_dict()}
    meta = res.run.meta.to_dict()
    meta["duration"], meta["robot"] = duration, robot.name
    return ClosedChainRun(data["t"], data["x"], data["u"], np.asarray(res.constraint_wrench), np.asarray(res.pose_error),
                          Trajectory._adopt(robot, data, meta))
