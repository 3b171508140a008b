"""Tangent coordinates of the configuration (docs/derivatives.md).

The base attitude is a quasi-coordinate, so configuration increments live in the tangent space
of dimension ``6 + N``: ``dx = [dr0 (3), dtheta (3), dq (N)]``, where ``dtheta`` is a rotation
increment about the axes of the inertial frame 𝒥 applied on the left, ``R0 <- exp(dtheta^) R0``.
The time derivative of ``x`` in these coordinates is the generalized velocity ``u`` itself.
Every derivative with respect to ``x`` (``Robot.mass_matrix_partials``,
``Robot.forward_dynamics_derivatives``, ``Robot.linearize``...) uses them.
"""

from __future__ import annotations

import numpy as np

from .._util.arrays import vector
from ..errors import NonFiniteError, QuaternionError
from ..rotations import _finite_rotation_angle, quat_exp, quat_log, quat_multiply

__all__ = ["configuration_plus", "configuration_difference"]


def _checked(x: np.ndarray, name: str) -> np.ndarray:
    """A configuration with finite entries and a unit quaternion (tolerance 1e-6, as the core)."""
    if not np.all(np.isfinite(x)):
        raise NonFiniteError(f"{name} must be finite, got {x}")
    norm = float(np.linalg.norm(x[3:7]))
    if abs(norm - 1.0) > 1e-6:
        raise QuaternionError(f"the base quaternion {name}[3:7] must have unit norm (tolerance 1e-6), got norm {norm}")
    return x


def configuration_plus(x, dx, n_dof: int) -> np.ndarray:
    r"""$x \oplus \delta x$: $r_0 + \delta r_0$, $R_0 \leftarrow \exp([\delta\theta]_\times) R_0$, $q + \delta q$ (``dx`` $= \delta x$ of length 6+N)."""
    x = _checked(vector(x, "x", 7 + n_dof), "x")
    dx = vector(dx, "dx", 6 + n_dof)
    if not np.all(np.isfinite(dx)):
        raise NonFiniteError(f"dx must be finite, got {dx}")
    _finite_rotation_angle(dx[3:6], "dx[3:6] (the attitude increment)")
    quat = quat_multiply(quat_exp(dx[3:6]), x[3:7])
    with np.errstate(over="ignore", invalid="ignore"):
        out = np.concatenate([x[0:3] + dx[0:3], quat / np.linalg.norm(quat), x[7:] + dx[6:]])
    if not np.all(np.isfinite(out)):
        bad = np.flatnonzero(~np.isfinite(out))
        raise NonFiniteError(f"x ⊕ dx overflows: components {bad.tolist()} of the result are not finite "
                             f"(|x| + |dx| beyond the largest float, {np.finfo(float).max:.3g})")
    return out


def configuration_difference(x1, x0, n_dof: int) -> np.ndarray:
    r"""``dx`` $= \delta x$ with $x_0 \oplus \delta x = x_1$ (the attitude part is $\log(R_1 R_0^T)$, length $\le \pi$)."""
    x1 = _checked(vector(x1, "x1", 7 + n_dof), "x1")
    x0 = _checked(vector(x0, "x0", 7 + n_dof), "x0")
    q0 = x0[3:7]
    conj = np.array([-q0[0], -q0[1], -q0[2], q0[3]])
    dtheta = quat_log(quat_multiply(x1[3:7], conj))
    return np.concatenate([x1[0:3] - x0[0:3], dtheta, x1[7:] - x0[7:]])
