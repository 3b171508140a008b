"""The result of [`spacearm.plan.point_to_point`][spacearm.plan.point_to_point]: the plan, the solver's report, the
re-simulation and the figure."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from .._util.atomic import atomic_open
from ..errors import ArgumentError


def attitude_angle(quats: np.ndarray) -> np.ndarray:
    """Angle (rad) of each base attitude ``quats[k]`` relative to ``quats[0]``."""
    q = quats / np.linalg.norm(quats, axis=1, keepdims=True)
    c = q[0] * np.array([-1.0, -1.0, -1.0, 1.0])
    v = q[:, 3:4] * c[:3] + c[3] * q[:, :3] + np.cross(q[:, :3], c[:3])
    w = q[:, 3] * c[3] - q[:, :3] @ c[:3]
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=1), np.abs(w))


@dataclass
class Plan:
    """A planned point-to-point maneuver of a free-floating system, in spacearm's conventions
    (docs/conventions.md; SI units).

    ``t`` (K+1,) knot times; ``x`` (K+1, 7+N), ``u`` (K+1, 6+N) and ``tau`` (K+1, N) the
    states and joint torques at the knots, the torque linear between knots. ``status`` is
    IPOPT's return status and ``solver_success`` whether it converged; ``verification`` is the
    check of the plan by its shooting defect and its re-simulation ([`spacearm.plan.verify`][spacearm.plan.verify]),
    and ``success`` holds only if both the solver and the check passed (``failure`` says why
    not). A plan that did not succeed holds IPOPT's last iterate, which need not satisfy the
    constraints; [`point_to_point`][spacearm.plan.point_to_point] warns about it (``PlanCheckWarning``).
    """

    robot: Any = field(repr=False)
    objective: str
    target: np.ndarray
    point: Any
    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    tau: np.ndarray
    status: str
    solver_success: bool
    iterations: int
    cost: float
    solve_time: float  #: s, IPOPT's wall time
    substeps: int  #: RK4 steps per knot interval in the transcription
    warm_start: Any = field(default=None, repr=False)  #: the RMRC Motion used as initial guess, if any
    verification: Any = field(default=None, repr=False)  #: the check of the plan (``spacearm.plan.verify.Verification``)

    @property
    def success(self) -> bool:
        """IPOPT converged and the plan passed its check (defect and re-simulation)."""
        return bool(self.solver_success and self.verification is not None and self.verification.passed)

    @property
    def failure(self) -> Optional[str]:
        """Why the plan is not a success, in words (``None`` if it is)."""
        if self.success:
            return None
        reasons = [] if self.solver_success else [f"IPOPT did not solve it ({self.status} after {self.iterations} iterations)"]
        if self.verification is None:
            reasons.append("it was not checked")
        else:
            reasons.extend(self.verification.failures)
        return "; ".join(reasons)

    @property
    def resimulation(self):
        """The re-simulation of the check ([`resimulate`][spacearm.plan.Plan.resimulate] with its default gains), a
        [`Trajectory`][spacearm.Trajectory], or ``None`` if it failed."""
        return None if self.verification is None else self.verification.trajectory

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    @property
    def point_position(self) -> np.ndarray:
        """(K+1, 3) position of the planned point in 𝒥 at the knots."""
        return np.array([self.robot.point_position(xk, self.point) for xk in self.x])

    @property
    def final_position_error(self) -> float:
        """Distance (m) from the planned point's final position to the target."""
        return float(np.linalg.norm(self.point_position[-1] - self.target))

    @property
    def attitude_change(self) -> np.ndarray:
        """(K+1,) base rotation angle (rad) since ``t[0]``, at the knots."""
        return attitude_angle(self.x[:, 3:7])

    @property
    def effort(self) -> float:
        """``∫ |tau|² dt`` (N²·m²·s) by the trapezoidal rule over the knots."""
        sq = np.sum(self.tau ** 2, axis=1)
        return float(np.sum(0.5 * (sq[1:] + sq[:-1]) * np.diff(self.t)))

    def resimulate(self, kp: float = 400.0, kd: float = 40.0, dt: Optional[float] = None):
        """Run the plan in the native simulator ([`spacearm.simulate`][spacearm.simulate], floating mode, RK4)
        under the native computed torque tracking the plan's joint motion (``spacearm.plan.reference``),
        from the plan's initial state. ``dt`` defaults to a quarter of the plan's RK4 step (at
        most 0.01 s, so that the stiff tracking loop is integrated accurately), so the check uses
        another discretisation than the plan. Returns the
        [`Trajectory`][spacearm.Trajectory]."""
        from ..control import ComputedTorque
        from ..sim.simulation import simulate
        from .reference import plan_reference

        step = self.duration / ((len(self.t) - 1) * self.substeps)
        dt = min(0.25 * step, 0.01) if dt is None else float(dt)
        reference = plan_reference(self.robot, self, self.substeps)
        # Every joint follows the plan (wheels=[]: no joint is left to a base controller).
        return simulate(self.robot, self.duration, x0=self.x[0], u0=self.u[0], mode="floating", integrator="rk4", dt=dt,
                        controller=ComputedTorque(kp=float(kp), kd=float(kd), reference=reference), wheels=[], joint_limits=False)

    def save(self, path) -> str:
        """Write ``t``, ``x``, ``u``, ``tau``, ``target`` and the solver's report to an ``.npz``
        file (atomically); returns the path."""
        path = os.fspath(path)
        if not path.endswith(".npz"):
            raise ArgumentError(f"a plan is saved as .npz, got {path!r}")
        with atomic_open(path, "wb", suffix=".npz") as f:
            np.savez(f, t=self.t, x=self.x, u=self.u, tau=self.tau, target=self.target, objective=self.objective,
                     status=self.status, solver_success=self.solver_success, success=self.success,
                     defect=self.verification.defect if self.verification else np.nan,
                     resim_point_error=self.verification.point_error if self.verification else np.nan,
                     resim_attitude_error=self.verification.attitude_error if self.verification else np.nan, iterations=self.iterations, cost=self.cost,
                     robot=self.robot.name)
        return path

    def comparison(self):
        """The plan, its re-simulation (the check's: the native simulator under computed torque
        tracking the plan, [`resimulation`][spacearm.plan.Plan.resimulation]) and two other ways to make the same move, each
        over the plan's duration from its initial state: a rest-to-rest quintic joint move to the plan's final
        joint configuration (simulated under computed torque) and the RMRC motion to the target
        the plan was warm-started from (reactionless, or minimum-disturbance where the
        reactionless motion cannot reach the target). Returns ``{name: (t, attitude angle, |tau|, point path)}``."""
        from ..analysis.reactionless import move_to
        from ..control import ComputedTorque, QuinticJoint
        from ..sim.simulation import simulate

        robot = self.robot
        out = {f"plan ({self.objective})": (self.t, self.attitude_change, np.linalg.norm(self.tau, axis=1), self.point_position)}
        resim = self.resimulation
        if resim is not None:
            path = np.array([robot.point_position(xk, self.point) for xk in resim.x])
            out["re-simulation of the plan"] = (resim.t, resim.base_rotation_angle, np.linalg.norm(resim.tau, axis=1), path)
        ref = QuinticJoint(self.x[0][7:], self.x[-1][7:], 0.0, self.duration)
        traj = simulate(robot, self.duration, x0=self.x[0], u0=self.u[0], dt=self.duration / 400, joint_limits=False,
                        controller=ComputedTorque(kp=400.0, kd=40.0, reference=ref))
        path = np.array([robot.point_position(xk, self.point) for xk in traj.x])
        out["quintic joint move"] = (traj.t, traj.base_rotation_angle, np.linalg.norm(traj.tau, axis=1), path)
        motion = self.warm_start
        if motion is None:
            motion = move_to(robot, self.target, x0=self.x[0], point=self.point, strategy="reactionless",
                             duration=self.duration, settle=0.0, dt=self.duration / 400)
        times, qd = motion.times, motion.qd
        qdd = np.gradient(qd, times, axis=0)
        zero_momentum = [np.concatenate([robot.base_velocity_from_momentum(xk, qk), qk]) for xk, qk in zip(motion.x, qd)]
        torque = [np.linalg.norm(robot.generalized_inertia(xk) @ a + robot.generalized_bias(xk, uk))
                  for xk, uk, a in zip(motion.x, zero_momentum, qdd)]
        out[f"{motion.strategy.replace('_', '-')} RMRC"] = (times, motion.attitude_change, np.array(torque), motion.point_position)
        return out

    def figure(self, title: Optional[str] = None):
        """Base attitude change, joint-torque norm and point path (inertial x–y) of the plan,
        a quintic joint move to the same end configuration and the RMRC motion
        ([`comparison`][spacearm.plan.Plan.comparison]). Returns the matplotlib ``Figure`` (``spacearm.viz.plan.plan_figure``)."""
        from ..viz.plan import plan_figure

        return plan_figure(self, title)

    def plot(self, path, title: Optional[str] = None) -> str:
        """Write [`figure`][spacearm.plan.Plan.figure] to ``path`` in the format its suffix names (atomically); returns the path."""
        from ..viz.figures import plot_to

        return plot_to(path, lambda: self.figure(title), bbox_inches="tight")
