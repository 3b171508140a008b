"""Grasps that cannot happen are refused, before any run where possible (docs/capture.md,
"Grasps that are refused")."""

from __future__ import annotations

import os
import tempfile

import numpy as np
import pytest

import spacearm
from spacearm.capture import MAX_HANDLE_RATIO, Target, capture, grasp_impulse
from spacearm.cli import main


def _box_half_diagonal(a, b, c):
    return 0.5 * np.sqrt(a * a + b * b + c * c)


def test_a_handle_longer_than_the_bound_relative_to_the_target_size_is_refused():
    # A uniform 1 x 2 x 3 m box of 60 kg: principal moments m (b² + c²) / 12, ...; its size is
    # the half-diagonal, computed here from the sides (not from the inertia the rule reads).
    a, b, c, m = 1.0, 2.0, 3.0, 60.0
    inertia = [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]
    size = _box_half_diagonal(a, b, c)
    Target(m, inertia, grasp_points={"h": (0.0, 0.0, 0.99 * MAX_HANDLE_RATIO * size)})
    with pytest.raises(spacearm.ArgumentError, match="grasp point .h.: the grasp point is 3.7791 m from the CM .* more than 2 × its size 1.8708 m"):
        Target(m, inertia, grasp_points={"h": (0.0, 0.0, 1.01 * MAX_HANDLE_RATIO * size)})


def test_the_cli_default_handle_to_a_far_target_is_refused(capsys):
    # --target-at 10,0,0 made a 7.24 m handle (towards the end effector) on a 0.67 m target.
    rc = main(["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-at", "10,0,0"])
    assert rc == 2
    assert "no handle that long" in capsys.readouterr().err


def test_an_impact_with_the_grasp_points_apart_is_refused():
    robot = spacearm.presets.spatial6()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    target = Target(50.0, [4.0, 5.0, 6.0], grasp_points={"h": (-0.3, 0.0, 0.0)})
    X = robot.point_position(x)
    s = target.state(position=X + [0.3, 0.0, 0.0], angular_velocity=[0.0, 0.0, 0.2])
    assert grasp_impulse(robot, x, u, target, s).gap < 1e-12
    far = target.state(position=X + [1.3, 0.0, 0.0], angular_velocity=[0.0, 0.0, 0.2])  # handle 1 m from the gripper
    with pytest.raises(spacearm.ArgumentError, match=r"1.0000 m apart at the impact, more than the capture tolerance 0.01 m"):
        grasp_impulse(robot, x, u, target, far)
    assert grasp_impulse(robot, x, u, target, far, capture_tolerance=1.5).gap == pytest.approx(1.0, abs=1e-12)


def test_a_target_out_of_reach_is_refused_before_the_approach_runs():
    robot = spacearm.presets.spatial6()
    target = Target(50.0, [4.0, 5.0, 6.0])
    x0 = robot.neutral_configuration()
    cm = robot.center_of_mass(x0)
    # 1e5 m away: the bound of any configuration is a few metres; refused in milliseconds.
    with pytest.raises(spacearm.SimulationError, match="cannot reach the target"):
        capture(robot, target, target.state(position=cm + [1e5, 0.0, 0.0]))
    # Moving away from the robot: the closest approach is at t = 0.
    with pytest.raises(spacearm.SimulationError, match=r"closest at t = 0 s"):
        capture(robot, target, target.state(position=cm + [50.0, 0.0, 0.0], velocity=[1.0, 0.0, 0.0]))
    # Passing by at 50 m/s: it comes within reach during the approach, so it is not refused here.
    with pytest.raises(spacearm.SimulationError, match="did not reach the grasp point"):
        capture(robot, target, target.state(position=cm + [-200.0, 0.5, 0.0], velocity=[50.0, 0.0, 0.0]), approach_time=8.0,
                detumble_time=0.1)


def test_work_beyond_the_bounds_is_refused_before_it_starts():
    robot = spacearm.presets.spatial6()
    target = Target(50.0, [4.0, 5.0, 6.0])
    s = target.state(position=robot.point_position(robot.neutral_configuration()) + [0.3, 0, 0], angular_velocity=[0, 0, 1e6])
    with pytest.raises(spacearm.ArgumentError, match="spins at 1e\\+06 rad/s"):
        capture(robot, target, s)
    with pytest.raises(spacearm.ArgumentError, match="would record 4.1e\\+06 samples"):
        capture(robot, target, target.state(), dt=1e-5)


def test_capture_q0_sets_the_arm_start(capsys):
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q + 0.1
    args = ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--detumble-time", "0.5",
            "--q0", ",".join(f"{v:.17g}" for v in q0), "--out"]
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "c.npz")
        assert main(args + [path]) == 0
        with np.load(path) as f:
            np.testing.assert_allclose(f["x"][0, 7:], q0, rtol=0, atol=0)
    assert main(["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--q0", "1,2"]) == 2
    assert "--q0" in capsys.readouterr().err

