"""Small rotation helpers for model input and convention conversion.

Quaternions are unit, Hamilton, scalar LAST ``[x, y, z, w]`` (``docs/conventions.md``; the same
as ``scipy.spatial.transform.Rotation.as_quat()`` and Pinocchio). Every quaternion argument of
spacearm also accepts a ``scipy.spatial.transform.Rotation`` holding one rotation
(:func:`spacearm._util.arrays.quaternion`).
"""

from __future__ import annotations

import numpy as np

from ._util.arrays import quaternion

__all__ = ["quat_from_rpy", "quat_from_axis_angle", "quat_to_matrix", "quat_from_matrix", "IDENTITY_QUAT"]

#: The identity rotation ``[0, 0, 0, 1]``.
IDENTITY_QUAT = np.array([0.0, 0.0, 0.0, 1.0])


def quat_from_axis_angle(axis, angle: float) -> np.ndarray:
    """Quaternion ``[x, y, z, w]`` of a rotation by ``angle`` (rad) about ``axis``."""
    axis = np.asarray(axis, dtype=float)
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
    qx = quat_from_axis_angle([1, 0, 0], roll)
    qy = quat_from_axis_angle([0, 1, 0], pitch)
    qz = quat_from_axis_angle([0, 0, 1], yaw)
    return _mul(qz, _mul(qy, qx))


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion ``[x, y, z, w]`` (or a scipy ``Rotation``)."""
    q = quaternion(q, "quaternion")
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def quat_from_matrix(r) -> np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` (with ``w >= 0``) of a rotation matrix (Shepperd's
    method, stable for every rotation)."""
    r = np.asarray(r, dtype=float)
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
