"""The recursive algorithms of the Rust core, written once more on CasADi symbols.

Everything is built from :attr:`Robot.description` (the typed model parameters), never from a
closed form: forward kinematics, RNEA (inverse dynamics and the bias ``c``), CRBA (``H``), the
articulated-body algorithm (forward dynamics), point Jacobians and momentum. The expression
graphs therefore grow linearly (ABA, RNEA) or quadratically (CRBA) with the number of joints,
and a 30-joint model builds in well under a second (docs/optimal-control.md gives the
measurement).

Frames (docs/conventions.md): ``x = [r0, quat0 [x, y, z, w], q]``, ``u = [v0, w0, qd]`` with
``v0``, ``w0`` in 𝒥; spatial vectors ``[linear; angular]`` with the axes of 𝒥 about the point
that coincides with the base CM (see :mod:`._spatial`). With that reference point the base's
spatial velocity is ``[v0; w0]``, a spatial force on the base is ``[F0; N0]``, and the base's
spatial acceleration is ``[dv0/dt − w0 × v0; dw0/dt]`` because ``dv0/dt`` is classical.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from ..rotations import quat_to_matrix
from ._spatial import axis_rotation, body_inertia, force_cross, motion_cross, quaternion_to_matrix, skew


@dataclass
class _Body:
    """One link's constants, read from its :class:`~spacearm.description.LinkDescription`."""

    parent: int  #: body index of the parent (0 = base)
    kind: str  #: "revolute", "prismatic" or "fixed"
    axis: np.ndarray  #: unit axis in the link frame
    origin: np.ndarray  #: joint position in the parent frame, from the parent's CM
    rotation: np.ndarray  #: link frame in the parent frame at q = 0 (3×3)
    com: np.ndarray  #: CM from the joint, in the link frame
    mass: float
    inertia: np.ndarray  #: about the CM, link axes
    dof: Optional[int]


class Kinematics:
    """Forward kinematics of every body at the symbolic configuration ``x``, and the spatial
    quantities the recursions share (motion subspaces and spatial inertias about the base CM)."""

    def __init__(self, ca, description, x):
        self.ca = ca
        n = sum(1 for link in description.links if link.dof is not None)
        self.n_dof = n
        self.bodies: List[_Body] = [
            _Body(link.parent_index, link.type, np.asarray(link.axis), np.asarray(link.origin), quat_to_matrix(link.rotation),
                  np.asarray(link.com), link.mass, np.asarray(link.inertia), link.dof)
            for link in description.links
        ]
        self.r0 = x[0:3]
        self.q = x[7:7 + n]
        R0 = quaternion_to_matrix(ca, x[3:7])
        #: rotation body -> 𝒥 and CM position in 𝒥, per body (0 = base)
        self.rotation = [R0]
        self.com = [self.r0]
        #: motion subspace (6-vector about the base CM) of each body's joint, None if fixed
        self.subspace: List[Optional[object]] = [None]
        for body in self.bodies:
            Rp, rp = self.rotation[body.parent], self.com[body.parent]
            joint = rp + ca.mtimes(Rp, body.origin)
            R = ca.mtimes(Rp, body.rotation)
            com_local = body.com
            if body.kind == "revolute":
                R = ca.mtimes(R, axis_rotation(ca, body.axis, self.q[body.dof]))
            elif body.kind == "prismatic":
                com_local = body.com + body.axis * self.q[body.dof]
            self.rotation.append(R)
            self.com.append(joint + ca.mtimes(R, com_local))
            if body.kind == "fixed":
                self.subspace.append(None)
                continue
            k = ca.mtimes(R, body.axis)  # joint axis in 𝒥
            if body.kind == "revolute":
                # twist about the base CM of a unit rotation about the axis through `joint`
                self.subspace.append(ca.vertcat(ca.cross(joint - self.r0, k), k))
            else:
                self.subspace.append(ca.vertcat(k, ca.DM.zeros(3)))
        base = description.base
        self.inertia = [body_inertia(ca, base.mass, ca.DM.zeros(3), ca.mtimes([R0, np.asarray(base.inertia), R0.T]))]
        for i, body in enumerate(self.bodies, start=1):
            R = self.rotation[i]
            self.inertia.append(body_inertia(ca, body.mass, self.com[i] - self.r0, ca.mtimes([R, body.inertia, R.T])))

    @property
    def n_bodies(self) -> int:
        return len(self.bodies) + 1

    def ancestors(self, body: int):
        """Bodies from ``body`` up to (not including) the base."""
        while body != 0:
            yield body
            body = self.bodies[body - 1].parent

    def body_twists(self, u):
        """Spatial velocity of every body (about the base CM, in 𝒥)."""
        twists = [u[0:6]]
        for i, body in enumerate(self.bodies, start=1):
            v = twists[body.parent]
            if body.dof is not None:
                v = v + self.subspace[i] * u[6 + body.dof]
            twists.append(v)
        return twists

    def point_position(self, body: int, offset):
        """Position in 𝒥 of the point at ``offset`` (body frame, from its CM) on ``body``."""
        return self.com[body] + self.ca.mtimes(self.rotation[body], np.asarray(offset, dtype=float))

    def point_jacobians(self, body: int, offset):
        """``(J_0X, J_mX)`` (6×6, 6×N) of a point: its twist ``[v_X; ω]`` is
        ``J_0X [v0; w0] + J_mX qd`` (paper eqs. 104–108)."""
        ca = self.ca
        d = self.point_position(body, offset) - self.r0
        # A twist about the base CM seen at the point: v_X = v_ref + ω × d.
        shift = ca.vertcat(ca.horzcat(ca.DM.eye(3), -skew(ca, d)), ca.horzcat(ca.DM.zeros(3, 3), ca.DM.eye(3)))
        Jm = ca.SX.zeros(6, self.n_dof)
        for b in self.ancestors(body):
            dof = self.bodies[b - 1].dof
            if dof is not None:
                Jm[:, dof] = ca.mtimes(shift, self.subspace[b])
        return shift, Jm


