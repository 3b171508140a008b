"""The rotation helpers, once for the package: quaternions (product, exponential and
logarithm, matrix, roll-pitch-yaw, axis-angle), rotation matrices (quaternion, rotation vector)
and the cross-product matrix ``skew``. The extension exports no rotation functions (its own
are inside the Rust core's ``math/``), so these are numpy; other modules import them from here
(``casadi/_spatial.py`` and ``symbolic/`` have their own on CasADi and SymPy symbols).

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
from ._util.arrays import _is_scipy_rotation, number, quaternion, real_array, rows, vector
from .errors import ArgumentError, NonFiniteError, QuaternionError, ShapeError, SpacearmTypeError

__all__ = [
    "quat_from_rpy",
    "quat_from_axis_angle",
    "quat_multiply",
    "quat_exp",
    "quat_log",
    "quat_to_matrix",
    "quat_from_matrix",
    "rotation_vector",
    "skew",
    "IDENTITY_QUAT",
    "MATRIX_TOLERANCE",
]

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


def _quaternions(value, name: str) -> np.ndarray:
    """One quaternion (4,) (or a scipy ``Rotation``) or a batch of them (K, 4), finite."""
    q = quaternion(value, name) if _is_scipy_rotation(value) else rows(value, name, 4)
    return _finite(q, name)


def quat_multiply(a, b) -> np.ndarray:
    """Hamilton product ``a ⊗ b`` of quaternions ``[x, y, z, w]``: for unit ones the rotation
    ``R(a) R(b)``. Either may be one quaternion (or a scipy ``Rotation``) or ``(K, 4)`` rows, the
    product row by row (one quaternion is used for every row). No unit norm is required (the
    configuration rate ``½ [ω; 0] ⊗ q`` is a product too)."""
    ax, ay, az, aw = np.moveaxis(_quaternions(a, "a"), -1, 0)
    bx, by, bz, bw = np.moveaxis(_quaternions(b, "b"), -1, 0)
    return np.stack([
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ], axis=-1)




def quat_exp(theta) -> np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` of the rotation vector ``theta`` (rotation by
    ``|theta|`` about ``theta / |theta|``); exact near zero."""
    theta = _finite(vector(theta, "theta", 3), "theta")
    angle = float(np.linalg.norm(theta))
    half = 0.5 * angle
    # sin(half)/angle, with its Taylor series near zero.
    k = np.sin(half) / angle if angle > 1e-8 else 0.5 - angle * angle / 48.0
    return np.array([theta[0] * k, theta[1] * k, theta[2] * k, np.cos(half)])


def quat_log(q) -> np.ndarray:
    """Rotation vector (length ≤ π) of a quaternion ``[x, y, z, w]`` (or scipy ``Rotation``),
    normalized first."""
    q = _finite(quaternion(q, "q"), "q")
    q = q / np.linalg.norm(q)
    if q[3] < 0:
        q = -q
    v = q[:3]
    s = float(np.linalg.norm(v))
    angle = 2.0 * np.arctan2(s, q[3])
    k = angle / s if s > 1e-12 else 2.0 / q[3]
    return v * k


