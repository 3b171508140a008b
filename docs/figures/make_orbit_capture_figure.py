#!/usr/bin/env python
"""Regenerate the capture-in-orbit figure of docs/orbit.md and print its comparison table
(about a minute):

    python docs/figures/make_orbit_capture_figure.py

- orbit_capture_spatial6.png: spatial6, its base aligned with LVLH, captures a 50 kg target
  tumbling at 0.1 rad/s about the orbit normal, placed 0.6 m beyond the end effector at rest in
  ECI axes (so drifting in LVLH at the orbit rate), in
  a 500 km, 51.6° orbit, floating, rigid grasp, 60 s of detumbling: the momentum balance, the
  base rate, the joint torques, the grasp wrench, the base attitude relative to LVLH and the
  target's path relative to the chaser's CM in LVLH.
- the table: the same capture in empty space and in orbit (``compare_in_orbit``).
"""

import math
import os

import numpy as np

import spacearm
from spacearm.capture import capture, compare_in_orbit

HERE = os.path.dirname(os.path.abspath(__file__))


def scene():
    robot = spacearm.presets.spatial6()
    orbit = spacearm.Orbit.circular(500e3, inclination=math.radians(51.6))
    frame = spacearm.Orbit.lvlh_to_eci(orbit.r0, orbit.v0)
    quat = spacearm.rotations.quat_from_matrix(frame)  # the base (and the target) aligned with LVLH
    x = robot.neutral_configuration(quat0=quat)
    x[:3] -= robot.center_of_mass(x)
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    at = robot.point_position(x) + 0.6 * frame[:, 0]
    w = np.cross(orbit.r0, orbit.v0) / np.dot(orbit.r0, orbit.r0)  # the LVLH rate
    rel = np.concatenate([frame.T @ at, frame.T @ -np.cross(w, at)])  # at rest in ECI axes
    return robot, orbit, x, target, rel, quat, frame @ np.array([0.0, 0.0, 0.1])


def main():
    robot, orbit, x, target, rel, quat, spin = scene()
    s = target.state_in_orbit(orbit, rel, quaternion=quat, angular_velocity=spin)
    res = capture(robot, target, s, x0=x, detumble_time=60.0, max_joint_torque=20.0, orbit=orbit)
    res.plot(os.path.join(HERE, "orbit_capture_spatial6.png"))
    print(res)
    print({k: v for k, v in res.summary().items() if k.startswith(("orbit", "external", "final", "drift", "target"))})
    for mode in ("floating", "flying"):
        cmp = compare_in_orbit(robot, target, rel, orbit, quaternion=quat, angular_velocity=spin, x0=x, mode=mode,
                               detumble_time=60.0, max_joint_torque=20.0, max_force=10.0, max_torque=5.0)
        print(f"\n{mode}:\n{cmp.table()}")


if __name__ == "__main__":
    main()
