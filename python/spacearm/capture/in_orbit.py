"""The same capture in empty space and in orbit, side by side
([`compare_in_orbit`][spacearm.capture.compare_in_orbit]; docs/orbit.md, "Capture in orbit").

The two runs start from the same states of the run's frame (relative to the orbit's point,
ECI axes): the robot's system CM at the origin with the robot at rest, the target placed by its
LVLH relative state about that CM ([`Target.state_in_orbit`][spacearm.capture.Target.state_in_orbit]). In empty space
the target then moves in a straight line and tumbles torque-free; in orbit it drifts under the
tidal acceleration and tumbles under its gravity gradient, and every body of the robot feels its
tidal wrench. The figures that change are collected in
[`OrbitComparison.rows`][spacearm.capture.OrbitComparison]; nothing here computes physics: both
runs are [`capture`][spacearm.capture.capture].
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..errors import ArgumentError
from ..rotations import rotation_vector
from .sequence import CaptureResult, capture

__all__ = ["OrbitComparison", "compare_in_orbit"]


class OrbitComparison(NamedTuple):
    """The two captures and what changed."""

    empty: CaptureResult  #: the capture in empty space
    orbital: CaptureResult  #: the same capture in orbit
    rows: dict  #: name -> (empty space, in orbit, unit)

    def table(self) -> str:
        """The rows as a Markdown table (what docs/orbit.md shows)."""
        lines = ["| quantity | empty space | in orbit | unit |", "|---|---|---|---|"]
        for name, (a, b, unit) in self.rows.items():
            lines.append(f"| {name} | {_fmt(a)} | {_fmt(b)} | {unit} |")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return "<OrbitComparison\n" + self.table() + "\n>"


def _fmt(v) -> str:
    if isinstance(v, str):
        return v
    if math.isnan(v):
        return "-"
    if not math.isfinite(v):
        return "never" if v > 0 else str(v)
    return f"{v:.4g}"


def _angle_deg(r) -> float:
    """The rotation angle of `r` in degrees (the norm of the core's rotation vector)."""
    return float(np.degrees(np.linalg.norm(rotation_vector(r))))


def _base_rotation(result: CaptureResult, k: int) -> np.ndarray:
    return result.robot.forward_kinematics(result.x[k]).body_to_world[0]


def compare_in_orbit(robot, target, relative, orbit, *, quaternion=(0.0, 0.0, 0.0, 1.0), angular_velocity=(0.0, 0.0, 0.0),
                     x0=None, **capture_options) -> OrbitComparison:
    """Run [`capture`][spacearm.capture.capture] of ``target`` by ``robot`` twice, in empty space and in
    ``orbit`` (with the gravity gradient), from the same states (module docstring): ``x0``
    (default the neutral configuration) shifted so that the system CM is at the origin, the
    target at LVLH relative state ``relative`` (6) about it with ``quaternion`` and
    ``angular_velocity`` (ECI axes). ``capture_options``: the other keywords of ``capture``
    (``mode``, ``kind``, times, gains, limits). Returns an [`OrbitComparison`][spacearm.capture.OrbitComparison]."""
    for key in ("orbit", "gravity_gradient", "u0"):
        if key in capture_options:
            raise ArgumentError(f"compare_in_orbit sets {key!r} itself (the robot starts at rest on the orbit)")
    x = np.array(robot.neutral_configuration() if x0 is None else x0, dtype=float)
    x[:3] -= robot.center_of_mass(x)
    center = np.concatenate([robot.center_of_mass(x), np.zeros(3)])
    s0 = target.state_in_orbit(orbit, relative, center=center, quaternion=quaternion, angular_velocity=angular_velocity)
    empty = capture(robot, target, s0, x0=x, **capture_options)
    orbital = capture(robot, target, s0, x0=x, orbit=orbit, gravity_gradient=True, **capture_options)
    se, so = empty.summary(), orbital.summary()
    ke, ko = (int(np.nonzero(r.phase >= 1)[0][0]) for r in (empty, orbital))
    drift = float(np.linalg.norm(orbital.target[ko, :3] - empty.target[ke, :3])) if ke == ko else math.nan
    tidal = so["external_angular_impulse_norm"] if orbital.mode == "floating" else math.nan
    rows = {
        "grasp time": (se["capture_time"], so["capture_time"], "s"),
        "target CM shift at the grasp (orbit - empty)": (0.0, drift, "m"),
        "grasp impulse, force": (se["impulse_force_norm"], so["impulse_force_norm"], "N s"),
        "grasp impulse, moment": (se["impulse_moment_norm"], so["impulse_moment_norm"], "N m s"),
        "base angular-rate jump": (float(np.linalg.norm(se["base_dw"])), float(np.linalg.norm(so["base_dw"])), "rad/s"),
        "time to detumble": (se["time_to_detumble"], so["time_to_detumble"], "s"),
        "residual base spin": (se["residual_spin"], so["residual_spin"], "rad/s"),
        "final base attitude, orbit vs empty": (0.0, _angle_deg(_base_rotation(empty, -1).T @ _base_rotation(orbital, -1)), "deg"),
        "base angle from LVLH, start / end": ("-", f"{so['initial_lvlh_angle_deg']:.4g} / {so['final_lvlh_angle_deg']:.4g}",
                                              "deg"),
        "integral of the tidal torque (floating)": (0.0, tidal, "N m s"),
        "L: drift (empty space) / balance residual (orbit)": (se["drift_L"], so["drift_L"], "relative"),
    }
    return OrbitComparison(empty, orbital, rows)
