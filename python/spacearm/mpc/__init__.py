r"""Model-predictive control on the core's dynamics: optimal-control problems over a horizon of
RK4 steps, solved by the core's box-constrained FDDP (``spacearm_core::optimal``; docs/mpc.md).

A [`Problem`][spacearm.mpc.Problem] is plain data — the horizon, the step, the mode, the
running and terminal cost terms ([`JointCost`][spacearm.mpc.JointCost],
[`StateCost`][spacearm.mpc.StateCost], [`BaseAttitudeCost`][spacearm.mpc.BaseAttitudeCost],
[`PointCost`][spacearm.mpc.PointCost], [`ControlCost`][spacearm.mpc.ControlCost]) and the
control limit — checked by the core when made; [`solve`][spacearm.mpc.solve] runs the core's
solver and returns a [`Solution`][spacearm.mpc.Solution], whose
[`resimulate`][spacearm.mpc.Solution.resimulate] replays its controls on the native simulator.

The controls are the joint torques, then the base wrench components the mode allows (the
torque ``N0`` in rotation-flying, ``[F0, N0]`` in flying).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np

from .. import _core
from .._util.arrays import vector

__all__ = ["Problem", "JointCost", "StateCost", "BaseAttitudeCost", "PointCost", "ControlCost", "Solution", "solve", "crocoddyl_action_model"]


def _numbers(value):
    """A number or a list of numbers, as plain data."""
    if np.ndim(value) == 0:
        return float(value)
    return [float(v) for v in np.asarray(value, dtype=float).ravel()]


@dataclass(frozen=True)
class JointCost:
    r"""$\tfrac12 \sum w_q (q - q_\mathrm{ref})^2 + \tfrac12 \sum w_{\dot q} (\dot q - \dot q_\mathrm{ref})^2$
    (weights: one number or one per joint)."""

    weight_q: object
    reference: Sequence[float]
    weight_qd: object = 0.0
    velocity_reference: Optional[Sequence[float]] = None

    def to_data(self) -> dict:
        d = {"kind": "joint", "weight_q": _numbers(self.weight_q), "reference": _numbers(list(self.reference)), "weight_qd": _numbers(self.weight_qd)}
        if self.velocity_reference is not None:
            d["velocity_reference"] = _numbers(list(self.velocity_reference))
        return d


@dataclass(frozen=True)
class StateCost:
    r"""$\tfrac12 \sum_i w_i \big((x, u) \ominus (x, u)_\mathrm{ref}\big)_i^2$ on the tangent
    state $[\delta r_0, \delta\theta, \delta q, \delta v_0, \delta\omega_0, \delta\dot q]$
    (``weights``: one or $2(6+N)$; ``reference``: $[x; u]$, $13+2N$ numbers)."""

    weights: object
    reference: Sequence[float]

    def to_data(self) -> dict:
        return {"kind": "state", "weights": _numbers(self.weights), "reference": _numbers(list(self.reference))}


@dataclass(frozen=True)
class BaseAttitudeCost:
    r"""The base attitude disturbance $\tfrac12 w\,|\log(\mathrm{quat} \otimes \mathrm{quat}_\mathrm{ref}^*)|^2 + \tfrac12 w_\omega |\omega_0|^2$."""

    weight: float
    rate_weight: float = 0.0
    reference: Sequence[float] = (0.0, 0.0, 0.0, 1.0)

    def to_data(self) -> dict:
        return {"kind": "base_attitude", "weight": float(self.weight), "rate_weight": float(self.rate_weight), "reference": _numbers(list(self.reference))}


def _target_data(target):
    """A point cost's target as the core's data: three numbers, or a moving point."""
    from ..control import FreeBodyPoint, _data

    if isinstance(target, FreeBodyPoint):
        data = _data(target)
        return {k: v for k, v in data.items() if k != "point" and not (k == "orbit" and v is None)}
    return _numbers(list(target))


@dataclass(frozen=True)
class PointCost:
    r"""$\tfrac12 \sum w_i (p(x) - p_\mathrm{target}(t))_i^2$ of the point at ``offset`` (m, body
    frame, from its CM) on ``body`` (index or link name). ``target``: a fixed point (m, in 𝒥) or
    a moving one, a [`FreeBodyPoint`][spacearm.control.FreeBodyPoint] (a tumbling target's grasp
    point, torque-free, or with ``orbit=`` the run's orbit, moving under gravity's tidal part
    relative to the orbit's point; its ``point`` is ignored), evaluated by the core at every knot's time
    ``problem.start_time + k * dt`` (in the native law, plus the run's sample time)."""

    body: object
    target: object
    weight: object = 1.0
    offset: Sequence[float] = (0.0, 0.0, 0.0)

    def to_data(self) -> dict:
        body = self.body if isinstance(self.body, str) else int(self.body)
        return {"kind": "point", "body": body, "target": _target_data(self.target), "weight": _numbers(self.weight), "offset": _numbers(list(self.offset))}


@dataclass(frozen=True)
class ControlCost:
    r"""$\tfrac12 \sum w_i (c - c_\mathrm{ref})_i^2$ on the controls (running only)."""

    weights: object
    reference: Optional[Sequence[float]] = None

    def to_data(self) -> dict:
        d = {"kind": "control", "weights": _numbers(self.weights)}
        if self.reference is not None:
            d["reference"] = _numbers(list(self.reference))
        return d


_COSTS = (JointCost, StateCost, BaseAttitudeCost, PointCost, ControlCost)


@dataclass(frozen=True)
class Problem:
    r"""An optimal-control problem: minimize $\sum_{k<T} h\,\ell(z_k, c_k) + \ell_T(z_T)$ over
    ``horizon`` steps of ``dt`` seconds in ``mode``, with $|c_i| \le$ ``control_limit``
    (one number or one per control; ``inf``: none). ``start_time``: the time (s, ≥ 0) of knot 0
    on the clock of the moving targets. ``discretization``: the knots' step, ``"rk4"`` (the
    simulator's RK4 step: a solution re-simulates exactly) or ``"euler"`` (semi-implicit Euler
    on the state manifold: one derivative evaluation per knot instead of four, a model that
    differs from the RK4 plant by $O(h)$). Checked by the core when made."""

    horizon: int
    dt: float
    running: Sequence[object] = ()
    terminal: Sequence[object] = ()
    mode: str = "floating"
    control_limit: object = math.inf
    start_time: float = 0.0
    discretization: str = "rk4"
    _data: dict = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        from ..errors import SpacearmTypeError

        for where in ("running", "terminal"):
            for c in getattr(self, where):
                if not isinstance(c, _COSTS):
                    raise SpacearmTypeError(f"{where} costs must be spacearm.mpc cost terms ({', '.join(t.__name__ for t in _COSTS)}), got {type(c).__name__}")
        data = {
            "horizon": self.horizon,
            "dt": self.dt,
            "mode": self.mode,
            "running": [c.to_data() for c in self.running],
            "terminal": [c.to_data() for c in self.terminal],
            "control_limit": _numbers(self.control_limit),
            "start_time": float(self.start_time),
            "discretization": self.discretization,
        }
        _core.check_spec("mpc_problem", data)
        object.__setattr__(self, "_data", data)

    def to_data(self) -> dict:
        """The problem as the core's plain data (``ProblemSpec``)."""
        return self._data


@dataclass(frozen=True)
class Solution:
    """The result of [`solve`][spacearm.mpc.solve]: the trajectory (``x``: ``(T+1, 7+N)``,
    ``u``: ``(T+1, 6+N)``), the controls (``controls``: ``(T, m)``; split into ``tau``,
    ``(T, N)``, and ``base_wrench``, ``(T, 6)``), the cost, the iterations, why the solver
    stopped (``stop``: ``"converged"``, ``"iteration_limit"``, ``"time_limit"``,
    ``"regularization_limit"``), the largest gap and the solve time (s)."""

    problem: Problem
    x: np.ndarray
    u: np.ndarray
    controls: np.ndarray
    tau: np.ndarray
    base_wrench: np.ndarray
    cost: float
    iterations: int
    steps: int
    converged: bool
    stop: str
    gap: float
    solve_time: float

    def resimulate(self, robot) -> float:
        """Replay the controls on the native simulator (``spacearm.Simulator``, RK4 at ``dt``,
        the problem's mode, each control held over its step) from ``x[0], u[0]``; returns the
        largest difference between the simulated states and the solution's (0 to rounding
        with ``discretization="rk4"``: the solver's step is the simulator's; with ``"euler"``,
        the difference between the plan's model and the RK4 plant)."""
        from ..sim.simulator import Simulator

        sim = Simulator(robot, dt=self.problem.dt, mode=self.problem.mode)
        sim.reset(self.x[0], self.u[0])
        worst = 0.0
        for k in range(self.problem.horizon):
            state = sim.step(self.tau[k], base_wrench=self.base_wrench[k])
            ref = np.concatenate([self.x[k + 1], self.u[k + 1]])
            if ref[6] * state[6] + ref[3:6] @ state[3:6] < 0:  # q and -q are one attitude
                state[3:7] = -state[3:7]
            worst = max(worst, float(np.max(np.abs(state - ref))))
        return worst


def solve(robot, problem: Problem, x0=None, u0=None, *, warm_start: Optional[Solution] = None, max_iterations: int = 100,
          time_limit: float = math.inf, tolerance: float = 1e-9) -> Solution:
    """Solve ``problem`` for ``robot`` from ``(x0, u0)`` (default: the neutral configuration at
    rest) by the core's FDDP, warm started from ``warm_start`` (a previous solution of a problem
    of the same horizon: its states and controls), within ``max_iterations`` iterations and
    ``time_limit`` seconds; ``tolerance`` on the predicted cost decrease."""
    if not isinstance(problem, Problem):
        from ..errors import SpacearmTypeError

        raise SpacearmTypeError(f"problem must be a spacearm.mpc.Problem, got {type(problem).__name__}")
    if warm_start is not None and not isinstance(warm_start, Solution):
        from ..errors import SpacearmTypeError

        raise SpacearmTypeError(f"warm_start must be a spacearm.mpc.Solution, got {type(warm_start).__name__}")
    x0 = robot.neutral_configuration() if x0 is None else vector(x0, "x0", robot.nx)
    u0 = robot.zero_velocity() if u0 is None else vector(u0, "u0", robot.nu)
    options = {"max_iterations": int(max_iterations), "time_limit": float(time_limit), "tolerance": float(tolerance)}
    states = controls = None
    if warm_start is not None:
        states = np.hstack([warm_start.x, warm_start.u])
        controls = warm_start.controls
    out = _core.mpc_solve(robot.core_model, problem.to_data(), x0, u0, options, states, controls)
    n, columns = robot.n_dof, out["control_columns"]
    t = problem.horizon
    tau, wrench = np.zeros((t, n)), np.zeros((t, 6))
    for i, col in enumerate(columns):
        if col >= 6:
            tau[:, col - 6] = out["controls"][:, i]
        else:
            wrench[:, col] = out["controls"][:, i]
    return Solution(
        problem=problem, x=out["x"], u=out["u"], controls=out["controls"], tau=tau, base_wrench=wrench, cost=out["cost"],
        iterations=out["iterations"], steps=out["steps"], converged=out["converged"], stop=out["stop"], gap=out["gap"],
        solve_time=out["solve_time"],
    )


def crocoddyl_action_model(robot, costs=None, *, mode: str = "floating", state=None):
    """A Crocoddyl differential action model backed by spacearm's forward dynamics and analytic
    derivatives (`spacearm.mpc.crocoddyl`, docs/mpc.md "Crocoddyl"; needs ``pip install crocoddyl``)."""
    from .crocoddyl import crocoddyl_action_model as make

    return make(robot, costs, mode=mode, state=state)
