"""Link and point Jacobians in closed form (paper eqs. 20–21, 104–108).

For every dof ``j`` on the path from the base to body ``i``:
``J_Ti[:, j] = k_j × (r_i − p_j)``, ``J_Ri[:, j] = k_j`` (revolute);
``J_Ti[:, j] = k_j``, ``J_Ri[:, j] = 0`` (prismatic); zero columns elsewhere.
Point ``X`` on body ``i``: ``J_0X = [[E, −r̃_0X], [0, E]]``, ``J_mX[:, j] = [k_j × (x − p_j); k_j]``.
All in the base frame (``r0 = 0``, ``R0 = E``); see ``spacearm.symbolic.frames``.
"""

from __future__ import annotations

import sympy as sp

from .kinematics import Kinematics, skew

__all__ = ["translational_jacobian", "rotational_jacobian", "point_jacobians"]


def _columns(kin: Kinematics, body: int, target: sp.Matrix, rotational: bool) -> sp.Matrix:
    J = sp.zeros(3, kin.n_dof)
    for j in kin.path[body]:
        b = kin.body_of_dof[j]
        k = kin.k[b]
        if rotational:
            col = k if kin.kind[b] == "revolute" else sp.zeros(3, 1)
        else:
            col = k.cross(target - kin.p[b]) if kin.kind[b] == "revolute" else k
        J[:, j] = col
    return J


def translational_jacobian(kin: Kinematics, body: int) -> sp.Matrix:
    """``J_Ti`` (3×N) of the CM of ``body`` (eq. 20)."""
    return _columns(kin, body, kin.r[body], rotational=False)


def rotational_jacobian(kin: Kinematics, body: int) -> sp.Matrix:
    """``J_Ri`` (3×N) of ``body`` (eq. 21)."""
    return _columns(kin, body, kin.r[body], rotational=True)


def point_jacobians(kin: Kinematics, body: int, offset):
    """``(J_0X, J_mX)`` (6×6, 6×N) of the point at ``offset`` on ``body`` (eqs. 104–108)."""
    x = kin.point(body, offset)
    J0 = sp.eye(6)
    J0[0:3, 3:6] = -skew(x)
    Jm = sp.zeros(6, kin.n_dof)
    Jm[0:3, :] = _columns(kin, body, x, rotational=False)
    Jm[3:6, :] = _columns(kin, body, x, rotational=True)
    return J0, Jm
