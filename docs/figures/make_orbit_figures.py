#!/usr/bin/env python
"""Regenerate the figures of docs/orbit.md (a few minutes: the second is an hour and a half of
simulated time with stiff joint servos):

    python docs/figures/make_orbit_figures.py

- orbit_pitch_libration.png: a rigid 750 kg spacecraft (principal inertias 100, 300, 350 kg m²
  along LVLH x radial, y along-track, z orbit normal) in a 700 km circular orbit, started 5°
  off in pitch and with a small roll rate: the pitch libration at n √(3 (I_y − I_x) / I_z)
  and the coupled roll/yaw modes;
- orbit_spatial6_floating.png: the spatial6 arm-carrying spacecraft, floating in a 500 km
  orbit for one orbit from an LVLH-held start with its joints held by a PD, its attitude
  relative to LVLH under the gravity gradient of the base and the extended arm.
"""

import math
import os

import numpy as np

import spacearm

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    sat = spacearm.RobotBuilder("sat", 750.0, [100.0, 300.0, 350.0]).build()
    orbit = spacearm.Orbit.circular(700e3)
    n = orbit.mean_motion
    quat = spacearm.rotations.quat_exp(np.array([0.0, 0.0, math.radians(5.0)]))
    u0 = np.array([0.0, 0.0, 0.0, 0.0, 2e-5, n])
    traj = spacearm.simulate(sat, 3 * orbit.period, x0=sat.neutral_configuration(quat0=quat), u0=u0, orbit=orbit,
                             integrator="dopri5", dt=20.0, rtol=1e-10, atol=1e-14)
    traj.plot_lvlh(os.path.join(HERE, "orbit_pitch_libration.png"))

    robot = spacearm.presets.spatial6()
    orbit = spacearm.Orbit.circular(500e3, inclination=math.radians(51.6))
    x0 = robot.neutral_configuration()
    x0[:3] -= robot.center_of_mass(x0)  # the system CM on the orbit
    lvlh = spacearm.Orbit.lvlh_to_eci(orbit.r0, orbit.v0)
    x0[3:7] = spacearm.rotations.quat_from_matrix(lvlh)
    u0 = robot.zero_velocity()
    u0[3:6] = orbit.mean_motion * lvlh[:, 2]  # rotating with LVLH
    q0 = robot.initial_q
    hold = spacearm.control.JointPD(kp=50.0, kd=20.0, reference=spacearm.control.QuinticJoint(q0, q0, 0.0, 1.0))
    traj = spacearm.simulate(robot, orbit.period, x0=x0, u0=u0, orbit=orbit, controller=hold, integrator="dopri5", dt=10.0,
                             rtol=1e-10, atol=1e-14)
    traj.plot_lvlh(os.path.join(HERE, "orbit_spatial6_floating.png"))


if __name__ == "__main__":
    main()