def inverse_dynamics(kin: Kinematics, u, du):
    """RNEA (Featherstone §5.3, floating base): the generalized force ``f = [F0; N0; tau]``
    with ``H du + c = f``."""
    ca = kin.ca
    twists = kin.body_twists(u)
    acc = [ca.vertcat(du[0:3] - ca.cross(u[3:6], u[0:3]), du[3:6])]
    forces = []
    for i, body in enumerate(kin.bodies, start=1):
        a = acc[body.parent]
        if body.dof is not None:
            s = kin.subspace[i]
            a = a + s * du[6 + body.dof] + motion_cross(ca, twists[i], s * u[6 + body.dof])
        acc.append(a)
    for i in range(kin.n_bodies):
        inertia = kin.inertia[i]
        forces.append(ca.mtimes(inertia, acc[i]) + force_cross(ca, twists[i], ca.mtimes(inertia, twists[i])))
    tau = [None] * kin.n_dof
    for i in range(kin.n_bodies - 1, 0, -1):
        body = kin.bodies[i - 1]
        if body.dof is not None:
            tau[body.dof] = ca.dot(kin.subspace[i], forces[i])
        forces[body.parent] = forces[body.parent] + forces[i]
    return ca.vertcat(forces[0], *tau)


def composite_inertias(kin: Kinematics):
    """Spatial inertia of each body's subtree about the base CM (CRBA's backward pass)."""
    composite = list(kin.inertia)
    for i in range(kin.n_bodies - 1, 0, -1):
        p = kin.bodies[i - 1].parent
        composite[p] = composite[p] + composite[i]
    return composite


def mass_matrix(kin: Kinematics):
    """CRBA (Featherstone §6.2): ``H`` ((6+N)², paper eq. 36). ``H0`` is the composite inertia
    of the whole system; column ``j`` of ``H0m`` is ``Iᶜ_b S_j``; ``Hm[i, j] = S_iᵀ Iᶜ_b S_j``
    for ``i`` on the path from body ``b`` of dof ``j`` to the base."""
    ca = kin.ca
    n = kin.n_dof
    composite = composite_inertias(kin)
    H = ca.SX.zeros(6 + n, 6 + n)
    H[0:6, 0:6] = composite[0]
    for b in range(1, kin.n_bodies):
        j = kin.bodies[b - 1].dof
        if j is None:
            continue
        F = ca.mtimes(composite[b], kin.subspace[b])
        H[0:6, 6 + j] = F
        H[6 + j, 0:6] = F.T
        for a in kin.ancestors(b):
            i = kin.bodies[a - 1].dof
            if i is not None:
                H[6 + i, 6 + j] = ca.dot(kin.subspace[a], F)
                H[6 + j, 6 + i] = H[6 + i, 6 + j]
    return H


def forward_dynamics(kin: Kinematics, u, f):
    """Articulated-body algorithm with a floating base (Featherstone §9.3): ``du`` with
    ``H du + c = f``, ``f = [F0; N0; tau]``. O(N) operations, so the graph grows linearly."""
    ca = kin.ca
    twists = kin.body_twists(u)
    nb = kin.n_bodies
    bias_acc = [None] * nb  # velocity-product acceleration of each joint (c_i)
    art_inertia = list(kin.inertia)
    art_bias = [force_cross(ca, twists[i], ca.mtimes(kin.inertia[i], twists[i])) for i in range(nb)]
    art_bias[0] = art_bias[0] - f[0:6]
    U, D, uu = [None] * nb, [None] * nb, [None] * nb
    for i in range(nb - 1, 0, -1):
        body = kin.bodies[i - 1]
        Ia, pa = art_inertia[i], art_bias[i]
        if body.dof is not None:
            s = kin.subspace[i]
            bias_acc[i] = motion_cross(ca, twists[i], s * u[6 + body.dof])
            U[i] = ca.mtimes(Ia, s)
            D[i] = ca.dot(s, U[i])
            uu[i] = f[6 + body.dof] - ca.dot(s, pa)
            Ia = Ia - ca.mtimes(U[i], U[i].T) / D[i]
            pa = pa + ca.mtimes(Ia, bias_acc[i]) + U[i] * (uu[i] / D[i])
        art_inertia[body.parent] = art_inertia[body.parent] + Ia
        art_bias[body.parent] = art_bias[body.parent] + pa
    acc = [None] * nb
    acc[0] = -ca.solve(art_inertia[0], art_bias[0])
    qdd = [None] * kin.n_dof
    for i in range(1, nb):
        body = kin.bodies[i - 1]
        a = acc[body.parent]
        if body.dof is not None:
            a = a + bias_acc[i]
            qdd[body.dof] = (uu[i] - ca.dot(U[i], a)) / D[i]
            a = a + kin.subspace[i] * qdd[body.dof]
        acc[i] = a
    base = acc[0]
    return ca.vertcat(base[0:3] + ca.cross(u[3:6], u[0:3]), base[3:6], *qdd)


def momentum_about_base(kin: Kinematics, u):
    """``[P; L_base]``: linear momentum and angular momentum about the base CM, ``Σ I_i V_i``."""
    ca = kin.ca
    twists = kin.body_twists(u)
    h = ca.mtimes(kin.inertia[0], twists[0])
    for i in range(1, kin.n_bodies):
        h = h + ca.mtimes(kin.inertia[i], twists[i])
    return h
