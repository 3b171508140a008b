"""Argument conversion at the Python boundary: anything array-like in, contiguous float64 out,
with errors that name the argument. A quaternion argument also accepts a
``scipy.spatial.transform.Rotation`` (see :func:`quaternion`)."""

from __future__ import annotations

import numpy as np

from ..errors import ArgumentError, NonFiniteError, ShapeError, SpacearmTypeError


def vector(value, name: str, length: int | None = None) -> np.ndarray:
    """Convert ``value`` to a contiguous 1-D float64 array, checking its length if given."""
    try:
        arr = np.asarray(value)
        complex_values = arr.dtype.kind == "c"  # casting would drop the imaginary parts silently
        if not complex_values:
            arr = np.ascontiguousarray(arr, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 1-D array of numbers, got {value!r}") from exc
    if complex_values:
        raise ShapeError(f"{name} must be real numbers, got complex values {value!r}")
    if arr.ndim != 1:
        raise ShapeError(f"{name} must be a 1-D array, got an array of shape {arr.shape}")
    if length is not None and arr.shape[0] != length:
        raise ShapeError(f"{name} must have length {length}, got {arr.shape[0]}")
    return arr


def number(value, name: str) -> float:
    """A scalar argument as a float (range checks are the caller's): a string that is not a
    number is an :class:`ArgumentError`, an object of another kind (``None``, a list) a
    :class:`SpacearmTypeError` (the builtin bases of the errors ``float()`` itself raises)."""
    try:
        return float(value)
    except ValueError:
        raise ArgumentError(f"{name} must be a number, got {value!r}") from None
    except TypeError:
        raise SpacearmTypeError(f"{name} must be a number, got {type(value).__name__} {value!r}") from None


def integer(value, name: str) -> int:
    """An integer argument (a count, a resolution, an index): an ``int``, a numpy integer or a
    float with an integral value; anything else is an :class:`ArgumentError` (a value such as
    ``2.5`` or ``"x"``) or a :class:`SpacearmTypeError` (``None``, a list)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return int(value)
    as_float = number(value, name)
    if not as_float.is_integer():
        raise ArgumentError(f"{name} must be an integer, got {value!r}")
    return int(as_float)


def vector3(value, name: str) -> np.ndarray:
    arr = vector(value, name, 3)
    if not np.all(np.isfinite(arr)):
        raise NonFiniteError(f"{name} must be finite, got {arr}")
    return arr


def matrix3(value, name: str) -> list:
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 3x3 matrix of numbers, got {value!r}") from exc
    if arr.shape == (3,):
        arr = np.diag(arr)
    if arr.shape != (3, 3):
        raise ShapeError(f"{name} must be a 3x3 matrix (or the 3 diagonal entries), got shape {arr.shape}")
    return arr.tolist()


def _is_scipy_rotation(value) -> bool:
    """Whether ``value`` is a ``scipy.spatial.transform.Rotation``, recognized without importing
    scipy (not a dependency of spacearm)."""
    return hasattr(value, "as_quat") and type(value).__module__.startswith("scipy.spatial.transform")


def quaternion(value, name: str) -> np.ndarray:
    """A quaternion argument ``[x, y, z, w]`` (unit, Hamilton, scalar last) as a contiguous
    float64 4-vector; unit norm is checked where the quaternion is used.

    ``value`` may be any 4-element array-like or a ``scipy.spatial.transform.Rotation`` holding
    one rotation: its ``as_quat()`` is scalar last by default (``scalar_first=False`` since
    scipy 1.14, the only order before), the same convention as spacearm's. A Rotation holding
    several rotations raises :class:`~spacearm.errors.ShapeError`.
    """
    if _is_scipy_rotation(value):
        quat = np.asarray(value.as_quat(), dtype=np.float64)
        if quat.shape != (4,):
            raise ShapeError(f"{name} must be one rotation, got a scipy Rotation holding {quat.size // 4} rotations "
                             f"(as_quat() shape {quat.shape}); index it, e.g. rotation[0]")
        return np.ascontiguousarray(quat)
    return vector(value, name, 4)
