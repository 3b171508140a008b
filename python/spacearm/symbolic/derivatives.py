"""Joint-coordinate and time derivatives of the inertia matrices.

``∂X/∂q_k`` is exact symbolic differentiation of the base-frame expression (the world form is
``T (∂X_b/∂q_k) Tᵀ``, since ``R0`` does not depend on ``q``).

The total time derivative in the world frame of a quantity ``X = Tr X_b Tcᵀ``
(``spacearm.symbolic.frames``), with ``Ṫ = Ω̃ T`` (``Ω̃ = blkdiag(ω̃0, ω̃0, 0)``), is
``Ẋ = Tr (Σ_k ∂X_b/∂q_k q̇_k + Ω̃_b X_b − X_b Ω̃_bᵀ...)`` — precisely
``Ẋ_b = Σ_k ∂X_b/∂q_k q̇_k + Ω̃_r X_b − X_b Ω̃_c`` with ``Ω̃_r``/``Ω̃_c`` the row/column
rotation generators built from the base-frame angular velocity ``ω_b = R0ᵀ ω0``.
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

from .kinematics import skew

__all__ = ["partial", "joint_rate_derivative", "time_derivative", "rotation_generator"]


def partial(X: sp.Matrix, qk: sp.Symbol) -> sp.Matrix:
    """``∂X/∂q_k`` entry by entry (symmetric matrices differentiate their upper triangle only)."""
    n, m = X.shape
    if n == m and n > 1 and all(X[i, j] is X[j, i] or X[i, j] == X[j, i] for i in range(n) for j in range(i)):
        up = {(i, j): sp.diff(X[i, j], qk) for i in range(n) for j in range(i, n)}
        return sp.Matrix(n, n, lambda i, j: up[(min(i, j), max(i, j))])
    return X.diff(qk)


def joint_rate_derivative(partials: Sequence[sp.Matrix], qd: Sequence[sp.Symbol]) -> sp.Matrix:
    """``Σ_k ∂X/∂q_k q̇_k`` from precomputed partials."""
    out = sp.zeros(*partials[0].shape) if partials else None
    for P, r in zip(partials, qd):
        out = out + P * r
    return out


def rotation_generator(n: int, groups: int, w: sp.Matrix) -> sp.Matrix:
    """``blkdiag(w̃, …, w̃, 0)`` (``groups`` copies of ``w̃``) of size ``n``."""
    O = sp.zeros(n, n)
    for g in range(groups):
        O[3 * g:3 * g + 3, 3 * g:3 * g + 3] = skew(w)
    return O


def time_derivative(X: sp.Matrix, partials: Sequence[sp.Matrix], qd, w: sp.Matrix, row_groups: int, col_groups: int) -> sp.Matrix:
    """Base-frame form of ``dX/dt`` (see the module docstring)."""
    Xd = joint_rate_derivative(partials, qd) if partials else sp.zeros(*X.shape)
    if row_groups:
        Xd = Xd + rotation_generator(X.shape[0], row_groups, w) * X
    if col_groups:
        Xd = Xd - X * rotation_generator(X.shape[1], col_groups, w)
    return Xd
