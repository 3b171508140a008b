"""spacearm.plan: a small planar4 maneuver planned both ways and checked by re-simulation in
the native simulator (computed torque tracking the plan), not by the optimiser's report; the
attitude plan compared with an independent quintic joint move; limits and end conditions."""

import sys

import numpy as np
import pytest

import spacearm

pytest.importorskip("casadi")
from spacearm.plan import point_to_point  # noqa: E402
from spacearm.control import ComputedTorque, QuinticJoint  # noqa: E402

DURATION, NODES = 3.0, 10


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.planar4()


@pytest.fixture(scope="module")
def target(robot):
    return robot.point_position(robot.neutral_configuration()) + np.array([-0.25, 0.35, 0.0])


@pytest.fixture(scope="module")
def attitude_plan(robot, target):
    return point_to_point(robot, target, duration=DURATION, nodes=NODES, objective="attitude")


@pytest.fixture(scope="module")
def effort_plan(robot, target):
    return point_to_point(robot, target, duration=DURATION, nodes=NODES, objective="effort", effort_limit=0.9, velocity_limit=1.0)


def _angle_between(qa, qb):
    """Rotation angle between unit quaternions (rows), rad."""
    return 2.0 * np.arccos(np.clip(np.abs(np.sum(qa * qb, axis=1)), 0.0, 1.0))


@pytest.mark.parametrize("which", ["attitude_plan", "effort_plan"])
def test_resimulated_plan_reaches_the_target_and_the_planned_attitude(which, request, robot, target):
    plan = request.getfixturevalue(which)
    assert plan.success, plan.status
    assert plan.x.shape == (NODES + 1, robot.nx) and plan.u.shape == (NODES + 1, robot.nu) and plan.tau.shape == (NODES + 1, robot.n_dof)
    traj = plan.resimulate()
    final = robot.point_position(traj.x[-1])
    assert np.linalg.norm(final - target) < 1e-3
    knots = np.searchsorted(traj.t, plan.t - 1e-9)
    np.testing.assert_allclose(traj.t[knots], plan.t, atol=1e-12)
    # The base attitude of the re-simulation is the plan's at every knot (the attitude itself,
    # not only its angle from the start).
    # Tolerance: the plan integrates with RK4 at T/(2K), the re-simulation at a quarter of that.
    assert np.max(_angle_between(traj.x[knots, 3:7], plan.x[:, 3:7])) < 1e-4
    # It moved: the arm travelled, so the comparison is not between two resting states.
    assert np.linalg.norm(traj.x[-1, 7:] - traj.x[0, 7:]) > 0.1
    # At rest at the end (rest_at_end, zero momentum).
    assert np.max(np.abs(traj.u[-1, 6:])) < 1e-3


def test_attitude_plan_disturbs_the_base_less_than_a_quintic_joint_move(attitude_plan, effort_plan, robot):
    q0, q1 = attitude_plan.x[0, 7:], attitude_plan.x[-1, 7:]
    quintic = spacearm.simulate(robot, DURATION, dt=DURATION / 300, joint_limits=False,
                                controller=ComputedTorque(kp=400.0, kd=40.0, reference=QuinticJoint(q0, q1, 0.0, DURATION)))
    quintic_disturbance = quintic.base_rotation_angle.max()
    assert quintic_disturbance > 1e-4  # the comparison means something
    assert attitude_plan.attitude_change.max() < 0.1 * quintic_disturbance
    assert attitude_plan.attitude_change.max() < effort_plan.attitude_change.max()


def test_effort_plan_obeys_its_limits_and_spends_less(effort_plan, attitude_plan):
    assert np.max(np.abs(effort_plan.tau)) <= 0.9 + 1e-6
    assert np.max(np.abs(effort_plan.u[:, 6:])) <= 1.0 + 1e-6
    assert effort_plan.effort < attitude_plan.effort


def test_plan_file_holds_the_plan(attitude_plan, tmp_path):
    path = attitude_plan.save(tmp_path / "plan.npz")
    with np.load(path) as data:
        for key in ("t", "x", "u", "tau", "target"):
            np.testing.assert_array_equal(data[key], getattr(attitude_plan, key))
        assert str(data["status"]) == attitude_plan.status


def test_bad_input(robot, target):
    with pytest.raises(spacearm.errors.ArgumentError, match="objective"):
        point_to_point(robot, target, objective="speed")
    with pytest.raises(spacearm.errors.ArgumentError, match="nodes"):
        point_to_point(robot, target, nodes=1)
    with pytest.raises(spacearm.errors.ShapeError):
        point_to_point(robot, target[:2])
    with pytest.raises(spacearm.errors.ArgumentError, match="duration"):
        point_to_point(robot, target, duration=-1.0)
    with pytest.raises(spacearm.errors.ArgumentError, match="effort limit"):
        point_to_point(robot, target, effort_limit=[1.0, 2.0])
    with pytest.raises(spacearm.errors.SpacearmTypeError):
        point_to_point("planar4", target)
    with pytest.raises(spacearm.errors.ArgumentError, match=".npz"):
        pytest.importorskip("casadi")
        from spacearm.plan import Plan

        Plan.save(type("P", (), {})(), "plan.txt")


def test_missing_casadi_names_the_extra(monkeypatch, robot, target):
    monkeypatch.setitem(sys.modules, "casadi", None)
    with pytest.raises(spacearm.errors.MissingDependencyError, match=r"spacearm\[optimal-control\]"):
        point_to_point(robot, target, warm_start="hold")


def test_reactionless_end_stops_the_base_not_the_arm(robot, target):
    plan = point_to_point(robot, target, duration=2.0, nodes=8, objective="effort", rest_at_end=False, reactionless_end=True)
    assert plan.success, plan.status
    traj = plan.resimulate()
    assert np.linalg.norm(robot.point_position(traj.x[-1]) - target) < 1e-3
    assert np.linalg.norm(traj.u[-1, 3:6]) < 1e-5  # the base does not turn at the end
    assert np.linalg.norm(traj.u[-1, 6:]) > 1e-3  # while the arm still moves (no rest required)