def skew(v) -> np.ndarray:
    """The cross-product matrix ``[v]×`` (``[v]× w = v × w``) of a 3-vector, or of each row of
    ``(..., 3)`` (shape ``(..., 3, 3)``)."""
    v = _finite(real_array(v, "v"), "v")
    if v.ndim == 0 or v.shape[-1] != 3:
        raise ShapeError(f"v must be a 3-vector or an array of shape (..., 3), got shape {v.shape}")
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Quaternion of the URDF roll-pitch-yaw convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    roll, pitch, yaw = _angle(roll, "roll"), _angle(pitch, "pitch"), _angle(yaw, "yaw")
    qx = quat_from_axis_angle([1, 0, 0], roll)
    qy = quat_from_axis_angle([0, 1, 0], pitch)
    qz = quat_from_axis_angle([0, 0, 1], yaw)
    return quat_multiply(qz, quat_multiply(qy, qx))


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion ``[x, y, z, w]`` (or a scipy ``Rotation``), or the
    matrices ``(K, 3, 3)`` of ``(K, 4)`` rows; each of unit norm within the core's tolerance."""
    q = _quaternions(q, "quaternion")
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    worst = float(np.max(np.abs(norm - 1.0))) if q.size else 0.0
    if worst > _core.QUATERNION_TOLERANCE:
        raise QuaternionError(f"quaternion must be a unit quaternion [x, y, z, w] (|q| = 1 within "
                              f"{_core.QUATERNION_TOLERANCE:g}), got norm {float(norm.ravel()[np.argmax(np.abs(norm - 1.0))])}")
    x, y, z, w = np.moveaxis(q / norm, -1, 0)
    r = np.empty(q.shape[:-1] + (3, 3))
    r[..., 0, 0] = 1 - 2 * (y * y + z * z)
    r[..., 0, 1] = 2 * (x * y - z * w)
    r[..., 0, 2] = 2 * (x * z + y * w)
    r[..., 1, 0] = 2 * (x * y + z * w)
    r[..., 1, 1] = 1 - 2 * (x * x + z * z)
    r[..., 1, 2] = 2 * (y * z - x * w)
    r[..., 2, 0] = 2 * (x * z - y * w)
    r[..., 2, 1] = 2 * (y * z + x * w)
    r[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return r


def _rotation_matrix(r, batch: bool = False) -> np.ndarray:
    """``r`` as a 3×3 float64 proper rotation matrix within :data:`MATRIX_TOLERANCE` (with
    ``batch``, also ``(B, 3, 3)`` rows of them)."""
    try:
        r = np.asarray(r)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise ShapeError(f"r must be a 3x3 rotation matrix, got {r!r}") from exc
    if r.dtype.kind not in "biuf":
        raise SpacearmTypeError(f"r must be a 3x3 matrix of real numbers, got dtype {r.dtype}")
    r = r.astype(np.float64)
    if r.shape[-2:] != (3, 3) or r.ndim not in ((2, 3) if batch else (2,)):
        rows = " (or (B, 3, 3) rows of them)" if batch else ""
        raise ShapeError(f"r must be a 3x3 rotation matrix{rows}, got shape {r.shape}")
    _finite(r, "r")
    if r.ndim == 3 and r.shape[0] == 0:
        return r
    with np.errstate(over="ignore", invalid="ignore"):  # huge entries: inf, refused below
        off = float(np.max(np.abs(np.swapaxes(r, -1, -2) @ r - np.eye(3))))
        dets = np.atleast_1d(np.linalg.det(r))
        det = float(dets[int(np.argmax(np.abs(dets - 1.0)))]) if np.all(np.isfinite(dets)) else float("nan")
    if not (off <= MATRIX_TOLERANCE and abs(det - 1.0) <= MATRIX_TOLERANCE):
        raise ArgumentError(f"r must be a rotation matrix (R^T R = I and det R = +1 within {MATRIX_TOLERANCE:g}), "
                            f"got |R^T R - I| = {off:.3g}, det R = {det:.6g}")
    return r


def rotation_vector(r) -> np.ndarray:
    """The rotation vector ``θ`` (``|θ| ≤ π``) with ``exp([θ]×) = r`` of a rotation matrix
    (a proper one within :data:`MATRIX_TOLERANCE`): ``log(r)``."""
    r = _rotation_matrix(r)
    c = np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(c)
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return 0.5 * w if angle < 1e-8 else angle / (2.0 * np.sin(angle)) * w


def quat_from_matrix(r) -> np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` (with ``w >= 0``) of a rotation matrix (Shepperd's
    method, stable for every rotation). ``r`` must be a proper rotation matrix within
    :data:`MATRIX_TOLERANCE`; ``(B, 3, 3)`` rows of them give ``(B, 4)``."""
    r = _rotation_matrix(r, batch=True)
    if r.ndim == 3:
        return np.array([_quat_of(m) for m in r]).reshape(len(r), 4) if len(r) else np.zeros((0, 4))
    return _quat_of(r)


def _quat_of(r: np.ndarray) -> np.ndarray:
    """Shepperd's method on one checked rotation matrix."""
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
