"""Classical RK4 for the phases ``simulate`` cannot run (a wrench between two bodies, a loop
closure): the configuration ``x = [r0, quat0, q]`` is integrated through its own rate
``ẋ = [v0, ½ [ω0; 0] ⊗ quat0, q̇]`` (the quaternion re-normalized after every stage), which keeps
the method fourth order — unlike adding the stages' tangent increments, whose rotations do not
commute."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from ..rotations import quat_multiply

__all__ = ["configuration_rate", "rk4_step"]


def configuration_rate(x: np.ndarray, u: np.ndarray) -> np.ndarray:
    """``ẋ`` of a configuration under the generalized velocity ``u`` (ω0 in 𝒥: left product)."""
    w = u[3:6]
    return np.concatenate([u[:3], 0.5 * quat_multiply(np.array([w[0], w[1], w[2], 0.0]), x[3:7]), u[6:]])


def _normalized(x: np.ndarray) -> np.ndarray:
    x = x.copy()
    x[3:7] /= np.linalg.norm(x[3:7])
    return x


def rk4_step(t: float, h: float, xs: Sequence[np.ndarray], us: Sequence[np.ndarray],
             accelerations: Callable[[float, list, list], list]):
    """One RK4 step of several coupled systems: ``accelerations(t, xs, us)`` returns the ``du/dt``
    of each. Returns ``(xs, us)`` after the step."""
    def stage(tt, xx, uu):
        return [configuration_rate(x, u) for x, u in zip(xx, uu)], accelerations(tt, xx, uu)

    def shift(base_x, base_u, kx, ku, c):
        return [_normalized(x + c * dx) for x, dx in zip(base_x, kx)], [u + c * du for u, du in zip(base_u, ku)]

    k1x, k1u = stage(t, xs, us)
    x2, u2 = shift(xs, us, k1x, k1u, 0.5 * h)
    k2x, k2u = stage(t + 0.5 * h, x2, u2)
    x3, u3 = shift(xs, us, k2x, k2u, 0.5 * h)
    k3x, k3u = stage(t + 0.5 * h, x3, u3)
    x4, u4 = shift(xs, us, k3x, k3u, h)
    k4x, k4u = stage(t + h, x4, u4)
    out_x = [_normalized(x + h / 6.0 * (a + 2 * b + 2 * c + d)) for x, a, b, c, d in zip(xs, k1x, k2x, k3x, k4x)]
    out_u = [u + h / 6.0 * (a + 2 * b + 2 * c + d) for u, a, b, c, d in zip(us, k1u, k2u, k3u, k4u)]
    return out_x, out_u
