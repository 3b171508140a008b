"""The bias vector ``c(x, u)`` from the Lagrangian: ``Ḣ`` and ``∂H/∂q`` with the quasi-coordinate
correction for the base angular velocity.

``T = ½ uᵀ H u`` with ``u = [v0; ω0; q̇]``. ``r0`` and ``q`` are true coordinates (``H`` does not
depend on ``r0``), but ``ω0`` is a quasi-velocity: there is no attitude coordinate whose rate it
is. Lagrange's equations in Hamel's form for the world-frame angular velocity read
``d/dt(∂T/∂ω0) − ∂T/∂θ − ω0 × ∂T/∂ω0 = N0``, where ``∂T/∂θ`` is the change of ``T`` under a
small rotation ``δθ`` of the whole system about the base CM at fixed ``u``. Since ``H`` rotates
as ``T H_b Tᵀ``, ``∂T/∂θ = −(v0 × P + ω0 × L)`` with ``[P; L] = H0 ẋ0 + H0m q̇`` (the upper six
rows of ``H u``). The ``ω0 × L`` terms cancel and

``c = Ḣ u − [0; −v0 × P; (½ uᵀ ∂H/∂q_k u)_k]``,

with ``Ḣ`` the total time derivative of the world-frame ``H`` (``.derivatives``). A single
rigid body checks the signs: ``c = [0; ω × Iω]`` (Euler). In the base frame this is evaluated as
``c_b = Σ_k q̇_k ∂H_b/∂q_k u_b + [ω × P; ω × L + v × P; 0] − H_b[:, 0:3](ω × v) − [0; 0; ½ u_bᵀ ∂H_b/∂q_k u_b]``
with ``u_b = Tᵀ u = [v; ω; q̇]``; the world bias is ``T c_b``. The test suite holds it against
the recursive Newton–Euler bias of the Rust core (``Robot.bias_forces``).
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

__all__ = ["bias_from_lagrangian"]


def bias_from_lagrangian(H: sp.Matrix, dH: Sequence[sp.Matrix], ub: sp.Matrix) -> sp.Matrix:
    """Base-frame bias ``c_b`` from ``H_b``, its partials ``∂H_b/∂q_k`` and ``u_b``."""
    n = H.shape[0]
    N = n - 6
    v, w, qd = ub[0:3, :], ub[3:6, :], ub[6:, :]
    Hu = H * ub
    P, L = Hu[0:3, :], Hu[3:6, :]
    c = sp.zeros(n, 1)
    for k in range(N):
        dHu = dH[k] * ub
        c = c + qd[k] * dHu
        c[6 + k] = c[6 + k] - (ub.T * dHu)[0] / 2
    c[0:3, :] = c[0:3, :] + w.cross(P)
    c[3:6, :] = c[3:6, :] + w.cross(L) + v.cross(P)
    c = c - H[:, 0:3] * w.cross(v)
    return c
