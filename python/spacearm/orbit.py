"""Orbits: the central body's constants, osculating two-body elements, and the orbit a run's
system centre of mass follows (two-body + J2), computed by the core (docs/orbit.md).

The classes are the extension's (``spacearm._core``): [`Orbit`][spacearm.Orbit] (``Orbit.circular``,
``Orbit.from_elements``, ``Orbit.from_state``; ``propagate``, ``elements``, ``lvlh_to_eci``,
``j2_secular_rates``), [`CentralBody`][spacearm.CentralBody] (μ, R, J2; ``CentralBody.earth()``) and
[`OrbitalElements`][spacearm.OrbitalElements]. SI units and radians; ECI's z is the central body's pole; LVLH has x
radial, z along the orbit normal.

>>> import spacearm
>>> orbit = spacearm.Orbit.circular(500e3, inclination=0.9)
>>> round(orbit.period / 60.0, 2)
94.62
"""

from __future__ import annotations

import numpy as np

from ._core import CentralBody, Orbit, OrbitalElements
from .rotations import quat_to_matrix

__all__ = ["Orbit", "CentralBody", "OrbitalElements", "attitude_lvlh"]


def attitude_lvlh(r_cm_eci, v_cm_eci, quaternions) -> np.ndarray:
    """Attitudes ``quaternions`` (K, 4: body → ECI) relative to the LVLH frames of the ECI
    states ``r_cm_eci``, ``v_cm_eci`` (K, 3): rotation matrices body → LVLH, (K, 3, 3) (the one
    composition behind ``Trajectory.attitude_lvlh`` and ``CaptureResult.attitude_lvlh``)."""
    lvlh = Orbit.lvlh_to_eci(np.asarray(r_cm_eci, dtype=float), np.asarray(v_cm_eci, dtype=float))
    return np.einsum("kji,kjl->kil", lvlh, quat_to_matrix(np.asarray(quaternions, dtype=float)))
