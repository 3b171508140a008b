"""The rotation helpers, once for the package: quaternions (product, exponential and
logarithm, matrix, roll-pitch-yaw, axis-angle), rotation matrices (quaternion, rotation vector)
and the cross-product matrix ``skew``. The rotation math lives once, in the Rust core
(``crates/spacearm-core/src/math/rotations.rs`` and ``math::spatial::skew``): each helper
checks its input here, then calls the extension's binding of the core function
(``crates/spacearm-py/src/rotations_py.rs``), which computes one item or every row of a batch.
Other modules import the helpers from here (``casadi/_spatial.py`` and ``symbolic/`` have their
own on CasADi and SymPy symbols).

Quaternions are unit, Hamilton, scalar LAST ``[x, y, z, w]`` (``docs/conventions.md``; the same
as ``scipy.spatial.transform.Rotation.as_quat()`` and Pinocchio). Every quaternion argument of
spacearm also accepts a ``scipy.spatial.transform.Rotation`` holding one rotation
(``spacearm._util.arrays.quaternion``).

Every helper checks its input: shapes, finite values, a unit quaternion (norm 1 within the
core's tolerance, ``_core.QUATERNION_TOLERANCE`` = 1e-6, then normalized exactly) and a proper
rotation matrix (orthonormal with determinant +1 within 1e-6); a bad input raises the
[`spacearm.errors`][spacearm.errors] class that says what was wrong.
"""

from __future__ import annotations

import numpy as _np

from . import _core
from ._util.arrays import _is_scipy_rotation
from ._util.arrays import number as _number, quaternion as _quaternion, real_array as _real_array, rows as _rows, vector as _vector
from .errors import ArgumentError as _ArgumentError, NonFiniteError as _NonFiniteError, QuaternionError as _QuaternionError
from .errors import ShapeError as _ShapeError, SpacearmTypeError as _SpacearmTypeError

# The module exports its API only (__all__): every helper above is imported under a private name.
del annotations

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
IDENTITY_QUAT = _np.array([0.0, 0.0, 0.0, 1.0])


#: A rotation matrix must be orthonormal with determinant +1 within this (largest entry of
#: ``R^T R - I``, and ``|det R - 1|``).
MATRIX_TOLERANCE = 1e-6


def _finite(arr: _np.ndarray, name: str) -> _np.ndarray:
    if not _np.all(_np.isfinite(arr)):
        raise _NonFiniteError(f"{name} must be finite, got {arr}")
    return arr


def _angle(value, name: str) -> float:
    angle = _number(value, name)
    if not _np.isfinite(angle):
        raise _NonFiniteError(f"{name} must be a finite angle in rad, got {angle}")
    return angle


def quat_from_axis_angle(axis, angle: float) -> _np.ndarray:
    """Quaternion ``[x, y, z, w]`` of a rotation by ``angle`` (rad) about ``axis`` (any non-zero
    3-vector; it is normalized)."""
    axis = _finite(_vector(axis, "axis", 3), "axis")
    angle = _angle(angle, "angle")
    largest = float(_np.max(_np.abs(axis)))
    if largest == 0.0:
        raise _ArgumentError(f"axis must be a non-zero vector (it is normalized), got {axis}")
    axis = axis / largest  # scaled first, so that the norm cannot overflow or underflow
    axis = axis / _np.linalg.norm(axis)
    s = _np.sin(angle / 2.0)
    return _np.array([axis[0] * s, axis[1] * s, axis[2] * s, _np.cos(angle / 2.0)])


def _quaternions(value, name: str) -> _np.ndarray:
    """One quaternion (4,) (or a scipy ``Rotation``) or a batch of them (K, 4), finite."""
    q = _quaternion(value, name) if _is_scipy_rotation(value) else _rows(value, name, 4)
    return _finite(q, name)


def quat_multiply(a, b) -> _np.ndarray:
    r"""Hamilton product $a \otimes b$ of quaternions ``[x, y, z, w]``: for unit ones the rotation
    $R(a)\, R(b)$. Either may be one quaternion (or a scipy ``Rotation``) or ``(K, 4)`` rows, the
    product row by row (one quaternion is used for every row). No unit norm is required (the
    configuration rate $\tfrac12 [\omega; 0] \otimes q$ is a product too)."""
    return _core.quat_multiply(_quaternions(a, "a"), _quaternions(b, "b"))


