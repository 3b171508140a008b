"""Argument conversion at the Python boundary: anything array-like in, contiguous float64 out,
with errors that name the argument. A quaternion argument also accepts a
``scipy.spatial.transform.Rotation`` (see ``quaternion``)."""

from __future__ import annotations

import math

import numpy as np

from ..errors import ArgumentError, NonFiniteError, ShapeError, SpacearmTypeError
from .show import shown


#: numpy dtype kinds accepted as numbers: bool, signed and unsigned integers, floats. Complex
#: values would lose their imaginary part; objects, datetimes, timedeltas, strings and records
#: are not numbers. The extension applies the same rule to what it converts (convert.rs).
REAL_KINDS = "biuf"


def real_array(value, name: str) -> np.ndarray:
    """``value`` as a contiguous float64 array of any shape, refusing anything that is not real
    numbers: a [`SpacearmTypeError`][spacearm.SpacearmTypeError] naming ``name`` and the dtype (complex, object,
    datetime, string...), a [`ShapeError`][spacearm.ShapeError] for a ragged sequence."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be an array of numbers, got {type(value).__name__} that numpy cannot read as one ({exc})") from None
    if arr.dtype.kind not in REAL_KINDS:
        got = f"a {type(value).__name__}" if arr.ndim == 0 and arr.dtype.kind == "O" else f"an array of dtype {arr.dtype}"
        raise SpacearmTypeError(f"{name} must hold real numbers (bool, int or float), got {got}")
    return np.ascontiguousarray(arr, dtype=np.float64)


def vector(value, name: str, length: int | None = None) -> np.ndarray:
    """Convert ``value`` to a contiguous 1-D float64 array (see ``real_array``), checking
    its length if given."""
    arr = real_array(value, name)
    if arr.ndim != 1:
        raise ShapeError(f"{name} must be a 1-D array, got an array of shape {arr.shape}")
    if length is not None and arr.shape[0] != length:
        raise ShapeError(f"{name} must have length {length}, got {arr.shape[0]}")
    return arr


def rows(value, name: str, width: int) -> np.ndarray:
    """One vector (1-D, length ``width``) or a batch of them (2-D, one per row, ``width``
    columns) as a contiguous float64 array."""
    arr = real_array(value, name)
    if arr.ndim not in (1, 2) or arr.shape[-1] != width:
        raise ShapeError(f"{name} must have shape ({width},) or (B, {width}) for a batch of B, got {arr.shape}")
    return arr


def finite(arr: np.ndarray, name: str) -> np.ndarray:
    """``arr`` itself if every entry is finite, else a [`NonFiniteError`][spacearm.NonFiniteError] naming ``name``
    and the first non-finite entry."""
    if not np.all(np.isfinite(arr)):
        index = int(np.flatnonzero(~np.isfinite(arr.ravel()))[0])
        raise NonFiniteError(f"{name} must be finite, but entry {index} is {arr.ravel()[index]}")
    return arr


def number(value, name: str) -> float:
    """A scalar argument as a float (range checks are the caller's): a string that is not a
    number is an [`ArgumentError`][spacearm.ArgumentError], an object of another kind (``None``, a list) a
    [`SpacearmTypeError`][spacearm.SpacearmTypeError] (the builtin bases of the errors ``float()`` itself raises)."""
    try:
        return float(value)
    except ValueError:
        raise ArgumentError(f"{name} must be a number, got {shown(value)}") from None
    except TypeError:
        raise SpacearmTypeError(f"{name} must be a number, got {type(value).__name__} {shown(value)}") from None


def integer(value, name: str) -> int:
    """An integer argument (a count, a resolution, an index): an ``int``, a numpy integer or a
    float with an integral value; anything else is an [`ArgumentError`][spacearm.ArgumentError] (a value such as
    ``2.5`` or ``"x"``) or a [`SpacearmTypeError`][spacearm.SpacearmTypeError] (``None``, a list)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return int(value)
    as_float = number(value, name)
    if not as_float.is_integer():
        raise ArgumentError(f"{name} must be an integer, got {shown(value)}")
    return int(as_float)


def positive_number(value, name: str, *, zero_allowed: bool = False) -> float:
    """A finite number > 0 (``zero_allowed``: >= 0) as a float, else an
    [`ArgumentError`][spacearm.ArgumentError] naming ``name`` (an option of the Python layer that
    the core does not take: an environment's weights, a video's speed)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if not (math.isfinite(v) and (v >= 0 if zero_allowed else v > 0)):
        raise ArgumentError(f"{name} must be a finite number {'>=' if zero_allowed else '>'} 0, got {value!r}")
    return v


#: The largest count a door passes to the core (its `usize`; PyO3 raises a builtin
#: OverflowError beyond it).
MAX_COUNT = 2**63 - 1


def count(value, name: str) -> int:
    """A count (copies, steps, a recording stride): an integer in ``[1, MAX_COUNT]``, else an
    [`ArgumentError`][spacearm.ArgumentError] (a bool, a float, 0, 10**130...)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= MAX_COUNT:
        raise ArgumentError(f"{name} must be an integer from 1 to 2**63 - 1, got {shown(value)}")
    return int(value)


def vector3(value, name: str) -> np.ndarray:
    arr = vector(value, name, 3)
    if not np.all(np.isfinite(arr)):
        raise NonFiniteError(f"{name} must be finite, got {arr}")
    return arr


def matrix3(value, name: str) -> list:
    arr = real_array(value, name)
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
    several rotations raises [`ShapeError`][spacearm.ShapeError].
    """
    if _is_scipy_rotation(value):
        quat = np.asarray(value.as_quat(), dtype=np.float64)
        if quat.shape != (4,):
            raise ShapeError(f"{name} must be one rotation, got a scipy Rotation holding {quat.size // 4} rotations "
                             f"(as_quat() shape {quat.shape}); index it, e.g. rotation[0]")
        return np.ascontiguousarray(quat)
    return vector(value, name, 4)
