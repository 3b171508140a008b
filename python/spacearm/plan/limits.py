"""Joint limits a plan obeys: the model's, unless overridden."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ArgumentError


@dataclass(frozen=True)
class JointBounds:
    """Per-joint bounds in ``q`` order (length N each; infinite entries are no bound):
    positions ``lower``/``upper`` (rad or m), speeds ``velocity`` (rad/s or m/s) and efforts
    ``effort`` (N·m or N), the speed and effort bounds symmetric about zero."""

    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray

    @classmethod
    def of(cls, robot, position=None, velocity=None, effort=None) -> "JointBounds":
        """The model's joint limits (``Robot.description``), each kind replaced when given:
        ``position`` as ``(lower, upper)`` (numbers or one per joint), ``velocity`` and
        ``effort`` as a number or one per joint."""
        n = robot.n_dof
        links = sorted((link for link in robot.description.links if link.dof is not None), key=lambda link: link.dof)
        lower = np.array([link.limits.lower for link in links], dtype=float)
        upper = np.array([link.limits.upper for link in links], dtype=float)
        vel = np.array([link.limits.velocity for link in links], dtype=float)
        eff = np.array([link.limits.effort for link in links], dtype=float)
        if position is not None:
            try:
                lo, hi = position
            except (TypeError, ValueError):
                raise ArgumentError(f"position limits are (lower, upper), got {position!r}") from None
            lower, upper = _per_joint(lo, n, "lower position limit"), _per_joint(hi, n, "upper position limit")
        if velocity is not None:
            vel = _per_joint(velocity, n, "velocity limit")
        if effort is not None:
            eff = _per_joint(effort, n, "effort limit")
        if np.any(lower >= upper):
            raise ArgumentError(f"every lower position limit must be below the upper one, got lower {lower}, upper {upper}")
        for what, v in (("velocity", vel), ("effort", eff)):
            if np.any(v <= 0) or np.any(np.isnan(v)):
                raise ArgumentError(f"{what} limits must be > 0 (inf for none), got {v}")
        return cls(lower, upper, vel, eff)


def _per_joint(value, n: int, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,) or np.any(np.isnan(arr)):
        raise ArgumentError(f"{name} must be a number or {n} numbers (one per joint), got {value!r}")
    return arr
