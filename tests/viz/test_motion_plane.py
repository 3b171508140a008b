"""The reactionless figure draws the path in the plane of the motion (issue 26: spatial7's
motion in x–z was drawn in x–y)."""

from __future__ import annotations

import numpy as np

import spacearm
from spacearm import analysis


def _titles(fig):
    return {ax.get_title(): ax for ax in fig.axes}


def test_a_motion_in_x_z_is_drawn_in_x_z():
    robot = spacearm.presets.spatial7()
    x0 = robot.neutral_configuration()
    target = robot.point_position(x0) + np.array([-0.3, 0.0, 0.2])  # the CLI's default move for a spatial arm
    m = analysis.move_to(robot, target, x0=x0, duration=1.0, settle=0.2, dt=0.02)
    p = m.point_position
    ptp = np.ptp(np.vstack([p, target]), axis=0)
    assert ptp[1] < min(ptp[0], ptp[2])  # the independent fact: y moves least
    fig = m.figure()
    ax = _titles(fig)["end-effector path (inertial x–z, the plane of the motion)"]
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "z (m)"
    np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), p[:, 0])
    np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), p[:, 2])
