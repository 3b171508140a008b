"""Small rotation helpers for model input and convention conversion.

Quaternions are unit, Hamilton, scalar LAST ``[x, y, z, w]`` (``docs/conventions.md``; the same
as ``scipy.spatial.transform.Rotation.as_quat()`` and Pinocchio). Every quaternion argument of
spacearm also accepts a ``scipy.spatial.transform.Rotation`` holding one rotation
(:func:`spacearm._util.arrays.quaternion`).

Every helper checks its input: shapes, finite values, a unit quaternion (norm 1 within the
core's tolerance, ``_core.QUATERNION_TOLERANCE`` = 1e-6, then normalized exactly) and a proper
rotation matrix (orthonormal with determinant +1 within 1e-6); a bad input raises the
:mod:`spacearm.errors` class that says what was wrong.
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._util.arrays import number, quaternion, vector
from .errors import ArgumentError, NonFiniteError, QuaternionError, ShapeError, SpacearmTypeError

__all__ = ["quat_from_rpy", "quat_from_axis_angle", "quat_to_matrix", "quat_from_matrix", "IDENTITY_QUAT", "MATRIX_TOLERANCE"]

#: The identity rotation ``[0, 0, 0, 1]``.
IDENTITY_QUAT = np.array([0.0, 0.0, 0.0, 1.0])


#: A rotation matrix must be orthonormal with determinant +1 within this (largest entry of
#: ``R^T R - I``, and ``|det R - 1|``).
MATRIX_TOLERANCE = 1e-6


def _finite(arr: np.ndarray, name: str) -> np.ndarray:
    if not np.all(np.isfinite(arr)):
        raise NonFiniteError(f"{name} must be finite, got {arr}")
    return arr


def _angle(value, name: str) -> float:
    angle = number(value, name)
    if not np.isfinite(angle):
        raise NonFiniteError(f"{name} must be a finite angle in rad, got {angle}")
    return angle


def _unit_quaternion(value, name: str) -> np.ndarray:
    """A finite quaternion of unit norm within the core's tolerance, normalized exactly."""
    q = _finite(quaternion(value, name), name)
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > _core.QUATERNION_TOLERANCE:
        raise QuaternionError(
            f"{name} must be a unit quaternion [x, y, z, w] (|q| = 1 within {_core.QUATERNION_TOLERANCE:g}), got norm {norm}")
    return q / norm


def quat_from_axis_angle(axis, angle: float) -> np.ndarray:
    """Quaternion ``[x, y, z, w]`` of a rotation by ``angle`` (rad) about ``axis`` (any non-zero
    3-vector; it is normalized)."""
    axis = _finite(vector(axis, "axis", 3), "axis")
    angle = _angle(angle, "angle")
    largest = float(np.max(np.abs(axis)))
    if largest == 0.0:
        raise ArgumentError(f"axis must be a non-zero vector (it is normalized), got {axis}")
    axis = axis / largest  # scaled first, so that the norm cannot overflow or underflow
    axis = axis / np.linalg.norm(axis)
    s = np.sin(angle / 2.0)
    return np.array([axis[0] * s, axis[1] * s, axis[2] * s, np.cos(angle / 2.0)])


def _mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ])


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Quaternion of the URDF roll-pitch-yaw convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    roll, pitch, yaw = _angle(roll, "roll"), _angle(pitch, "pitch"), _angle(yaw, "yaw")
    qx = quat_from_axis_angle([1, 0, 0], roll)
    qy = quat_from_axis_angle([0, 1, 0], pitch)
    qz = quat_from_axis_angle([0, 0, 1], yaw)
    return _mul(qz, _mul(qy, qx))


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion ``[x, y, z, w]`` (or a scipy ``Rotation``)."""
    x, y, z, w = _unit_quaternion(q, "quaternion")
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def quat_from_matrix(r) -> np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` (with ``w >= 0``) of a rotation matrix (Shepperd's
    method, stable for every rotation). ``r`` must be a proper rotation matrix within
    :data:`MATRIX_TOLERANCE`."""
    try:
        r = np.asarray(r)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise ShapeError(f"r must be a 3x3 rotation matrix, got {r!r}") from exc
    if r.dtype.kind not in "biuf":
        raise SpacearmTypeError(f"r must be a 3x3 matrix of real numbers, got dtype {r.dtype}")
    r = r.astype(np.float64)
    if r.shape != (3, 3):
        raise ShapeError(f"r must be a 3x3 rotation matrix, got shape {r.shape}")
    _finite(r, "r")
    with np.errstate(over="ignore", invalid="ignore"):  # huge entries: inf, refused below
        off = float(np.max(np.abs(r.T @ r - np.eye(3))))
        det = float(np.linalg.det(r))
    if not (off <= MATRIX_TOLERANCE and abs(det - 1.0) <= MATRIX_TOLERANCE):
        raise ArgumentError(f"r must be a rotation matrix (R^T R = I and det R = +1 within {MATRIX_TOLERANCE:g}), "
                            f"got |R^T R - I| = {off:.3g}, det R = {det:.6g}")
    tr = np.trace(r)
    diag = np.array([r[0, 0], r[1, 1], r[2, 2], tr])
    k = int(np.argmax(diag))
    if k == 3:
        w = np.sqrt(1.0 + tr) / 2.0
        q = np.array([(r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w), w])
    else:
        i, j, l = k, (k + 1) % 3, (k + 2) % 3
        s = np.sqrt(1.0 + r[i, i] - r[j, j] - r[l, l]) * 2.0
        q = np.zeros(4)
        q[i] = s / 4.0
        q[j] = (r[j, i] + r[i, j]) / s
        q[l] = (r[l, i] + r[i, l]) / s
        q[3] = (r[l, j] - r[j, l]) / s
    if q[3] < 0:
        q = -q
    return q / np.linalg.norm(q)
