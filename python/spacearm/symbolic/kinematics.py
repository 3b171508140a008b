"""Forward kinematics in closed form (paper §2–3; frames of ``docs/conventions.md``).

Every body frame has its origin at the body's CM. For link ``i`` with parent ``p``:
``R_i = R_p · C_i · Rot(a_i, q_i)`` (revolute; ``C_i`` the fixed rotation of the model,
``Rot`` by Rodrigues' formula), joint position ``p_i = r_p + R_p · origin_i``, joint axis
``k_i = R_i a_i``, CM ``r_i = p_i + R_i · com_i`` (prismatic: ``com_i + a_i q_i``).

The chain is derived in the **base frame** (base CM at the origin, ``R0 = E``): every inertia
matrix is a function of the joint coordinates there, and the world form is a rotation of it
(``spacearm.symbolic.frames``). ``Kinematics.world`` gives the world form with the base
attitude as a direction-cosine matrix of symbols or as a unit quaternion.
"""

from __future__ import annotations

from typing import List, Optional

import sympy as sp

from ..rotations import quat_to_matrix
from .parameters import Parameters, exact_number
from ..errors import ArgumentError

__all__ = ["Kinematics", "skew", "rodrigues", "dcm_symbols", "quaternion_symbols", "quaternion_dcm"]


def skew(a) -> sp.Matrix:
    """Cross-product matrix ``ã`` (``ã b = a × b``)."""
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def rodrigues(axis: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """``Rot(a, θ) = cos θ E + sin θ ã + (1 − cos θ) a aᵀ`` for a unit axis ``a``."""
    c, s = sp.cos(angle), sp.sin(angle)
    return c * sp.eye(3) + s * skew(axis) + (1 - c) * (axis * axis.T)


def dcm_symbols() -> sp.Matrix:
    """The base attitude as a direction-cosine matrix of nine symbols ``R0_11 … R0_33``."""
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R0_{i + 1}{j + 1}", real=True))


def quaternion_symbols():
    """The base attitude quaternion ``[x, y, z, w]`` (scalar last, ``docs/conventions.md``) as symbols."""
    return sp.symbols("eta0_x eta0_y eta0_z eta0_w", real=True)


def quaternion_dcm(quat) -> sp.Matrix:
    """``R0`` of a unit quaternion ``[x, y, z, w]`` (Hamilton, scalar last)."""
    x, y, z, w = quat
    return sp.Matrix([
        [1 - 2 * (y**2 + z**2), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x**2 + z**2), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x**2 + y**2)],
    ])


def _exact_matrix(m) -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: exact_number(m[i][j]))


class Kinematics:
    """Closed-form kinematics of every body in the base frame.

    Attributes (lists indexed by body, 0 = base): ``R`` body-to-base rotations, ``r`` CM
    positions, ``p`` joint positions, ``k`` joint axes (zero for the base and fixed joints);
    ``dof_of_body`` (``None`` for the base and fixed joints), ``body_of_dof``, ``parent``,
    ``kind`` (``"base"``, ``"revolute"``, ``"prismatic"``, ``"fixed"``), ``path[i]`` the dofs
    on the path from the base to body ``i``; ``q`` the joint coordinate symbols ``q1 … qN``.
    """

    def __init__(self, params: Parameters):
        d = params.description
        links = d.links
        self.n_bodies = 1 + len(links)
        self.parent: List[Optional[int]] = [None]
        self.kind = ["base"]
        self.dof_of_body: List[Optional[int]] = [None]
        self.body_of_dof: List[int] = []
        for i, link in enumerate(links, start=1):
            self.parent.append(link.parent_index)
            self.kind.append(link.type)
            if link.type == "fixed":
                self.dof_of_body.append(None)
            else:
                self.dof_of_body.append(len(self.body_of_dof))
                self.body_of_dof.append(i)
        self.n_dof = len(self.body_of_dof)
        self.q = list(sp.symbols(f"q1:{self.n_dof + 1}", real=True)) if self.n_dof else []
        zero = sp.zeros(3, 1)
        self.R = [sp.eye(3)]
        self.r = [zero]
        self.p = [zero]
        self.k = [zero]
        self.path: List[List[int]] = [[]]
        for i, link in enumerate(links, start=1):
            par = self.parent[i]
            rp, Rp = self.r[par], self.R[par]
            C = _exact_matrix(quat_to_matrix(link.rotation))
            axis = sp.Matrix([exact_number(v) for v in link.axis]) if link.type != "fixed" else zero
            com = params.com[i]
            j = self.dof_of_body[i]
            if link.type == "revolute":
                Ri = Rp * C * rodrigues(axis, self.q[j])
            else:
                Ri = Rp * C
            if link.type == "prismatic":
                com = com + axis * self.q[j]
            pi = rp + Rp * params.origin[i]
            self.R.append(Ri)
            self.p.append(pi)
            self.k.append(Rp * C * axis)
            self.r.append(pi + Ri * com)
            self.path.append(self.path[par] + ([] if j is None else [j]))
        self.params = params

    def point(self, body: int, offset) -> sp.Matrix:
        """Base-frame position of a point fixed to ``body`` at ``offset`` (body frame, from its CM)."""
        off = sp.Matrix([exact_number(v) for v in offset])
        return self.r[body] + self.R[body] * off

    def world(self, attitude: str = "quaternion"):
        """World-frame kinematics with a symbolic base pose: ``(r0, R0, R, r, p, k)``.

        ``attitude="dcm"``: ``R0`` is a matrix of nine symbols ``R0_ij`` (the paper's DCM form);
        ``"quaternion"``: ``R0`` is the rotation of the unit quaternion
        ``[eta0_x, eta0_y, eta0_z, eta0_w]`` (the paper's quaternion form). ``R_i^𝒥 = R0 R_i``,
        ``r_i^𝒥 = r0 + R0 r_i`` and likewise for ``p_i``; ``k_i^𝒥 = R0 k_i``.
        """
        if attitude == "dcm":
            R0 = dcm_symbols()
        elif attitude == "quaternion":
            R0 = quaternion_dcm(quaternion_symbols())
        else:
            raise ArgumentError(f"attitude must be 'dcm' or 'quaternion', got {attitude!r}")
        r0 = sp.Matrix(sp.symbols("r0_x r0_y r0_z", real=True))
        return (r0, R0, [R0 * R for R in self.R], [r0 + R0 * r for r in self.r],
                [r0 + R0 * p for p in self.p], [R0 * k for k in self.k])
