"""SPART (a MATLAB library): a spacearm state in SPART's variables and back (states only;
conventions in the docstring of [`spacearm.interop`][spacearm.interop])."""

from __future__ import annotations

from typing import NamedTuple, Tuple

import numpy as np

from ..rotations import quat_from_matrix
from ._common import _checked_state, _finite, _rotation

__all__ = ["SpartState", "to_spart_state", "from_spart_state"]


class SpartState(NamedTuple):
    """A spacearm state in SPART's variables (``R0, r0, qm, u0, um`` of SPART's kinematics)."""

    R0: np.ndarray  #: 3×3 rotation, base frame → inertial frame
    r0: np.ndarray  #: base CM position in the inertial frame
    qm: np.ndarray  #: joint positions (N)
    u0: np.ndarray  #: ``[ω0 in the base frame; ṙ0 in the inertial frame]`` (angular first)
    um: np.ndarray  #: joint velocities (N)


def to_spart_state(robot, x, u) -> SpartState:
    """spacearm ``(x, u)`` → SPART's ``(R0, r0, qm, u0, um)``.

    ``R0`` is the base rotation of the quaternion ``x[3:7]``; ``u0 = [R0ᵀ ω0; v0]`` (SPART's
    base angular velocity is in the base frame and comes first; its linear velocity is the
    base CM velocity in the inertial frame).
    """
    r0, rot, q, u = _checked_state(robot, x, u)
    return SpartState(rot, r0, q, np.concatenate([rot.T @ u[3:6], u[0:3]]), u[6:].copy())


def from_spart_state(robot, R0, r0, qm, u0, um) -> Tuple[np.ndarray, np.ndarray]:
    """SPART's ``(R0, r0, qm, u0, um)`` → spacearm ``(x, u)``: ``x = [r0, quat(R0), qm]``,
    ``u = [u0[3:6], R0 u0[0:3], um]``. ``R0`` must be a rotation matrix (base → inertial)."""
    n = robot.n_dof
    rot = _rotation(R0, "R0")
    u0 = _finite(u0, "u0", 6)
    x = np.concatenate([_finite(r0, "r0", 3), quat_from_matrix(rot), _finite(qm, "qm", n)])
    return x, np.concatenate([u0[3:6], rot @ u0[0:3], _finite(um, "um", n)])