def quat_exp(theta) -> _np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` of the rotation vector ``theta`` (rotation by
    ``|theta|`` about ``theta / |theta|``); exact near zero."""
    theta = _finite(_vector(theta, "theta", 3), "theta")
    _finite_rotation_angle(theta, "theta")
    return _core.quat_exp(theta)


def _finite_rotation_angle(theta: _np.ndarray, name: str) -> None:
    """Refuse a finite rotation vector whose norm (the angle) overflows: its quaternion would be NaN."""
    with _np.errstate(over="ignore"):
        angle = float(_np.sqrt(_np.dot(theta, theta)))
    if not _np.isfinite(angle):
        raise _NonFiniteError(f"{name} = {theta.tolist()}: its norm, the rotation angle, overflows (beyond "
                             f"{_np.finfo(float).max:.3g} rad); a rotation vector must have a finite norm")


def quat_log(q) -> _np.ndarray:
    r"""Rotation vector (length $\le \pi$) of a quaternion ``[x, y, z, w]`` (or scipy ``Rotation``),
    normalized first."""
    return _core.quat_log(_finite(_quaternion(q, "q"), "q"))


def skew(v) -> _np.ndarray:
    r"""The cross-product matrix $[v]_\times$ ($[v]_\times w = v \times w$) of a 3-vector, or of each row of
    ``(..., 3)`` (shape ``(..., 3, 3)``)."""
    v = _finite(_real_array(v, "v"), "v")
    if v.ndim == 0 or v.shape[-1] != 3:
        raise _ShapeError(f"v must be a 3-vector or an array of shape (..., 3), got shape {v.shape}")
    if v.ndim <= 2:
        return _core.skew(v)
    return _core.skew(v.reshape(-1, 3)).reshape(v.shape[:-1] + (3, 3))


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> _np.ndarray:
    """Quaternion of the URDF roll-pitch-yaw convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    return _core.quat_from_rpy(_angle(roll, "roll"), _angle(pitch, "pitch"), _angle(yaw, "yaw"))


def quat_to_matrix(q) -> _np.ndarray:
    """Rotation matrix of a unit quaternion ``[x, y, z, w]`` (or a scipy ``Rotation``), or the
    matrices ``(K, 3, 3)`` of ``(K, 4)`` rows; each of unit norm within the core's tolerance."""
    q = _quaternions(q, "quaternion")
    norm = _np.linalg.norm(q, axis=-1, keepdims=True)
    worst = float(_np.max(_np.abs(norm - 1.0))) if q.size else 0.0
    if worst > _core.QUATERNION_TOLERANCE:
        raise _QuaternionError(f"quaternion must be a unit quaternion [x, y, z, w] (|q| = 1 within "
                              f"{_core.QUATERNION_TOLERANCE:g}), got norm {float(norm.ravel()[_np.argmax(_np.abs(norm - 1.0))])}")
    return _core.quat_to_matrix(q)  # each divided by its norm


def _rotation_matrix(r, batch: bool = False) -> _np.ndarray:
    """``r`` as a 3×3 float64 proper rotation matrix within [`MATRIX_TOLERANCE`][spacearm.rotations.MATRIX_TOLERANCE] (with
    ``batch``, also ``(B, 3, 3)`` rows of them, each checked)."""
    try:
        r = _np.asarray(r)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise _ShapeError(f"r must be a 3x3 rotation matrix, got {r!r}") from exc
    if r.dtype.kind not in "biuf":
        raise _SpacearmTypeError(f"r must be a 3x3 matrix of real numbers, got dtype {r.dtype}")
    r = _np.ascontiguousarray(r, dtype=_np.float64)
    if r.shape[-2:] != (3, 3) or r.ndim not in ((2, 3) if batch else (2,)):
        rows_text = " (or (B, 3, 3) rows of them)" if batch else ""
        raise _ShapeError(f"r must be a 3x3 rotation matrix{rows_text}, got shape {r.shape}")
    _finite(r, "r")
    if r.size == 0:
        return r
    with _np.errstate(over="ignore", invalid="ignore"):  # huge entries: inf, refused below
        if r.ndim == 2:
            off = float(_np.max(_np.abs(r.T @ r - _np.eye(3))))
            det = float(_np.linalg.det(r))
        else:
            off = float(_np.max(_np.abs(_np.swapaxes(r, -1, -2) @ r - _np.eye(3))))
            dets = _np.linalg.det(r)
            # The worst row's determinant (nan when one is not finite: refused below).
            det = float(dets[int(_np.argmax(_np.abs(dets - 1.0)))]) if _np.all(_np.isfinite(dets)) else float("nan")
    if not (off <= MATRIX_TOLERANCE and abs(det - 1.0) <= MATRIX_TOLERANCE):
        raise _ArgumentError(f"r must be a rotation matrix (R^T R = I and det R = +1 within {MATRIX_TOLERANCE:g}), "
                            f"got |R^T R - I| = {off:.3g}, det R = {det:.6g}")
    return r


def rotation_vector(r) -> _np.ndarray:
    r"""The rotation vector $\theta$ ($\lVert\theta\rVert \le \pi$) with $\exp([\theta]_\times) = r$ of a rotation matrix
    (a proper one within [`MATRIX_TOLERANCE`][spacearm.rotations.MATRIX_TOLERANCE]): $\log(r)$."""
    return _core.rotation_vector(_rotation_matrix(r))


def quat_from_matrix(r) -> _np.ndarray:
    """Unit quaternion ``[x, y, z, w]`` (with ``w >= 0``) of a rotation matrix (Shepperd's
    method, stable for every rotation). ``r`` must be a proper rotation matrix within
    [`MATRIX_TOLERANCE`][spacearm.rotations.MATRIX_TOLERANCE]; ``(B, 3, 3)`` rows of them give ``(B, 4)``."""
    return _core.quat_from_matrix(_rotation_matrix(r, batch=True))
