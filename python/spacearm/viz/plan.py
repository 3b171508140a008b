"""The figure of a plan (``plan_figure``): the plan and its re-simulation in the native
simulator beside a quintic joint move and the RMRC motion to the same target
([`spacearm.plan.result.Plan.comparison`][spacearm.plan.Plan.comparison])."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .figures import new_figure

__all__ = ["plan_figure"]


def plan_figure(plan, title: Optional[str] = None):
    """Base attitude change, joint-torque norm and point path (inertial x–y) of the plan, its
    re-simulation (dashed), a quintic joint move to the same end configuration and the RMRC motion
    ([`Plan.comparison`][spacearm.plan.Plan.comparison]). Returns the matplotlib ``Figure``."""
    fig = new_figure(figsize=(13, 4.2))
    ax_att, ax_tau, ax_path = fig.subplots(1, 3)
    for name, (t, angle, torque, path) in plan.comparison().items():
        effort = np.sum(0.5 * (torque[1:] ** 2 + torque[:-1] ** 2) * np.diff(t))
        style = {"ls": "--", "color": "k", "lw": 1.0} if name.startswith("re-simulation") else {}
        ax_att.plot(t, np.degrees(angle), label=f"{name}: max {np.degrees(np.nanmax(angle)):.3g}°", **style)
        ax_tau.plot(t, torque, label=f"{name}: ∫|τ|²dt = {effort:.3g}", **style)
        ax_path.plot(path[:, 0], path[:, 1], label=name, **style)
    ax_path.plot([plan.target[0]], [plan.target[1]], "r*", ms=12, label="target")
    ax_att.set_xlabel("t (s)")
    ax_att.set_ylabel("base attitude change (deg)")
    ax_att.set_title("base attitude disturbance", fontsize=10)
    ax_tau.set_xlabel("t (s)")
    ax_tau.set_ylabel("|τ| (N·m)")
    ax_tau.set_title("joint effort", fontsize=10)
    ax_path.set_xlabel("x (m)")
    ax_path.set_ylabel("y (m)")
    ax_path.set_aspect("equal", adjustable="datalim")
    ax_path.set_title("point path (inertial x–y)", fontsize=10)
    for ax in (ax_att, ax_tau, ax_path):
        ax.legend(fontsize=7)
    check = plan.verification
    verdict = "checked" if plan.success else "FAILED its check"
    if check is not None and check.trajectory is not None:
        verdict += (f": re-simulation {check.point_error * 1e3:.2g} mm from the target, attitude within "
                    f"{np.degrees(check.attitude_error):.2g}° of the plan")
    fig.suptitle(title or (f"{plan.robot.name}: planned maneuver ({plan.objective}, T = {plan.duration:g} s, "
                           f"{len(plan.t) - 1} intervals; IPOPT: {plan.status}; {verdict})"), fontsize=10)
    return fig
