"""Re-simulating a plan: the plan as a joint reference, tracked by computed torque in the
native simulator.

The reference is the plan's own motion between the knots, not a spline through them: each
interval is cut into the plan's RK4 sub-steps, the states there come from the same RK4 map the
plan was built with (:func:`spacearm.casadi.rk4_step`, torque linear between knots), the joint
accelerations from forward dynamics under the torque of that instant, and each sub-step is a
quintic Hermite segment matching ``q``, ``qd`` and ``qdd`` at both ends (the torque is
continuous, so is the reference's ``qdd``). The computed-torque law on the reduced equations (paper eqs. 112–115),
``tau = H* (qdd_ref + kd ė + kp e) + c*``, then drives the plant; with the exact model it
follows the plan to integration accuracy, so the re-simulation checks the plan with an
independent integrator step rather than the optimiser's own report.
"""

from __future__ import annotations

import numpy as np

from ..casadi import forward_dynamics, rk4_step

# Quintic Hermite: the polynomial in s ∈ [0, 1] with value, first and second derivative given
# at both ends; rows of _HERMITE map [p0, v0, a0, p1, v1, a1] (scaled to s) to coefficients.
_POWERS = np.arange(6)
_HERMITE = np.linalg.inv(np.array([
    [1, 0, 0, 0, 0, 0],
    [0, 1, 0, 0, 0, 0],
    [0, 0, 2, 0, 0, 0],
    [1, 1, 1, 1, 1, 1],
    [0, 1, 2, 3, 4, 5],
    [0, 0, 2, 6, 12, 20],
], dtype=float))


class PlanReference:
    """``(q, qd, qdd)`` of the plan at any time in ``[0, T]`` (clamped outside)."""

    def __init__(self, robot, plan, substeps: int):
        step = rk4_step(robot, 1, torque="linear")
        fd = forward_dynamics(robot)
        zero = np.zeros(6)
        n = robot.n_dof
        times, coeffs = [], []
        for k in range(len(plan.t) - 1):
            h = (plan.t[k + 1] - plan.t[k]) / substeps
            x, u = plan.x[k], plan.u[k]
            for m in range(substeps):
                tau0 = plan.tau[k] + (plan.tau[k + 1] - plan.tau[k]) * (m / substeps)
                tau1 = plan.tau[k] + (plan.tau[k + 1] - plan.tau[k]) * ((m + 1) / substeps)
                x1, u1 = (np.array(v, dtype=float).ravel() for v in step(x, u, tau0, tau1, zero, h))
                a0 = np.array(fd(x, u, tau0, zero)).ravel()[6:]
                a1 = np.array(fd(x1, u1, tau1, zero)).ravel()[6:]
                ends = np.stack([x[7:], u[6:] * h, a0 * h * h, x1[7:], u1[6:] * h, a1 * h * h])  # (6, n)
                times.append(plan.t[k] + m * h)
                coeffs.append(_HERMITE @ ends)
                x, u = x1, u1
        self._t = np.array(times + [plan.t[-1]])
        self._coeffs = np.array(coeffs).reshape(len(coeffs), 6, n)
        self._end = (plan.x[-1][7:], plan.u[-1][6:])

    def __call__(self, t: float):
        t = min(max(float(t), self._t[0]), self._t[-1])
        i = min(int(np.searchsorted(self._t, t, side="right")) - 1, len(self._coeffs) - 1)
        h = self._t[i + 1] - self._t[i]
        s = (t - self._t[i]) / h
        c = self._coeffs[i]
        q = (s ** _POWERS) @ c
        qd = (_POWERS[1:] * s ** (_POWERS[1:] - 1)) @ c[1:] / h
        qdd = (_POWERS[2:] * (_POWERS[2:] - 1) * s ** (_POWERS[2:] - 2)) @ c[2:] / (h * h)
        return q, qd, qdd


def computed_torque_tracking(robot, reference: PlanReference, kp: float, kd: float):
    """The control law ``fn(t, x, u) -> tau`` of :class:`spacearm.control.Callback`."""

    def law(t, x, u):
        q_ref, qd_ref, qdd_ref = reference(t)
        command = qdd_ref + kd * (qd_ref - u[6:]) + kp * (q_ref - x[7:])
        return robot.generalized_inertia(x) @ command + robot.generalized_bias(x, u)

    return law
