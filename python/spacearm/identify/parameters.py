r"""The ten inertial parameters of a rigid payload and their physical form.

A rigid body carried by a body ``g`` of the robot (the grasp body: a gripper link holding a
captured target) is described, in ``g``'s frame (origin at ``g``'s CM, ``docs/conventions.md``),
by the parameter vector

    π = [m, m cx, m cy, m cz, Īxx, Īyy, Īzz, Īxy, Īxz, Īyz]

with ``m`` its mass, ``c`` its CM measured from ``g``'s CM in ``g``'s axes, and ``Ī`` its
inertia about ``g``'s CM (not its own), in ``g``'s axes, as a tensor (``Īxy`` is the
off-diagonal entry, not its negative). The payload's momentum is linear in π (Yoshida & Abiko
2002); the physical parameters are not: $c = h/m$ and, by the parallel-axis theorem,
$I = \bar I - m (\lVert c \rVert^2 E - c c^T)$ about the payload's own CM.
"""

from __future__ import annotations

import numpy as np

from ..errors import SingularError

__all__ = ["PARAMETER_NAMES", "to_parameters", "from_parameters", "physical_jacobian"]

#: Names of the entries of π, in order (units: kg, kg·m, kg·m²).
PARAMETER_NAMES = ("m", "m*cx", "m*cy", "m*cz", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")

#: The six independent entries of a symmetric tensor, in the order of π[4:].
_TENSOR_ENTRIES = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


def _skew_square(c: np.ndarray) -> np.ndarray:
    """``|c|² E − c cᵀ`` (the parallel-axis term per unit mass)."""
    return float(c @ c) * np.eye(3) - np.outer(c, c)


def _tensor(entries) -> np.ndarray:
    t = np.empty((3, 3))
    for value, (i, j) in zip(entries, _TENSOR_ENTRIES):
        t[i, j] = t[j, i] = value
    return t


def _entries(tensor: np.ndarray) -> np.ndarray:
    return np.array([tensor[i, j] for i, j in _TENSOR_ENTRIES])


def to_parameters(mass: float, com, inertia) -> np.ndarray:
    """π from the mass, the CM ``com`` (from the grasp body's CM, in its axes) and the inertia
    about the payload's CM in the grasp body's axes (3×3)."""
    c = np.asarray(com, dtype=float).reshape(3)
    i_about_g = np.asarray(inertia, dtype=float).reshape(3, 3) + mass * _skew_square(c)
    return np.concatenate([[mass], mass * c, _entries(i_about_g)])


def from_parameters(pi) -> tuple:
    """``(mass, com, inertia)`` from π: the inverse of [`to_parameters`][spacearm.identify.to_parameters]. A mass that is
    not positive has no CM: [`SingularError`][spacearm.SingularError]."""
    pi = np.asarray(pi, dtype=float).reshape(10)
    m = float(pi[0])
    if not m > 0.0:
        raise SingularError(f"the estimated payload mass is {m:.6g} kg, not positive: its CM (m c / m) and inertia "
                            "about it are undefined; the motion did not determine the mass (see the estimate's rank)")
    h = pi[1:4]
    c = h / m
    inertia = _tensor(pi[4:]) - _skew_square(h) / m
    return m, c, inertia


def physical_jacobian(pi) -> np.ndarray:
    """Jacobian (10×10) of ``[m, c (3), I entries (6, in π's tensor order)]`` with respect to
    π, for propagating a covariance to the physical parameters (first order)."""
    pi = np.asarray(pi, dtype=float).reshape(10)
    m, h = float(pi[0]), pi[1:4]
    jac = np.zeros((10, 10))
    jac[0, 0] = 1.0
    jac[1:4, 0] = -h / m**2
    jac[1:4, 1:4] = np.eye(3) / m
    # I = Ī − (|h|² E − h hᵀ)/m: ∂/∂m = +(|h|² E − h hᵀ)/m², ∂/∂h_k = −(2 h_k E − e_k hᵀ − h e_kᵀ)/m.
    jac[4:, 0] = _entries(_skew_square(h)) / m**2
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1.0
        jac[4:, 1 + k] = -_entries(2.0 * h[k] * np.eye(3) - np.outer(e, h) - np.outer(h, e)) / m
    jac[4:, 4:] = np.eye(6)
    return jac
