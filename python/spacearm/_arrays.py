"""Argument conversion at the Python boundary: anything array-like in, contiguous float64 out,
with errors that name the argument."""

from __future__ import annotations

import numpy as np

from .errors import NonFiniteError, ShapeError


def vector(value, name: str, length: int | None = None) -> np.ndarray:
    """Convert ``value`` to a contiguous 1-D float64 array, checking its length if given."""
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 1-D array of numbers, got {value!r}") from exc
    if arr.ndim != 1:
        raise ShapeError(f"{name} must be a 1-D array, got an array of shape {arr.shape}")
    if length is not None and arr.shape[0] != length:
        raise ShapeError(f"{name} must have length {length}, got {arr.shape[0]}")
    return arr


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
