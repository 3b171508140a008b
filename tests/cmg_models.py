"""A spacecraft with a 4-CMG pyramid cluster (docs/cmg.md) and a two-joint arm, shared by the CMG
tests (tests/model/test_cmg.py) and the controller doors (tests/fmi/test_controller_doors.py)."""

from __future__ import annotations

import numpy as np

import spacearm

BETA = np.arccos(1.0 / np.sqrt(3.0))  # 54.74°: the pyramid whose envelope is nearly spherical
J_S = 0.05  # rotor spin moment, kg m^2


def rodrigues(axis, angle):
    """The rotation matrix by ``angle`` about the unit ``axis`` (Rodrigues' formula)."""
    k = np.asarray(axis, float)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def pyramid_axes(beta: float = BETA):
    """Gimbal axes normal to the faces of a pyramid of skew angle ``beta`` and the spin axes at
    zero gimbal angle (Wie's 4-CMG pyramid)."""
    sb, cb = np.sin(beta), np.cos(beta)
    gimbals = [(sb, 0, cb), (0, sb, cb), (-sb, 0, cb), (0, -sb, cb)]
    spins = [(0, 1, 0), (-1, 0, 0), (0, -1, 0), (1, 0, 0)]
    return [np.array(g, float) for g in gimbals], [np.array(s, float) for s in spins]


def pyramid_sat(arm: bool = True, variable_speed: bool = False) -> spacearm.Robot:
    b = spacearm.Robot.builder("cmg-sat", base_mass=200.0, base_inertia=[30.0, 34.0, 38.0])
    for i, (g, s) in enumerate(zip(*pyramid_axes())):
        b.add_cmg(f"cmg{i + 1}", position=0.3 * np.cross(g, s), gimbal_axis=g, spin_axis=s, rotor_inertia=J_S,
                  gimbal_inertia=[0.02, 0.015, 0.018], rotor_mass=3.0, gimbal_mass=1.5, variable_speed=variable_speed,
                  max_wheel_speed=800.0)
    if arm:
        b.add_link("upper", joint="revolute", axis=(0, 1, 0), origin=(0.8, 0, 0.2), com=(0.5, 0, 0), mass=6.0,
                   inertia=[0.02, 0.5, 0.5])
        b.add_link("fore", parent="upper", joint="revolute", axis=(0, 0, 1), origin=(1.0, 0, 0), com=(0.4, 0, 0),
                   mass=4.0, inertia=[0.01, 0.2, 0.2])
    return b.build()


