r"""The momentum regressor of a payload carried by one body of a robot (Yoshida & Abiko 2002).

A rigid payload fixed to the grasp body ``g`` moves with it: with ``r_g`` the position of ``g``'s
CM in 𝒥, $R_g$ its rotation (body to 𝒥), $v_g$ the velocity of its CM and $\omega$ its angular
velocity (both in 𝒥), a point $\rho$ of the payload (from ``g``'s CM, in ``g``'s axes) is at
$r = r_g + R_g \rho$ with velocity $v_g + \omega \times R_g \rho$. Integrating over the payload's mass,

$$
\begin{aligned}
P_\text{payload} &= m\, v_g + [\omega]_\times R_g h \\
L_\text{payload} &= r_g \times P_\text{payload} + (R_g h) \times v_g + R_g \bar I R_g^T \omega \qquad \text{(about the origin of } \mathcal{J}\text{)}
\end{aligned}
$$

with $h = m c$ and $\bar I$ the payload's inertia about ``g``'s CM in ``g``'s axes. Both are linear
in the parameter vector $\pi$ of [`spacearm.identify.parameters`][spacearm.identify.parameters]:

$$
\begin{bmatrix} P \\ L \end{bmatrix}_\text{payload} = Y(x, u)\, \pi, \qquad
Y = \begin{bmatrix} v_g & [\omega]_\times R_g & 0 \\
r_g \times v_g & \bigl([r_g]_\times [\omega]_\times - [v_g]_\times\bigr) R_g & R_g \Lambda(R_g^T \omega) \end{bmatrix}
$$

where $\Lambda(w)$ maps the six tensor entries to $\bar I w$. The robot's own momentum ``[P; L_origin]``
comes from the known model. With no external wrench, the combined system's momentum
$h_\text{robot}(x, u) + Y(x, u)\, \pi$ stays constant along the motion: the equation the estimator solves.
"""

from __future__ import annotations

import numpy as np

from ..rotations import skew

__all__ = ["momentum_regressor", "robot_momentum"]


def _tensor_times(w: np.ndarray) -> np.ndarray:
    """``Λ(w)`` (..., 3, 6): ``Ī w`` for ``Ī`` given by its entries (xx, yy, zz, xy, xz, yz)."""
    lam = np.zeros(w.shape[:-1] + (3, 6))
    x, y, z = w[..., 0], w[..., 1], w[..., 2]
    lam[..., 0, 0], lam[..., 0, 3], lam[..., 0, 4] = x, y, z
    lam[..., 1, 1], lam[..., 1, 3], lam[..., 1, 5] = y, x, z
    lam[..., 2, 2], lam[..., 2, 4], lam[..., 2, 5] = z, x, y
    return lam


def _grasp_body_motion(robot, body: int, xs: np.ndarray, us: np.ndarray):
    """``r_g, R_g, v_g, ω`` of body ``body``'s CM frame for every sample (shapes (K, 3), (K, 3, 3),
    (K, 3), (K, 3)), from the robot's kinematics and point Jacobians (eqs. 104–108), one batch
    call each."""
    kin = robot.forward_kinematics(xs)
    j0, jm = robot.point_jacobian(xs, (body, np.zeros(3)))
    twist = np.einsum("kij,kj->ki", j0, us[:, :6]) + np.einsum("kij,kj->ki", jm, us[:, 6:])
    return kin.com_in_world[:, body], kin.body_to_world[:, body], twist[:, :3], twist[:, 3:]


def momentum_regressor(robot, body: int, xs, us) -> np.ndarray:
    """``Y`` (K, 6, 10) for every sample: ``[P; L_origin]`` of a payload fixed to body index
    ``body`` of ``robot`` is ``Y π`` (module docstring). ``xs`` (K, 7+N), ``us`` (K, 6+N)."""
    xs, us = np.asarray(xs, dtype=float), np.asarray(us, dtype=float)
    r_g, rot, v_g, w = _grasp_body_motion(robot, body, xs, us)
    y = np.zeros((len(xs), 6, 10))
    y[:, :3, 0] = v_g
    y[:, :3, 1:4] = skew(w) @ rot
    y[:, 3:, 0] = np.cross(r_g, v_g)
    y[:, 3:, 1:4] = (skew(r_g) @ skew(w) - skew(v_g)) @ rot
    w_body = np.einsum("kji,kj->ki", rot, w)  # R_gᵀ ω
    y[:, 3:, 4:] = rot @ _tensor_times(w_body)
    return y


def robot_momentum(robot, xs, us) -> np.ndarray:
    """``[P; L_origin]`` (K, 6) of the robot's own bodies for every sample (one batch call)."""
    m = robot.momentum(np.asarray(xs, dtype=float), np.asarray(us, dtype=float))
    return np.hstack([m.P, m.L_origin])
