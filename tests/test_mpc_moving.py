"""spacearm.mpc's moving reference: a tumbling target's grasp point (a torque-free body
propagated by the core, spacearm_core::scenario::free_body) as the target of a point cost,
evaluated at every knot's time and moved on with the native law's samples (docs/mpc.md,
"Tracking a tumbling target")."""

import dataclasses

import numpy as np
import pytest

import spacearm
import spacearm.mpc as mpc
from spacearm.control import MPC, FreeBodyPoint
from spacearm.errors import ArgumentError, ShapeError

OMEGA = 0.1  # rad/s, about the target's principal axis z
OFFSET = np.array([0.3, 0.0, 0.0])  # the grasp point from the target's CM, body axes (m)


def tumbling(robot, x0, gap=(0.01, -0.01, 0.005)):
    """A target spinning about its principal axis z (so its grasp point has a closed form), placed
    so that the grasp point starts ``gap`` (m) from the end effector."""
    cm = robot.point_position(x0) + np.asarray(gap) - OFFSET
    state = np.concatenate([cm, [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, OMEGA]])
    return FreeBodyPoint([3.0, 4.0, 5.0], state, offset=OFFSET), cm


def grasp_point(cm, t):
    """The grasp point in closed form: ``cm + Rz(ω t) offset``."""
    t = np.atleast_1d(t)
    c, s = np.cos(OMEGA * t), np.sin(OMEGA * t)
    return cm + np.stack([OFFSET[0] * c - OFFSET[1] * s, OFFSET[0] * s + OFFSET[1] * c, np.full_like(t, OFFSET[2])], axis=1)


def tracking_problem(robot, target, horizon=8, dt=0.05, start_time=0.0):
    body, offset = robot.resolve_point(None)
    return mpc.Problem(
        horizon=horizon, dt=dt, start_time=start_time,
        running=[mpc.PointCost(body, target, weight=1e4, offset=offset), mpc.BaseAttitudeCost(10.0, rate_weight=1.0),
                 mpc.JointCost(0.0, robot.initial_q, weight_qd=1.0), mpc.ControlCost(1e-3)],
        terminal=[mpc.PointCost(body, target, weight=1e3, offset=offset)],
        control_limit=5.0,
    )


def test_the_solve_aims_at_the_targets_point_at_each_knots_time():
    robot = spacearm.presets.spatial6()
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    target, cm = tumbling(robot, x0, gap=(0.0, 0.0, 0.0))
    fixed = grasp_point(cm, 0.0)[0]
    # Over 2 s the grasp point moves 6 cm: a plan aimed at the moving point ends near where the
    # point is at the horizon's end, one aimed at the fixed start does not move away from it.
    body, offset = robot.resolve_point(None)
    for start in (0.0, 3.0):
        moving = mpc.Problem(horizon=10, dt=0.2, start_time=start, running=[mpc.ControlCost(1e-3)],
                             terminal=[mpc.PointCost(body, target, weight=1e4, offset=offset)])
        sol = mpc.solve(robot, moving, x0, u0, max_iterations=50)
        end = robot.point_position(sol.x[-1])
        goal = grasp_point(cm, start + 2.0)[0]
        assert np.linalg.norm(end - goal) < 2e-3, (start, end - goal)
        assert np.linalg.norm(goal - fixed) > 0.05
    still = mpc.Problem(horizon=10, dt=0.2, running=[mpc.ControlCost(1e-3)],
                        terminal=[mpc.PointCost(body, fixed, weight=1e4, offset=offset)])
    sol = mpc.solve(robot, still, x0, u0, max_iterations=50)
    assert np.linalg.norm(robot.point_position(sol.x[-1]) - fixed) < 2e-3
    # The core's propagation of the target (what the cost reads) against the closed form.
    t = np.linspace(0.0, 5.0, 11)
    assert np.abs(target.evaluate(t)[0] - grasp_point(cm, t)).max() < 1e-12


def test_the_closed_loop_tracks_the_grasp_point_to_a_millimetre():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    target, cm = tumbling(robot, x0)
    dt, duration = 0.05, 3.0
    traj = spacearm.simulate(robot, duration, dt=dt, controller=MPC(tracking_problem(robot, target, dt=dt), max_iterations=3))
    ee = np.array([robot.point_position(x) for x in traj.x])
    err = np.linalg.norm(ee - grasp_point(cm, traj.t), axis=1)
    assert err[0] > 0.01  # it starts 1.5 cm away
    settled = traj.t >= 1.0
    assert err[settled].max() < 1e-3, err[settled].max()
    # The grasp point moved: following it is not holding still.
    assert np.linalg.norm(grasp_point(cm, duration)[0] - grasp_point(cm, 0.0)[0]) > 0.08
    # The base attitude disturbance, reported: the rotation angle of the base from its start.
    q = traj.x[:, 3:7]
    angle = 2 * np.arccos(np.clip(np.abs(q @ q[0]), 0.0, 1.0))
    print(f"max tracking error after 1 s {err[settled].max() * 1e3:.3f} mm, base attitude disturbance {np.degrees(angle.max()):.3f} deg")
    assert 0.0 < angle.max() < np.radians(5.0)
    # Free floating: the arm's reaction turns the base, momentum stays zero (to RK4's truncation
    # of the first samples' large torques over 50 ms steps).
    assert np.abs(traj["L_com"]).max() < 1e-4


def test_bad_moving_targets_are_refused():
    robot = spacearm.presets.spatial6()
    target, _ = tumbling(robot, robot.neutral_configuration())
    with pytest.raises(ArgumentError, match="start_time"):
        tracking_problem(robot, target, start_time=-1.0)
    with pytest.raises(ShapeError, match="13"):  # refused when the target is made
        tracking_problem(robot, dataclasses.replace(target, state=target.state[:12]))
    with pytest.raises(ArgumentError, match="target"):
        mpc.Problem(horizon=2, dt=0.1, terminal=[mpc.PointCost(6, [1.0, 2.0])])
