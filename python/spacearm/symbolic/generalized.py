"""Generalized (reduced) quantities in closed form: ``H*`` (eq. 45), ``c*`` and ``J*`` (eq. 110).

Writing ``A = J_TS``, ``B = H_Sq`` and ``H0m = [A; B]``, the Schur-form inverse of eq. 52 gives
``H0⁻¹ H0m = [A/M + r̃_0g Y; Y]`` with ``Y = S⁻¹ G`` and ``G = B − r̃_0g A``. Hence, without any
6×6 product,

- ``H* = Hm − H0mᵀ H0⁻¹ H0m = Hm − AᵀA/M − Gᵀ S⁻¹ G`` (eq. 45),
- ``c* = c_m − H0mᵀ H0⁻¹ c0 = c_m − Aᵀ c_v/M − Gᵀ S⁻¹ (c_w − r̃_0g c_v)`` (``c0 = [c_v; c_w]``),
- ``J* = J_mX − J_0X H0⁻¹ H0m = J_mX − [A/M + (r̃_0g − r̃_0X) Y; Y]`` (eq. 110),

with ``S⁻¹ = adj(S)/det(S)`` from ``spacearm.symbolic.schur``.
"""

from __future__ import annotations

import sympy as sp

from .inertia import SymbolicInertia
from .kinematics import skew
from .schur import SchurInverse

__all__ = ["coupling_G", "generalized_inertia", "generalized_bias", "generalized_jacobian"]


def coupling_G(b: SymbolicInertia) -> sp.Matrix:
    """``G = H_Sq − r̃_0g J_TS`` (3×N)."""
    return b.H_Sq - skew(b.r_0g) * b.J_TS


def generalized_inertia(b: SymbolicInertia, s: SchurInverse) -> sp.Matrix:
    """``H* = Hm − J_TSᵀ J_TS / M − Gᵀ S⁻¹ G`` (N×N, symmetric; eq. 45)."""
    G = coupling_G(b)
    n = b.Hm.shape[0]
    full = b.Hm - (b.J_TS.T * b.J_TS) / b.M - G.T * (s.S_inv * G)
    return sp.Matrix(n, n, lambda i, j: full[min(i, j), max(i, j)])


def generalized_bias(b: SymbolicInertia, s: SchurInverse, c: sp.Matrix) -> sp.Matrix:
    """``c* = c_m − J_TSᵀ c_v / M − Gᵀ S⁻¹ (c_w − r̃_0g c_v)`` (N) from the full bias ``c``."""
    cv, cw, cm = c[0:3, :], c[3:6, :], c[6:, :]
    G = coupling_G(b)
    return cm - (b.J_TS.T * cv) / b.M - G.T * (s.S_inv * (cw - skew(b.r_0g) * cv))


def generalized_jacobian(b: SymbolicInertia, s: SchurInverse, x: sp.Matrix, Jm: sp.Matrix) -> sp.Matrix:
    """``J*`` (6×N; eq. 110) of a point at base-frame position ``x`` with fixed-base Jacobian ``Jm``."""
    Y = s.S_inv * coupling_G(b)
    top = b.J_TS / b.M + (skew(b.r_0g) - skew(x)) * Y
    return Jm - sp.Matrix.vstack(top, Y)
