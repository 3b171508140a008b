"""Attitude control holding LVLH in orbit (issue 25, docs/orbit.md "Holding LVLH"): with reaction
wheels (rotation-floating) and with thrusters (rotation-flying), the reference turns with the
orbit's LVLH frame. Checked against the LVLH frame built here from the recorded CM state
(x̂ = r̂, ẑ = r × v normalized, written in the test) and the orbit rate n = √(μ/a³) by hand; the
inertial hold of the same controller leaves LVLH at that rate."""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm
from spacearm.control import AttitudeControl, BaseThrusterControl
from spacearm.rotations import quat_from_matrix, quat_to_matrix

MU = 3.986004418e14
ORBIT = spacearm.Orbit.circular(500e3, inclination=math.radians(51.6))


def _lvlh(r, v):
    x = r / np.linalg.norm(r, axis=1, keepdims=True)
    z = np.cross(r, v)
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=2)  # columns: LVLH axes in ECI


def _angle(a, b):
    """Rotation angle (rad) between rotation matrices a and b, (K, 3, 3) each."""
    tr = np.einsum("kij,kij->k", a, b)
    return np.arccos(np.clip(0.5 * (tr - 1.0), -1.0, 1.0))


def _sat():
    b = spacearm.RobotBuilder("sat", 500.0, [80.0, 120.0, 150.0])
    for axis in ([1, 0, 0], [0, 1, 0], [0, 0, 1]):
        b.add_reaction_wheel(axis, 0.05, position=(0.0, 0.0, 0.0), mass=2.0)
    return b.build()


def _start(robot, q_rel):
    frame = spacearm.Orbit.lvlh_to_eci(ORBIT.r0, ORBIT.v0)
    x0 = robot.neutral_configuration(quat0=quat_from_matrix(frame @ quat_to_matrix(q_rel)))
    x0[:3] -= robot.center_of_mass(x0)
    n = math.sqrt(MU / np.linalg.norm(ORBIT.r0) ** 3)
    u0 = robot.zero_velocity()
    u0[3:6] = n * frame[:, 2]  # at rest in LVLH: turning at n about the orbit normal
    return x0, u0, n


Q_REL = np.array([0.0, 0.0, math.sin(0.05), math.cos(0.05)])  # 0.1 rad about the orbit normal


@pytest.mark.parametrize("actuator", ["wheels", "thrusters"])
def test_lvlh_hold_follows_the_frame(actuator):
    robot = _sat()
    x0, u0, n = _start(robot, Q_REL)
    duration = 0.25 * ORBIT.period
    if actuator == "wheels":
        hold = AttitudeControl(Q_REL, kp=5.0, kd=60.0, orbit=ORBIT)
        still = AttitudeControl(x0[3:7], kp=5.0, kd=60.0)
        mode = "rotation-floating"
    else:
        hold = BaseThrusterControl(kp_position=0.0, kd_position=0.0, kp_attitude=5.0, kd_attitude=60.0, orbit=ORBIT)
        still = BaseThrusterControl(kp_position=0.0, kd_position=0.0, kp_attitude=5.0, kd_attitude=60.0)
        mode = "rotation-flying"
    runs = [spacearm.simulate(robot, duration, x0=x0, u0=u0, mode=mode, controller=c, orbit=ORBIT, integrator="dopri5",
                              dt=10.0, rtol=1e-10, atol=1e-12) for c in (hold, still)]
    want = np.einsum("kij,jl->kil", _lvlh(runs[0].r_cm_eci, runs[0].v_cm_eci), quat_to_matrix(Q_REL))
    base = quat_to_matrix(runs[0].x[:, 3:7])
    assert np.degrees(_angle(base, want)).max() < 0.01  # held in LVLH through a quarter orbit
    w = runs[0].u[:, 3:6]
    normal = _lvlh(runs[0].r_cm_eci, runs[0].v_cm_eci)[:, :, 2]
    np.testing.assert_allclose(w, n * normal, atol=1e-3 * n)
    # the inertial hold leaves LVLH at the orbit rate: 90 degrees in a quarter orbit
    off = _angle(quat_to_matrix(runs[1].x[:, 3:7]), np.einsum("kij,jl->kil", _lvlh(runs[1].r_cm_eci, runs[1].v_cm_eci),
                                                                   quat_to_matrix(Q_REL)))
    assert np.degrees(off[-1]) == pytest.approx(90.0, abs=1.0)
