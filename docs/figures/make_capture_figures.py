#!/usr/bin/env python
"""Regenerate the figures of docs/capture.md (about a minute):

    python docs/figures/make_capture_figures.py

1. capture_spatial6_floating.png — the capture sequence of the page's tutorial, floating mode;
2. capture_spatial6_flying.png — the same with base thrusters (flying mode, 2 N m torque limit);
3. capture_envelope_spatial6.png — the capture envelope in flying mode: spin rate × error of the
   controller's target mass and inertia.
"""

import os

import numpy as np

import spacearm
from spacearm.capture import capture, capture_envelope

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    state = target.state(position=robot.point_position(x0) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.05, 0.0, 0.2))
    for mode in ("floating", "flying"):
        result = capture(robot, target, state, mode=mode, detumble_time=20.0, max_joint_torque=10.0, max_torque=2.0, max_force=10.0)
        result.plot(os.path.join(HERE, f"capture_spatial6_{mode}.png"))
        print(mode, {k: v for k, v in result.summary().items() if np.ndim(v) == 0})
    envelope = capture_envelope(robot, target, spin_rates=(0.05, 0.1, 0.2, 0.4, 0.8), inertia_errors=(-0.5, -0.25, 0.0, 0.25, 0.5),
                                spin_axis=(0.3, 0.2, 1.0), mode="flying", duration=20.0, dt=0.05, max_joint_torque=10.0,
                                max_torque=2.0, max_force=10.0, max_grasp_torque=2.0)
    envelope.plot(os.path.join(HERE, "capture_envelope_spatial6.png"))
    print(envelope.success)
    print(envelope.time_to_detumble)


if __name__ == "__main__":
    main()
