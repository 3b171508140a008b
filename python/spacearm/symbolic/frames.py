"""From the base-frame derivation to the world frame 𝒥.

Every quantity is derived with the base CM at the origin and ``R0 = E``. None of them depends on
``r0`` (they involve only ``r_i − r0`` and ``r_i − p_j``), and each depends on the attitude ``R0``
covariantly: with ``T = blkdiag(R0, R0, E_N)``,

| quantity | world form |
| --- | --- |
| ``H``, ``H0``, ``H0⁻¹``, ``∂H/∂q_k`` | ``T X Tᵀ`` (6×6 blocks: ``blkdiag(R0, R0)``) |
| ``H_S`` | ``R0 X R0ᵀ`` |
| ``H0m``, ``J*``, ``J_0X``-rows, ``J_mX`` | ``T X`` (rows only) |
| ``J_TS``, ``H_Sq``, ``J_Ti``, ``J_Ri``, ``r_0g`` | ``R0 X`` |
| ``Hm``, ``H*`` | unchanged (invariant to the base pose) |
| ``c`` | ``T c_b(q, Tᵀu)``; ``c* = c*_b(q, Tᵀu)`` |
| ``Ḣ`` | ``T (Ḣ_b(q, q̇, ω_b)) Tᵀ``, ``Ḣ_b = Σ_k ∂H_b/∂q_k q̇_k + Ω̃_b H_b − H_b Ω̃_b`` |

(``ω_b = R0ᵀ ω0``, ``Ω̃_b = blkdiag(ω̃_b, ω̃_b, 0)``.) A transformation is described by
``(row_groups, col_groups)``: how many leading groups of three rows (columns) rotate with ``R0``.
"""

from __future__ import annotations

import numpy as np

from ..rotations import quat_to_matrix

__all__ = ["rotate", "quat_to_dcm", "to_base_velocity"]


def quat_to_dcm(quat) -> np.ndarray:
    """``R0`` of a (normalized here) quaternion ``[x, y, z, w]``."""
    q = np.asarray(quat, dtype=float)
    return quat_to_matrix(q / np.linalg.norm(q))


def rotate(X: np.ndarray, R0: np.ndarray, row_groups: int, col_groups: int) -> np.ndarray:
    """``Tr X Tcᵀ`` where ``Tr`` (``Tc``) rotates the first ``row_groups`` (``col_groups``)
    groups of three rows (columns) by ``R0``."""
    X = np.array(X, dtype=float, copy=True)
    for g in range(row_groups):
        X[3 * g:3 * g + 3] = R0 @ X[3 * g:3 * g + 3]
    for g in range(col_groups):
        X[:, 3 * g:3 * g + 3] = X[:, 3 * g:3 * g + 3] @ R0.T
    return X


def to_base_velocity(u: np.ndarray, R0: np.ndarray) -> np.ndarray:
    """``Tᵀ u``: base linear and angular velocity in base axes, joint rates unchanged."""
    u = np.array(u, dtype=float, copy=True)
    u[0:3] = R0.T @ u[0:3]
    u[3:6] = R0.T @ u[3:6]
    return u
