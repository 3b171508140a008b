"""The capture mission as one core run (crates/spacearm-core/src/sim/capture.rs): its records held
against independent computations from the recorded states — the ledger against the models'
momentum, the grasp instant against the gap between the two grasp points, the target's states
against the captured system's kinematics and the free body's propagation, and the spec's rules."""

from __future__ import annotations

import functools

import numpy as np
import pytest

import spacearm
from spacearm import _core
from spacearm.capture import capture


def _scene():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.1, 0.2))
    return robot, target, s


@functools.lru_cache(maxsize=None)
def _run(kind: str, mode: str = "floating"):
    robot, target, s = _scene()
    return capture(robot, target, s, kind=kind, mode=mode, detumble_time=2.0, post_time=0.3, soft_time=0.2,
                   max_joint_torque=20.0, max_force=10.0, max_torque=5.0)


@pytest.mark.parametrize("kind, mode", [("rigid", "floating"), ("point", "floating"), ("soft", "flying")])
def test_the_mission_is_one_core_run(kind, mode):
    res = _run(kind, mode)
    assert isinstance(res.run, _core.CaptureRun)
    assert res.P is res.run.P and res.t is res.run.t  # the binding's arrays, not copies
    assert list(np.unique(res.phase)) == [0, 1, 2, 3]


@pytest.mark.parametrize("kind", ["rigid", "point", "soft"])
def test_ledger_is_the_momentum_of_the_recorded_states(kind):
    """P and L of robot + target recomputed here, sample by sample, from the robot's (or the
    captured system's) momentum and the free target's."""
    res = _run(kind)
    robot, target = res.robot, res.target_model
    P, L = np.zeros_like(res.P), np.zeros_like(res.L)
    rides = np.zeros(len(res.t), dtype=bool)
    if res.captured is not None:  # from the grasp sample on, the target is a link of the captured system
        rides[np.nonzero(res.phase >= 1)[0][-1] - np.count_nonzero(res.phase >= 2):] = True
    for k in range(len(res.t)):
        if rides[k]:
            m = res.captured.robot.momentum(res.x[k], res.u[k])
            P[k], L[k] = m.P, m.L_origin
        else:
            m, mt = robot.momentum(res.x[k], res.u[k]), target.momentum(res.target[k])
            P[k], L[k] = m.P + mt.P, m.L_origin + mt.L_origin
    scale = max(np.abs(L).max(), 1.0)
    assert np.abs(P - res.P).max() <= 1e-12 * scale and np.abs(L - res.L).max() <= 1e-12 * scale
    # the drift by its definition: the largest deviation from the first sample, relative
    sp, sl = res.run.drift_scales
    assert res.drift["P"] == pytest.approx(np.linalg.norm(P - P[0], axis=1).max() / max(np.linalg.norm(P[0]), sp), rel=1e-6, abs=1e-18)
    assert res.drift["L"] == pytest.approx(np.linalg.norm(L - L[0], axis=1).max() / max(np.linalg.norm(L[0]), sl), rel=1e-6, abs=1e-18)
    assert res.drift["P"] < 1e-9 and res.drift["L"] < 1e-9 and np.abs(res.L).max() > 0.1


@pytest.mark.parametrize("kind", ["rigid", "point"])
def test_the_grasp_is_the_root_of_the_gap(kind):
    """The approach ends where |p_robot − p_target| reaches the tolerance: at the last approach
    sample the gap is the tolerance (located within the step), before it larger."""
    res = _run(kind)
    robot, target = res.robot, res.target_model
    gaps = np.linalg.norm(robot.point_position(res.x[res.phase == 0]) - np.array([target.grasp_position(s) for s in res.target[res.phase == 0]]), axis=1)
    assert gaps[-1] == pytest.approx(0.01, rel=1e-6)
    assert np.all(gaps[:-1] > 0.01)
    assert res.phase_start("capture") == res.t[res.phase == 0][-1] == res.run.approach_end
    assert res.impact.gap == pytest.approx(gaps[-1], rel=1e-12)


def test_target_states_follow_the_captured_system_and_the_free_body():
    rigid = _run("rigid")
    after = rigid.phase >= 2
    sys_ = rigid.captured.robot
    payload = sys_.body_index(rigid.captured.payload)
    kin = sys_.forward_kinematics(rigid.x[after])
    assert np.abs(kin.com_in_world[:, payload] - rigid.target[after][:, :3]).max() < 1e-12
    # the point contact's target flies free: its own propagation from the state after the impact
    point = _run("point")
    k = np.nonzero(point.phase == 1)[0][-1]
    t_free = point.t[point.phase == 2]
    want = point.target_model.propagate(point.target[k], float(t_free[-1] - point.t[k]), dt=1e-4)
    assert np.abs(point.target[point.phase == 2][-1] - want).max() < 1e-9


def test_the_spec_rules_are_the_core_s():
    robot, target, s = _scene()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    spec = {"target_state": s.tolist(), "kind": "glue"}
    with pytest.raises(spacearm.ArgumentError, match=r"kind must be one of \['rigid', 'point', 'soft'\], got 'glue'"):
        _core.check_capture(robot.core_model, x, u, target.body.core_model, spec)
    with pytest.raises(spacearm.ArgumentError, match="unknown field"):
        _core.check_capture(robot.core_model, x, u, target.body.core_model, {"target_state": s.tolist(), "dtt": 0.1})
    _core.check_capture(robot.core_model, x, u, target.body.core_model, {"target_state": s.tolist()})
