"""The checks of a target before any solve (docs/optimal-control.md, "Checks of the target"):
a target no motion can reach is refused in milliseconds, with the reason, instead of being
found out by IPOPT after minutes.

The numbers are the core's (``spacearm_core::analysis::reach``): where the system CM will be
at the end of the maneuver, the largest distance of the point from it in any configuration
(Vafa & Dubowsky's virtual manipulator, ``R_max = Σ |V_b|``) and, for a planar system in a
planar state, the plane the point cannot leave. The joint limits enter through the initial
configuration (it must satisfy them) and through [`JointBounds`][spacearm.plan.JointBounds]; ``R_max``
ignores position limits, so a target inside it may still be out of reach of a limited arm
(then IPOPT's status and the plan's check say so).
"""

from __future__ import annotations

import numpy as np

from .. import _core
from ..errors import ArgumentError

#: How far (m) off the plane of a planar system a target may be (rounding of the input).
PLANE_TOLERANCE = 1e-6


def check_target(robot, x0: np.ndarray, u0: np.ndarray, target: np.ndarray, point, duration: float, bounds) -> None:
    """Raise [`ArgumentError`][spacearm.errors.ArgumentError] naming the reason if ``point`` of
    ``robot`` cannot be at ``target`` after ``duration`` s from ``(x0, u0)`` (module docstring)."""
    q0 = x0[7:]
    outside = np.flatnonzero((q0 < bounds.lower) | (q0 > bounds.upper))
    if outside.size:
        names = robot.joint_names
        raise ArgumentError("the initial joint configuration is outside the position limits: "
                            + ", ".join(f"{names[j]} = {q0[j]:.6g} not in [{bounds.lower[j]:.6g}, {bounds.upper[j]:.6g}]" for j in outside))
    body, offset = robot.resolve_point(point)
    center, radius, plane = _core.analysis_reach(robot.core_model, x0, u0, body, offset, float(duration))
    if plane is not None:
        normal, on_plane = plane
        off = float(np.dot(target - on_plane, normal))
        if abs(off) > PLANE_TOLERANCE:
            raise ArgumentError(f"the target {target} is {abs(off):.6g} m off the plane {robot.name} moves in (normal "
                                f"{np.round(normal, 12)} through {np.round(on_plane, 12)}): every joint axis, mass and the point lie "
                                "in that plane and the state moves in it, so the point cannot leave it")
    if radius is not None:
        distance = float(np.linalg.norm(target - center))
        if distance > radius:
            raise ArgumentError(f"the target {target} is out of reach of {robot.name}: it is {distance:.6g} m from where the "
                                f"system CM will be at t = {duration:g} s ({np.round(center, 6)}), and no configuration puts "
                                f"the point farther than {radius:.6g} m from it (the free-floating reach, "
                                "docs/optimal-control.md)")
