r"""Free-floating kinematics: the base motion that follows from prescribed joint motion when the
system momentum is conserved (zero by default). Exact by momentum conservation — no dynamics
or joint torques are involved: $[v_0; \omega_0] = H_0^{-1} (M_0 - H_{0m} \dot q)$ (paper eqs. 43, 109) is
integrated with RK4 on the quaternion (renormalized). See ``docs/reactionless.md``.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .. import _core
from .._util.arrays import number, quaternion, vector3
from ..errors import ArgumentError

__all__ = ["integrate_prescribed", "attitude_change"]


def integrate_prescribed(robot, q_of_t: Callable, qd_of_t: Callable, t_end: float, dt: float, x0=None,
                         P=(0.0, 0.0, 0.0), L=(0.0, 0.0, 0.0)):
    """Base pose under the joint motion ``q(t)``, ``q̇(t)`` (callables returning N values) for
    ``t`` in ``[0, t_end]`` with RK4 steps ``dt``. ``x0`` gives the initial base pose (default:
    at the origin, aligned with 𝒥); its ``q`` part is replaced by ``q(0)``. Returns
    ``(times (K+1), x (K+1, 7+N))``."""
    t_end, dt = number(t_end, "t_end"), number(dt, "dt")
    if not (np.isfinite(t_end) and t_end > 0 and np.isfinite(dt) and dt > 0):
        raise ArgumentError(f"t_end and dt must be finite and > 0, got {t_end} and {dt}")
    k = max(1, int(round(t_end / dt)))
    h = t_end / k
    half = np.linspace(0.0, t_end, 2 * k + 1)
    q = np.array([np.asarray(q_of_t(t), dtype=float) for t in half])
    qd = np.array([np.asarray(qd_of_t(t), dtype=float) for t in half])
    x = robot.neutral_configuration(q=q[0]) if x0 is None else np.array(x0, dtype=float)
    x[7:] = q[0]
    xs = _core.analysis_integrate_prescribed(robot.core_model, x, h, q, qd, vector3(P, "P"), vector3(L, "L"))
    return half[::2], xs


def attitude_change(quat_a, quat_b) -> float:
    """Rotation angle (rad, 0..π) between two attitudes given as ``[x, y, z, w]`` quaternions
    (or scipy ``Rotation`` objects)."""
    a, b = quaternion(quat_a, "quat_a"), quaternion(quat_b, "quat_b")
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    return float(2.0 * np.arccos(min(1.0, abs(float(np.dot(a, b))))))
