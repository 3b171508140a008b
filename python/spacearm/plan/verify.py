r"""The check of a plan after the solve, whatever IPOPT said (docs/optimal-control.md, "Checks").

Two numbers decide whether a plan is one:

- the **defect** of the transcription: the largest residual of the shooting constraints
  $y_{k+1} - \Phi(y_k, \tau_k, \tau_{k+1}, T/K)$ at the returned knots, $\Phi$ being the plan's own RK4
  map ([`rk4_step`][spacearm.casadi.rk4_step]); a plan whose knots do not follow its own dynamics is
  no plan, whatever the solver's status;
- the **re-simulation**: the plan's joint motion tracked by the native computed-torque
  controller in the native simulator ([`Plan.resimulate`][spacearm.plan.Plan.resimulate], another step size). The
  re-simulated point must end within ``POINT_TOLERANCE`` of the target, and the
  re-simulated base attitude must stay, at every knot, within ``ATTITUDE_RELATIVE`` of the
  plan's largest base rotation (at least ``ATTITUDE_FLOOR``) of the planned attitude. This
  catches a plan that exploits the error of its own discretisation: its knots satisfy the
  shooting constraints, but the continuous dynamics along the same joint path turn the base
  otherwise and miss the target.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional, Tuple

import numpy as np

from ..errors import SpacearmError

#: Largest shooting-constraint residual of an accepted plan (state units: m, quaternion
#: components, rad, m/s, rad/s).
DEFECT_TOLERANCE = 1e-6
#: Largest distance (m) of the re-simulated point from the target at the end.
POINT_TOLERANCE = 1e-3
#: Largest angle between the re-simulated and the planned base attitude at a knot, as a
#: fraction of the plan's largest base rotation ...
ATTITUDE_RELATIVE = 0.1
#: ... and at least this (rad), for plans that hardly turn the base.
ATTITUDE_FLOOR = 1e-5


def quaternion_angle(qa: np.ndarray, qb: np.ndarray) -> np.ndarray:
    """Angle (rad) of the rotation between unit quaternions ``qa[k]`` and ``qb[k]`` (rows)."""
    dot = np.abs(np.sum(qa * qb, axis=-1)) / (np.linalg.norm(qa, axis=-1) * np.linalg.norm(qb, axis=-1))
    return 2.0 * np.arccos(np.clip(dot, 0.0, 1.0))


@dataclass(frozen=True)
class Verification:
    """What the check of a plan found ([`verify`][spacearm.plan.verify.verify]); ``passed`` if every number is within
    its tolerance. ``failures`` says, in words, which are not."""

    defect: float  #: largest shooting-constraint residual at the knots
    transcription_error: float  #: estimate of the RK4 map's local error ([`transcription_error`][spacearm.plan.verify.transcription_error])
    point_error: float  #: m, re-simulated point at ``T`` from the target (inf if it failed)
    attitude_error: float  #: rad, largest angle between re-simulated and planned base attitude at the knots
    attitude_tolerance: float  #: rad, the bound ``attitude_error`` is held to
    failures: Tuple[str, ...]
    trajectory: Any = field(default=None, repr=False)  #: the re-simulation (Trajectory), None if it failed

    @property
    def passed(self) -> bool:
        return not self.failures


def _interval_ends(plan, substeps: int) -> np.ndarray:
    """``[x; u]`` at the end of every interval (K, 13+2N): ``substeps`` RK4 steps of the plan's
    map ([`rk4_step`][spacearm.casadi.rk4_step], torque linear) from each knot under its torques."""
    from ..casadi import rk4_step

    K = len(plan.t) - 1
    step = rk4_step(plan.robot, substeps, torque="linear").map(K)
    x_next, u_next = step(plan.x[:-1].T, plan.u[:-1].T, plan.tau[:-1].T, plan.tau[1:].T, np.zeros((6, K)), np.diff(plan.t)[None, :])
    return np.concatenate([np.array(x_next, dtype=float).T, np.array(u_next, dtype=float).T], axis=1)


def _max_abs(a: np.ndarray) -> float:
    return float(np.max(np.abs(a))) if np.all(np.isfinite(a)) else float("inf")


def shooting_defect(plan) -> float:
    """Largest residual of the plan's shooting constraints at its knots (module docstring)."""
    return _max_abs(_interval_ends(plan, plan.substeps) - np.concatenate([plan.x[1:], plan.u[1:]], axis=1))


def transcription_error(plan) -> float:
    """Estimate of the local error of the plan's RK4 map: the largest difference, over the
    intervals, between ``substeps`` and ``2 * substeps`` RK4 steps from the same knot under the
    same torques (Richardson: RK4's local error falls 32-fold when the step halves, so this is
    the coarse map's error to within 1/31). State units; reported, not a criterion (the
    re-simulation is)."""
    return _max_abs(_interval_ends(plan, plan.substeps) - _interval_ends(plan, 2 * plan.substeps))


def verify(plan) -> Verification:
    """Check ``plan`` by its defect and its re-simulation (module docstring)."""
    failures = []
    defect = shooting_defect(plan)
    if not defect <= DEFECT_TOLERANCE:
        failures.append(f"its knots do not follow its own dynamics (shooting defect {defect:.3g}, tolerance {DEFECT_TOLERANCE:g})")
    terr = transcription_error(plan)
    planned_rotation = float(np.max(plan.attitude_change))
    attitude_tolerance = max(ATTITUDE_RELATIVE * planned_rotation, ATTITUDE_FLOOR)
    trajectory: Optional[Any] = None
    try:
        trajectory = plan.resimulate()
    except SpacearmError as exc:
        failures.append(f"its re-simulation failed ({exc})")
        return Verification(defect, terr, float("inf"), float("inf"), attitude_tolerance, tuple(failures))
    point_error = float(np.linalg.norm(plan.robot.point_position(trajectory.x[-1], plan.point) - plan.target))
    knots = np.clip(np.searchsorted(trajectory.t, plan.t - 1e-9 * plan.duration), 0, len(trajectory.t) - 1)
    attitude_error = float(np.max(quaternion_angle(trajectory.x[knots, 3:7], plan.x[:, 3:7])))
    if not point_error <= POINT_TOLERANCE:
        failures.append(f"its re-simulation ends {point_error * 1e3:.3g} mm from the target (tolerance {POINT_TOLERANCE * 1e3:g} mm)")
    if not attitude_error <= attitude_tolerance:
        failures.append(f"its re-simulated base attitude departs from the plan's by {np.degrees(attitude_error):.3g} deg "
                        f"(tolerance {np.degrees(attitude_tolerance):.3g} deg: {ATTITUDE_RELATIVE:g} of the planned "
                        f"{np.degrees(planned_rotation):.3g} deg, at least {np.degrees(ATTITUDE_FLOOR):.2g} deg)")
    return Verification(defect, terr, point_error, attitude_error, attitude_tolerance, tuple(failures), trajectory)

