"""The paper's inertia blocks in closed form (eqs. 27–36), in the base frame.

- ``H_S  = I0 + Σ (I_i + m_i r̃_0iᵀ r̃_0i)`` (eq. 29), ``I_i = R_i I_i^body R_iᵀ``
- ``J_TS = Σ m_i J_Ti``, ``H_Sq = Σ (I_i J_Ri + m_i r̃_0i J_Ti)`` (eqs. 32–33)
- ``H0 = [[M E, −M r̃_0g], [M r̃_0g, H_S]]`` (eq. 30), ``H0m = [J_TS; H_Sq]`` (eq. 31)
- ``Hm = Σ (J_Riᵀ I_i J_Ri + m_i J_Tiᵀ J_Ti)`` (eq. 34), ``H = [[H0, H0m], [H0mᵀ, Hm]]`` (eq. 36)

In the base frame ``r_0i = r_i`` (the base CM is the origin) and ``R0 = E``.
"""

from __future__ import annotations

from typing import NamedTuple

import sympy as sp

from .jacobians import rotational_jacobian, translational_jacobian
from .kinematics import Kinematics, skew

__all__ = ["SymbolicInertia", "inertia_blocks", "assemble"]


class SymbolicInertia(NamedTuple):
    M: sp.Expr
    r_0g: sp.Matrix
    H_S: sp.Matrix
    J_TS: sp.Matrix
    H_Sq: sp.Matrix
    H0: sp.Matrix
    H0m: sp.Matrix
    Hm: sp.Matrix


def _symmetric(m: sp.Matrix) -> sp.Matrix:
    """Mirror the upper triangle (the lower one is the same expression in another order)."""
    n = m.shape[0]
    return sp.Matrix(n, n, lambda i, j: m[i, j] if i <= j else m[j, i])


def inertia_blocks(kin: Kinematics) -> SymbolicInertia:
    par = kin.params
    n = kin.n_dof
    M = par.total_mass
    H_S = par.inertia[0]
    J_TS = sp.zeros(3, n)
    H_Sq = sp.zeros(3, n)
    Hm = sp.zeros(n, n)
    msum = sp.zeros(3, 1)
    for i in range(1, kin.n_bodies):
        m, R, r = par.mass[i], kin.R[i], kin.r[i]
        Ii = R * par.inertia[i] * R.T
        JT = translational_jacobian(kin, i)
        JR = rotational_jacobian(kin, i)
        rt = skew(r)
        H_S = H_S + Ii + m * (rt.T * rt)
        J_TS = J_TS + m * JT
        H_Sq = H_Sq + Ii * JR + m * (rt * JT)
        Hm = Hm + JR.T * Ii * JR + m * (JT.T * JT)
        msum = msum + m * r
    r_0g = msum / M
    H_S = _symmetric(H_S)
    Hm = _symmetric(Hm)
    H0 = sp.zeros(6, 6)
    H0[0:3, 0:3] = M * sp.eye(3)
    H0[0:3, 3:6] = -M * skew(r_0g)
    H0[3:6, 0:3] = M * skew(r_0g)
    H0[3:6, 3:6] = H_S
    H0m = sp.Matrix.vstack(J_TS, H_Sq)
    return SymbolicInertia(M, r_0g, H_S, J_TS, H_Sq, H0, H0m, Hm)


def assemble(b: SymbolicInertia) -> sp.Matrix:
    """``H = [[H0, H0m], [H0mᵀ, Hm]]`` (eq. 36)."""
    return sp.Matrix.vstack(sp.Matrix.hstack(b.H0, b.H0m), sp.Matrix.hstack(b.H0m.T, b.Hm))
