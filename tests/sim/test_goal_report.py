"""RMRC says when its goal is out of reach: a warning and meta["goal"], with the distance and the
smallest singular value checked against the records through independent calls."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import spacearm
from spacearm import control


def _run(robot, goal, duration=3.0):
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = control.CartesianLine(p0, goal, 0.0, 0.5 * duration)
    return spacearm.simulate(robot, duration, x0=x0, dt=0.005, controller=control.ResolvedMotionRate(line, gain=2.0))


def test_an_unreachable_goal_is_warned_about_and_flagged_with_distance_and_singular_value():
    robot = spacearm.presets.spatial6()
    p0 = robot.point_position(robot.neutral_configuration())
    goal = p0 + np.array([5.0, 0.0, 0.0])  # far beyond the arm's length
    with pytest.warns(RuntimeWarning, match="goal is out of reach"):
        traj = _run(robot, goal)
    g = traj.meta["goal"]
    assert g["unreachable"] is True
    x_end = traj.x[-1]
    # the distance from the point's own kinematics at the final state
    assert g["distance"] == pytest.approx(np.linalg.norm(goal - robot.point_position(x_end)), rel=1e-9)
    assert g["distance"] > 1.0
    # the smallest singular value of the translational rows of J* (eq. 110) by numpy's SVD
    sv = np.linalg.svd(robot.generalized_jacobian(x_end)[:3], compute_uv=False)
    assert g["sigma_min"] == pytest.approx(sv.min(), rel=1e-6, abs=1e-9)
    assert g["sigma_min"] < spacearm._core.DLS_DEFAULTS.threshold


def test_a_reachable_goal_is_not_flagged():
    robot = spacearm.presets.spatial6()
    p0 = robot.point_position(robot.neutral_configuration())
    goal = p0 + np.array([0.05, 0.05, -0.05])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        traj = _run(robot, goal)
    g = traj.meta["goal"]
    assert g["unreachable"] is False and g["distance"] < spacearm._core.GOAL_TOLERANCE
    assert g["distance"] == pytest.approx(np.linalg.norm(goal - robot.point_position(traj.x[-1])), rel=1e-6, abs=1e-12)


def test_controllers_that_drive_no_point_report_no_goal():
    robot = spacearm.presets.spatial6()
    traj = spacearm.simulate(robot, 0.05, dt=0.01)
    assert "goal" not in traj.meta
