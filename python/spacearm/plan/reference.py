"""Re-simulating a plan: the plan as a sampled joint reference, tracked by the native
computed-torque controller.

The reference is the plan's own motion between the knots, not a spline through them: each
interval is cut into the plan's RK4 sub-steps, the states there come from the same RK4 map the
plan was built with ([`spacearm.casadi.rk4_step`][spacearm.casadi.rk4_step], torque linear between knots), and the
joint accelerations from forward dynamics under the torque of that instant. Those sub-step
states are the knots of a [`SampledJoint`][spacearm.control.SampledJoint], which the core interpolates
by quintic Hermite segments matching ``q``, ``qd`` and ``qdd`` at both ends (the torque is
continuous, so is the reference's ``qdd``). The native
[`ComputedTorque`][spacearm.control.ComputedTorque] on the reduced equations (paper eqs. 112–115),
``tau = H* (qdd_ref + kd ė + kp e) + c*``, then drives the plant; with the exact model it follows
the plan to integration accuracy, so the re-simulation checks the plan with an independent
integrator step rather than the optimiser's own report.
"""

from __future__ import annotations

import numpy as np

from ..casadi import forward_dynamics, rk4_step
from ..control import SampledJoint


def plan_reference(robot, plan, substeps: int) -> SampledJoint:
    """The plan's joint motion at its RK4 sub-steps, as a sampled reference (module docstring)."""
    step = rk4_step(robot, 1, torque="linear")
    fd = forward_dynamics(robot)
    zero = np.zeros(6)
    times, qs, qds, qdds = [], [], [], []
    for k in range(len(plan.t) - 1):
        h = (plan.t[k + 1] - plan.t[k]) / substeps
        x, u = plan.x[k], plan.u[k]
        for m in range(substeps):
            tau0 = plan.tau[k] + (plan.tau[k + 1] - plan.tau[k]) * (m / substeps)
            tau1 = plan.tau[k] + (plan.tau[k + 1] - plan.tau[k]) * ((m + 1) / substeps)
            times.append(plan.t[k] + m * h)
            qs.append(x[7:]), qds.append(u[6:]), qdds.append(np.array(fd(x, u, tau0, zero)).ravel()[6:])
            x, u = (np.array(v, dtype=float).ravel() for v in step(x, u, tau0, tau1, zero, h))
    # the last knot: the RK4 map's end state under the final torque
    times.append(plan.t[-1])
    qs.append(x[7:]), qds.append(u[6:]), qdds.append(np.array(fd(x, u, plan.tau[-1], zero)).ravel()[6:])
    return SampledJoint(np.array(times), np.array(qs), np.array(qds), np.array(qdds))
