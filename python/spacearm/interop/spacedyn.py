"""SpaceDyn (a MATLAB library): a spacearm state in SpaceDyn's variables and back (states
only; conventions in the docstring of [`spacearm.interop`][spacearm.interop])."""

from __future__ import annotations

from typing import NamedTuple, Tuple

import numpy as np

from ..rotations import quat_from_matrix
from ._common import _checked_state, _finite, _rotation

__all__ = ["SpaceDynState", "to_spacedyn_state", "from_spacedyn_state"]


class SpaceDynState(NamedTuple):
    """A spacearm state in SpaceDyn's variables (``R0, A0, v0, w0, q, qd``).

    Beware the names: SpaceDyn's ``R0`` is the base CM *position* and ``A0`` the base rotation.
    """

    R0: np.ndarray  #: base CM position in the inertial frame
    A0: np.ndarray  #: 3×3 rotation, base frame → inertial frame
    v0: np.ndarray  #: base CM velocity, inertial frame
    w0: np.ndarray  #: base angular velocity, inertial frame
    q: np.ndarray  #: joint positions (N)
    qd: np.ndarray  #: joint velocities (N)


def to_spacedyn_state(robot, x, u) -> SpaceDynState:
    """spacearm ``(x, u)`` → SpaceDyn's ``(R0, A0, v0, w0, q, qd)``: the same vectors (SpaceDyn's
    ``v0``, ``w0`` are in the inertial frame), with the base attitude as the rotation matrix
    ``A0`` (base → inertial) instead of a quaternion."""
    r0, rot, q, u = _checked_state(robot, x, u)
    return SpaceDynState(r0, rot, u[0:3].copy(), u[3:6].copy(), q, u[6:].copy())


def from_spacedyn_state(robot, R0, A0, v0, w0, q, qd) -> Tuple[np.ndarray, np.ndarray]:
    """SpaceDyn's ``(R0, A0, v0, w0, q, qd)`` → spacearm ``(x, u)``. ``R0`` is SpaceDyn's base
    CM position, ``A0`` its base rotation matrix (base → inertial)."""
    n = robot.n_dof
    rot = _rotation(A0, "A0")
    x = np.concatenate([_finite(R0, "R0", 3), quat_from_matrix(rot), _finite(q, "q", n)])
    u = np.concatenate([_finite(v0, "v0", 3), _finite(w0, "w0", 3), _finite(qd, "qd", n)])
    return x, u
