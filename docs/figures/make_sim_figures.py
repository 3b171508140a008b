#!/usr/bin/env python
"""Regenerate the run figure of docs/simulation.md (a few seconds):

    python docs/figures/make_sim_figures.py

The run is the spatial6 computed-torque case of examples/floating_case_studies.py (the same
goal, gains, step and recording); that example also draws the paths figure
(sim_spatial6_computed_torque_paths.png).
"""

import os

import numpy as np

import spacearm
from spacearm import control

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    goal = q0 + np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5])
    controller = control.ComputedTorque(kp=25.0, kd=10.0, reference=control.QuinticJoint(q0, goal, 0.0, 4.0))
    traj = spacearm.simulate(robot, 5.0, dt=1e-3, record_every=10, controller=controller)
    traj.plot(os.path.join(HERE, "sim_spatial6_computed_torque.png"))


if __name__ == "__main__":
    main()
