"""Closed-form inverse of the base inertia ``H0`` (paper eqs. 52–61).

With the symmetric Schur complement ``S = H_S + M r̃_0g r̃_0g`` inverted by its adjugate,
``S⁻¹ = adj(S) / det(S)`` (eqs. 54–61),
``H0⁻¹ = [[E/M − r̃_0g S⁻¹ r̃_0g, r̃_0g S⁻¹], [−S⁻¹ r̃_0g, S⁻¹]]`` (eq. 52).
"""

from __future__ import annotations

from typing import NamedTuple

import sympy as sp

from .inertia import SymbolicInertia
from .kinematics import skew

__all__ = ["SchurInverse", "schur_inverse"]


class SchurInverse(NamedTuple):
    S: sp.Matrix  #: Schur complement (eq. 53)
    det_S: sp.Expr  #: its determinant
    adj_S: sp.Matrix  #: its adjugate (symmetric)
    S_inv: sp.Matrix  #: adj_S / det_S
    H0_inv: sp.Matrix  #: 6×6 (eq. 52)


def schur_inverse(b: SymbolicInertia, det_symbol: sp.Symbol = None) -> SchurInverse:
    """``H0⁻¹`` in closed form. With ``det_symbol`` the determinant stays a symbol in ``S_inv``
    and ``H0_inv`` (for printing); otherwise it is the expression ``det_S``."""
    rg = skew(b.r_0g)
    S = b.H_S + b.M * rg * rg
    S = sp.Matrix(3, 3, lambda i, j: S[min(i, j), max(i, j)])
    a = lambda i, j: S[i, j]  # noqa: E731
    adj = sp.Matrix([
        [a(1, 1) * a(2, 2) - a(1, 2) ** 2, a(0, 2) * a(1, 2) - a(0, 1) * a(2, 2), a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)],
        [0, a(0, 0) * a(2, 2) - a(0, 2) ** 2, a(0, 1) * a(0, 2) - a(0, 0) * a(1, 2)],
        [0, 0, a(0, 0) * a(1, 1) - a(0, 1) ** 2],
    ])
    for i in range(3):
        for j in range(i):
            adj[i, j] = adj[j, i]
    det = a(0, 0) * adj[0, 0] + a(0, 1) * adj[1, 0] + a(0, 2) * adj[2, 0]
    S_inv = adj / (det if det_symbol is None else det_symbol)
    H0_inv = sp.zeros(6, 6)
    H0_inv[0:3, 0:3] = sp.eye(3) / b.M - rg * S_inv * rg
    H0_inv[0:3, 3:6] = rg * S_inv
    H0_inv[3:6, 0:3] = -S_inv * rg
    H0_inv[3:6, 3:6] = S_inv
    return SchurInverse(S, det, adj, S_inv, H0_inv)
