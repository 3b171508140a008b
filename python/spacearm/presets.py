"""The two models of the paper's case studies (Wilde et al. 2018, §6), with exactly the
parameters of the project's issue #2.

Both are built with the paper's link convention: every link frame aligns with the base frame
at ``q = 0``, links extend along their x axis, the CM is at mid-length, and joint ``i+1`` sits
at the tip of link ``i``.
"""

from __future__ import annotations

import numpy as np

from .builder import RobotBuilder
from .robot import Robot

__all__ = ["planar4", "spatial6", "PRESETS", "get"]


def _bar_inertia(mass: float, length: float, width: float) -> list:
    """A square bar along x: Ixx = m w²/6, Iyy = Izz = m (L² + w²)/12."""
    return [mass * width**2 / 6.0, mass * (length**2 + width**2) / 12.0, mass * (length**2 + width**2) / 12.0]


def _serial(name, base_mass, base_inertia, first_joint, axes, lengths, masses, width, q0) -> Robot:
    b = RobotBuilder(name, base_mass, base_inertia)
    parent, origin = "base", first_joint
    for i, (axis, length, mass) in enumerate(zip(axes, lengths, masses), start=1):
        b.add_link(
            f"link{i}",
            parent=parent,
            joint="revolute",
            joint_name=f"joint{i}",
            axis=axis,
            origin=origin,
            com=(length / 2.0, 0.0, 0.0),
            mass=mass,
            inertia=_bar_inertia(mass, length, width),
        )
        # The next joint sits at this link's tip: half a length beyond its CM.
        parent, origin = f"link{i}", (length / 2.0, 0.0, 0.0)
    b.add_point("end_effector", body=parent, offset=origin)
    b.set_end_effector("end_effector")
    b.set_initial_q(q0)
    return b.build()


def planar4() -> Robot:
    """Planar 4-link arm on a 100 kg cube (paper case study 1).

    Base: 100 kg, 0.5 m cube (4.1667 kg·m² about each axis). Four revolute joints about +z;
    joint 1 at (0.25, 0, 0) m from the base CM; links 10 kg, 1 m, 0.05 m square bars;
    initial angles [π/4, −π/4, −π/4, π/4].
    """
    return _serial(
        "planar4",
        100.0,
        [4.1667, 4.1667, 4.1667],
        (0.25, 0.0, 0.0),
        [(0, 0, 1)] * 4,
        [1.0] * 4,
        [10.0] * 4,
        0.05,
        [np.pi / 4, -np.pi / 4, -np.pi / 4, np.pi / 4],
    )


def spatial6() -> Robot:
    """Spatial 6-link arm on a 500 kg box (paper case study 2, after Yoshida & Umetani 1993).

    Base: 500 kg, 1.2 × 1.0 × 0.8 m (Ixx 68.33, Iyy 86.67, Izz 101.67 kg·m²); joint 1 at
    (0.6, 0, 0) m; axes x, y, y, x, y, x; lengths 0.2, 1.0, 1.0, 0.15, 0.15, 0.2 m; masses 8,
    15, 12, 4, 3, 3 kg; 0.1 m square bars; initial angles [0, π/4, −π/2, 0, π/4, 0].
    """
    x, y = (1, 0, 0), (0, 1, 0)
    return _serial(
        "spatial6",
        500.0,
        [68.33, 86.67, 101.67],
        (0.6, 0.0, 0.0),
        [x, y, y, x, y, x],
        [0.2, 1.0, 1.0, 0.15, 0.15, 0.2],
        [8.0, 15.0, 12.0, 4.0, 3.0, 3.0],
        0.1,
        [0.0, np.pi / 4, -np.pi / 2, 0.0, np.pi / 4, 0.0],
    )


#: Preset constructors by name (as accepted by the CLI).
PRESETS = {"planar4": planar4, "spatial6": spatial6}


def get(name: str) -> Robot:
    """A preset by name."""
    try:
        return PRESETS[name]()
    except KeyError:
        from .errors import NotFoundError

        raise NotFoundError(f"no preset named '{name}'; presets are {sorted(PRESETS)}") from None
